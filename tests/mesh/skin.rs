//! glTF skinning (glTF 2.0 §3.7.3) against linear-blend skinning written
//! here in f64 from the spec: a strip of ten vertices bound to two joints,
//! the second joint turned by an animation, the influences split over two
//! JOINTS/WEIGHTS sets and some of them not normalised.

use std::path::Path;

use holo::mesh::load::SceneSource;

/// Key times (s) and the second joint's rotation about x, degrees.
const KEYS: [(f32, f64); 3] = [(0.0, 0.0), (1.0, 40.0), (2.0, -25.0)];

/// The unit quaternion (x, y, z, w) of a turn about x.
fn quaternion_x(deg: f64) -> [f64; 4] {
    let h = deg.to_radians() / 2.0;
    [h.sin(), 0.0, 0.0, h.cos()]
}

/// The strip's vertices: x in {0, 1}, y = 0, 0.5, …, 2.
fn vertices() -> Vec<[f64; 3]> {
    (0..10).map(|i| [(i % 2) as f64, (i / 2) as f64 * 0.5, 0.0]).collect()
}

/// Vertex `i`'s weight on joint 1 (the upper joint): 0 at the bottom, 1 at
/// the top; the two weights are stored doubled on the middle rows (their
/// sum 2, which a reader divides away).
fn weights(i: usize) -> (f64, f64, f64) {
    let upper = ((i / 2) as f64 / 4.0).clamp(0.0, 1.0);
    let scale = if (2..8).contains(&i) { 2.0 } else { 1.0 };
    (scale * (1.0 - upper), scale * upper, scale)
}

fn f32s(out: &mut Vec<u8>, values: impl IntoIterator<Item = f64>) {
    for v in values {
        out.extend_from_slice(&(v as f32).to_le_bytes());
    }
}

