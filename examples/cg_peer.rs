//! holo's compressed-geometry codec behind the command-line interface of the
//! Java 3D peer tool (`tests/peer/java3d/README.md`), so `.ci/peers.sh` can
//! check the two against each other (`HOLO_CG`):
//!
//! ```text
//! cg_peer encode IN.ply OUT.cg POSBITS COLORBITS NORMALBITS [--no-stripify]
//! cg_peer decode FILE.cg [--hex] [--indexed]     (always prints hex values, triangles layout)
//! cg_peer time FILE.cg N                        (Java-order decode to triangles, and streaming)
//! ```
//!
//! `encode` reads an ASCII PLY (`x y z`, optional `nx ny nz`, optional
//! `red green blue [alpha]` as floats or as bytes divided by 255) and writes
//! a one-object `.cg` file; it reports the centre and scale
//! (`model = normalised / scale + centre`) and that holo rounds positions to
//! the nearest quantum (`quantization nearest`; Java 3D truncates).

use std::path::Path;
use std::process::ExitCode;

use holo::holoflick::cg::{decode, decode_with, encode as encode_mesh, CgFile, EncodeOptions, Mesh, Primitive, Vertex};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("encode") if args.len() >= 6 => encode(&args[1..]),
        Some("decode") if args.len() >= 2 => decode_file(args.last().map(String::as_str).unwrap_or_default()),
        Some("time") if args.len() == 3 => time(&args[1], &args[2]),
        _ => Err("usage: cg_peer encode IN.ply OUT.cg P C N | decode FILE.cg | time FILE.cg N".into()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("cg_peer: {e}");
            ExitCode::from(1)
        }
    }
}

type Ply = (Vec<[f64; 3]>, Option<Vec<[f32; 3]>>, Option<Vec<[f32; 4]>>, Vec<[u32; 3]>);

/// An ASCII PLY as the peer tool reads it.
fn read_ply(path: &str) -> Result<Ply, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lines = text.lines();
    let (mut vertices, mut faces, mut props, mut element) = (0usize, 0usize, Vec::new(), String::new());
    for line in lines.by_ref() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["end_header"] => break,
            ["element", name, n] => {
                element = name.to_string();
                let n: usize = n.parse().map_err(|_| format!("{path}: bad count {n}"))?;
                if element == "vertex" {
                    vertices = n;
                } else if element == "face" {
                    faces = n;
                }
            }
            ["property", kind, name] if element == "vertex" => {
                props.push((name.to_string(), matches!(*kind, "uchar" | "uint8")))
            }
            _ => {}
        }
    }
    let at = |name: &str| props.iter().position(|p| p.0 == name);
    let (normals, colours) = (at("nx").is_some(), at("red").is_some());
    let (mut p, mut n, mut c) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..vertices {
        let line = lines.next().ok_or(format!("{path}: too few vertices"))?;
        let v: Vec<f64> = line.split_whitespace().map(|t| t.parse::<f64>().unwrap_or(f64::NAN)).collect();
        let get = |name: &str| {
            at(name).and_then(|i| v.get(i).map(|x| if props[i].1 { (*x / 255.0) as f32 } else { *x as f32 }))
        };
        p.push([get("x"), get("y"), get("z")].map(|x| x.unwrap_or(0.0) as f64));
        if normals {
            n.push([get("nx"), get("ny"), get("nz")].map(|x| x.unwrap_or(0.0)));
        }
        if colours {
            c.push([get("red"), get("green"), get("blue"), get("alpha").or(Some(1.0))].map(|x| x.unwrap_or(0.0)));
        }
    }
    let mut triangles = Vec::new();
    for _ in 0..faces {
        let line = lines.next().ok_or(format!("{path}: too few faces"))?;
        let f: Vec<u32> = line.split_whitespace().skip(1).map(|t| t.parse().unwrap_or(u32::MAX)).collect();
        for k in 1..f.len().saturating_sub(1) {
            triangles.push([f[0], f[k], f[k + 1]]);
        }
    }
    Ok((p, normals.then_some(n), colours.then_some(c), triangles))
}

fn encode(args: &[String]) -> Result<(), String> {
    let (input, output) = (&args[0], &args[1]);
    let bits: Vec<u32> =
        args[2..5].iter().map(|b| b.parse().map_err(|_| format!("bad bits {b}"))).collect::<Result<_, _>>()?;
    let (positions, normals, colours, triangles) = read_ply(input)?;
    let options = EncodeOptions { position_bits: bits[0], color_bits: bits[1], normal_bits: bits[2], alpha: true };
    let mesh =
        Mesh { positions: &positions, normals: normals.as_deref(), colors: colours.as_deref(), triangles: &triangles };
    let encoded = encode_mesh(&mesh, &options).map_err(|e| e.to_string())?;
    // A test driver's scratch output: replaced in place, no temporary file.
    std::fs::write(output, CgFile::from_encoded(&encoded).to_bytes()).map_err(|e| format!("{output}: {e}"))?;
    let file_bytes = std::fs::metadata(output).map(|m| m.len()).unwrap_or(0);
    let h = encoded.header;
    let present = u32::from(h.normals) | u32::from(h.colors) << 1 | u32::from(h.alpha) << 2;
    println!(
        "input {input} vertices {} triangles {} normals {} colors {}",
        positions.len(),
        triangles.len(),
        u32::from(normals.is_some()),
        if colours.is_some() { "rgba" } else { "none" }
    );
    println!("options pos {} color {} normal {} stripify 0", bits[0], bits[1], bits[2]);
    println!("quantization nearest");
    let c = encoded.center;
    println!("center {} {} {} scale {}", c[0], c[1], c[2], encoded.scale);
    println!(
        "output {output} objects 1 stream_bytes {} file_bytes {file_bytes} data_present {present}",
        encoded.bytes.len()
    );
    println!(
        "bytes_per_triangle {:.4} (stream bytes / input triangles)",
        encoded.bytes.len() as f64 / triangles.len().max(1) as f64
    );
    Ok(())
}

