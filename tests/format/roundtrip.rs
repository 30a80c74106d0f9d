//! read(write(m)) == m: exactly for f32 with lossless compression, and equal
//! to m rounded to f16 for f16. Random, non-zero modulations of many shapes.

use std::borrow::Cow;

use holo::format::{read, write, write_frames, Compression, HoloFile, Region, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, ColourChannel, Geometry, ViewSpacing, Views};
use holo::Modulation;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn geometry(hololines: usize, emitters: usize, views: usize, rgb: bool) -> Geometry {
    Geometry::centred(
        hololines,
        emitters,
        Views::tan_spaced(views, -0.2, if views > 1 { 0.2 } else { -0.2 }),
        1.3e-4,
        2.4e-4,
        0.027,
        0.6,
        if rgb { rgb_channels() } else { mono_channel() },
    )
}

/// Random radiance over several decades, a few exact zeros, never all zero.
pub(crate) fn random(g: Geometry, seed: u64) -> Modulation {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    Modulation::from_fn(g, |_, _, _, _| {
        if rng.gen_bool(0.05) {
            0.0
        } else {
            10f32.powf(rng.gen_range(-4.0..3.0)) * rng.gen_range(0.5..1.0)
        }
    })
    .unwrap()
}

fn rounded_to_f16(m: &Modulation) -> Modulation {
    let mut r = m.clone();
    r.samples_mut().iter_mut().for_each(|x| *x = half::f16::from_f32(*x).to_f32());
    r
}

fn options(sample_type: SampleType, compression: Compression) -> WriteOptions {
    WriteOptions { sample_type, compression, source: "roundtrip test".into(), ..WriteOptions::default() }
}

#[test]
fn every_lossless_compression_round_trips_f32_and_f16() {
    let dir = tempfile::tempdir().unwrap();
    for (k, (h, e, v, rgb)) in
        [(7, 5, 3, false), (33, 17, 9, true), (1, 1, 1, false), (20, 64, 32, true)].into_iter().enumerate()
    {
        let m = random(geometry(h, e, v, rgb), k as u64 + 1);
        for compression in [Compression::None, Compression::Rle, Compression::Zips, Compression::Zip, Compression::Piz]
        {
            for sample_type in [SampleType::F32, SampleType::F16] {
                let path = dir.path().join(format!("{k}-{}-{sample_type:?}.holo", compression.name()));
                write(&path, &m, &options(sample_type, compression)).unwrap();
                let back = read(&path).unwrap();
                let expected = if sample_type == SampleType::F32 { m.clone() } else { rounded_to_f16(&m) };
                assert_eq!(back, expected, "{}", path.display());
            }
        }
        // PXR24 is lossless for f16 samples.
        let path = dir.path().join(format!("{k}-pxr24.holo"));
        write(&path, &m, &options(SampleType::F16, Compression::Pxr24)).unwrap();
        assert_eq!(read(&path).unwrap(), rounded_to_f16(&m));
    }
}

#[test]
fn lossy_compressions_warn_and_stay_close() {
    let dir = tempfile::tempdir().unwrap();
    // Smooth content, which is what lossy codecs are for.
    let g = geometry(32, 48, 8, true);
    let m = Modulation::from_fn(g, |c, j, e, v| 0.5 + 0.4 * ((j + 2 * e + 3 * v + c) as f32 * 0.05).sin()).unwrap();
    for compression in [Compression::Pxr24, Compression::B44, Compression::B44a, Compression::Dwaa, Compression::Dwab] {
        let sample_type = if compression == Compression::Pxr24 { SampleType::F32 } else { SampleType::F16 };
        let path = dir.path().join(format!("{}.holo", compression.name()));
        let report = write(&path, &m, &options(sample_type, compression)).unwrap();
        assert!(report.warnings.iter().any(|w| w.contains("lossy")), "{:?}", report.warnings);
        // The digest describes what was stored, so the file validates.
        assert!(holo::validate(&path).unwrap().is_valid(), "{}", compression.name());
        let file = HoloFile::open(&path).unwrap();
        let region = file.read_frame(0).unwrap();
        assert_eq!(region, file.read_region(0, &Region::all(m.geometry())).unwrap());
        let worst = m.samples().iter().zip(region.samples()).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
        assert!(worst < 0.05, "{}: worst error {worst}", compression.name());
    }
}

