//! The other direction of the peer check (`.ci/peers.sh`): `.holo` files that
//! OpenEXR wrote (`tests/peer/openexr_peer.py write` and `rewrite`), read by
//! this crate and compared exactly with what the writer says it wrote.
//!
//! ```text
//! cargo run --release --example peer_read -- FILE.holo FILE.peer.json [FILE.holo FILE.peer.json ...]
//! cargo run --release --example peer_read -- DIR      # every DIR/NAME.peer.json with DIR/<its "file">
//! ```
//!
//! For each file: `HoloFile::open` and `validate` accept it; the geometry,
//! sample type, compression, radiometry, frame numbers, data windows and
//! digests equal the JSON's (doubles compared by bit pattern); every frame
//! reads back (`read_frame`, which checks the digest) with every sample
//! bit-equal to the JSON's f32 bit patterns; `read` and `read_region` agree.
//! One line per check; the last line is `N passed, M failed`; the exit status
//! is non-zero on any failure.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use holo::format::{parse_channel_name, Compression, HoloFile, Region, SampleType};
use holo::geometry::{ColourChannel, Geometry, Parallax, ViewSpacing, Views};
use holo::validate;
use serde_json::Value;

#[derive(Default)]
struct Checks {
    passed: usize,
    failed: usize,
}

impl Checks {
    fn check(&mut self, ok: bool, what: impl AsRef<str>, detail: impl FnOnce() -> String) -> bool {
        if ok {
            self.passed += 1;
            println!("PASS {}", what.as_ref());
        } else {
            self.failed += 1;
            println!("FAIL {}: {}", what.as_ref(), detail());
        }
        ok
    }
    fn info(&self, text: impl AsRef<str>) {
        println!("info {}", text.as_ref());
    }
}

fn field<'a>(v: &'a Value, path: &str) -> Result<&'a Value, String> {
    let mut at = v;
    for key in path.split('.') {
        at = at.get(key).ok_or_else(|| format!("the JSON has no {path}"))?;
    }
    Ok(at)
}
fn uint(v: &Value, path: &str) -> Result<u64, String> {
    field(v, path)?.as_u64().ok_or_else(|| format!("{path} is not an unsigned integer"))
}
fn text<'a>(v: &'a Value, path: &str) -> Result<&'a str, String> {
    field(v, path)?.as_str().ok_or_else(|| format!("{path} is not a string"))
}
/// A double given as its IEEE bit pattern.
fn bits(v: &Value, path: &str) -> Result<f64, String> {
    Ok(f64::from_bits(uint(v, path)?))
}

/// The geometry the JSON says was written.
fn expected_geometry(doc: &Value) -> Result<Geometry, String> {
    let g = field(doc, "geometry")?;
    let count = uint(g, "views")? as usize;
    let spacing = match text(g, "view_spacing")? {
        "tan" => ViewSpacing::Tan,
        "sin" => ViewSpacing::Sin,
        "angle" => ViewSpacing::Angle,
        "explicit" => ViewSpacing::Explicit(
            field(g, "view_angles_bits")?
                .as_array()
                .ok_or("view_angles_bits is not a list")?
                .iter()
                .map(|b| b.as_u64().map(f64::from_bits).ok_or("view_angles_bits holds a non-integer"))
                .collect::<Result<_, _>>()?,
        ),
        other => return Err(format!("view_spacing {other:?} is unknown")),
    };
    let channels = field(g, "channels")?
        .as_array()
        .ok_or("channels is not a list")?
        .iter()
        .map(|c| Ok(ColourChannel { name: text(c, "name")?.to_string(), wavelength_m: bits(c, "wavelength_bits")? }))
        .collect::<Result<Vec<_>, String>>()?;
    Ok(Geometry {
        parallax: match text(g, "parallax")? {
            "horizontal" => Parallax::Horizontal,
            "full" => Parallax::Full,
            other => return Err(format!("parallax {other:?} is unknown")),
        },
        hololines: uint(g, "hololines")? as usize,
        emitters: uint(g, "emitters")? as usize,
        views: Views {
            count,
            first_theta_rad: bits(g, "doubles_bits.view_first_rad")?,
            last_theta_rad: bits(g, "doubles_bits.view_last_rad")?,
            spacing,
        },
        vertical_views: None,
        hololine_pitch_m: bits(g, "doubles_bits.hololine_pitch_m")?,
        hololine_top_y_m: bits(g, "doubles_bits.hololine_top_y_m")?,
        emitter_pitch_m: bits(g, "doubles_bits.emitter_pitch_m")?,
        emitter_left_x_m: bits(g, "doubles_bits.emitter_left_x_m")?,
        emitter_z_m: bits(g, "doubles_bits.emitter_z_m")?,
        viewer_distance_m: bits(g, "doubles_bits.viewer_distance_m")?,
        viewer_height_m: bits(g, "doubles_bits.viewer_height_m")?,
        channels,
    })
}

