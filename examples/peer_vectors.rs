//! Test vectors for readers that are not this crate (`tests/peer/openexr_peer.py`,
//! `.ci/peers.sh`): several `.holo` files with deterministic pseudo-random
//! non-zero samples, each with `NAME.expect.json` saying what a conforming
//! reader must find in it.
//!
//! ```text
//! cargo run --release --example peer_vectors -- OUTDIR
//! ```
//!
//! `NAME.expect.json` holds the geometry, the sample and compression types, the
//! channel list, every `holo.*` attribute with its EXR type and value, each
//! part's name, data window and digest (from the `WriteReport`), and probe
//! samples `{channel, x, y, part, value, bits}`: `value` is the f32 this crate
//! wrote (after rounding to f16 for f16 files) and `bits` its IEEE bit pattern.
//! Doubles carry their bit patterns too (`bits`), so nothing depends on how a
//! JSON parser rounds decimals.

use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use holo::format::{
    channel_name, view_digits, write_frames, Compression, FormatVersion, Radiometry, SampleType, WriteOptions,
};
use holo::geometry::{rgb_channels, ColourChannel, Geometry, Parallax, ViewSpacing, Views};
use holo::Modulation;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde_json::{json, Value};

/// One test file.
struct Case {
    name: &'static str,
    geometry: Geometry,
    sample_type: SampleType,
    compression: Compression,
    frames: usize,
    /// Non-zero samples only inside (x0, y0, x1, y1), inclusive; zeros elsewhere.
    covered: Option<(usize, usize, usize, usize)>,
    first_frame_number: i32,
    frames_per_second: Option<(i32, u32)>,
    radiometry: Radiometry,
    source: &'static str,
    seed: u64,
    /// 1.2 (headers sealed), 1.1 (the pixel aspect ratio the emitter grid's), or 1.0 (square).
    version: FormatVersion,
}

fn geometry(
    hololines: usize,
    emitters: usize,
    views: Views,
    channels: Vec<ColourChannel>,
    hololine_pitch_m: f64,
    emitter_pitch_m: f64,
) -> Geometry {
    Geometry {
        parallax: Parallax::Horizontal,
        hololines,
        emitters,
        views,
        vertical_views: None,
        hololine_pitch_m,
        // Values that are not exactly representable in f32, so that a reader
        // that narrows a double attribute shows up.
        hololine_top_y_m: (hololines as f64 - 1.0) * hololine_pitch_m / 2.0 + 1.0e-7 / 3.0,
        emitter_pitch_m,
        emitter_left_x_m: -(emitters as f64 - 1.0) * emitter_pitch_m / 2.0 - 2.0e-7 / 3.0,
        emitter_z_m: 0.0271828182845904,
        viewer_distance_m: 0.6180339887498949,
        viewer_height_m: -0.0123456789012345,
        channels,
    }
}