/// Real content: the bundled Spot on a black background, whose dark edges
/// make B44 and DWA undershoot below zero. Every lossy compression converts
/// it, the file validates, a reader gets no negative sample (spec §3.4) and
/// stays close to the lossless conversion.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn every_lossy_compression_converts_the_bundled_spot() {
    use holo::mesh::convert::{convert_mesh, ConvertOptions};
    let dir = tempfile::tempdir().unwrap();
    let spot = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/spot/spot.obj");
    // Mark III's emitters and views, 48 of its hololines.
    let mut g = holo::layout::mark3().geometry;
    g.hololines = 48;
    let convert = |compression: Compression, sample_type: SampleType| {
        let path = dir.path().join(format!("{}-{sample_type:?}.holo", compression.name()));
        let options = ConvertOptions {
            write: WriteOptions { compression, sample_type, ..WriteOptions::default() },
            ..ConvertOptions::default()
        };
        let report = convert_mesh(&spot, &g, &path, &options, &holo::progress::Silent)
            .unwrap_or_else(|e| panic!("{}: {e}", compression.name()));
        assert!(holo::validate(&path).unwrap().is_valid(), "{}", compression.name());
        (report, read(&path).unwrap())
    };
    let (_, exact) = convert(Compression::Zip, SampleType::F32);
    let peak = exact.samples().iter().fold(0f32, |a, &b| a.max(b));
    assert!(peak > 0.1 && exact.samples().iter().filter(|&&x| x == 0.0).count() > exact.samples().len() / 10);
    let lossy = [
        (Compression::B44, SampleType::F16),
        (Compression::B44a, SampleType::F16),
        (Compression::Dwaa, SampleType::F16),
        (Compression::Dwab, SampleType::F16),
        (Compression::Pxr24, SampleType::F32),
    ];
    let mut undershoot = false;
    for (compression, sample_type) in lossy {
        let (report, got) = convert(compression, sample_type);
        assert!(report.written.warnings.iter().any(|w| w.contains("lossy")), "{:?}", report.written.warnings);
        assert!(
            got.samples().iter().all(|&x| x >= 0.0),
            "{}: a negative sample reached the reader",
            compression.name()
        );
        let file = HoloFile::open(dir.path().join(format!("{}-{sample_type:?}.holo", compression.name()))).unwrap();
        assert!(file.is_lossy());
        // What the codec itself returned (the digest's samples) may undershoot.
        undershoot |= file.read_decoded(0, &Region::all(&g)).unwrap().samples().iter().any(|&x| x < 0.0);
        let (mut worst, mut sum) = (0f32, 0f64);
        for (a, b) in exact.samples().iter().zip(got.samples()) {
            worst = worst.max((a - b).abs());
            sum += f64::from((a - b).abs());
        }
        let mean = sum / exact.samples().len() as f64;
        assert!(
            worst < 0.5 * peak && mean < 0.01 * f64::from(peak),
            "{}: worst {worst}, mean {mean}",
            compression.name()
        );
    }
    assert!(undershoot, "no codec undershot: the content does not test the rule");
}

#[test]
fn regions_read_only_what_they_ask_and_match_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let m = random(geometry(70, 23, 11, true), 99);
    let path = dir.path().join("r.holo");
    write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
    let file = HoloFile::open(&path).unwrap();
    let region = Region { hololines: 17..53, emitters: 3..20, views: 2..9, vertical_views: 0..1 };
    let part = file.read_region(0, &region).unwrap();
    for c in 0..3 {
        for j in region.hololines.clone() {
            for e in region.emitters.clone() {
                for v in region.views.clone() {
                    assert_eq!(part.get(c, j - 17, e - 3, v - 2), m.get(c, j, e, v));
                }
            }
        }
    }
    let g = part.geometry();
    assert_eq!(g.emitter_left_x_m, m.geometry().emitter_x_m(3));
    assert_eq!(g.hololine_top_y_m, m.geometry().hololine_y_m(17));
    assert!((g.views.theta_rad(0) - m.geometry().views.theta_rad(2)).abs() < 1e-15);
    assert!((g.views.theta_rad(6) - m.geometry().views.theta_rad(8)).abs() < 1e-12);
    assert!(file
        .read_region(0, &Region { hololines: 0..71, emitters: 0..1, views: 0..1, vertical_views: 0..1 })
        .is_err());
    assert!(file.read_frame(1).is_err());
}