/// Which fields of two geometries differ (for a readable failure).
fn geometry_diff(a: &Geometry, b: &Geometry) -> String {
    let mut out = Vec::new();
    let mut d = |name: &str, x: String, y: String| {
        if x != y {
            out.push(format!("{name}: file {x}, JSON {y}"));
        }
    };
    d("parallax", format!("{:?}", a.parallax), format!("{:?}", b.parallax));
    d("hololines", a.hololines.to_string(), b.hololines.to_string());
    d("emitters", a.emitters.to_string(), b.emitters.to_string());
    d("views", format!("{:?}", a.views), format!("{:?}", b.views));
    for (n, x, y) in [
        ("hololine_pitch_m", a.hololine_pitch_m, b.hololine_pitch_m),
        ("hololine_top_y_m", a.hololine_top_y_m, b.hololine_top_y_m),
        ("emitter_pitch_m", a.emitter_pitch_m, b.emitter_pitch_m),
        ("emitter_left_x_m", a.emitter_left_x_m, b.emitter_left_x_m),
        ("emitter_z_m", a.emitter_z_m, b.emitter_z_m),
        ("viewer_distance_m", a.viewer_distance_m, b.viewer_distance_m),
        ("viewer_height_m", a.viewer_height_m, b.viewer_height_m),
    ] {
        d(n, format!("{x:?} ({:#x})", x.to_bits()), format!("{y:?} ({:#x})", y.to_bits()));
    }
    d("channels", format!("{:?}", a.channels), format!("{:?}", b.channels));
    out.join("; ")
}

fn check_file(c: &mut Checks, holo: &Path, json: &Path) -> Result<(), String> {
    let label = holo.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let doc: Value =
        serde_json::from_str(&std::fs::read_to_string(json).map_err(|e| format!("{}: {e}", json.display()))?)
            .map_err(|e| format!("{}: {e}", json.display()))?;
    if let Some(w) = doc.get("writer").and_then(Value::as_str) {
        c.info(format!("{label}: written by {w}"));
    }

    let file = match HoloFile::open(holo) {
        Ok(f) => f,
        Err(e) => {
            c.check(false, format!("{label}: HoloFile::open accepts it"), || e.to_string());
            return Ok(());
        }
    };
    c.check(true, format!("{label}: HoloFile::open accepts it"), String::new);
    match validate(holo) {
        Ok(v) => {
            c.check(v.is_valid(), format!("{label}: validate finds no violation"), || v.violations.join("; "));
            for w in &v.warnings {
                c.info(format!("{label}: validate warns: {w}"));
            }
        }
        Err(e) => {
            c.check(false, format!("{label}: validate runs"), || e.to_string());
        }
    }

    let info = file.info();
    let expected = expected_geometry(&doc)?;
    c.check(info.geometry == expected, format!("{label}: geometry equals the writer's exactly"), || {
        geometry_diff(&info.geometry, &expected)
    });
    let st = match text(&doc, "sample_type")? {
        "f16" => SampleType::F16,
        "f32" => SampleType::F32,
        other => return Err(format!("sample_type {other:?} is unknown")),
    };
    c.check(info.sample_type == st, format!("{label}: sample type {st:?}"), || format!("found {:?}", info.sample_type));
    let comp = Compression::from_name(text(&doc, "compression")?).ok_or("unknown compression")?;
    c.check(info.compression == comp, format!("{label}: compression {}", comp.name()), || {
        format!("found {}", info.compression.name())
    });
    let r = &info.radiometry;
    let (enc, scale, unit) =
        (text(&doc, "radiometry.encoding")?, bits(&doc, "radiometry.scale_bits")?, text(&doc, "radiometry.unit")?);
    c.check(
        r.encoding == enc && r.scale.to_bits() == scale.to_bits() && r.unit == unit,
        format!("{label}: radiometry {enc}, scale {scale:?}, unit {unit:?}"),
        || format!("found {r:?}"),
    );

    let frames = field(&doc, "frames")?.as_array().ok_or("frames is not a list")?;
    if !c.check(info.frames.len() == frames.len(), format!("{label}: {} frame(s)", frames.len()), || {
        format!("found {}", info.frames.len())
    }) {
        return Ok(());
    }
    let g = info.geometry.clone();
    let mut first_frame = None;
    for (i, (fi, fj)) in info.frames.iter().zip(frames).enumerate() {
        let fl = format!("{label} frame {i}");
        let number = fj.get("number").and_then(Value::as_i64).ok_or("frame number missing")?;
        c.check(fi.number == number, format!("{fl}: holo.frame {number}"), || format!("found {}", fi.number));
        let digest = text(fj, "digest")?;
        c.check(
            fi.digest.as_deref() == Some(digest),
            format!("{fl}: digest {}…", &digest[..20.min(digest.len())]),
            || format!("found {:?}", fi.digest),
        );
        let w = &fi.data_window;
        let (x, y, wd, ht) = (
            uint(fj, "data_window.x")? as usize,
            uint(fj, "data_window.y")? as usize,
            uint(fj, "data_window.width")? as usize,
            uint(fj, "data_window.height")? as usize,
        );
        c.check(
            (w.x, w.y, w.width, w.height) == (x, y, wd, ht),
            format!("{fl}: data window {wd}×{ht} at ({x}, {y})"),
            || format!("found {w:?}"),
        );

        let m = match file.read_frame(i) {
            Ok(m) => m,
            Err(e) => {
                c.check(false, format!("{fl}: read_frame (digest verified)"), || e.to_string());
                continue;
            }
        };
        c.check(true, format!("{fl}: read_frame (digest verified)"), String::new);
        let samples = field(fj, "samples")?.as_object().ok_or("samples is not an object")?;
        let mut bad = Vec::new();
        let mut seen = 0usize;
        for (name, rows) in samples {
            let Some((v, colour, _)) = parse_channel_name(name) else {
                bad.push(format!("channel {name} not understood"));
                continue;
            };
            let Some(ci) = g.channel_index(colour) else {
                bad.push(format!("channel {name}: colour {colour} not in the file"));
                continue;
            };
            let rows = rows.as_array().ok_or("a channel's samples are not a list")?;
            for (j, row) in rows.iter().enumerate() {
                for (e, b) in row.as_array().ok_or("a row is not a list")?.iter().enumerate() {
                    let want = b.as_u64().ok_or("a sample is not an integer")? as u32;
                    seen += 1;
                    let got = m.get(ci, j, e, v);
                    if got.to_bits() != want {
                        bad.push(format!("{name} x={e} y={j}: {got:?}, expected {:?}", f32::from_bits(want)));
                    }
                }
            }
        }
        let total = g.samples_per_frame() as usize;
        c.check(bad.is_empty() && seen == total, format!("{fl}: all {total} samples bit-exact"), || {
            format!(
                "{} compared; {} differ: {}",
                seen,
                bad.len(),
                bad.iter().take(5).cloned().collect::<Vec<_>>().join("; ")
            )
        });

        // A region read must agree with the whole frame.
        if g.hololines > 1 && g.emitters > 1 {
            let region = Region {
                hololines: g.hololines / 2..g.hololines,
                emitters: 1..g.emitters,
                views: g.views.count.saturating_sub(2).min(1)..g.views.count,
                vertical_views: 0..1,
            };
            match file.read_region(i, &region) {
                Ok(sub) => {
                    let mut same = true;
                    for ci in 0..g.channels.len() {
                        for (jj, j) in region.hololines.clone().enumerate() {
                            for (ee, e) in region.emitters.clone().enumerate() {
                                for (vv, v) in region.views.clone().enumerate() {
                                    same &= sub.get(ci, jj, ee, vv).to_bits() == m.get(ci, j, e, v).to_bits();
                                }
                            }
                        }
                    }
                    c.check(same, format!("{fl}: read_region {region:?} agrees with read_frame"), || {
                        "samples differ".into()
                    });
                }
                Err(e) => {
                    c.check(false, format!("{fl}: read_region {region:?}"), || e.to_string());
                }
            }
        }
        if i == 0 {
            first_frame = Some(m);
        }
    }
    if let Some(m) = first_frame {
        match holo::format::read(holo) {
            Ok(r) => {
                c.check(r == m, format!("{label}: holo::format::read equals frame 0"), || "differs".into());
            }
            Err(e) => {
                c.check(false, format!("{label}: holo::format::read"), || e.to_string());
            }
        }
    }
    Ok(())
}

