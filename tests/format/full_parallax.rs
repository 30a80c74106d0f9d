//! Full parallax in the file (spec §8): one part per (frame, view), the
//! colours its channels; round trips of whole frames and of regions (one view,
//! a window of views, a band of rows) on random content; headers as the spec
//! lays them out; older versions refused.

use std::borrow::Cow;

use holo::format::{read, write, write_frames, Compression, FormatVersion, HoloFile, Region, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, Geometry, ViewSpacing, Views};
use holo::Modulation;
use rand::{Rng, SeedableRng};

use crate::roundtrip::random;
use rand_chacha::ChaCha8Rng;

/// `rows × columns` emitters, `v × w` views.
pub(crate) fn geometry(rows: usize, columns: usize, v: usize, w: usize, rgb: bool) -> Geometry {
    let spread = |n: usize, a: f64| if n > 1 { (-a, a) } else { (0.0, 0.0) };
    let (h0, h1) = spread(v, 0.25);
    let (k0, k1) = spread(w, 0.15);
    Geometry::centred(
        rows,
        columns,
        Views::tan_spaced(v, h0, h1),
        3.0e-4,
        2.0e-4,
        0.01,
        0.6,
        if rgb { rgb_channels() } else { mono_channel() },
    )
    .with_vertical_views(Views { count: w, first_theta_rad: k0, last_theta_rad: k1, spacing: ViewSpacing::Sin })
}

fn options(sample_type: SampleType, compression: Compression) -> WriteOptions {
    WriteOptions { sample_type, compression, source: "full parallax test".into(), ..WriteOptions::default() }
}

/// Sample (c, j, e, h, k) of `m`.
fn at(m: &Modulation, c: usize, j: usize, e: usize, h: usize, k: usize) -> f32 {
    m.get(c, j, e, m.geometry().view_index(h, k))
}

#[test]
fn whole_frames_round_trip_in_every_lossless_compression() {
    let dir = tempfile::tempdir().unwrap();
    for (n, (rows, columns, v, w, rgb)) in
        [(5, 7, 3, 2, true), (40, 9, 4, 5, false), (1, 1, 1, 3, true)].into_iter().enumerate()
    {
        let m = random(geometry(rows, columns, v, w, rgb), n as u64 + 7);
        for compression in [Compression::None, Compression::Rle, Compression::Zips, Compression::Zip, Compression::Piz]
        {
            let path = dir.path().join(format!("{n}-{}.holo", compression.name()));
            let report = write(&path, &m, &options(SampleType::F32, compression)).unwrap();
            assert_eq!(report.digests.len(), v * w, "one digest per view");
            assert_eq!(read(&path).unwrap(), m, "{n} {}", compression.name());
        }
        let path = dir.path().join(format!("{n}-f16.holo"));
        write(&path, &m, &options(SampleType::F16, Compression::Zip)).unwrap();
        let back = read(&path).unwrap();
        for (a, b) in back.samples().iter().zip(m.samples()) {
            assert_eq!(*a, half::f16::from_f32(*b).to_f32());
        }
    }
}

#[test]
fn a_region_decodes_its_views_and_rows_alone() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(70, 11, 5, 4, true);
    let m = random(g.clone(), 3);
    let path = dir.path().join("region.holo");
    write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
    let file = HoloFile::open(&path).unwrap();
    for region in [
        Region { hololines: 0..70, emitters: 0..11, views: 2..3, vertical_views: 1..2 },
        Region { hololines: 17..53, emitters: 3..10, views: 1..4, vertical_views: 2..4 },
        Region { hololines: 33..34, emitters: 0..11, views: 0..5, vertical_views: 0..4 },
    ] {
        let part = file.read_region(0, &region).unwrap();
        let sub = part.geometry();
        assert_eq!((sub.views.count, sub.vertical_view_count()), (region.views.len(), region.vertical_views.len()));
        // The region's views point where the file's do.
        let (h0, k0) = (region.views.start, region.vertical_views.start);
        let ray = sub.ray(0, 0, 0);
        let whole = g.ray(region.hololines.start, region.emitters.start, g.view_index(h0, k0));
        assert!((ray.slope_x - whole.slope_x).abs() < 1e-15 && (ray.slope_y - whole.slope_y).abs() < 1e-15);
        for c in 0..3 {
            for (jj, j) in region.hololines.clone().enumerate() {
                for (ee, e) in region.emitters.clone().enumerate() {
                    for (kk, k) in region.vertical_views.clone().enumerate() {
                        for (hh, h) in region.views.clone().enumerate() {
                            assert_eq!(at(&part, c, jj, ee, hh, kk), at(&m, c, j, e, h, k), "{region:?}");
                        }
                    }
                }
            }
        }
    }
    let bad = Region { hololines: 0..1, emitters: 0..1, views: 0..1, vertical_views: 3..5 };
    let err = file.read_region(0, &bad).unwrap_err().to_string();
    assert!(err.contains("vertical views 3..5") && err.contains("70×11×5×4"), "{err}");
}

