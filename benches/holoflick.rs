//! Compressed geometry: bytes per triangle, encode time and decode
//! speed (fast and reference decoders, Java-order and streaming) for real
//! meshes of 5.8k–6.3k triangles at 16/9/6 and 10/8/6 bits
//! (position/colour/normal), RGBA colours and per-vertex normals, as Java 3D's
//! own encoder was measured (~10 and ~7.3 bytes/triangle).
//! `cargo bench --bench holoflick` (`-- --test`: one quick pass, as CI runs it).
//! Then Java 3D's own encoder and decoder, Draco and holo's `.cg` tool on
//! the same meshes, side by side, when Java 3D is installed ([`peers`]).
//!
//! The meshes come from `../shared/data` (skipped, and said so, without it):
//! the Utah teapot (6 320 triangles, no normals in the file: area-weighted
//! vertex normals) and Spot (5 856). Neither has vertex colours, so colours
//! are a smooth gradient over the bounds (realistic deltas, not constants).

// Shared with the frame benchmarks; `band` is theirs.
#[allow(dead_code)]
mod common;
use common::cpu_time;

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use holo::holoflick::cg::{decode, decode_reference, decode_with, encode, EncodeOptions, Encoded, Mesh, Primitive};

struct Model {
    label: &'static str,
    positions: Vec<[f64; 3]>,
    normals: Vec<[f32; 3]>,
    colors: Vec<[f32; 4]>,
    triangles: Vec<[u32; 3]>,
}

impl Model {
    fn mesh(&self) -> Mesh<'_> {
        Mesh {
            positions: &self.positions,
            normals: Some(&self.normals),
            colors: Some(&self.colors),
            triangles: &self.triangles,
        }
    }
}

