//! Compressed geometry (issue 6): encode → decode round trips on random and
//! real meshes within the quantization bounds, hand-built streams for each
//! command decoded from the format's text, the fast and reference decoders
//! agreeing on valid and random streams, bad input, and `.cg` files.

use std::collections::HashMap;
use std::path::PathBuf;

use holo::holoflick::cg::{
    decode, decode_reference, decode_with, encode, file::CgFile, normal_error_bound_rad, read_cg_file, write_cg_file,
    BlockKind, CgHeader, Decoded, EncodeOptions, Mesh, Primitive, Vertex,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

mod common;
use common::shared_data;

/// A random connected mesh: a jittered grid of `w × h` quads, each split
/// along a random diagonal, with smooth random normals and colours.
struct TestMesh {
    positions: Vec<[f64; 3]>,
    normals: Vec<[f32; 3]>,
    colors: Vec<[f32; 4]>,
    triangles: Vec<[u32; 3]>,
}

fn random_mesh(rng: &mut ChaCha8Rng, w: u32, h: u32) -> TestMesh {
    let mut m = TestMesh { positions: vec![], normals: vec![], colors: vec![], triangles: vec![] };
    let scale = 10f64.powf(rng.gen_range(-3.0..4.0));
    let offset = [rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3), rng.gen_range(-1e3..1e3)];
    for y in 0..=h {
        for x in 0..=w {
            let (fx, fy) = (f64::from(x) + rng.gen_range(-0.3..0.3), f64::from(y) + rng.gen_range(-0.3..0.3));
            let z = (fx * 0.3).sin() * (fy * 0.2).cos() * 2.0;
            m.positions.push([offset[0] + fx * scale, offset[1] + fy * scale, offset[2] + z * scale]);
            let n = [rng.gen_range(-1.0f32..1.0), rng.gen_range(-1.0f32..1.0), rng.gen_range(-1.0f32..1.0)];
            m.normals.push(if n.iter().all(|c| c.abs() < 1e-3) { [0.0, 0.0, 1.0] } else { n });
            m.colors.push([
                rng.gen_range(0.0..=1.0),
                rng.gen_range(0.0..=1.0),
                rng.gen_range(0.0..=1.0),
                rng.gen_range(0.0..=1.0),
            ]);
        }
    }
    let v = |x: u32, y: u32| y * (w + 1) + x;
    for y in 0..h {
        for x in 0..w {
            if rng.gen_bool(0.5) {
                m.triangles.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
                m.triangles.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
            } else {
                m.triangles.push([v(x, y), v(x + 1, y), v(x, y + 1)]);
                m.triangles.push([v(x + 1, y), v(x + 1, y + 1), v(x, y + 1)]);
            }
        }
    }
    m
}

fn angle(a: [f32; 3], b: [f32; 3]) -> f64 {
    let d: f64 = (0..3).map(|k| f64::from(a[k]) * f64::from(b[k])).sum();
    let la = (0..3).map(|k| f64::from(a[k]).powi(2)).sum::<f64>().sqrt();
    let lb = (0..3).map(|k| f64::from(b[k]).powi(2)).sum::<f64>().sqrt();
    (d / (la * lb)).clamp(-1.0, 1.0).acos()
}

/// Largest errors found: (position, colour, normal angle rad).
#[derive(Debug, Default)]
struct Errors {
    position: f64,
    color: f64,
    normal_rad: f64,
}