#[test]
fn each_view_is_a_part_of_colour_channels_and_the_headers_say_which() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(4, 6, 3, 2, true);
    let frames: Vec<Modulation> = (0..2).map(|f| random(g.clone(), 20 + f)).collect();
    let path = dir.path().join("two.holo");
    write_frames(&path, &g, 2, &options(SampleType::F16, Compression::Zip), |f| Ok(Cow::Borrowed(&frames[f]))).unwrap();
    let meta = exr::meta::MetaData::read_from_file(&path, false).unwrap();
    assert_eq!(meta.headers.len(), 2 * 3 * 2);
    for (p, header) in meta.headers.iter().enumerate() {
        let (f, k, h) = (p / 6, (p / 3) % 2, p % 3);
        let names: Vec<String> = header.channels.list.iter().map(|c| c.name.to_string()).collect();
        assert_eq!(names, ["B", "G", "R"]);
        assert_eq!(
            header.own_attributes.layer_name.as_ref().unwrap().to_string(),
            format!("frame{f:05}.v{h:03}_{k:03}")
        );
        let attr = |n: &str| header.own_attributes.other.get(&exr::meta::attribute::Text::from(n)).cloned();
        assert_eq!(
            attr("holo.view"),
            Some(exr::meta::attribute::AttributeValue::IntVec2(exr::math::Vec2(h as i32, k as i32)))
        );
        assert_eq!(attr("holo.frame"), Some(exr::meta::attribute::AttributeValue::I32(f as i32)));
        assert_eq!(attr("holo.frameCount"), Some(exr::meta::attribute::AttributeValue::I32(2)));
    }
    let file = HoloFile::open(&path).unwrap();
    assert_eq!(file.info().version, (1, 3));
    assert_eq!(file.info().frames.len(), 2);
    assert_eq!(file.info().frames[1].views.len(), 6);
    for (f, frame) in frames.iter().enumerate() {
        let back = file.read_frame(f).unwrap();
        for (a, b) in back.samples().iter().zip(frame.samples()) {
            assert_eq!(*a, half::f16::from_f32(*b).to_f32());
        }
    }
    let v = holo::format::validate_format(&path).unwrap();
    assert!(v.violations.is_empty(), "{:?}", v.violations);
}

#[test]
fn full_parallax_needs_version_1_3_and_horizontal_parallax_stays_1_2() {
    let dir = tempfile::tempdir().unwrap();
    let m = random(geometry(3, 4, 2, 2, false), 5);
    for version in [FormatVersion::V1_1, FormatVersion::V1_0] {
        let err = write(dir.path().join("old.holo"), &m, &WriteOptions { version, ..WriteOptions::default() })
            .unwrap_err()
            .to_string();
        assert!(err.contains("full parallax needs format version 1.3"), "{err}");
    }
    assert!(!dir.path().join("old.holo").exists());
    // Horizontal parallax asked for as 1.3 is written as 1.2 (spec §8).
    let mut hpo = m.geometry().clone();
    hpo.parallax = holo::geometry::Parallax::Horizontal;
    hpo.vertical_views = None;
    let flat = Modulation::from_fn(hpo, |_, j, e, v| (j + e + v) as f32).unwrap();
    let path = dir.path().join("hpo.holo");
    write(&path, &flat, &WriteOptions { version: FormatVersion::V1_3, ..WriteOptions::default() }).unwrap();
    assert_eq!(HoloFile::open(&path).unwrap().info().version, (1, 2));
}