/// Write the skinned strip as `skin.gltf` + `skin.bin` in `dir`.
fn write_strip(dir: &Path) -> std::path::PathBuf {
    let mut bin = Vec::new();
    // 0: positions (120 bytes)
    f32s(&mut bin, vertices().into_iter().flatten());
    // 120: normals (120)
    f32s(&mut bin, (0..10).flat_map(|_| [0.0, 0.0, 1.0]));
    // 240: JOINTS_0 u16 (80): joint 0 in the first slot; JOINTS_1 (80): joint 1.
    for j in [0u16, 1] {
        for _ in 0..10 {
            for k in [j, 0, 0, 0] {
                bin.extend_from_slice(&k.to_le_bytes());
            }
        }
    }
    // 400: WEIGHTS_0 (160), 560: WEIGHTS_1 (160).
    f32s(&mut bin, (0..10).flat_map(|i| [weights(i).0, 0.0, 0.0, 0.0]));
    f32s(&mut bin, (0..10).flat_map(|i| [weights(i).1, 0.0, 0.0, 0.0]));
    // 720: indices u16, 8 triangles (48).
    for q in 0..4u16 {
        let a = 2 * q;
        for k in [a, a + 1, a + 3, a, a + 3, a + 2] {
            bin.extend_from_slice(&k.to_le_bytes());
        }
    }
    // 768: inverse bind matrices, column-major (128): identity, and a
    // translation by −1 in y (the second joint sits at y = 1).
    f32s(&mut bin, [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1.]);
    f32s(&mut bin, [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0., 0., -1., 0., 1.]);
    // 896: key times (12), 908: rotations (48).
    f32s(&mut bin, KEYS.iter().map(|k| k.0 as f64));
    f32s(&mut bin, KEYS.iter().flat_map(|k| quaternion_x(k.1)));
    assert_eq!(bin.len(), 956);
    std::fs::write(dir.join("skin.bin"), &bin).unwrap();
    let view =
        |offset: usize, length: usize| format!(r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {length}}}"#);
    let views = [
        view(0, 120),
        view(120, 120),
        view(240, 80),
        view(320, 80),
        view(400, 160),
        view(560, 160),
        view(720, 48),
        view(768, 128),
        view(896, 12),
        view(908, 48),
    ]
    .join(",\n");
    let gltf = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [
    {{"mesh": 0, "skin": 0, "translation": [5, 5, 5]}},
    {{"children": [2]}},
    {{"translation": [0, 1, 0]}}
  ],
  "skins": [{{"joints": [1, 2], "inverseBindMatrices": 7}}],
  "meshes": [{{"primitives": [{{
    "attributes": {{"POSITION": 0, "NORMAL": 1, "JOINTS_0": 2, "JOINTS_1": 3, "WEIGHTS_0": 4, "WEIGHTS_1": 5}},
    "indices": 6
  }}]}}],
  "animations": [{{
    "channels": [{{"sampler": 0, "target": {{"node": 2, "path": "rotation"}}}}],
    "samplers": [{{"input": 8, "output": 9, "interpolation": "LINEAR"}}]
  }}],
  "buffers": [{{"uri": "skin.bin", "byteLength": 956}}],
  "bufferViews": [{views}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 10, "type": "VEC3", "min": [0, 0, 0], "max": [1, 2, 0]}},
    {{"bufferView": 1, "componentType": 5126, "count": 10, "type": "VEC3"}},
    {{"bufferView": 2, "componentType": 5123, "count": 10, "type": "VEC4"}},
    {{"bufferView": 3, "componentType": 5123, "count": 10, "type": "VEC4"}},
    {{"bufferView": 4, "componentType": 5126, "count": 10, "type": "VEC4"}},
    {{"bufferView": 5, "componentType": 5126, "count": 10, "type": "VEC4"}},
    {{"bufferView": 6, "componentType": 5123, "count": 24, "type": "SCALAR"}},
    {{"bufferView": 7, "componentType": 5126, "count": 2, "type": "MAT4"}},
    {{"bufferView": 8, "componentType": 5126, "count": 3, "type": "SCALAR", "min": [0], "max": [2]}},
    {{"bufferView": 9, "componentType": 5126, "count": 3, "type": "VEC4"}}
  ]
}}"#
    );
    let path = dir.join("skin.gltf");
    std::fs::write(&path, gltf).unwrap();
    path
}

/// The spec's skinning, here in f64: joint 0 stays at the origin, joint 1
/// is at y = 1 turned by `deg` about x; with the inverse bind matrices its
/// joint matrix turns the strip about the line y = 1, z = 0. A vertex goes
/// to the weighted sum of its joints' images (weights over their sum); the
/// mesh node's own translation is ignored. Normals: the inverse transpose of
/// the blended matrix.
fn reference(deg: f64) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let (s, c) = deg.to_radians().sin_cos();
    let turn = |p: [f64; 3]| [p[0], 1.0 + c * (p[1] - 1.0) - s * p[2], s * (p[1] - 1.0) + c * p[2]];
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    for (i, p) in vertices().into_iter().enumerate() {
        let (w0, w1, sum) = weights(i);
        let (w0, w1) = (w0 / sum, w1 / sum);
        let q = turn(p);
        positions.push([0, 1, 2].map(|k| w0 * p[k] + w1 * q[k]));
        // The blended linear part is [[1, 0, 0], [0, a, −b], [0, b, a]] with
        // a = w0 + w1 c, b = w1 s; its inverse transpose is itself over
        // a² + b², so the normal (0, 0, 1) goes to (0, −b, a), normalised.
        let (a, b) = (w0 + w1 * c, w1 * s);
        let len = (a * a + b * b).sqrt();
        normals.push([0.0, -b / len, a / len]);
    }
    (positions, normals)
}

