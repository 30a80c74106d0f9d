//! The compressed-geometry codec (the `holo-cg` crate, tested on its own in
//! `cg/tests/`) on real meshes: loading them needs holo's mesh loader, so
//! this one test lives here. It shares the round-trip check with the
//! crate's tests.

use holo_cg::EncodeOptions;

use crate::common::{missing, shared_data};

#[path = "../../cg/tests/round_trip/mod.rs"]
mod round_trip;
use round_trip::{check_round_trip, TestMesh};

/// A real mesh from `../shared/data`: all objects merged, smooth normals
/// (area-weighted) where the file has none, colours from the file or else a
/// smooth gradient over the bounds (so colour deltas are realistic).
fn load_real(relative: &str) -> Option<TestMesh> {
    let path = shared_data()?.join(relative);
    if !path.exists() {
        missing(&path.display().to_string());
        return None;
    }
    let scene = holo::mesh::load::SceneSource::open(&path).and_then(|s| s.scene_at(0.0)).expect("load");
    let mut m = TestMesh::default();
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
#[ignore = "slow: the full run takes it (README, Development)"]
fn real_meshes_round_trip_within_bounds() {
    if shared_data().is_none() {
        missing("../shared/data");
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