#[test]
fn a_damaged_view_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let m = random(geometry(6, 5, 2, 3, false), 9);
    let path = dir.path().join("damaged.holo");
    write(&path, &m, &options(SampleType::F32, Compression::None)).unwrap();
    // The last part's last sample: the file's last four bytes.
    let mut bytes = std::fs::read(&path).unwrap();
    let n = bytes.len();
    bytes[n - 2] ^= 0x01;
    std::fs::write(&path, &bytes).unwrap();
    let err = read(&path).unwrap_err().to_string();
    assert!(err.contains("view (1 2)") && err.contains("digest"), "{err}");
}

/// Frame 0 of `path` read band by band and put together again.
fn read_in_bands(path: &std::path::Path, band_rows: usize) -> holo::Result<Modulation> {
    let file = HoloFile::open(path)?;
    let g = file.geometry().clone();
    let mut whole = Modulation::zeros(g.clone())?;
    let mut next = 0;
    file.read_frame_in_bands(0, band_rows, |rows, band| {
        assert_eq!(rows.start, next, "bands in order");
        next = rows.end;
        assert_eq!(band.geometry().hololine_top_y_m, g.hololine_y_m(rows.start));
        for c in 0..g.channels.len() {
            for (line, j) in rows.clone().enumerate() {
                let at = whole.index(c, j, 0, 0);
                let n = band.hololine(c, line).len();
                whole.samples_mut()[at..at + n].copy_from_slice(band.hololine(c, line));
            }
        }
        Ok(())
    })?;
    assert_eq!(next, g.hololines);
    Ok(whole)
}

#[test]
fn a_frame_read_band_by_band_or_a_view_alone_is_the_frame_its_digests_checked() {
    let dir = tempfile::tempdir().unwrap();
    let full = random(geometry(9, 5, 2, 3, true), 21);
    let mut horizontal = random(geometry(9, 5, 4, 1, false), 22);
    horizontal = Modulation::from_samples(
        Geometry {
            vertical_views: None,
            parallax: holo::geometry::Parallax::Horizontal,
            ..horizontal.geometry().clone()
        },
        horizontal.samples().to_vec(),
    )
    .unwrap();
    for (name, m) in [("full", &full), ("horizontal", &horizontal)] {
        let path = dir.path().join(format!("{name}.holo"));
        write(&path, m, &options(SampleType::F32, Compression::None)).unwrap();
        for band_rows in [1, 4, 9, 100] {
            assert_eq!(&read_in_bands(&path, band_rows).unwrap(), m, "{name}, bands of {band_rows}");
        }
        let file = HoloFile::open(&path).unwrap();
        let g = m.geometry();
        for k in 0..g.vertical_view_count() {
            for h in 0..g.views.count {
                let view = file.read_view(0, h, k).unwrap();
                assert_eq!(view.geometry().views_per_emitter(), 1);
                assert_eq!(view.geometry().views.theta_rad(0), g.views.theta_rad(h));
                for (c, j, e) in [(0, 0, 0), (g.channels.len() - 1, 8, 4), (0, 3, 2)] {
                    assert_eq!(view.get(c, j, e, 0), at(m, c, j, e, h, k), "{name} view ({h} {k})");
                }
            }
        }
        let err = file.read_view(0, g.views.count, 0).unwrap_err().to_string();
        assert!(err.contains(&format!("view ({} 0) is not one of its", g.views.count)), "{err}");
        // A flipped bit in the last sample: the bands are all handed on,
        // then the digest says the frame is damaged.
        let mut bytes = std::fs::read(&path).unwrap();
        let n = bytes.len();
        bytes[n - 2] ^= 0x01;
        std::fs::write(&path, &bytes).unwrap();
        let err = read_in_bands(&path, 4).unwrap_err();
        match name {
            "full" => assert!(err.to_string().contains("view (1 2)") && err.to_string().contains("digest"), "{err}"),
            _ => assert!(matches!(err, holo::Error::DigestMismatch { frame: 0, .. }), "{err}"),
        }
        if name == "full" {
            let file = HoloFile::open(&path).unwrap();
            assert!(file.read_view(0, 1, 2).unwrap_err().to_string().contains("view (1 2)"));
            file.read_view(0, 0, 2).unwrap();
        }
    }
}