#[test]
fn cropped_data_window_keeps_zeros_outside_and_the_same_digest() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(40, 30, 4, false);
    let m = Modulation::from_fn(
        g,
        |_, j, e, v| if (10..20).contains(&j) && (5..9).contains(&e) { 1.0 + v as f32 } else { 0.0 },
    )
    .unwrap();
    let path = dir.path().join("crop.holo");
    let report = write(&path, &m, &options(SampleType::F16, Compression::Zip)).unwrap();
    let file = HoloFile::open(&path).unwrap();
    let w = file.info().frames[0].data_window;
    assert_eq!((w.x, w.y, w.width, w.height), (5, 10, 4, 10));
    assert_eq!(file.read_frame(0).unwrap(), m);
    // The digest covers the whole display window, so it does not depend on cropping.
    let frames = write_frames(dir.path().join("uncropped.holo"), m.geometry(), 2, &WriteOptions::default(), |_| {
        Ok(Cow::Borrowed(&m))
    })
    .unwrap();
    assert_eq!(frames.digests[0], report.digests[0]);
}

#[test]
fn streamed_frames_round_trip_and_bytes_are_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(12, 9, 5, true);
    let frames: Vec<Modulation> = (0..4).map(|i| random(g.clone(), 1000 + i)).collect();
    let opts = WriteOptions {
        frames_per_second: Some((24, 1)),
        first_frame_number: 100,
        ..options(SampleType::F32, Compression::Piz)
    };
    let a = dir.path().join("a.holo");
    let b = dir.path().join("b.holo");
    for p in [&a, &b] {
        write_frames(p, &g, 4, &opts, |i| Ok(Cow::Borrowed(&frames[i]))).unwrap();
    }
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap(), "same input, different bytes");
    let file = HoloFile::open(&a).unwrap();
    assert_eq!(file.info().frames.len(), 4);
    assert_eq!(file.info().frames_per_second, Some((24, 1)));
    for (i, f) in frames.iter().enumerate() {
        assert_eq!(file.info().frames[i].number, 100 + i as i64);
        assert_eq!(&file.read_frame(i).unwrap(), f);
    }
    assert!(holo::validate(&a).unwrap().is_valid());
}

#[test]
fn f16_limits_are_kept_or_refused() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(3, 4, 2, false);
    // The largest f16, the smallest normal and subnormal f16, and values that flush to zero.
    let values = [65504.0f32, 6.103_515_6e-5, 5.960_464_5e-8, 1e-9, 0.0, 1.0];
    let m = Modulation::from_fn(g.clone(), |_, j, e, v| values[(j + e + v) % values.len()]).unwrap();
    let path = dir.path().join("limits.holo");
    write(&path, &m, &WriteOptions::default()).unwrap();
    assert_eq!(read(&path).unwrap(), rounded_to_f16(&m));
    let too_big = Modulation::from_fn(g, |_, j, e, _| if j == 2 && e == 1 { 70000.0 } else { 1.0 }).unwrap();
    let err = write(dir.path().join("big.holo"), &too_big, &WriteOptions::default()).unwrap_err().to_string();
    assert!(err.contains("hololine 2, emitter 1") && err.contains("f16"), "{err}");
    // The same value is fine in f32.
    write(dir.path().join("big32.holo"), &too_big, &options(SampleType::F32, Compression::Zip)).unwrap();
}