fn cases() -> Vec<Case> {
    let deg = std::f64::consts::PI / 180.0;
    let explicit: Vec<f64> = [-13.0, -6.5, 0.1, 7.25, 14.0].iter().map(|d| d * deg).collect();
    vec![
        Case {
            name: "mono_f16_zip",
            geometry: geometry(
                37,
                21,
                Views::tan_spaced(7, -15.0 * deg, 15.0 * deg),
                vec![ColourChannel::new("Y", 532.1e-9)],
                1.3e-4,
                2.4e-4,
            ),
            sample_type: SampleType::F16,
            compression: Compression::Zip,
            frames: 1,
            covered: None,
            first_frame_number: 0,
            frames_per_second: None,
            radiometry: Radiometry::default(),
            source: "",
            seed: 1,
            version: FormatVersion::V1_1,
        },
        Case {
            name: "rgb_f32_piz",
            geometry: geometry(
                40,
                19,
                Views { count: 6, first_theta_rad: -0.31, last_theta_rad: 0.29, spacing: ViewSpacing::Sin },
                rgb_channels(),
                1.7e-4,
                3.1e-4,
            ),
            sample_type: SampleType::F32,
            compression: Compression::Piz,
            frames: 1,
            covered: None,
            first_frame_number: 0,
            frames_per_second: None,
            radiometry: Radiometry { encoding: "linear".into(), scale: 2.5e-3, unit: "W/(sr m^2)".into() },
            source: "peer_vectors: pseudo-random samples (ChaCha8, seed 2)",
            seed: 2,
            version: FormatVersion::V1_0,
        },
        Case {
            name: "rgb_f16_none_cropped",
            geometry: geometry(
                18,
                24,
                Views {
                    count: explicit.len(),
                    first_theta_rad: explicit[0],
                    last_theta_rad: *explicit.last().unwrap(),
                    spacing: ViewSpacing::Explicit(explicit.clone()),
                },
                vec![ColourChannel::new("R", 640e-9), ColourChannel::new("G", 520e-9), ColourChannel::new("B", 450e-9)],
                1.0e-4,
                1.0e-4,
            ),
            sample_type: SampleType::F16,
            compression: Compression::None,
            frames: 1,
            covered: Some((5, 3, 17, 11)),
            first_frame_number: 0,
            frames_per_second: None,
            radiometry: Radiometry::default(),
            source: "",
            seed: 3,
            version: FormatVersion::V1_2,
        },
        Case {
            name: "multi3_rgb_f16_zip",
            geometry: geometry(
                20,
                9,
                Views { count: 4, first_theta_rad: -0.2, last_theta_rad: 0.2, spacing: ViewSpacing::Angle },
                rgb_channels(),
                1.3e-4,
                2.4e-4,
            ),
            sample_type: SampleType::F16,
            compression: Compression::Zip,
            frames: 3,
            covered: None,
            first_frame_number: 10,
            frames_per_second: Some((24, 1)),
            radiometry: Radiometry::default(),
            source: "",
            seed: 4,
            version: FormatVersion::V1_2,
        },
        Case {
            name: "views1001_mono_f16",
            geometry: geometry(
                2,
                3,
                Views::tan_spaced(1001, -0.5, 0.5),
                vec![ColourChannel::new("Y", 633e-9)],
                2.0e-4,
                2.0e-4,
            ),
            sample_type: SampleType::F16,
            compression: Compression::Zip,
            frames: 1,
            covered: None,
            first_frame_number: 0,
            frames_per_second: None,
            radiometry: Radiometry::default(),
            source: "",
            seed: 5,
            version: FormatVersion::V1_2,
        },
    ]
}

/// A non-zero sample: mostly log-uniform over seven decades, some tiny values
/// (f16 subnormals; f32 subnormals for f32 files), some near the f16 maximum.
fn sample(rng: &mut ChaCha8Rng, sample_type: SampleType) -> f32 {
    let r: f64 = rng.gen();
    let x: f32 = if r < 0.05 {
        match sample_type {
            SampleType::F16 => rng.gen_range(1.0e-6..6.0e-5),
            SampleType::F32 => rng.gen_range(1.0e-44..1.0e-38),
        }
    } else if r < 0.08 {
        rng.gen_range(30000.0..65000.0)
    } else {
        10f32.powf(rng.gen_range(-4.0..2.5)) * rng.gen_range(0.5..1.0)
    };
    let stored = stored(x, sample_type);
    assert!(stored > 0.0 && stored.is_finite(), "{x} stores as {stored}");
    stored
}

/// What the file holds for `x`: itself, or its f16 rounding.
fn stored(x: f32, sample_type: SampleType) -> f32 {
    match sample_type {
        SampleType::F16 => half::f16::from_f32(x).to_f32(),
        SampleType::F32 => x,
    }
}

fn frame(case: &Case, index: usize) -> Modulation {
    let mut rng = ChaCha8Rng::seed_from_u64(case.seed * 1000 + index as u64);
    let st = case.sample_type;
    Modulation::from_fn(case.geometry.clone(), |_, j, e, _| match case.covered {
        Some((x0, y0, x1, y1)) if !(x0..=x1).contains(&e) || !(y0..=y1).contains(&j) => 0.0,
        _ => sample(&mut rng, st),
    })
    .expect("valid geometry")
}

fn double(name: &str, x: f64) -> Value {
    json!({"name": name, "type": "double", "value": x, "bits": x.to_bits()})
}
fn int(name: &str, x: i64) -> Value {
    json!({"name": name, "type": "int", "value": x})
}
fn string(name: &str, s: &str) -> Value {
    json!({"name": name, "type": "string", "value": s})
}

