//! Smooth normals by angle for objects that have none.

use holo::math::{cross, dot, sub, unit};
use holo::mesh::load::SceneSource;
use holo::mesh::normals::smooth_normals;
use holo::mesh::Object;

use crate::common::shared_data;

/// A UV sphere of radius 1: `rings` × `segments` quads, poles fanned, the
/// seam's vertices shared.
fn sphere(rings: u32, segments: u32) -> Object {
    let mut positions = vec![[0.0, 0.0, 1.0]];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = 2.0 * std::f64::consts::PI * s as f64 / segments as f64;
            positions.push([theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()]);
        }
    }
    positions.push([0.0, 0.0, -1.0]);
    let south = positions.len() as u32 - 1;
    let at = |r: u32, s: u32| 1 + (r - 1) * segments + s % segments;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, at(1, s), at(1, s + 1)]);
        triangles.push([south, at(rings - 1, s + 1), at(rings - 1, s)]);
        for r in 1..rings - 1 {
            triangles.push([at(r, s), at(r + 1, s), at(r + 1, s + 1)]);
            triangles.push([at(r, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
    }
    Object { name: "sphere".into(), positions, triangles, ..Object::default() }
}

#[test]
fn a_sphere_gets_its_radial_normals_and_a_cube_keeps_its_edges() {
    let mut s = sphere(24, 48);
    let before = s.positions.len();
    assert!(smooth_normals(&mut s, 30.0));
    // Neighbouring facets are 7.5° apart: nothing is split, and each normal is
    // the radius within the facets' angle.
    assert_eq!(s.positions.len(), before);
    for (p, n) in s.positions.iter().zip(&s.normals) {
        let n = n.map(f64::from);
        assert!(dot(*p, n) > (4.0f64).to_radians().cos(), "{p:?}: {n:?}");
    }
    // Already has normals: left alone.
    assert!(!smooth_normals(&mut s, 30.0));

    // A cube's faces meet at 90°: at 30° every corner keeps its face's normal
    // (4 vertices per face); at 180° the corners are shared and point outwards.
    let cube = || {
        let positions: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64 * 2.0 - 1.0, (i >> 1 & 1) as f64 * 2.0 - 1.0, (i >> 2) as f64 * 2.0 - 1.0])
            .collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        Object { name: "cube".into(), positions, triangles, ..Object::default() }
    };
    let mut sharp = cube();
    smooth_normals(&mut sharp, 30.0);
    assert_eq!(sharp.positions.len(), 24);
    for t in &sharp.triangles {
        let p = t.map(|i| sharp.positions[i as usize]);
        let face = unit(cross(sub(p[1], p[0]), sub(p[2], p[0]))).unwrap();
        for &i in t {
            assert_eq!(sharp.normals[i as usize].map(f64::from), face);
        }
    }
    let mut round = cube();
    smooth_normals(&mut round, 180.0);
    assert_eq!(round.positions.len(), 8);
    for (p, n) in round.positions.iter().zip(&round.normals) {
        assert!(dot(*p, n.map(f64::from)) > 0.0, "{p:?} {n:?}");
    }
}

/// The real teapot (an OBJ without normals): every corner's smooth normal is
/// within the threshold of its own face's normal, and the object is no
/// longer flat.
#[test]
fn the_teapot_is_smoothed_within_its_threshold() {
    let Some(d) = shared_data() else { return };
    let path = std::fs::read_dir(d.join("mesh_utah_teapot"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "obj"))
        .expect("the teapot OBJ");
    let scene = SceneSource::open(&path).unwrap().scene_at(0.0).unwrap();
    for mut o in scene.objects {
        assert!(o.normals.is_empty(), "the teapot has no normals of its own");
        assert!(smooth_normals(&mut o, 30.0));
        let mut smoothed = 0;
        for t in &o.triangles {
            let p = t.map(|i| o.positions[i as usize]);
            let Some(face) = unit(cross(sub(p[1], p[0]), sub(p[2], p[0]))) else { continue };
            for &i in t {
                let n = o.normals[i as usize].map(f64::from);
                assert!(dot(n, face) >= 30f64.to_radians().cos() - 1e-6, "{n:?} against {face:?}");
                smoothed += usize::from(dot(n, face) < 1.0 - 1e-9);
            }
        }
        assert!(smoothed > o.triangles.len(), "{smoothed} corners differ from their face");
    }
}