#[test]
fn explicit_and_other_view_spacings_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    for spacing in [ViewSpacing::Sin, ViewSpacing::Angle, ViewSpacing::Explicit(vec![-0.3, -0.1, 0.05, 0.2, 0.31])] {
        let mut g = geometry(4, 6, 5, false);
        g.views.spacing = spacing.clone();
        if let ViewSpacing::Explicit(list) = &spacing {
            g.views.first_theta_rad = list[0];
            g.views.last_theta_rad = list[4];
        }
        g.channels = vec![ColourChannel::new("Y", 532.123e-9)];
        let m = random(g, 5);
        let path = dir.path().join(format!("{}.holo", spacing.name()));
        write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
        assert_eq!(read(&path).unwrap(), m);
    }
}

/// 24 random geometries (seeded, so a failure names the case that
/// reproduces it), either sample type: ZIP round-trips them exactly (f16 as
/// the samples rounded to f16).
#[test]
fn any_geometry_round_trips() {
    let mut cases = ChaCha8Rng::seed_from_u64(0x0e0c_a5e5);
    for case in 0..24 {
        let (h, e, v) = (cases.gen_range(1usize..40), cases.gen_range(1usize..40), cases.gen_range(1usize..24));
        let (rgb, f32, seed) = (cases.gen::<bool>(), cases.gen::<bool>(), cases.gen::<u64>());
        let dir = tempfile::tempdir().unwrap();
        let m = random(geometry(h, e, v, rgb), seed);
        let path = dir.path().join("p.holo");
        let sample_type = if f32 { SampleType::F32 } else { SampleType::F16 };
        write(&path, &m, &options(sample_type, Compression::Zip)).unwrap();
        let back = read(&path).unwrap();
        let expected = if f32 { m } else { rounded_to_f16(&m) };
        assert!(back == expected, "case {case}: {h}×{e}×{v}, rgb {rgb}, f32 {f32}, seed {seed}");
    }
}

#[cfg(unix)]
#[test]
fn written_files_honour_the_umask() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("mode.holo");
    write(&path, &random(geometry(2, 2, 2, false), 3), &WriteOptions::default()).unwrap();
    let mode = std::fs::metadata(&path).unwrap().permissions().mode() & 0o777;
    // Readable by others unless the umask forbids it; never the 0600 of a temp file under umask 022.
    assert_ne!(mode, 0o600, "mode {mode:o}: the umask was ignored");
    assert_eq!(mode & 0o111, 0, "not executable");
}

/// A frame whose non-zero samples sit in an inner rectangle (so the written
/// data window is cropped), copied band by band.
fn bands_of(m: &Modulation, band: &mut holo::Band) {
    let g = m.geometry();
    let n = g.emitters * g.views.count;
    let lines = band.hololines();
    for c in 0..g.channels.len() {
        for j in lines.clone() {
            let at = (c * lines.len() + j - lines.start) * n;
            band.samples_mut()[at..at + n].copy_from_slice(m.hololine(c, j));
        }
    }
}

#[test]
fn banded_writes_give_the_same_bytes_as_whole_writes() {
    let dir = tempfile::tempdir().unwrap();
    for (k, (h, e, v, rgb)) in [(37, 23, 5, true), (16, 9, 3, false), (1, 4, 2, false)].into_iter().enumerate() {
        let g = geometry(h, e, v, rgb);
        let mut m = random(g.clone(), 40 + k as u64);
        // Zero a border so the data window is cropped on every side.
        let (h, e, v) = (g.hololines, g.emitters, g.views.count);
        for c in 0..g.channels.len() {
            for j in 0..h {
                for ei in 0..e {
                    if (h > 2 && (j < 2 || j + 3 > h)) || ei < 1 || ei + 2 > e {
                        for vi in 0..v {
                            m.set(c, j, ei, vi, 0.0);
                        }
                    }
                }
            }
        }
        for (sample_type, compression) in [
            (SampleType::F16, Compression::Zip),
            (SampleType::F32, Compression::Piz),
            (SampleType::F16, Compression::None),
            // Lossy: the digest is made from what is read back, band by band.
            (SampleType::F32, Compression::Pxr24),
        ] {
            let whole = dir.path().join(format!("{k}-{}-{sample_type:?}-whole.holo", compression.name()));
            let written = write(&whole, &m, &options(sample_type, compression)).unwrap();
            for band_hololines in [1, 7, 16, h + 5] {
                let banded =
                    dir.path().join(format!("{k}-{}-{sample_type:?}-{band_hololines}.holo", compression.name()));
                let mut calls = 0;
                let report = holo::format::write_frame_in_bands(
                    &banded,
                    &g,
                    band_hololines,
                    &options(sample_type, compression),
                    |band| {
                        calls += 1;
                        assert!(band.hololines().len() <= band_hololines);
                        bands_of(&m, band);
                        Ok(())
                    },
                )
                .unwrap();
                assert_eq!(calls, h.div_ceil(band_hololines));
                assert_eq!(report.digests, written.digests);
                assert!(
                    std::fs::read(&whole).unwrap() == std::fs::read(&banded).unwrap(),
                    "{k} {compression:?} {sample_type:?}: banded ({band_hololines} lines) and whole bytes differ"
                );
            }
        }
    }
    // Nothing is left beside the outputs: the spool and partial files are gone.
    for entry in std::fs::read_dir(dir.path()).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().into_owned();
        assert!(name.ends_with(".holo") && !name.starts_with('.'), "left behind: {name}");
    }
}