/// Every `holo.*` attribute shared by the parts, as the spec defines it
/// (built from the geometry here, not from the writer's attribute code).
fn shared_attributes(case: &Case) -> Vec<Value> {
    let g = &case.geometry;
    let mut a = vec![
        json!({"name": "holo.version", "type": "v2i", "value": [case.version.number().0, case.version.number().1]}),
        string("holo.parallax", "horizontal"),
        int("holo.hololines", g.hololines as i64),
        int("holo.emitters", g.emitters as i64),
        int("holo.views", g.views.count as i64),
        double("holo.hololinePitch", g.hololine_pitch_m),
        double("holo.hololineTopY", g.hololine_top_y_m),
        double("holo.emitterPitch", g.emitter_pitch_m),
        double("holo.emitterLeftX", g.emitter_left_x_m),
        double("holo.emitterZ", g.emitter_z_m),
        double("holo.viewerDistance", g.viewer_distance_m),
        double("holo.viewerHeight", g.viewer_height_m),
        string("holo.viewSpacing", g.views.spacing.name()),
        double("holo.viewFirst", g.views.first_theta_rad),
        double("holo.viewLast", g.views.last_theta_rad),
        string("holo.radiometry", &case.radiometry.encoding),
        double("holo.scale", case.radiometry.scale),
        string("holo.unit", &case.radiometry.unit),
    ];
    if let ViewSpacing::Explicit(list) = &g.views.spacing {
        // The text is a list of decimal numbers; a reader compares the numbers.
        let bits: Vec<u64> = list.iter().map(|t| t.to_bits()).collect();
        a.push(json!({"name": "holo.viewAngles", "type": "string", "numbers": list, "bits": bits}));
    }
    for c in &g.channels {
        a.push(double(&format!("holo.wavelength.{}", c.name), c.wavelength_m));
    }
    if !case.source.is_empty() {
        a.push(string("holo.source", case.source));
    }
    a
}

fn window(x0: usize, y0: usize, x1: usize, y1: usize) -> Value {
    json!({"min": [x0, y0], "max": [x1, y1]})
}

