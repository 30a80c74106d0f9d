//! read(write(m)) == m: exactly for f32 with lossless compression, and equal
//! to m rounded to f16 for f16. Random, non-zero modulations of many shapes.

use std::borrow::Cow;

use holo::format::{read, write, write_frames, Compression, HoloFile, Region, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, ColourChannel, Geometry, ViewSpacing, Views};
use holo::Modulation;
use proptest::prelude::*;
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
fn random(g: Geometry, seed: u64) -> Modulation {
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
        assert!(holo::format::validate(&path).unwrap().is_valid(), "{}", compression.name());
        let file = HoloFile::open(&path).unwrap();
        let region = file.read_frame(0).unwrap();
        assert_eq!(region, file.read_region(0, &Region::all(m.geometry())).unwrap());
        let worst = m.samples().iter().zip(region.samples()).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
        assert!(worst < 0.05, "{}: worst error {worst}", compression.name());
    }
}

#[test]
fn regions_read_only_what_they_ask_and_match_the_whole() {
    let dir = tempfile::tempdir().unwrap();
    let m = random(geometry(70, 23, 11, true), 99);
    let path = dir.path().join("r.holo");
    write(&path, &m, &options(SampleType::F32, Compression::Zip)).unwrap();
    let file = HoloFile::open(&path).unwrap();
    let region = Region { hololines: 17..53, emitters: 3..20, views: 2..9 };
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
    assert!(file.read_region(0, &Region { hololines: 0..71, emitters: 0..1, views: 0..1 }).is_err());
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
    assert!(holo::format::validate(&a).unwrap().is_valid());
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

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]
    #[test]
    fn any_geometry_round_trips(h in 1usize..40, e in 1usize..40, v in 1usize..24, rgb in any::<bool>(), f32 in any::<bool>(), seed in any::<u64>()) {
        let dir = tempfile::tempdir().unwrap();
        let m = random(geometry(h, e, v, rgb), seed);
        let path = dir.path().join("p.holo");
        let sample_type = if f32 { SampleType::F32 } else { SampleType::F16 };
        write(&path, &m, &options(sample_type, Compression::Zip)).unwrap();
        let back = read(&path).unwrap();
        let expected = if f32 { m } else { rounded_to_f16(&m) };
        prop_assert_eq!(back, expected);
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