fn values(v: &Vertex) -> [f32; 10] {
    let n = v.normal.unwrap_or([0.0; 3]);
    let c = v.color.unwrap_or([0.0; 4]);
    [v.position[0], v.position[1], v.position[2], n[0], n[1], n[2], c[0], c[1], c[2], c[3]]
}

/// A triangle, given by its corners' positions, with two corners in one place.
fn degenerate(p: [[f32; 3]; 3]) -> bool {
    p[0] == p[1] || p[1] == p[2] || p[0] == p[2]
}

fn decode_file(path: &str) -> Result<(), String> {
    use std::fmt::Write as _;
    use std::io::Write as _;
    let file = CgFile::read(Path::new(path)).map_err(|e| e.to_string())?;
    let [a, b, c] = file.version;
    let mut out = String::new();
    // Lines gathered and written once (a closed pipe is not an error here).
    macro_rules! println {
        ($($t:tt)*) => {{ let _ = writeln!(out, $($t)*); }};
    }
    println!("# CgTool decode hex triangles (holo {})", env!("CARGO_PKG_VERSION"));
    println!("cg {path} version {a}.{b}.{c} objects {}", file.objects.len());
    for (i, o) in file.objects.iter().enumerate() {
        let d = decode(&o.header, &o.bytes).map_err(|e| format!("object {i}: {e}"))?;
        let h = o.header;
        let flags =
            format!("normals {} colors {} alpha {}", u8::from(h.normals), u8::from(h.colors), u8::from(h.alpha));
        let t = d.triangles.len();
        let degenerate = d.triangles.iter().filter(|t| degenerate(t.map(|v| v.position))).count();
        println!(
            "object {i} type triangle {flags} bytes {} segments 1 vertices {} triangles {t} degenerate {degenerate}",
            o.bytes.len(),
            3 * t
        );
        println!("segment 0 {flags} vertices {} triangles {t}", 3 * t);
        for tri in &d.triangles {
            for v in tri {
                let line: Vec<String> = values(v).iter().map(|x| format!("{:08x}", x.to_bits())).collect();
                println!("{}", line.join(" "));
            }
        }
        println!("end");
    }
    let _ = std::io::stdout().lock().write_all(out.as_bytes());
    Ok(())
}

fn time(path: &str, runs: &str) -> Result<(), String> {
    let runs: usize = runs.parse().map_err(|_| format!("bad run count {runs}"))?;
    let file = CgFile::read(Path::new(path)).map_err(|e| e.to_string())?;
    // Java 3D's order, into triangle arrays, as CgTool times Java 3D.
    let java_order = rate(runs, || {
        let mut count = 0;
        for o in &file.objects {
            let d = decode(&o.header, &o.bytes).map_err(|e| e.to_string())?;
            count += d.triangles.iter().filter(|t| !degenerate(t.map(|v| v.position))).count();
        }
        Ok(count)
    })?;
    // The streaming decoder (what holo's own readers use): triangles handed
    // out as decoded, nothing stored.
    let streaming = rate(runs, || {
        let mut count = 0;
        for o in &file.objects {
            decode_with(&o.header, &o.bytes, |p| {
                if let Primitive::Triangle(t) = p {
                    count += usize::from(!degenerate(t.map(|v| v.position)));
                }
            })
            .map_err(|e| e.to_string())?;
        }
        Ok(count)
    })?;
    println!("file {path} passes {}", runs.max(1));
    println!("nondegenerate triangles/s {java_order}");
    println!("streaming nondegenerate triangles/s {streaming}");
    Ok(())
}

/// `runs` timed passes of `pass` (which returns the non-degenerate
/// triangles it decoded): "mean X median Y" triangles per second.
fn rate(runs: usize, mut pass: impl FnMut() -> Result<usize, String>) -> Result<String, String> {
    let mut seconds = Vec::with_capacity(runs.max(1));
    let mut triangles = 0;
    for _ in 0..runs.max(1) {
        let start = std::time::Instant::now();
        triangles = pass()?;
        seconds.push(start.elapsed().as_secs_f64());
    }
    let mean = seconds.iter().sum::<f64>() / seconds.len() as f64;
    seconds.sort_by(f64::total_cmp);
    let median = seconds[seconds.len() / 2];
    Ok(format!("mean {:.0} median {:.0}", triangles as f64 / mean, triangles as f64 / median))
}
