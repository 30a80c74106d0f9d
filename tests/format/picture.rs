//! The one tone mapping of every picture `holo` writes: views exported at the
//! largest sample come back within half a code step, `auto` clips only the
//! brightest 0.1 %, quilts and views code a sample alike, and sidecars
//! written before keep reading.

use holo::cameras::quilt::{quilt_from_modulation, QuiltSpec};
use holo::geometry::{mono_channel, rgb_channels, ColourChannel, Views};
use holo::picture::{srgb_encode, Bits, Tone, White};
use holo::views::{export_views, import_views, read_sidecar, ToneMapping, SIDECAR};
use holo::{Geometry, Modulation};

/// 20 hololines × 30 emitters × 4 views.
fn geometry(channels: Vec<ColourChannel>) -> Geometry {
    Geometry::centred(20, 30, Views::tan_spaced(4, -0.2, 0.2), 0.5e-3, 0.5e-3, 0.004, 0.5, channels)
}

/// A smooth scene up to about 0.9 with two specular glints of 25.
fn glinting(g: Geometry) -> Modulation {
    Modulation::from_fn(g, |c, j, e, v| {
        if (j, e) == (2, 4) && v < 2 && c == 0 {
            25.0
        } else {
            0.9 * ((c * 7 + j * 13 + e * 5 + v * 3) % 37) as f32 / 36.0
        }
    })
    .unwrap()
}

/// The worst difference between `a` and `b` in sRGB-encoded units of `white`.
fn worst_encoded(a: &Modulation, b: &Modulation, white: f32) -> f64 {
    let e = |x: f32| srgb_encode(f64::from(x) / f64::from(white));
    a.samples().iter().zip(b.samples()).map(|(&x, &y)| (e(x) - e(y)).abs()).fold(0.0, f64::max)
}

#[test]
fn views_exported_at_the_largest_sample_import_within_half_a_step() {
    for channels in [mono_channel(), rgb_channels()] {
        let m = glinting(geometry(channels));
        for bits in [8u8, 16] {
            let dir = tempfile::tempdir().unwrap();
            let white = White::Max.level(m.samples().iter().copied());
            assert_eq!(white, 25.0);
            export_views(&m, dir.path(), &ToneMapping { white, bits }, false).unwrap();
            let sidecar = read_sidecar(&dir.path().join(SIDECAR)).unwrap();
            assert_eq!(sidecar.tone, ToneMapping { white, bits });
            let back = import_views(dir.path(), &sidecar.geometry, &sidecar.tone).unwrap();
            let half_step = 0.5 / f64::from(Bits::from_count(bits).unwrap().max_code());
            let worst = worst_encoded(&m, &back, white);
            assert!(worst <= half_step + 1e-6, "{bits} bits: {worst} vs half a step {half_step}");
        }
    }
}

#[test]
fn auto_white_clips_only_the_glints() {
    let m = glinting(geometry(rgb_channels()));
    let white = White::Auto.level(m.samples().iter().copied());
    assert!((0.85..=0.9).contains(&white), "{white}");
    let dir = tempfile::tempdir().unwrap();
    export_views(&m, dir.path(), &ToneMapping { white, bits: 16 }, false).unwrap();
    let back = import_views(dir.path(), m.geometry(), &ToneMapping { white, bits: 16 }).unwrap();
    let mut clipped = 0;
    for (&x, &y) in m.samples().iter().zip(back.samples()) {
        if x > white {
            clipped += 1;
            assert_eq!(y, white);
        } else {
            let e = |s: f32| srgb_encode(f64::from(s / white));
            assert!((e(x) - e(y)).abs() <= 0.5 / 65535.0 + 1e-6, "{x} -> {y}");
        }
    }
    // The two glints and the scene's brightest samples above the percentile.
    assert!(clipped >= 2 && clipped * 1000 <= m.samples().len() + 1000, "{clipped}");
}

#[test]
fn a_quilt_codes_a_sample_as_the_views_do() {
    // Every view the same picture: each quilt tile's pixels are samples of it.
    let g = geometry(mono_channel());
    let m = Modulation::from_fn(g, |_, j, e, _| 0.002 * (j * 30 + e) as f32).unwrap();
    let spec = QuiltSpec { columns: 2, rows: 1, tile_width: 18, tile_height: 12, aspect: 1.5, ..QuiltSpec::portrait() };
    let quilt = quilt_from_modulation(&m, &spec).unwrap();
    let white = 1.3;
    let png = holo::picture::decode::decode(std::io::Cursor::new(quilt.png(white).unwrap())).unwrap().grey8();
    let tone = Tone::new(white, Bits::Eight).unwrap();
    for (i, p) in quilt.rgb.iter().enumerate() {
        let got = png[i];
        assert_eq!(u16::from(got), tone.code(p[0]), "pixel {i}");
    }
}

#[test]
fn a_sidecar_written_before_is_still_read() {
    // The layout export-views has always written: the geometry and {white, bits}.
    let g = geometry(rgb_channels());
    let json =
        format!(r#"{{"geometry": {}, "tone": {{"white": 0.5, "bits": 8}}}}"#, serde_json::to_string(&g).unwrap());
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(SIDECAR);
    std::fs::write(&path, json).unwrap();
    let sidecar = read_sidecar(&path).unwrap();
    assert_eq!((sidecar.geometry, sidecar.tone), (g, ToneMapping { white: 0.5, bits: 8 }));
}

#[test]
fn bad_tones_are_refused_before_anything_is_written() {
    let m = glinting(geometry(mono_channel()));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("views");
    for (tone, needle) in
        [(ToneMapping { white: 0.0, bits: 8 }, "white level 0"), (ToneMapping { white: 1.0, bits: 12 }, "12 bits")]
    {
        let err = export_views(&m, &out, &tone, false).unwrap_err().to_string();
        assert!(err.contains(needle) && err.contains("views"), "{err}");
        assert!(!out.exists());
    }
}
