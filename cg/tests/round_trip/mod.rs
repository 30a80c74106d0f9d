//! The encode → decode round-trip check shared by the codec's tests and the
//! real-mesh test in holo's `tests/holoflick_cg.rs` (which loads meshes with
//! holo and includes this file by path): the fast, reference and streaming
//! decoders agree, and every input triangle comes back with its orientation
//! within the quantization bounds.

use std::collections::HashMap;

use holo_cg::{
    decode, decode_reference, decode_with, encode, normal_error_bound_rad, EncodeOptions, Encoded, Mesh, Primitive,
    Vertex,
};

/// An indexed mesh with every attribute, owned.
#[derive(Default)]
pub struct TestMesh {
    pub positions: Vec<[f64; 3]>,
    pub normals: Vec<[f32; 3]>,
    pub colors: Vec<[f32; 4]>,
    pub triangles: Vec<[u32; 3]>,
}

pub fn angle(a: [f32; 3], b: [f32; 3]) -> f64 {
    let d: f64 = (0..3).map(|k| f64::from(a[k]) * f64::from(b[k])).sum();
    let la = (0..3).map(|k| f64::from(a[k]).powi(2)).sum::<f64>().sqrt();
    let lb = (0..3).map(|k| f64::from(b[k]).powi(2)).sum::<f64>().sqrt();
    (d / (la * lb)).clamp(-1.0, 1.0).acos()
}

/// Largest errors found: (position, colour, normal angle rad).
#[derive(Debug, Default)]
pub struct Errors {
    pub position: f64,
    pub color: f64,
    pub normal_rad: f64,
}

/// Decode `bytes` three ways, check they agree, and match every input
/// triangle (same orientation) to a decoded one within the bounds.
pub fn check_round_trip(
    positions: &[[f64; 3]],
    normals: Option<&[[f32; 3]]>,
    colors: Option<&[[f32; 4]]>,
    triangles: &[[u32; 3]],
    o: &EncodeOptions,
) -> (Errors, Encoded) {
    let mesh = Mesh { positions, normals, colors, triangles };
    let enc = encode(&mesh, o).expect("encode");
    assert_eq!(enc.bytes.len() % 8, 0);
    let dec = decode(&enc.header, &enc.bytes).expect("decode");
    let reference = decode_reference(&enc.header, &enc.bytes).expect("reference decode");
    assert_eq!(dec, reference, "fast and reference decoders differ");
    let mut streamed = Vec::new();
    decode_with(&enc.header, &enc.bytes, |p| {
        if let Primitive::Triangle(t) = p {
            streamed.push(t.map(|v| *v));
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
            for (&g, &want) in got[k].position.iter().zip(&p) {
                let e = (f64::from(g) - want).abs();
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

pub fn rotate_min(t: &[Vertex; 3], key: impl Fn(&Vertex) -> [i32; 3]) -> [Vertex; 3] {
    let r = [[t[0], t[1], t[2]], [t[1], t[2], t[0]], [t[2], t[0], t[1]]];
    *r.iter().min_by_key(|r| r.map(|v| key(&v))).unwrap()
}

/// Every bit of a vertex: position, then normal and colour when present.
pub fn vertex_bits(v: &Vertex) -> Vec<u32> {
    v.position.iter().chain(v.normal.iter().flatten()).chain(v.color.iter().flatten()).map(|c| c.to_bits()).collect()
}

/// Triangles as sorted bit strings, each rotated to start at its smallest
/// vertex (Java 3D and the streaming decoder may start a triangle at another corner).
pub fn sorted_keys(ts: &[[Vertex; 3]]) -> Vec<Vec<u32>> {
    let mut v: Vec<Vec<u32>> = ts
        .iter()
        .map(|t| {
            let k = t.map(|v| vertex_bits(&v));
            [[0, 1, 2], [1, 2, 0], [2, 0, 1]]
                .iter()
                .map(|r| r.iter().flat_map(|&i| k[i].clone()).collect())
                .min()
                .unwrap()
        })
        .collect();
    v.sort();
    v
}