/// (holo file, JSON) pairs from the command line.
fn pairs(args: &[String]) -> Result<Vec<(PathBuf, PathBuf)>, String> {
    if let [dir] = args {
        let dir = Path::new(dir);
        if dir.is_dir() {
            let mut out = Vec::new();
            let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            let mut names: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
            names.sort();
            for json in names {
                if json.to_string_lossy().ends_with(".peer.json") {
                    let doc: Value = serde_json::from_str(
                        &std::fs::read_to_string(&json).map_err(|e| format!("{}: {e}", json.display()))?,
                    )
                    .map_err(|e| format!("{}: {e}", json.display()))?;
                    let file = text(&doc, "file").map_err(|e| format!("{}: {e}", json.display()))?;
                    out.push((dir.join(file), json));
                }
            }
            if out.is_empty() {
                return Err(format!("{}: no *.peer.json files", dir.display()));
            }
            return Ok(out);
        }
    }
    if args.is_empty() || args.len() % 2 != 0 {
        return Err("usage: peer_read FILE.holo FILE.peer.json [...] | peer_read DIR".into());
    }
    Ok(args.chunks(2).map(|p| (PathBuf::from(&p[0]), PathBuf::from(&p[1]))).collect())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let list = match pairs(&args) {
        Ok(l) => l,
        Err(e) => {
            eprintln!("peer_read: {e}");
            println!("0 passed, 1 failed");
            return ExitCode::from(2);
        }
    };
    let mut c = Checks::default();
    for (holo, json) in list {
        if let Err(e) = check_file(&mut c, &holo, &json) {
            c.check(false, format!("{}: checking ran to the end", holo.display()), || e);
        }
    }
    println!("{} passed, {} failed", c.passed, c.failed);
    if c.failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    }
}