#[test]
fn an_f32_file_reads_as_f16_rounded_its_views_checked_as_stored() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(6, 5, 3, 2, true);
    let m = random(g.clone(), 12);
    let path = dir.path().join("floats.holo");
    write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
    // Each view's digest covers the stored f32 samples, not their f16 roundings.
    let halves = HoloFile::open(&path).unwrap().read_frame_samples::<half::f16>(0).unwrap();
    assert!(halves.iter().zip(m.samples()).all(|(h, &x)| h.to_bits() == half::f16::from_f32(x).to_bits()));
    // One beyond f16's range is an error naming it, not infinity.
    let mut big = m.clone();
    big.set(1, 4, 2, g.view_index(2, 1), 1e6);
    write(&path, &big, &WriteOptions { overwrite: true, ..options(SampleType::F32, Compression::Zip) }).unwrap();
    let err = HoloFile::open(&path).unwrap().read_frame_samples::<half::f16>(0).unwrap_err().to_string();
    assert!(err.contains("too large for f16") && err.contains("hololine 4") && err.contains("view (2 1)"), "{err}");
    // A damaged view is still found (uncompressed: the last sample of the last view).
    write(&path, &m, &WriteOptions { overwrite: true, ..options(SampleType::F32, Compression::None) }).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let n = bytes.len();
    bytes[n - 2] ^= 0x01;
    std::fs::write(&path, &bytes).unwrap();
    let err = HoloFile::open(&path).unwrap().read_frame_samples::<half::f16>(0).unwrap_err().to_string();
    assert!(err.contains("digest"), "{err}");
}

#[test]
fn lossy_files_are_sealed_with_what_a_reader_decodes() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(24, 20, 3, 2, true);
    // Smooth content, as lossy codecs expect.
    let m = Modulation::from_fn(g, |c, j, e, v| 0.2 + 0.01 * (c + j + e) as f32 + 0.03 * v as f32).unwrap();
    for compression in [Compression::B44, Compression::Dwaa] {
        let path = dir.path().join(format!("{}.holo", compression.name()));
        let report = write(&path, &m, &options(SampleType::F16, compression)).unwrap();
        assert!(report.warnings.iter().any(|w| w.contains("lossy")), "{:?}", report.warnings);
        // Read whole, each view's digest checked against what decodes.
        let back = read(&path).unwrap();
        let worst = back.samples().iter().zip(m.samples()).map(|(a, b)| (a - b).abs() / b).fold(0f32, f32::max);
        assert!(worst < 0.02, "{} {worst}", compression.name());
        let v = holo::format::validate_format(&path).unwrap();
        assert!(v.violations.is_empty(), "{:?}", v.violations);
    }
}

#[test]
fn a_bad_sample_is_refused_before_the_file_is_made() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(5, 4, 2, 2, false);
    let path = dir.path().join("bad.holo");
    let mut m = random(g.clone(), 1);
    m.set(0, 3, 2, g.view_index(1, 1), f32::NAN);
    let err = write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap_err().to_string();
    // The view named by its two indices, as its picture's name has them.
    assert!(err.contains("not a number") && err.contains("view (1 1)"), "{err}");
    let mut m = random(g.clone(), 2);
    m.set(0, 1, 0, g.view_index(0, 1), 1e6);
    let err = write(&path, &m, &options(SampleType::F16, Compression::Zip)).unwrap_err().to_string();
    assert!(err.contains("too large for f16") && err.contains("view (0 1)"), "{err}");
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none(), "nothing left behind");
}

#[test]
fn full_parallax_rays_leave_each_emitter_in_both_directions_of_their_view() {
    let g = geometry(9, 13, 7, 5, true);
    let vertical = g.vertical_views.clone().unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(33);
    for _ in 0..2000 {
        let (j, e, h, k) = (rng.gen_range(0..9), rng.gen_range(0..13), rng.gen_range(0..7), rng.gen_range(0..5));
        let v = g.view_index(h, k);
        assert_eq!(g.view_of_index(v), (h, k));
        let ray = g.ray(j, e, v);
        // From the emitter itself (both centres of projection, spec §8) ...
        let origin =
            [g.emitter_left_x_m + e as f64 * g.emitter_pitch_m, g.hololine_top_y_m - j as f64 * g.hololine_pitch_m];
        assert!((ray.origin_m[0] - origin[0]).abs() < 1e-15 && (ray.origin_m[1] - origin[1]).abs() < 1e-15);
        // ... with slopes tan θ_h and tan φ_k, φ by its own spacing rule
        // (sin here: equal steps of sin φ).
        let theta = (((7 - 1 - h) as f64 * (-0.25f64).tan() + h as f64 * 0.25f64.tan()) / 6.0).atan();
        let phi = (((4 - k) as f64 * (-0.15f64).sin() + k as f64 * 0.15f64.sin()) / 4.0).asin();
        assert!((ray.slope_x - theta.tan()).abs() < 1e-14, "({h} {k})");
        assert!((ray.slope_y - phi.tan()).abs() < 1e-14, "({h} {k})");
        // Not toward the viewer line: the slope does not depend on the row.
        assert_eq!(g.ray(0, e, v).slope_y, ray.slope_y);
        assert!((vertical.theta_rad(k) - phi).abs() < 1e-14);
    }
}