#[test]
fn banded_writes_refuse_bad_samples_and_keep_what_was_there() {
    let dir = tempfile::tempdir().unwrap();
    let g = geometry(20, 6, 3, true);
    let path = dir.path().join("kept.holo");
    std::fs::write(&path, b"mine").unwrap();
    let refused = holo::format::write_frame_in_bands(&path, &g, 4, &WriteOptions::default(), |_| Ok(()));
    assert!(matches!(refused, Err(holo::Error::Output { problem: holo::OutputProblem::Exists, .. })));
    assert_eq!(std::fs::read(&path).unwrap(), b"mine");

    let out = dir.path().join("bad.holo");
    let result = holo::format::write_frame_in_bands(&out, &g, 4, &WriteOptions::default(), |band| {
        if band.hololines().contains(&13) {
            let at = (2 * band.hololines().len() + 13 - band.hololines().start) * 6 * 3 + 2 * 3 + 1;
            band.samples_mut()[at] = f32::NAN;
        }
        Ok(())
    });
    match result {
        Err(holo::Error::BadSample { hololine, emitter, view, ref channel, .. }) => {
            assert_eq!((hololine, emitter, view), (13, 2, 1));
            assert_eq!(channel, &g.channels[2].name);
        }
        other => panic!("expected a bad-sample error, got {:?}", other.map(|r| r.path)),
    }
    let result = holo::format::write_frame_in_bands(&out, &g, 4, &WriteOptions::default(), |band| {
        band.samples_mut()[0] = 1.0e6;
        Ok(())
    });
    assert!(matches!(result, Err(holo::Error::BadSample { why, .. }) if why.contains("f16")));
    assert!(!out.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "only the user's file remains");
}

