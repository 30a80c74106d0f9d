//! Mesh objects through HoloFlick geometry objects and back: world
//! positions, normals and colours (radiance above 1 included) within the
//! quantization bounds, and a mirroring transform keeps fronts in front.

use holo::holoflick::cg::{normal_error_bound_rad, EncodeOptions};
use holo::holoflick::objects::{decode_object, encode_object};
use holo::mesh::Object;
use rand::{Rng, SeedableRng};

/// A bumpy random grid surface in world metres with smooth normals and
/// colours up to 3 (baked radiance).
fn surface(seed: u64, n: usize) -> Object {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut o = Object { name: "surface".into(), ..Object::default() };
    let h: Vec<f64> = (0..n * n).map(|_| rng.gen_range(-0.002..0.002)).collect();
    for j in 0..n {
        for i in 0..n {
            o.positions.push([0.1 + 0.003 * i as f64, -0.02 + 0.002 * j as f64, 0.05 + h[j * n + i]]);
            let t: [f32; 3] = [rng.gen_range(-0.3..0.3), rng.gen_range(-0.3..0.3), 1.0];
            let l = (t[0] * t[0] + t[1] * t[1] + 1.0).sqrt();
            o.normals.push(t.map(|x| x / l));
            o.colours.push([rng.gen_range(0.0..3.0), rng.gen_range(0.0..1.0), rng.gen_range(0.0..0.2), 1.0]);
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = (j * n + i) as u32;
            o.triangles.extend([[a, a + 1, a + n as u32 + 1], [a, a + n as u32 + 1, a + n as u32]]);
        }
    }
    o
}

#[test]
fn objects_round_trip_within_the_quantization_bounds() {
    for (bits, seed) in [((16, 9, 6), 1), ((10, 8, 6), 2), ((12, 12, 4), 3)] {
        let o = surface(seed, 24);
        let options = EncodeOptions { position_bits: bits.0, color_bits: bits.1, normal_bits: bits.2, alpha: false };
        let (g, stats) = encode_object(7, &o, &options).unwrap();
        assert_eq!(g.id, 7);
        assert!(g.radiance_scale > 2.9, "radiance above 1 is scaled: {}", g.radiance_scale);
        let (d, skipped) = decode_object("surface", &g.block, &g.world_from_object, g.radiance_scale).unwrap();
        assert_eq!(skipped, 0);
        assert_eq!(d.triangles.len(), o.triangles.len());
        // Bounds: half a quantum of the normalised frame in metres (the
        // extent fills 2 (2^(b−1) − 1)/2^(b−1) of the frame's 2, cut in 2^b
        // steps); the normal grid's angle; half a colour step (2^(1−b)) times
        // the scale.
        let extent = 0.003 * 23.0;
        let half_step = 2f64.powi(bits.0 as i32 - 1);
        let dp = 0.5 * extent / 2f64.powi(bits.0 as i32) * half_step / (half_step - 1.0) * (1.0 + 1e-9);
        let dn = normal_error_bound_rad(bits.2);
        let dc = 0.5 * g.radiance_scale * 2f64.powi(1 - bits.1 as i32) * (1.0 + 1e-6);
        let (mut worst_p, mut worst_n, mut worst_c) = (0.0f64, 0.0f64, 0.0f64);
        for (i, p) in d.positions.iter().enumerate() {
            // The source vertex nearest the decoded one.
            let (k, dist) = o
                .positions
                .iter()
                .enumerate()
                .map(|(k, q)| (k, (0..3).map(|a| (p[a] - q[a]).abs()).fold(0.0, f64::max)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            worst_p = worst_p.max(dist);
            let (n, m) = (d.normals[i], o.normals[k]);
            let cos = (n[0] * m[0] + n[1] * m[1] + n[2] * m[2]) as f64;
            worst_n = worst_n.max(cos.clamp(-1.0, 1.0).acos());
            for c in 0..3 {
                worst_c = worst_c.max((d.colours[i][c] as f64 - o.colours[k][c] as f64).abs());
            }
        }
        println!(
            "{bits:?}: {} bytes, {:.2} B/triangle; worst position {worst_p:.2e} m (bound {dp:.2e}), normal {worst_n:.4} rad ({dn:.4}), colour {worst_c:.4} ({dc:.4})",
            stats.bytes,
            stats.bytes as f64 / o.triangles.len() as f64
        );
        assert!(worst_p <= dp && worst_n <= dn && worst_c <= dc);
    }
}

#[test]
fn mirroring_transforms_keep_fronts_in_front() {
    let o = surface(4, 8);
    let (mut g, _) = encode_object(1, &o, &EncodeOptions::default()).unwrap();
    g.world_from_object[0] = g.world_from_object[0].map(|x| -x);
    let (d, _) = decode_object("mirrored", &g.block, &g.world_from_object, g.radiance_scale).unwrap();
    for t in &d.triangles {
        let p = t.map(|i| d.positions[i as usize]);
        let (u, v) = ([0, 1, 2].map(|k| p[1][k] - p[0][k]), [0, 1, 2].map(|k| p[2][k] - p[0][k]));
        let face = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
        let n = d.normals[t[0] as usize];
        assert!(face[0] * n[0] as f64 + face[1] * n[1] as f64 + face[2] * n[2] as f64 > 0.0, "front turned back");
    }
    // A singular transform is refused, naming the object.
    g.world_from_object[2] = [0.0; 4];
    let e = decode_object("flat", &g.block, &g.world_from_object, 1.0).unwrap_err().to_string();
    assert!(e.contains("flat") && e.contains("inverted"), "{e}");
}

/// A player decodes each frame into the last frame's objects: what it gets
/// is what a fresh decode gets, whatever the lists held before (another
/// object, larger, with UVs, tangents, another material, a mirrored
/// transform's turned winding).
#[test]
fn decoding_into_used_objects_equals_a_fresh_decode() {
    use holo::holoflick::objects::{decode_block, decode_block_into, to_world, to_world_into};
    let big = surface(5, 20);
    let small = surface(6, 7);
    let (big_g, _) = encode_object(1, &big, &EncodeOptions::default()).unwrap();
    let (small_g, _) = encode_object(2, &small, &EncodeOptions::default()).unwrap();
    let mut mirrored = big_g.world_from_object;
    mirrored[0] = mirrored[0].map(|x| -x);
    // Used lists: the big object decoded and placed mirrored, with UVs and tangents added.
    let mut local = decode_block("big", &big_g.block).unwrap().0;
    let mut world = to_world(&local, &mirrored, 2.0).unwrap();
    for o in [&mut local, &mut world] {
        o.uv_sets = vec![vec![[0.5, 0.5]; o.positions.len()]];
        o.tangents = vec![[1.0, 0.0, 0.0, 1.0]; o.positions.len()];
        o.material.shininess = 77.0;
    }
    let skipped = decode_block_into("small", &small_g.block, &mut local).unwrap();
    to_world_into(&local, &small_g.world_from_object, small_g.radiance_scale, &mut world).unwrap();
    let (fresh_local, fresh_skipped) = decode_block("small", &small_g.block).unwrap();
    let fresh_world = to_world(&fresh_local, &small_g.world_from_object, small_g.radiance_scale).unwrap();
    assert_eq!(skipped, fresh_skipped);
    assert_eq!(local, fresh_local);
    assert_eq!(world, fresh_world);
    assert!(world.uv_sets.is_empty() && world.tangents.is_empty() && world.material.shininess != 77.0);
    assert!(world.triangles.len() < big.triangles.len());
}