/// Decode `bytes` three ways, check they agree, and match every input
/// triangle (same orientation) to a decoded one within the bounds.
fn check_round_trip(
    positions: &[[f64; 3]],
    normals: Option<&[[f32; 3]]>,
    colors: Option<&[[f32; 4]]>,
    triangles: &[[u32; 3]],
    o: &EncodeOptions,
) -> (Errors, holo::holoflick::cg::Encoded) {
    let mesh = Mesh { positions, normals, colors, triangles };
    let enc = encode(&mesh, o).expect("encode");
    assert_eq!(enc.bytes.len() % 8, 0);
    let dec = decode(&enc.header, &enc.bytes).expect("decode");
    let reference = decode_reference(&enc.header, &enc.bytes).expect("reference decode");
    assert_eq!(dec, reference, "fast and reference decoders differ");
    let mut streamed = Vec::new();
    decode_with(&enc.header, &enc.bytes, |p| {
        if let Primitive::Triangle(t) = p {
            streamed.push(*t);
        }
    })
    .expect("streaming decode");
    assert_eq!(dec.triangles.len(), triangles.len());
    assert_eq!(sorted_keys(&streamed), sorted_keys(&dec.triangles), "streaming and Java-order triangles differ");

    // Decoded triangles by their (rotation-normalised) quantized positions.
    let key = |v: &Vertex| v.position.map(|c| (c * 32768.0) as i32);
    let mut pool: HashMap<[[i32; 3]; 3], Vec<[Vertex; 3]>> = HashMap::new();
    for t in &dec.triangles {
        let r = rotate_min(t, key);
        pool.entry(r.map(|v| key(&v))).or_default().push(r);
    }
    let pos_bound = 0.5f64.powi(o.position_bits as i32) + 1e-6;
    let col_step = 0.5f64.powi(o.color_bits as i32 - 1);
    let col_bound = 0.5 * col_step + 1e-6;
    let nor_bound = normal_error_bound_rad(o.normal_bits);
    let mut err = Errors::default();
    let to_frame = |p: [f64; 3]| [0, 1, 2].map(|k| (p[k] - enc.center[k]) * enc.scale);
    for t in triangles {
        let want: [Vertex; 3] = t.map(|i| {
            let p = to_frame(positions[i as usize]);
            let q = p.map(|c| {
                let step = f64::from(1u32 << (16 - o.position_bits)) / 32768.0;
                ((c / step).round() * step) as f32
            });
            Vertex { position: q, normal: None, color: None }
        });
        let want_r = rotate_min(&want, key);
        let found = pool.get_mut(&want_r.map(|v| key(&v))).and_then(|v| v.pop());
        let Some(got) = found else { panic!("input triangle {t:?} not decoded with its orientation") };
        // Which input vertex is at each decoded corner.
        let order: Vec<u32> = want_r
            .iter()
            .map(|w| {
                t.iter().copied().find(|&i| key(&want[t.iter().position(|&j| j == i).unwrap()]) == key(w)).unwrap()
            })
            .collect();
        for (k, &i) in order.iter().enumerate() {
            let i = i as usize;
            let p = to_frame(positions[i]);
            for c in 0..3 {
                let e = (f64::from(got[k].position[c]) - p[c]).abs();
                err.position = err.position.max(e);
                assert!(e <= pos_bound, "position error {e} > {pos_bound}");
            }
            if let Some(n) = normals {
                let a = angle(n[i], got[k].normal.expect("normal"));
                err.normal_rad = err.normal_rad.max(a);
                assert!(a <= nor_bound, "normal error {a} rad > {nor_bound}");
            }
            if let Some(c) = colors {
                let gc = got[k].color.expect("colour");
                let comps = if o.alpha { 4 } else { 3 };
                for ch in 0..comps {
                    let clamped = f64::from(c[i][ch]).clamp(0.0, 1.0 - col_step);
                    let e = (f64::from(gc[ch]) - clamped).abs();
                    err.color = err.color.max(e);
                    assert!(e <= col_bound, "colour error {e} > {col_bound}");
                }
            }
        }
    }
    (err, enc)
}

fn rotate_min(t: &[Vertex; 3], key: impl Fn(&Vertex) -> [i32; 3]) -> [Vertex; 3] {
    let r = [[t[0], t[1], t[2]], [t[1], t[2], t[0]], [t[2], t[0], t[1]]];
    *r.iter().min_by_key(|r| r.map(|v| key(&v))).unwrap()
}