/// `holo.placement` round-trips bit for bit (any finite doubles), is absent
/// when not given, and stored as OpenEXR's `m44d` (Imath's row-vector
/// layout: the translation in the last row of what is stored).
#[test]
fn the_placement_round_trips_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let m = random(geometry(2, 3, 2, false), 4);
    let placement = [
        [0.1 + f64::EPSILON, -2.5e-7, 3.0, 0.0123456789012345],
        [1e-300, 7.0, -0.25, -1.5],
        [0.0, 0.333_333_333_333_333_3, 1e10, 2.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let path = dir.path().join("placed.holo");
    write(&path, &m, &WriteOptions { placement: Some(placement), ..WriteOptions::default() }).unwrap();
    let file = HoloFile::open(&path).unwrap();
    assert_eq!(file.info().placement, Some(placement));
    assert!(holo::validate(&path).unwrap().is_valid());
    // The bytes after the type name: the transpose, little-endian.
    let bytes = std::fs::read(&path).unwrap();
    let at = bytes.windows(5).position(|w| w == b"m44d\0").unwrap() + 5 + 4;
    let stored: Vec<f64> = bytes[at..at + 128].chunks(8).map(|c| f64::from_le_bytes(c.try_into().unwrap())).collect();
    assert_eq!(stored[3 * 4], placement[0][3], "translation x in the last stored row");
    assert_eq!(stored[1], placement[1][0]);
    // Not given: absent.
    let plain = dir.path().join("plain.holo");
    write(&plain, &m, &WriteOptions::default()).unwrap();
    assert_eq!(HoloFile::open(&plain).unwrap().info().placement, None);
}

/// `holo.placement` and the conversion record are version 1.1's: a file
/// written for 1.0 readers holds neither (byte for byte the file written
/// without them), one of today's version both, and the record reads back whole.
#[test]
fn the_provenance_of_1_1_is_left_out_of_a_1_0_file() {
    use holo::format::FormatVersion;
    use holo::holoflick::convert::HoloFlickConvertOptions;
    use holo::provenance::{Conversion, ConverterOptions};
    let dir = tempfile::tempdir().unwrap();
    let m = random(geometry(2, 3, 2, false), 5);
    let options = HoloFlickConvertOptions { frames: Some(2..3), fit: true, ..Default::default() };
    let conversion =
        Conversion { input: "movie.hflk".into(), input_sha256: None, options: ConverterOptions::HoloFlick(options) };
    let placement = [[2.0, 0.0, 0.0, 0.5], [0.0, 2.0, 0.0, -0.5], [0.0, 0.0, 2.0, 0.25], [0.0, 0.0, 0.0, 1.0]];
    let with = |version| WriteOptions {
        version,
        placement: Some(placement),
        conversion: Some(conversion.record()),
        ..WriteOptions::default()
    };
    let (old, plain) = (dir.path().join("old.holo"), dir.path().join("plain.holo"));
    write(&old, &m, &with(FormatVersion::V1_0)).unwrap();
    write(&plain, &m, &WriteOptions { version: FormatVersion::V1_0, ..WriteOptions::default() }).unwrap();
    assert_eq!(std::fs::read(&old).unwrap(), std::fs::read(&plain).unwrap());
    let new = dir.path().join("new.holo");
    write(&new, &m, &with(FormatVersion::default())).unwrap();
    let file = HoloFile::open(&new).unwrap();
    assert_eq!(file.info().placement, Some(placement));
    assert_eq!(file.info().conversion().unwrap(), Some(conversion.clone()));
    let v = holo::validate(&new).unwrap();
    assert!(v.is_valid() && v.warnings.is_empty(), "{v:?}");
}

#[test]
fn the_digest_is_checked_from_the_stored_blocks_in_any_order() {
    // A frame large enough for the parallel decoder (blocks may come back out
    // of order), lit only inside a window, so the data window is smaller than
    // the display window on every side and the digest's +0.0 padding is used.
    for (sample_type, compression) in [(SampleType::F16, Compression::Zip), (SampleType::F32, Compression::Zips)] {
        let g = geometry(200, 120, 24, true);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let m = Modulation::from_fn(g.clone(), |_, j, e, _| {
            if (13..181).contains(&j) && (7..110).contains(&e) {
                rng.gen_range(0.0..1.0)
            } else {
                0.0
            }
        })
        .unwrap();
        let want = if sample_type == SampleType::F16 { rounded_to_f16(&m) } else { m.clone() };
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("window.holo");
        write(&path, &want, &options(sample_type, compression)).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1 << 20, "big enough for the parallel decoder");
        let f = HoloFile::open(&path).unwrap();
        let window = f.info().frames[0].data_window;
        assert!(window.x > 0 && window.y > 0 && window.width < 120 && window.height < 200, "{window:?}");
        // The digest from the blocks matches the stored one, computed by the
        // writer from the samples.
        let back = f.read_frame(0).unwrap();
        assert_eq!(back.samples(), want.samples());
        assert_eq!(f.info().frames[0].digest.as_deref(), Some(holo::format::frame_digest(&back, sample_type).as_str()));
        // One sample changed in the file's samples: the stored digest no longer matches.
        let mut other = want.clone();
        other.set(1, 50, 40, 3, 0.25);
        let forged = dir.path().join("forged.holo");
        write(&forged, &other, &options(sample_type, compression)).unwrap();
        let mut bytes = std::fs::read(&forged).unwrap();
        let stored = f.info().frames[0].digest.clone().unwrap();
        let theirs = HoloFile::open(&forged).unwrap().info().frames[0].digest.clone().unwrap();
        let at = bytes.windows(theirs.len()).position(|w| w == theirs.as_bytes()).unwrap();
        bytes[at..at + stored.len()].copy_from_slice(stored.as_bytes());
        super::seal::reseal(&mut bytes);
        std::fs::write(&forged, &bytes).unwrap();
        let err = HoloFile::open(&forged).unwrap().read_frame(0).unwrap_err().to_string();
        assert!(err.contains("digest"), "{err}");
    }
}