fn run(out: &Path) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut written = Vec::new();
    for case in cases() {
        let g = &case.geometry;
        let frames: Vec<Modulation> = (0..case.frames).map(|i| frame(&case, i)).collect();
        let path = out.join(format!("{}.holo", case.name));
        let options = WriteOptions {
            sample_type: case.sample_type,
            compression: case.compression,
            radiometry: case.radiometry.clone(),
            source: case.source.to_string(),
            frames_per_second: case.frames_per_second,
            first_frame_number: case.first_frame_number,
            overwrite: true,
            version: case.version,
            placement: None,
            conversion: None,
        };
        let report = write_frames(&path, g, case.frames, &options, |i| Ok(Cow::Borrowed(&frames[i])))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        if report.digests.len() != case.frames {
            return Err(format!("{}: {} digests for {} frames", path.display(), report.digests.len(), case.frames));
        }

        let digits = view_digits(g.views.count);
        let mut channels: Vec<String> =
            (0..g.views.count).flat_map(|v| g.channels.iter().map(move |c| channel_name(v, &c.name, digits))).collect();
        channels.sort();
        let data_window = match case.covered {
            Some((x0, y0, x1, y1)) if case.frames == 1 => window(x0, y0, x1, y1),
            _ => window(0, 0, g.emitters - 1, g.hololines - 1),
        };
        let parts: Vec<Value> = (0..case.frames)
            .map(|i| {
                let mut attributes = vec![
                    int("holo.frame", i64::from(case.first_frame_number) + i as i64),
                    int("holo.frameCount", case.frames as i64),
                    string("holo.digest", &report.digests[i]),
                ];
                if case.version.is_sealed() {
                    // Its value is the stored header's SHA-256 (spec §7.2): a reader recomputes it.
                    attributes.push(json!({"name": "holo.headerDigest", "type": "string", "sealed": true}));
                }
                json!({
                    "name": format!("frame{i:05}"),
                    "data_window": data_window,
                    "attributes": attributes,
                })
            })
            .collect();

        // Probes: the four corners of the display window and of the covered
        // region, the first and last view of every colour, then random ones.
        let mut rng = ChaCha8Rng::seed_from_u64(case.seed + 77);
        let mut probes = Vec::new();
        let mut probe = |part: usize, c: usize, v: usize, x: usize, y: usize| {
            let value = frames[part].get(c, y, x, v);
            probes.push(json!({
                "channel": channel_name(v, &g.channels[c].name, digits),
                "x": x, "y": y, "part": part,
                "value": value, "bits": value.to_bits(),
            }));
        };
        let (w, h, nv, nc) = (g.emitters, g.hololines, g.views.count, g.channels.len());
        let mut corners = vec![(0, 0), (w - 1, 0), (0, h - 1), (w - 1, h - 1)];
        if let Some((x0, y0, x1, y1)) = case.covered {
            corners.extend([(x0, y0), (x1, y0), (x0, y1), (x1, y1), (x0 - 1, y0), (x1 + 1, y1), (x0, y0 - 1)]);
        }
        for part in 0..case.frames {
            for &(x, y) in &corners {
                probe(part, rng.gen_range(0..nc), rng.gen_range(0..nv), x, y);
            }
            for c in 0..nc {
                probe(part, c, 0, rng.gen_range(0..w), rng.gen_range(0..h));
                probe(part, c, nv - 1, rng.gen_range(0..w), rng.gen_range(0..h));
            }
            // At least 60 inside the covered region (non-zero samples), and
            // for a cropped file 10 more anywhere (mostly zeros outside it).
            let (x0, y0, x1, y1) = case.covered.unwrap_or((0, 0, w - 1, h - 1));
            for _ in 0..60 {
                probe(part, rng.gen_range(0..nc), rng.gen_range(0..nv), rng.gen_range(x0..=x1), rng.gen_range(y0..=y1));
            }
            if case.covered.is_some() {
                for _ in 0..10 {
                    probe(part, rng.gen_range(0..nc), rng.gen_range(0..nv), rng.gen_range(0..w), rng.gen_range(0..h));
                }
            }
        }

        let expect = json!({
            "file": path.file_name().unwrap().to_string_lossy(),
            "writer": "holo::format::write_frames",
            "geometry": g,
            "sample_type": match case.sample_type { SampleType::F16 => "f16", SampleType::F32 => "f32" },
            "exr_pixel_type": match case.sample_type { SampleType::F16 => "HALF", SampleType::F32 => "FLOAT" },
            "compression": case.compression.name(),
            "display_window": window(0, 0, g.emitters - 1, g.hololines - 1),
            // A pixel's width over its height (spec §3.1), as the f32 the header holds.
            "pixel_aspect": if case.version == FormatVersion::V1_0 { 1.0 } else { (g.emitter_pitch_m / g.hololine_pitch_m) as f32 as f64 },
            "channels": channels,
            "frames_per_second": case.frames_per_second.map(|(n, d)| json!([n, d])),
            "shared_attributes": shared_attributes(&case),
            "parts": parts,
            "digests": report.digests,
            "file_bytes": report.file_bytes,
            "probes": probes,
        });
        let json_path = out.join(format!("{}.expect.json", case.name));
        let text = serde_json::to_string_pretty(&expect).map_err(|e| e.to_string())?;
        std::fs::write(&json_path, text + "\n").map_err(|e| format!("{}: {e}", json_path.display()))?;
        println!(
            "wrote {} ({} frame(s), {} channels, {:?}, {}, {} bytes) and {}",
            path.display(),
            case.frames,
            g.views.count * g.channels.len(),
            case.sample_type,
            case.compression.name(),
            report.file_bytes,
            json_path.display()
        );
        written.push(path);
    }
    Ok(written)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [out] = args.as_slice() else {
        eprintln!("usage: peer_vectors OUTDIR");
        return ExitCode::from(2);
    };
    match run(Path::new(out)) {
        Ok(files) => {
            println!("{} files written", files.len());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("peer_vectors: {e}");
            ExitCode::FAILURE
        }
    }
}