#[test]
fn parallax_and_vertical_views_must_agree() {
    let mut g = geometry(2, 2, 2, 2, false);
    g.vertical_views = None;
    assert!(
        g.problems().iter().any(|p| p.contains("full parallax needs vertical view directions")),
        "{:?}",
        g.problems()
    );
    let mut g = geometry(2, 2, 2, 2, false);
    g.parallax = holo::geometry::Parallax::Horizontal;
    assert!(g.problems().iter().any(|p| p.contains("horizontal parallax has no vertical view")), "{:?}", g.problems());
    let mut g = geometry(2, 2, 2, 3, false);
    if let Some(v) = g.vertical_views.as_mut() {
        v.last_theta_rad = -0.3;
    }
    assert!(g.problems().iter().any(|p| p.starts_with("vertical ")), "{:?}", g.problems());
    assert!(write(
        tempfile::tempdir().unwrap().path().join("x.holo"),
        &Modulation::zeros(geometry(2, 2, 2, 2, false)).unwrap(),
        &WriteOptions::default()
    )
    .is_ok());
}

#[test]
fn a_full_parallax_quilt_is_the_quilt_of_the_views_toward_the_viewer_line() {
    use holo::cameras::quilt::{export_quilt, quilt_from_modulation, QuiltOptions, QuiltSpec};
    use holo::picture::White;
    // 12 rows 3 mm apart (±16.5 mm), 4 vertical views over ±0.02 in tan; the
    // viewer line 2 mm up at 500 mm: the rows' directions toward it run
    // from −0.029 to +0.037 in tan, beyond the views at both ends.
    let mut g = Geometry::centred(12, 10, Views::tan_spaced(6, -0.2, 0.2), 3e-3, 2e-3, 0.0, 0.5, rgb_channels())
        .with_vertical_views(Views::tan_spaced(4, -0.02f64.atan(), 0.02f64.atan()));
    g.viewer_height_m = 0.002;
    // Linear in the vertical view k, so the interpolation is exact by hand.
    let a = |c: usize, j: usize, e: usize, h: usize| 0.1 + 0.01 * (c + j + e + h) as f32;
    let b = |c: usize, h: usize| 0.05 + 0.001 * (c + h) as f32;
    let m = Modulation::from_fn(g.clone(), |c, j, e, view| {
        let (h, k) = g.view_of_index(view);
        a(c, j, e, h) + b(c, h) * k as f32
    })
    .unwrap();
    // The horizontal-parallax frame by hand: row j's fractional vertical
    // view is where tan φ_j = (y_v − y_j)/D falls among equal steps of tan.
    let flat = Geometry { vertical_views: None, parallax: holo::geometry::Parallax::Horizontal, ..g.clone() };
    let index = |j: usize| ((g.viewer_height_m - g.hololine_y_m(j)) / 0.5 + 0.02) / 0.04 * 3.0;
    let by_hand = Modulation::from_fn(flat, |c, j, e, h| {
        let f = index(j);
        if (-0.5..=3.5).contains(&f) {
            a(c, j, e, h) + b(c, h) * f.clamp(0.0, 3.0) as f32
        } else {
            0.0
        }
    })
    .unwrap();
    let black: Vec<usize> = (0..12).filter(|&j| !(-0.5..=3.5).contains(&index(j))).collect();
    assert!(black.contains(&0) && black.contains(&11) && black.len() < 8, "{black:?}");
    assert_eq!(holo::rows_beyond_vertical_views(&g), black);
    let converted = holo::full_to_horizontal(&m).unwrap();
    assert_eq!(converted.geometry(), by_hand.geometry());
    for (x, y) in converted.samples().iter().zip(by_hand.samples()) {
        assert!((x - y).abs() < 1e-6, "{x} {y}");
    }
    // The file's quilt, read band by band, is the hand-built frame's.
    let spec =
        QuiltSpec { columns: 3, rows: 2, tile_width: 30, tile_height: 40, aspect: 0.75, ..QuiltSpec::portrait() };
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("full.holo");
    write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
    let options = QuiltOptions { white: White::Value(1.0), overwrite: false };
    let report = export_quilt(&path, 0, &spec, &dir.path().join("q.png"), &options).unwrap();
    assert!(report.warnings.iter().any(|w| w.contains(&format!("{} of 12 emitter rows send no view", black.len()))));
    let quilt = quilt_from_modulation(&by_hand, &spec).unwrap();
    let mine = quilt_from_modulation(&converted, &spec).unwrap();
    for (p, q) in mine.rgb.iter().zip(&quilt.rgb) {
        assert!((0..3).all(|i| (p[i] - q[i]).abs() < 1e-6), "{p:?} {q:?}");
    }
    assert_eq!(std::fs::read(dir.path().join("q.png")).unwrap(), mine.png(1.0).unwrap());
}