/// `read_frame_samples::<f16>`: an f16 file's samples exactly as stored (the
/// bits the f32 read widens), whole and by region, digest checked; an f32
/// file's rounded, with a sample f16 cannot hold refused by name; a lossy
/// file's undershoot read as +0 in f16 too.
#[test]
fn frames_read_as_f16_are_the_stored_halves() {
    use half::f16;
    let dir = tempfile::tempdir().unwrap();
    for (compression, seed) in [(Compression::Zip, 3), (Compression::None, 4), (Compression::Piz, 5)] {
        let m = rounded_to_f16(&random(geometry(37, 23, 7, true), seed));
        let path = dir.path().join(format!("halves-{seed}.holo"));
        write(&path, &m, &options(SampleType::F16, compression)).unwrap();
        let f = HoloFile::open(&path).unwrap();
        let halves = f.read_frame_samples::<f16>(0).unwrap();
        let want: Vec<f16> = m.samples().iter().map(|&x| f16::from_f32(x)).collect();
        assert!(halves.iter().map(|h| h.to_bits()).eq(want.iter().map(|h| h.to_bits())), "{compression:?}");
        let region = Region { hololines: 5..19, emitters: 3..20, views: 2..6, vertical_views: 0..1 };
        let part = f.read_region_samples::<f16>(0, &region).unwrap();
        let widened = f.read_region(0, &region).unwrap();
        assert!(part.iter().map(|h| h.to_f32()).eq(widened.samples().iter().copied()), "{compression:?} region");
    }
    // An f32 file: rounded to f16; a sample beyond f16's range is an error.
    let m = random(geometry(6, 5, 3, false), 6);
    let path = dir.path().join("floats.holo");
    write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
    let halves = HoloFile::open(&path).unwrap().read_frame_samples::<f16>(0).unwrap();
    assert!(halves.iter().zip(m.samples()).all(|(h, &x)| h.to_bits() == f16::from_f32(x).to_bits()));
    let mut big = m.clone();
    big.set(0, 2, 3, 1, 1e6);
    write(&path, &big, &WriteOptions { overwrite: true, ..options(SampleType::F32, Compression::Zip) }).unwrap();
    let err = HoloFile::open(&path).unwrap().read_frame_samples::<f16>(0).unwrap_err().to_string();
    assert!(err.contains("too large for f16") && err.contains("hololine 2"), "{err}");
    // The lossy vector: its twelve negative decoded samples read as +0.
    let lossy = HoloFile::open(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/v1.2/undershoot-y-f16-b44.holo"),
    )
    .unwrap();
    let halves = lossy.read_frame_samples::<f16>(0).unwrap();
    let floats = lossy.read_frame(0).unwrap();
    assert!(halves.iter().all(|h| h.to_bits() & 0x8000 == 0));
    assert!(halves.iter().map(|h| h.to_f32()).eq(floats.samples().iter().copied()));
    // A damaged sample is found by the digest in f16 as in f32.
    let m = rounded_to_f16(&random(geometry(4, 3, 2, false), 8));
    let path = dir.path().join("damaged.holo");
    write(&path, &m, &options(SampleType::F16, Compression::None)).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let at = bytes.len() - 3;
    bytes[at] ^= 0x01;
    std::fs::write(&path, &bytes).unwrap();
    let err = HoloFile::open(&path).unwrap().read_frame_samples::<f16>(0).unwrap_err();
    assert!(matches!(err, holo::Error::DigestMismatch { .. }), "{err}");
}