#[test]
fn skinned_frames_follow_the_joints_as_the_spec_skins_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_strip(dir.path());
    let source = SceneSource::open(&path).unwrap();
    let mut previous: Option<Vec<[f64; 3]>> = None;
    for (t, deg) in KEYS {
        let scene = source.scene_at(t as f64).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        let o = &scene.objects[0];
        let (want, want_normals) = reference(deg);
        assert_eq!(o.positions.len(), want.len());
        for (i, (got, want)) in o.positions.iter().zip(&want).enumerate() {
            for k in 0..3 {
                // The file holds f32 (positions, weights, matrices).
                assert!((got[k] - want[k]).abs() < 1e-6, "t = {t} vertex {i}: {got:?} against {want:?}");
            }
        }
        for (got, want) in o.normals.iter().zip(&want_normals) {
            assert!((0..3).all(|k| (f64::from(got[k]) - want[k]).abs() < 1e-6), "{got:?}");
        }
        if let Some(p) = &previous {
            assert!(p != &o.positions, "t = {t}: the frame is the previous frame again");
        }
        previous = Some(o.positions.clone());
    }
}

/// A joint index past the skin's joints is an error naming the file.
#[test]
fn a_vertex_bound_to_a_missing_joint_is_an_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = write_strip(dir.path());
    let text = std::fs::read_to_string(&path).unwrap().replace(r#""joints": [1, 2]"#, r#""joints": [1]"#);
    // One joint left: its inverse bind matrices must shrink to match.
    let text = text.replace(r#""count": 2, "type": "MAT4""#, r#""count": 1, "type": "MAT4""#);
    std::fs::write(&path, text).unwrap();
    let e = SceneSource::open(&path).and_then(|s| s.scene_at(0.0)).unwrap_err().to_string();
    assert!(e.contains("skin.gltf") && e.contains("joint 1") && e.contains("lists 1 joint"), "{e}");
}

/// A skinned animation as Blender's own glTF exporter writes it (a tube
/// bound to three bones with automatic weights, bent over 25 frames;
/// `tests/peer/blender/skinned_tube.py`): at each sampled frame every vertex
/// holo poses lies where Blender's armature deform put it, and every vertex
/// Blender deformed has a posed vertex there (the exporter splits vertices
/// at seams, so the two are matched by place).
#[test]
fn a_blender_export_is_skinned_as_blender_deforms_it() {
    let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh");
    let poses: serde_json::Value =
        serde_json::from_slice(&std::fs::read(fixtures.join("skinned_tube.poses.json")).unwrap()).unwrap();
    let fps = poses["fps"].as_f64().unwrap();
    let source = SceneSource::open(&fixtures.join("skinned_tube.glb")).unwrap();
    let nearest = |p: &[f64; 3], among: &[[f64; 3]]| {
        among.iter().map(|q| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>().sqrt()).fold(f64::INFINITY, f64::min)
    };
    let mut previous: Option<Vec<[f64; 3]>> = None;
    for frame in poses["frames"].as_array().unwrap() {
        let number = frame["frame"].as_f64().unwrap();
        let blender: Vec<[f64; 3]> = frame["positions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| std::array::from_fn(|k| p[k].as_f64().unwrap()))
            .collect();
        // Blender's exporter keys frame n at n / fps seconds.
        let scene = source.scene_at(number / fps).unwrap();
        assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
        let posed: Vec<[f64; 3]> = scene.objects.iter().flat_map(|o| o.positions.iter().copied()).collect();
        let worst_blender = blender.iter().map(|p| nearest(p, &posed)).fold(0.0, f64::max);
        let worst_holo = posed.iter().map(|p| nearest(p, &blender)).fold(0.0, f64::max);
        println!("frame {number}: {} vertices posed, {} from Blender; farthest apart {worst_blender:.2e} / {worst_holo:.2e} m", posed.len(), blender.len());
        // f32 in the file and in Blender: micrometres on a 2 m tube.
        assert!(worst_blender < 1e-5 && worst_holo < 1e-5, "frame {number}: {worst_blender} / {worst_holo}");
        if let Some(p) = &previous {
            assert!(p != &posed, "frame {number}: the same pose again");
        }
        previous = Some(posed);
    }
}