fn sorted_keys(ts: &[[Vertex; 3]]) -> Vec<Vec<u32>> {
    let mut v: Vec<Vec<u32>> = ts
        .iter()
        .map(|t| {
            let r = rotate_min(t, |v| v.position.map(|c| (c * 32768.0) as i32));
            r.iter()
                .flat_map(|v| {
                    v.position
                        .iter()
                        .chain(v.normal.iter().flatten())
                        .chain(v.color.iter().flatten())
                        .map(|c| c.to_bits())
                })
                .collect()
        })
        .collect();
    v.sort();
    v
}

const SETTINGS: [(u32, u32, u32); 4] = [(16, 9, 6), (10, 8, 6), (12, 4, 3), (6, 2, 0)];

#[test]
fn random_meshes_round_trip_within_bounds() {
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    for round in 0..12 {
        let (w, h) = (rng.gen_range(1..25), rng.gen_range(1..25));
        let m = random_mesh(&mut rng, w, h);
        for &(p, c, n) in &SETTINGS {
            for (with_n, with_c, alpha) in [
                (true, true, true),
                (true, true, false),
                (false, false, false),
                (true, false, false),
                (false, true, true),
            ] {
                let o = EncodeOptions { position_bits: p, color_bits: c, normal_bits: n, alpha };
                let (err, enc) = check_round_trip(
                    &m.positions,
                    with_n.then_some(&m.normals[..]),
                    with_c.then_some(&m.colors[..]),
                    &m.triangles,
                    &o,
                );
                if round == 0 {
                    println!("{w}x{h} {p}/{c}/{n} n{with_n} c{with_c} a{alpha}: {:?} {:?}", err, enc.stats);
                }
            }
        }
    }
}

/// A real mesh from `../shared/data`: all objects merged, smooth normals
/// (area-weighted) where the file has none, colours from the file or else a
/// smooth gradient over the bounds (so colour deltas are realistic).
fn load_real(relative: &str) -> Option<TestMesh> {
    let path = shared_data()?.join(relative);
    if !path.exists() {
        println!("SKIPPED: {} not present", path.display());
        return None;
    }
    let scene = holo::mesh::load::SceneSource::open(&path).and_then(|s| s.scene_at(0.0)).expect("load");
    let mut m = TestMesh { positions: vec![], normals: vec![], colors: vec![], triangles: vec![] };
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
        m.colors.extend(o.colours.iter().copied());
    }
    if m.colors.len() != m.positions.len() {
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
    }
    Some(m)
}

/// The real meshes the issue names: (path under shared data, label).
const REAL: [(&str, &str); 4] = [
    ("mesh_utah_teapot/teapot.obj", "teapot"),
    ("mesh_spot_textured_obj/spot_triangulated.obj", "spot"),
    ("gltf_khronos_BoxVertexColors/glTF/BoxVertexColors.gltf", "box-vertex-colours"),
    ("mesh_cube_obj_vertexcolors/cube_with_vertexcolors.obj", "cube-vertex-colours"),
];

#[test]
fn real_meshes_round_trip_within_bounds() {
    if shared_data().is_none() {
        println!("SKIPPED: ../shared/data not present");
        return;
    }
    for (path, label) in REAL {
        let Some(m) = load_real(path) else { continue };
        for (p, c, n) in [(16, 9, 6), (10, 8, 6)] {
            let o = EncodeOptions { position_bits: p, color_bits: c, normal_bits: n, alpha: true };
            let (err, enc) = check_round_trip(&m.positions, Some(&m.normals), Some(&m.colors), &m.triangles, &o);
            println!(
                "{label} {p}/{c}/{n} RGBA: {} triangles, {:.2} bytes/triangle, {} of {} vertices sent, {} mesh-buffer hits; worst errors {err:?}",
                enc.stats.triangles,
                enc.stats.bytes as f64 / enc.stats.triangles as f64,
                enc.stats.vertices_sent,
                enc.stats.unique_vertices,
                enc.stats.mesh_buffer_hits
            );
        }
    }
}
