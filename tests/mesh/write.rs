//! Meshes written as `.glb` and `.ply` read back through the loaders (the
//! `gltf` crate validates the glTF): the same vertices, normals, colours
//! (PLY: to 8-bit sRGB) and triangles, on random meshes.

use holo::mesh::load::SceneSource;
use holo::mesh::write::write_mesh;
use holo::mesh::Object;
use rand::{Rng, SeedableRng};

fn random_object(seed: u64, name: &str, vertices: usize, triangles: usize) -> Object {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let positions: Vec<[f64; 3]> =
        (0..vertices).map(|_| [rng.gen_range(-2.0..2.0), rng.gen_range(-1.0..1.0), rng.gen_range(-0.5..0.5)]).collect();
    let normals = (0..vertices)
        .map(|_| {
            let n: [f32; 3] = [rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen_range(0.1..1.0)];
            let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            n.map(|x| x / l)
        })
        .collect();
    let colours = (0..vertices).map(|_| [rng.gen(), rng.gen(), rng.gen(), rng.gen_range(0.5..1.0)]).collect();
    let mut tris = Vec::new();
    while tris.len() < triangles {
        let t =
            [rng.gen_range(0..vertices as u32), rng.gen_range(0..vertices as u32), rng.gen_range(0..vertices as u32)];
        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
            tris.push(t);
        }
    }
    Object { name: name.into(), positions, normals, colours, triangles: tris, ..Object::default() }
}

#[test]
fn glb_and_ply_read_back_through_the_loaders() {
    let dir = tempfile::tempdir().unwrap();
    let objects = vec![random_object(1, "first", 60, 90), random_object(2, "second", 25, 30)];
    for ext in ["glb", "ply"] {
        let path = dir.path().join(format!("mesh.{ext}"));
        write_mesh(&path, &objects, false).unwrap();
        let scene = SceneSource::open(&path).unwrap().scene_at(0.0).unwrap();
        // PLY holds one list: compare against the objects concatenated.
        let expected: Vec<&Object> = objects.iter().collect();
        let got: Vec<&Object> = scene.objects.iter().collect();
        let flatten = |list: &[&Object]| {
            let mut all = Object::default();
            for o in list {
                let first = all.positions.len() as u32;
                all.positions.extend(&o.positions);
                all.normals.extend(&o.normals);
                all.colours.extend(&o.colours);
                all.triangles.extend(o.triangles.iter().map(|t| t.map(|i| i + first)));
            }
            all
        };
        let (want, have) = (flatten(&expected), flatten(&got));
        assert_eq!(have.positions.len(), want.positions.len(), "{ext}");
        assert_eq!(have.triangles, want.triangles, "{ext}");
        for (a, b) in have.positions.iter().zip(&want.positions) {
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-6 * y.abs().max(1.0)), "{ext}: {a:?} vs {b:?}");
        }
        for (a, b) in have.normals.iter().zip(&want.normals) {
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6), "{ext}: normal {a:?} vs {b:?}");
        }
        // glTF stores linear floats; PLY 8-bit sRGB (half a step: < 0.5/255 in sRGB, less in linear except near 1).
        let tolerance = if ext == "glb" { 1e-7 } else { 0.5 / 255.0 * 2.5 };
        for (a, b) in have.colours.iter().zip(&want.colours) {
            assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tolerance), "{ext}: colour {a:?} vs {b:?}");
        }
        if ext == "glb" {
            assert_eq!(scene.objects.len(), 2);
            assert_eq!(scene.objects[1].name, "second");
        }
    }
}

#[test]
fn bad_meshes_and_existing_files_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut o = random_object(3, "broken", 10, 5);
    o.triangles.push([0, 1, 10]);
    let e = write_mesh(&dir.path().join("a.glb"), &[o], false).unwrap_err().to_string();
    assert!(e.contains("broken") && e.contains("past the 10"), "{e}");
    let mut o = random_object(4, "short", 10, 5);
    o.colours.pop();
    let e = write_mesh(&dir.path().join("a.ply"), &[o], false).unwrap_err().to_string();
    assert!(e.contains("short") && e.contains("9 colours"), "{e}");
    let e = write_mesh(&dir.path().join("a.stl"), &[random_object(5, "x", 4, 2)], false).unwrap_err().to_string();
    assert!(e.contains(".glb or .ply"), "{e}");
    let kept = dir.path().join("kept.ply");
    std::fs::write(&kept, b"mine").unwrap();
    assert!(write_mesh(&kept, &[random_object(6, "x", 4, 2)], false).is_err());
    assert_eq!(std::fs::read(&kept).unwrap(), b"mine");
    write_mesh(&kept, &[random_object(6, "x", 4, 2)], true).unwrap();
    assert!(std::fs::read(&kept).unwrap().starts_with(b"ply\n"));
}