/// `holo resample`: a full-parallax file made horizontal is, frame by frame
/// (a movie of two), what `full_to_horizontal` makes of each, with its
/// black rows said; a horizontal-parallax file made full has every vertical
/// view a copy of its views, said as such, and back again it is itself.
#[test]
fn resampling_between_full_and_horizontal_parallax() {
    use holo::parallax::resample_parallax;
    let dir = tempfile::tempdir().unwrap();
    let mut g = geometry(7, 9, 5, 4, true);
    g.viewer_height_m = 0.0005;
    let mut rng = ChaCha8Rng::seed_from_u64(41);
    let frames: Vec<Modulation> =
        (0..2).map(|_| Modulation::from_fn(g.clone(), |_, _, _, _| rng.gen_range(0.05f32..1.0)).unwrap()).collect();
    let full = dir.path().join("full.holo");
    write_frames(&full, &g, 2, &options(SampleType::F32, Compression::Zip), |f| Ok(Cow::Borrowed(&frames[f]))).unwrap();
    let flat_path = dir.path().join("flat.holo");
    let o = options(SampleType::F32, Compression::Zip);
    let run = resample_parallax(&full, None, &flat_path, o.clone(), &holo::progress::Silent).unwrap();
    let flat = HoloFile::open(&flat_path).unwrap();
    assert!(flat.geometry().vertical_views.is_none());
    assert_eq!(flat.info().frames.len(), 2);
    for (i, m) in frames.iter().enumerate() {
        assert_eq!(flat.read_frame(i).unwrap(), holo::full_to_horizontal(m).unwrap(), "frame {i}");
    }
    assert_eq!(run.warnings.is_empty(), holo::rows_beyond_vertical_views(&g).is_empty(), "{:?}", run.warnings);
    // Horizontal → full: replication, said.
    let vertical = Views::tan_spaced(3, -0.1, 0.1);
    let again = dir.path().join("again.holo");
    let run =
        resample_parallax(&flat_path, Some(vertical.clone()), &again, o.clone(), &holo::progress::Silent).unwrap();
    assert!(run.warnings.iter().any(|w| w.contains("copies")), "{:?}", run.warnings);
    let again = HoloFile::open(&again).unwrap();
    assert_eq!(again.geometry().vertical_views, Some(vertical));
    let (replicated, original) = (again.read_frame(1).unwrap(), flat.read_frame(1).unwrap());
    let a = replicated.geometry().clone();
    for (c, j, e) in [(0, 0, 0), (2, 6, 8), (1, 3, 4)] {
        for h in 0..5 {
            for k in 0..3 {
                assert_eq!(replicated.get(c, j, e, a.view_index(h, k)), original.get(c, j, e, h));
            }
        }
    }
    // Asking for the parallax a file has is refused, naming it.
    let e = resample_parallax(
        &full,
        Some(Views::tan_spaced(3, -0.1, 0.1)),
        &dir.path().join("x.holo"),
        o,
        &holo::progress::Silent,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("full.holo") && e.contains("full parallax already"), "{e}");
}