fn load(label: &'static str, relative: &str) -> Option<Model> {
    let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let shared =
        std::env::var("HOLO_SHARED_DATA").map(std::path::PathBuf::from).unwrap_or_else(|_| root.join("../shared/data"));
    let path = shared.join(relative);
    if !path.exists() {
        println!("SKIPPED {label}: {} not present", path.display());
        return None;
    }
    let scene = holo::mesh::load::SceneSource::open(&path).and_then(|s| s.scene_at(0.0)).expect("load");
    let mut m = Model { label, positions: vec![], normals: vec![], colors: vec![], triangles: vec![] };
    for o in &scene.objects {
        let base = m.positions.len() as u32;
        m.positions.extend(&o.positions);
        m.triangles.extend(o.triangles.iter().map(|t| t.map(|i| i + base)));
        if o.normals.len() == o.positions.len() {
            m.normals.extend(&o.normals);
        } else {
            let mut acc = vec![[0.0f64; 3]; o.positions.len()];
            for t in &o.triangles {
                let [a, b, c] = t.map(|i| o.positions[i as usize]);
                let (u, v) = ([0, 1, 2].map(|k| b[k] - a[k]), [0, 1, 2].map(|k| c[k] - a[k]));
                let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
                for &i in t {
                    for k in 0..3 {
                        acc[i as usize][k] += n[k];
                    }
                }
            }
            m.normals.extend(acc.iter().map(|n| n.map(|c| c as f32)));
        }
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in &m.positions {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    m.colors = m
        .positions
        .iter()
        .map(|p| {
            let f = |k: usize| ((p[k] - lo[k]) / (hi[k] - lo[k]).max(1e-30)) as f32;
            [f(0), f(1), f(2), 1.0]
        })
        .collect();
    Some(m)
}

fn models() -> Vec<Model> {
    [("teapot", "mesh_utah_teapot/teapot.obj"), ("spot", "mesh_spot_textured_obj/spot_triangulated.obj")]
        .iter()
        .filter_map(|(l, p)| load(l, p))
        .collect()
}

const SETTINGS: [(u32, u32, u32, f64); 2] = [(16, 9, 6, 10.0), (10, 8, 6, 7.3)];

fn options(p: u32, c: u32, n: u32) -> EncodeOptions {
    EncodeOptions { position_bits: p, color_bits: c, normal_bits: n, alpha: true }
}

/// Triangles decoded through the streaming interface (nothing stored).
fn stream_count(e: &Encoded) -> usize {
    let mut n = 0usize;
    decode_with(&e.header, &e.bytes, |p| {
        if let Primitive::Triangle(t) = p {
            black_box(t);
            n += 1;
        }
    })
    .expect("decode");
    n
}

fn table(models: &[Model], quick: bool) {
    let runs = if quick { 1 } else { 20 };
    println!(
        "\n{:<8} {:>9} {:>9} {:>10} {:>12} {:>10} {:>14} {:>14} {:>14}",
        "mesh",
        "bits",
        "triangles",
        "bytes/tri",
        "vs Java 3D",
        "encode ms",
        "stream Mtri/s",
        "decode Mtri/s",
        "reference Mtri/s"
    );
    for m in models {
        for (p, c, n, java) in SETTINGS {
            let o = options(p, c, n);
            let mut e = None;
            let t_encode = cpu_time(runs.min(5), || e = Some(encode(&m.mesh(), &o).expect("encode")));
            let e = e.expect("encoded");
            let tris = e.stats.triangles as f64;
            // Decoding is one thread: timed in its CPU time, so that other
            // processes on a shared machine do not count.
            let t_stream = cpu_time(runs * 3, || {
                black_box(stream_count(&e));
            });
            let t_decode = cpu_time(runs * 3, || {
                black_box(decode(&e.header, &e.bytes).expect("decode"));
            });
            let t_ref = cpu_time(runs.min(3), || {
                black_box(decode_reference(&e.header, &e.bytes).expect("decode"));
            });
            let bpt = e.stats.bytes as f64 / tris;
            println!(
                "{:<8} {:>9} {:>9} {:>10.2} {:>11.2}x {:>10.2} {:>14.1} {:>14.1} {:>14.2}",
                m.label,
                format!("{p}/{c}/{n}"),
                e.stats.triangles,
                bpt,
                bpt / java,
                t_encode * 1e3,
                tris / t_stream / 1e6,
                tris / t_decode / 1e6,
                tris / t_ref / 1e6
            );
            println!(
                "         vertices: {} distinct, {} sent, {} mesh-buffer references",
                e.stats.unique_vertices, e.stats.vertices_sent, e.stats.mesh_buffer_hits
            );
        }
    }
    println!();
}

/// The same meshes through Java 3D's own encoder and decoder, Draco, and
/// holo's `.cg` tool, side by side (`tests/peer/java3d/bench.sh`, which
/// prints one table; Deering's paper figure is its last row per mesh). Needs
/// Java 3D 1.5.2 and draco from Debian (`.ci/peers.sh` installs them); said
/// and skipped without them; `HOLO_BENCH_PEERS=0` skips them, `=1` runs
/// them in the quick pass too.
fn peers(quick: bool) {
    match std::env::var("HOLO_BENCH_PEERS").as_deref() {
        Ok("0") => {
            println!("peers (Java 3D, Draco): skipped (HOLO_BENCH_PEERS=0)\n");
            return;
        }
        Ok("1") => {}
        _ if quick => {
            println!("peers (Java 3D, Draco): skipped in the quick pass (HOLO_BENCH_PEERS=1 runs them)\n");
            return;
        }
        _ => {}
    }
    let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let jar = std::path::Path::new("/usr/share/java/j3dcore.jar");
    let java = std::process::Command::new("java").arg("-version").output().is_ok_and(|o| o.status.success());
    if !jar.exists() || !java {
        println!("peers (Java 3D, Draco): SKIPPED, no Java 3D here (apt-get install libjava3d-java draco, or .ci/peers.sh)\n");
        return;
    }
    // holo's side is the cg_peer example, built here so that it is this tree's codec.
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let built = std::process::Command::new(&cargo)
        .args(["build", "--release", "-q", "--example", "cg_peer"])
        .current_dir(&root)
        .status()
        .is_ok_and(|s| s.success());
    let mut script = std::process::Command::new("bash");
    script.arg("tests/peer/java3d/bench.sh").args(["--runs", if quick { "3" } else { "100" }]).current_dir(&root);
    if built {
        script.env("HOLO_CG", root.join("target/release/examples/cg_peer"));
    } else {
        println!("peers: building examples/cg_peer failed: holo rows left out");
    }
    println!("\npeers, side by side (tests/peer/java3d/bench.sh):");
    match script.status() {
        Ok(s) if s.success() => println!(),
        Ok(s) => println!("peers: bench.sh failed ({s})\n"),
        Err(e) => println!("peers: cannot run bash: {e}\n"),
    }
}

fn bench(c: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    let models = models();
    table(&models, quick);
    peers(quick);
    for m in &models {
        let mut group = c.benchmark_group(format!("cg_{}", m.label));
        group.sample_size(20);
        for (p, cb, n, _) in SETTINGS {
            let e = encode(&m.mesh(), &options(p, cb, n)).expect("encode");
            group.throughput(Throughput::Elements(e.stats.triangles as u64));
            group.bench_function(format!("stream_decode_{p}_{cb}_{n}"), |b| b.iter(|| stream_count(&e)));
            group.bench_function(format!("decode_{p}_{cb}_{n}"), |b| {
                b.iter(|| decode(&e.header, &e.bytes).expect("decode"))
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
