//! Scene loaders (glTF, OBJ + MTL, PLY) on real files from `../shared/data`
//! and on small files written here, good and bad.

use std::path::{Path, PathBuf};

use holo::mesh::load::{LoadLimits, SceneSource};
use holo::mesh::Scene;

use crate::common;
use common::shared_data;

/// The shared test data folder, or `None` (after saying so) when absent.
fn data_dir() -> Option<PathBuf> {
    let d = shared_data();
    if d.is_none() {
        println!("SKIPPED: ../shared/data not present");
    }
    d
}

/// For tests that run on their own files and add shared ones when present.
fn data_dir_for_extra() -> Option<PathBuf> {
    let d = shared_data();
    if d.is_none() {
        println!("PARTLY SKIPPED: ../shared/data not present; only the files written here were tried");
    }
    d
}

macro_rules! data {
    () => {
        match data_dir() {
            Some(d) => d,
            None => return,
        }
    };
}

fn load(p: &Path) -> holo::Result<Scene> {
    SceneSource::open(p)?.scene_at(0.0)
}

fn load_ok(p: &Path) -> Scene {
    match load(p) {
        Ok(s) => {
            for w in &s.warnings {
                println!("warning: {w}");
            }
            s
        }
        Err(e) => panic!("{} did not load: {e}", p.display()),
    }
}

fn err_of(p: &Path) -> String {
    match load(p) {
        Ok(_) => panic!("{} loaded but should not", p.display()),
        Err(e) => {
            println!("error as expected: {e}");
            e.to_string()
        }
    }
}

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/mesh")).join(name)
}

fn len3(v: [f32; 3]) -> f32 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

// ---------------------------------------------------------------- glTF

#[test]
fn box_textured_same_in_all_three_packagings() {
    let d = data!().join("gltf_khronos_BoxTextured");
    let scenes: Vec<Scene> = ["glTF/BoxTextured.gltf", "glTF-Binary/BoxTextured.glb", "glTF-Embedded/BoxTextured.gltf"]
        .iter()
        .map(|f| load_ok(&d.join(f)))
        .collect();
    for s in &scenes {
        assert_eq!(s.objects.len(), 1);
        let o = &s.objects[0];
        assert_eq!(o.positions.len(), 24);
        assert_eq!(o.triangles.len(), 12);
        assert_eq!(o.normals.len(), 24);
        assert_eq!(o.uv_sets.len(), 1);
        assert_eq!(s.textures.len(), 1);
        let t = &s.textures[0];
        assert!(t.width > 0 && t.height > 0);
        assert_eq!(t.texels.len(), t.width * t.height);
        let r = o.material.base_colour_texture.as_ref().expect("base colour texture");
        assert_eq!(r.texture, 0);
        for n in &o.normals {
            assert!((len3(*n) - 1.0).abs() < 1e-5);
        }
    }
    for s in &scenes[1..] {
        assert_eq!(s.objects[0].positions, scenes[0].objects[0].positions);
        assert_eq!(s.objects[0].triangles, scenes[0].objects[0].triangles);
        assert_eq!(s.textures[0].texels, scenes[0].textures[0].texels);
    }
    let src = SceneSource::open(&d.join("glTF/BoxTextured.gltf")).unwrap();
    assert_eq!(src.animation_duration_s(), None);
    assert!(src.scene_at(f64::NAN).unwrap_err().to_string().contains("BoxTextured.gltf"));
}

#[test]
fn box_vertex_colors_colours_and_hierarchy() {
    let d = data!().join("gltf_khronos_BoxVertexColors");
    for f in ["glTF/BoxVertexColors.gltf", "glTF-Binary/BoxVertexColors.glb", "glTF-Embedded/BoxVertexColors.gltf"] {
        let s = load_ok(&d.join(f));
        // Nodes RootNode > {Mesh, Cube, Texture Group}: one object, named after its node.
        assert_eq!(s.objects.len(), 1, "{f}");
        let o = &s.objects[0];
        assert_eq!(o.name, "Cube");
        assert_eq!(o.colours.len(), o.positions.len());
        assert!(o.colours.iter().all(|c| c.iter().all(|x| (0.0..=1.0).contains(x))));
        // Not all one colour.
        assert!(o.colours.iter().any(|c| c != &o.colours[0]));
        assert_eq!(o.triangles.len(), 12);
    }
}

#[test]
fn simple_meshes_one_mesh_two_nodes() {
    let d = data!().join("gltf_khronos_SimpleMeshes");
    for f in ["glTF/SimpleMeshes.gltf", "glTF-Binary/SimpleMeshes.glb", "glTF-Embedded/SimpleMeshes.gltf"] {
        let s = load_ok(&d.join(f));
        assert_eq!(s.objects.len(), 2, "{f}");
        let (a, b) = (&s.objects[0], &s.objects[1]);
        assert_eq!(a.triangles, b.triangles);
        assert_eq!(a.positions.len(), b.positions.len());
        // Node 1 is translated by (1, 0, 0).
        for (p, q) in a.positions.iter().zip(&b.positions) {
            assert!((q[0] - p[0] - 1.0).abs() < 1e-9 && (q[1] - p[1]).abs() < 1e-9 && (q[2] - p[2]).abs() < 1e-9);
        }
        assert_eq!(a.material.name, "default");
    }
}

/// Read `count` little-endian f32 vectors of `n` components of accessor `acc`.
fn accessor_f32(json: &serde_json::Value, bin: &[u8], acc: usize, n: usize) -> Vec<Vec<f32>> {
    let a = &json["accessors"][acc];
    let v = &json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let off = v["byteOffset"].as_u64().unwrap_or(0) as usize + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let stride = v["byteStride"].as_u64().map(|s| s as usize).unwrap_or(4 * n);
    (0..a["count"].as_u64().unwrap() as usize)
        .map(|i| {
            (0..n)
                .map(|c| {
                    let o = off + i * stride + 4 * c;
                    f32::from_le_bytes(bin[o..o + 4].try_into().unwrap())
                })
                .collect()
        })
        .collect()
}

fn rotate(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let [x, y, z, w] = q;
    let u = [x, y, z];
    let cross =
        |a: [f64; 3], b: [f64; 3]| [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    let t = cross(u, v).map(|c| 2.0 * c);
    let ut = cross(u, t);
    [v[0] + w * t[0] + ut[0], v[1] + w * t[1] + ut[1], v[2] + w * t[2] + ut[2]]
}

#[test]
fn animated_morph_cube_follows_its_weights() {
    let d = data!().join("gltf_khronos_AnimatedMorphCube/glTF");
    let src = SceneSource::open(&d.join("AnimatedMorphCube.gltf")).unwrap();
    let dur = src.animation_duration_s().expect("animated");
    assert!(dur > 4.0 && dur < 4.3, "duration {dur}");

    // Expected positions from the file itself: base + Σ wᵢ·dᵢ, then the
    // node's rotation and scale (100).
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("AnimatedMorphCube.gltf")).unwrap()).unwrap();
    let bin = std::fs::read(d.join("AnimatedMorphCube.bin")).unwrap();
    let base = accessor_f32(&json, &bin, 2, 3);
    let d0 = accessor_f32(&json, &bin, 4, 3);
    let d1 = accessor_f32(&json, &bin, 7, 3);
    let times = accessor_f32(&json, &bin, 10, 1);
    let weights = accessor_f32(&json, &bin, 11, 1);
    // The node's rotation, as the file gives it (about (0, 0.7071067, −0.7071068, 0)).
    let q: [f64; 4] = std::array::from_fn(|k| json["nodes"][0]["rotation"][k].as_f64().unwrap());
    let qn = {
        let l: f64 = q.iter().map(|x: &f64| x * x).sum::<f64>().sqrt();
        q.map(|x| x / l)
    };
    let mut differ = false;
    let first = src.scene_at(times[0][0] as f64).unwrap();
    for k in [0usize, 30, 63, 100] {
        let t = times[k][0] as f64;
        let (w0, w1) = (weights[2 * k][0] as f64, weights[2 * k + 1][0] as f64);
        let s = src.scene_at(t).unwrap();
        assert_eq!(s.objects.len(), 1);
        let o = &s.objects[0];
        assert_eq!(o.positions.len(), 24);
        for i in 0..24 {
            let local = [0, 1, 2].map(|c| (base[i][c] as f64 + w0 * d0[i][c] as f64 + w1 * d1[i][c] as f64) * 100.0);
            let e = rotate(qn, local);
            for c in 0..3 {
                assert!((o.positions[i][c] - e[c]).abs() < 1e-3, "t {t} vertex {i}: {:?} vs {e:?}", o.positions[i]);
            }
        }
        if o.positions != first.objects[0].positions {
            differ = true;
        }
    }
    assert!(differ, "the morph animation must move vertices");
    // Between keys the weights are interpolated linearly.
    let (ta, tb) = (times[30][0] as f64, times[31][0] as f64);
    let mid = src.scene_at(0.5 * (ta + tb)).unwrap();
    let (a, b) = (src.scene_at(ta).unwrap(), src.scene_at(tb).unwrap());
    for i in 0..24 {
        for c in 0..3 {
            let m = 0.5 * (a.objects[0].positions[i][c] + b.objects[0].positions[i][c]);
            assert!((mid.objects[0].positions[i][c] - m).abs() < 1e-3);
        }
    }
    // The .glb gives the same pose.
    let glb =
        SceneSource::open(&data!().join("gltf_khronos_AnimatedMorphCube/glTF-Binary/AnimatedMorphCube.glb")).unwrap();
    let g = glb.scene_at(ta).unwrap();
    assert_eq!(g.objects[0].positions, a.objects[0].positions);
}

#[test]
fn clearcoat_normal_maps_and_generated_tangents() {
    let d = data!().join("gltf_khronos_ClearCoatTest_normalmaps/glTF");
    let s = load_ok(&d.join("ClearCoatTest.gltf"));
    let n = s.triangle_count();
    assert!((30_000..45_000).contains(&n), "{n} triangles");
    let mapped: Vec<_> = s.objects.iter().filter(|o| o.material.normal_texture.is_some()).collect();
    assert!(!mapped.is_empty(), "some objects have normal maps");
    for o in &mapped {
        assert_eq!(o.tangents.len(), o.positions.len(), "object {} has tangents", o.name);
        for (t, nr) in o.tangents.iter().zip(&o.normals) {
            let tv = [t[0], t[1], t[2]];
            assert!((len3(tv) - 1.0).abs() < 1e-4, "unit tangent in {}", o.name);
            let dot = tv[0] * nr[0] + tv[1] * nr[1] + tv[2] * nr[2];
            assert!(dot.abs() < 1e-3, "tangent orthogonal to normal in {}: {dot}", o.name);
            assert!(t[3] == 1.0 || t[3] == -1.0);
        }
    }
    // Normal maps are linear, not sRGB-decoded: a flat normal texel stays near 0.5.
    for o in &mapped {
        let t = &s.textures[o.material.normal_texture.as_ref().unwrap().texture];
        let mean: f32 = t.texels.iter().map(|x| x[2]).sum::<f32>() / t.texels.len() as f32;
        assert!(mean > 0.5, "blue of a normal map in {} is {mean}", t.name);
    }
}

#[test]
fn cameras_scene_loads() {
    let d = data!().join("gltf_khronos_Cameras/glTF");
    let s = load_ok(&d.join("Cameras.gltf"));
    assert_eq!(s.objects.len(), 1);
    assert!(s.triangle_count() >= 2);
    assert!(s.objects[0].normals.is_empty(), "no NORMAL: flat shading");
}

// ---------------------------------------------------------------- OBJ

#[test]
fn obj_spot_triangles_and_quads() {
    let d = data!().join("mesh_spot_textured_obj");
    let tri = load_ok(&d.join("spot_triangulated.obj"));
    let quad = load_ok(&d.join("spot_quadrangulated.obj"));
    for s in [&tri, &quad] {
        assert_eq!(s.objects.len(), 1);
        let o = &s.objects[0];
        assert_eq!(o.uv_sets.len(), 1);
        assert!(o.uv_sets[0].iter().all(|uv| uv[0].is_finite() && uv[1].is_finite()));
        assert!(o.normals.is_empty());
        assert!(o.material.base_colour_texture.is_none(), "the OBJ names no material");
    }
    assert_eq!(tri.triangle_count(), 5856);
    assert_eq!(quad.triangle_count(), 2 * 2928);
    let (a, b) = (tri.bounds().unwrap(), quad.bounds().unwrap());
    for k in 0..3 {
        assert!((a.0[k] - b.0[k]).abs() < 1e-6 && (a.1[k] - b.1[k]).abs() < 1e-6);
    }
}

#[test]
fn obj_teapot_without_normals() {
    let d = data!().join("mesh_utah_teapot");
    let s = load_ok(&d.join("teapot.obj"));
    assert_eq!(s.objects.len(), 1);
    assert!(s.objects[0].normals.is_empty());
    assert!(s.objects[0].uv_sets.is_empty());
    let n = s.triangle_count();
    assert!(n > 6000 && n <= 6320, "{n}");
    if n < 6320 {
        assert!(s.warnings.iter().any(|w| w.contains("zero area")), "{:?}", s.warnings);
    }
}

#[test]
fn obj_cube_vertex_colours() {
    let d = data!().join("mesh_cube_obj_vertexcolors");
    let s = load_ok(&d.join("cube_with_vertexcolors.obj"));
    assert_eq!(s.objects.len(), 1);
    let o = &s.objects[0];
    assert_eq!(o.name, "cube");
    assert_eq!(o.triangles.len(), 12);
    assert_eq!(o.colours.len(), o.positions.len());
    assert_eq!(o.normals.len(), o.positions.len());
    // Corner (0,0,0) has the colour 0.48627 0.43137 0.47059, taken as linear.
    let i = o.positions.iter().position(|p| *p == [0.0, 0.0, 0.0]).unwrap();
    assert!((o.colours[i][0] - 0.48627).abs() < 1e-6 && (o.colours[i][1] - 0.43137).abs() < 1e-6);
    assert_eq!(o.colours[i][3], 1.0);
}

fn write_png(path: &Path, w: u32, h: u32) {
    let samples = common::pixels(w, h, |x, y| [(x * 60) as u8, (y * 60) as u8, 128, 255]);
    std::fs::write(path, common::png8(w, h, 4, &samples)).unwrap();
}

#[test]
fn obj_groups_materials_and_a_windows_texture_path() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("Textures")).unwrap();
    write_png(&dir.path().join("Textures/Wood.png"), 4, 2);
    std::fs::write(
        dir.path().join("Mats.mtl"),
        "# two materials\r\nnewmtl wood\r\nKd 0.5 0.25 1\r\nKs 0.1 0.1 0.1\r\nNs 50\r\nmap_Kd -s 2 2 1 -o 0.5 0 0 -bm 1 textures\\wood.PNG\r\n\r\nnewmtl glow\r\nKe 1 0 0\r\nd 0.5\r\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("scene.obj"),
        "mtllib mats.mtl\n\
         v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1 \\\n\n\
         vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n\
         vn 0 0 1\n\
         o first\nusemtl wood\nf 1/1/1 2/2/1 3/3/1 4/4/1\n\
         usemtl glow\nf -5//1 -4//1 -1//1 # relative\n\
         g second\nusemtl nosuch\nf 1 2 3\nf 1 2 2\n",
    )
    .unwrap();
    let s = load_ok(&dir.path().join("scene.obj"));
    assert_eq!(s.objects.len(), 3, "{:?}", s.objects.iter().map(|o| &o.name).collect::<Vec<_>>());
    let wood = &s.objects[0];
    assert_eq!(wood.name, "first (wood)");
    assert_eq!(wood.positions.len(), 4);
    assert_eq!(wood.triangles.len(), 2);
    assert_eq!(wood.material.base_colour, [0.5, 0.25, 1.0, 1.0]);
    assert_eq!(wood.material.shininess, 50.0);
    let r = wood.material.base_colour_texture.as_ref().expect("texture via textures\\wood.PNG");
    assert_eq!(s.textures[r.texture].width, 4);
    assert_eq!(r.transform.scale, [2.0, 2.0]);
    // OBJ (0,0) is our (0,1); with the MTL transform u' = 2u + 0.5, v' = 2v.
    assert_eq!(wood.uv_sets[0][0], [0.0, 1.0]);
    let t = r.transform.apply([0.0, 1.0]);
    assert!((t[0] - 0.5).abs() < 1e-6 && (t[1] - 1.0).abs() < 1e-6, "{t:?}");
    let glow = &s.objects[1];
    assert_eq!(glow.material.emissive, [1.0, 0.0, 0.0]);
    assert!(glow.positions.contains(&[0.0, 0.0, 1.0]));
    let second = &s.objects[2];
    assert_eq!(second.name, "second");
    assert_eq!(second.triangles.len(), 1, "the degenerate face is dropped");
    assert!(s.warnings.iter().any(|w| w.contains("nosuch")), "{:?}", s.warnings);
    assert!(s.warnings.iter().any(|w| w.contains("zero area") && w.contains("second")), "{:?}", s.warnings);
}

// ---------------------------------------------------------------- PLY

/// A quad and a triangle with normals, colours and UVs, plus properties
/// and elements the loader must read past.
fn ply_header(format: &str) -> String {
    format!(
        "ply\nformat {format} 1.0\ncomment made by the holo tests\ncomment TextureFile tex.png\n\
         element vertex 5\nproperty float x\nproperty double y\nproperty int z\nproperty float nx\nproperty float ny\nproperty float nz\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float quality\nproperty float u\nproperty float v\n\
         element face 2\nproperty list uchar int vertex_indices\nproperty list ushort float junk\nproperty short flags\n\
         element edge 1\nproperty list uint uint ends\nend_header\n"
    )
}

const PLY_VERTS: [([f32; 3], [u8; 3], [f32; 2]); 5] = [
    ([0.0, 0.0, 0.0], [255, 0, 0], [0.0, 0.0]),
    ([1.0, 0.0, 0.0], [0, 255, 0], [1.0, 0.0]),
    ([1.0, 1.0, 0.0], [0, 0, 255], [1.0, 1.0]),
    ([0.0, 1.0, 0.0], [128, 128, 128], [0.0, 1.0]),
    ([0.0, 0.0, 2.0], [10, 20, 30], [0.5, 0.5]),
];

fn write_ply(path: &Path, format: &str) {
    let mut out = ply_header(format).into_bytes();
    let faces: [&[i32]; 2] = [&[0, 1, 2, 3], &[0, 1, 4]];
    if format == "ascii" {
        let mut s = String::new();
        for (p, c, uv) in PLY_VERTS {
            s += &format!(
                "{} {} {} 0 0 1 {} {} {} 0.5 {} {}\r\n",
                p[0], p[1], p[2] as i32, c[0], c[1], c[2], uv[0], uv[1]
            );
        }
        for f in faces {
            s +=
                &format!("{} {} 2 1.5 2.5 7\n", f.len(), f.iter().map(|i| i.to_string()).collect::<Vec<_>>().join(" "));
        }
        s += "2 0 4\n";
        out.extend(s.into_bytes());
    } else {
        let be = format == "binary_big_endian";
        macro_rules! put {
            ($v:expr) => {
                if be {
                    out.extend_from_slice(&$v.to_be_bytes())
                } else {
                    out.extend_from_slice(&$v.to_le_bytes())
                }
            };
        }
        for (p, c, uv) in PLY_VERTS {
            put!(p[0]);
            put!(p[1] as f64);
            put!(p[2] as i32);
            put!(0.0f32);
            put!(0.0f32);
            put!(1.0f32);
            out.extend_from_slice(&c);
            put!(0.5f32);
            put!(uv[0]);
            put!(uv[1]);
        }
        for f in faces {
            out.push(f.len() as u8);
            for &i in f {
                put!(i);
            }
            put!(2u16);
            put!(1.5f32);
            put!(2.5f32);
            put!(7i16);
        }
        put!(2u32);
        put!(0u32);
        put!(4u32);
    }
    std::fs::write(path, out).unwrap();
}

/// A header as old exporters wrote them: a line of free text without the
/// `comment` keyword (Blender 2.4x), `obj_info`, CRLF line ends, in ASCII
/// and binary. It reads as the file without those lines does, with one
/// warning naming the free-text line; a malformed keyword line is still an
/// error.
#[test]
fn ply_headers_as_old_exporters_wrote_them_read_with_a_warning() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("tex.png"), 2, 2);
    let blender = "Created by Blender3D 247 - www.blender.org, source file: 'spot.blend'";
    for format in ["ascii", "binary_little_endian"] {
        let clean = dir.path().join(format!("clean-{format}.ply"));
        write_ply(&clean, format);
        let bytes = std::fs::read(&clean).unwrap();
        let split = bytes.windows(10).position(|w| w == b"end_header").unwrap();
        let header = std::str::from_utf8(&bytes[..split]).unwrap();
        let old_header = header
            .replacen("comment made by the holo tests\n", &format!("{blender}\nobj_info num_cols 2\n"), 1)
            .replace('\n', "\r\n");
        assert!(old_header.contains(blender));
        let old = dir.path().join(format!("old-{format}.ply"));
        std::fs::write(&old, [old_header.as_bytes(), &bytes[split..]].concat()).unwrap();
        let (want, got) = (load_ok(&clean), load_ok(&old));
        assert_eq!(got.objects[0].positions, want.objects[0].positions);
        assert_eq!(got.objects[0].triangles, want.objects[0].triangles);
        assert_eq!(got.objects[0].colours, want.objects[0].colours);
        let named: Vec<&String> = got.warnings.iter().filter(|w| w.contains(blender)).collect();
        assert_eq!(named.len(), 1, "{:?}", got.warnings);
        assert!(named[0].contains(&old.display().to_string()) && named[0].contains("header line 3"), "{}", named[0]);
        // A line that starts with a keyword but is malformed is not skipped.
        let broken = dir.path().join(format!("broken-{format}.ply"));
        std::fs::write(
            &broken,
            [old_header.replacen("element face 2", "element face", 1).as_bytes(), &bytes[split..]].concat(),
        )
        .unwrap();
        let e = load(&broken).unwrap_err().to_string();
        assert!(e.contains("broken-") && e.contains("element face"), "{e}");
    }
}

#[test]
fn ply_ascii_and_binary_load_identically() {
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("tex.png"), 2, 2);
    let mut scenes = Vec::new();
    for f in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let p = dir.path().join(format!("{f}.ply"));
        write_ply(&p, f);
        scenes.push(load_ok(&p));
    }
    let o = &scenes[0].objects[0];
    assert_eq!(o.name, "ascii");
    assert_eq!(o.positions.len(), 5);
    assert_eq!(o.triangles, vec![[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
    assert_eq!(o.positions[4], [0.0, 0.0, 2.0]);
    assert_eq!(o.normals[0], [0.0, 0.0, 1.0]);
    assert_eq!(o.colours[0], [1.0, 0.0, 0.0, 1.0]);
    // 128 is sRGB: about 0.216 linear.
    assert!((o.colours[3][0] - 0.2158605).abs() < 1e-4);
    // v flipped: PLY (0, 0) is our (0, 1).
    assert_eq!(o.uv_sets[0][0], [0.0, 1.0]);
    assert!(o.material.base_colour_texture.is_some());
    assert_eq!(scenes[0].textures.len(), 1);
    for s in &scenes[1..] {
        let b = &s.objects[0];
        assert_eq!(b.positions, o.positions);
        assert_eq!(b.triangles, o.triangles);
        assert_eq!(b.normals, o.normals);
        assert_eq!(b.colours, o.colours);
        assert_eq!(b.uv_sets, o.uv_sets);
    }
}

// ---------------------------------------------------------------- fixtures

#[test]
fn gltf_fixture_modes_lights_transforms() {
    let s = load_ok(&fixture("modes_lights.gltf"));
    let names: Vec<&str> = s.objects.iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["strip", "fan", "mirrored"], "{:?}", s.warnings);
    // The strip of 4 vertices gives 2 triangles, the fan of 5 gives 3.
    assert_eq!(s.objects[0].triangles.len(), 2);
    assert_eq!(s.objects[1].triangles.len(), 3);
    // Every triangle of the strip and the fan faces +z (counter-clockwise).
    for o in &s.objects {
        for t in &o.triangles {
            let [a, b, c] = t.map(|i| o.positions[i as usize]);
            let nz = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert!(nz > 0.0, "object {} triangle {t:?} is clockwise", o.name);
        }
    }
    // The mirrored node (scale x −1) has its winding reversed and normals still +z.
    let m = &s.objects[2];
    assert!(m.positions.iter().all(|p| p[0] <= 0.0));
    assert!(m.normals.iter().all(|n| (n[2] - 1.0).abs() < 1e-6));
    // The points primitive is skipped with a warning naming it.
    assert!(s.warnings.iter().any(|w| w.contains("dots") && w.contains("POINTS")), "{:?}", s.warnings);
    // Lights: a point light at its node, a directional one along the node's −z, a spot as point.
    use holo::mesh::Light;
    assert_eq!(s.lights.len(), 3);
    match &s.lights[0] {
        Light::Point { position, intensity, name } => {
            assert_eq!(*position, [1.0, 2.0, 3.0]);
            assert_eq!(*intensity, [10.0, 5.0, 0.0]);
            assert_eq!(name, "bulb");
        }
        other => panic!("{other:?}"),
    }
    match &s.lights[1] {
        Light::Directional { direction, .. } => {
            // Rotated 90° about x: −z becomes +y.
            assert!(
                (direction[1] - 1.0).abs() < 1e-6 && direction[0].abs() < 1e-6 && direction[2].abs() < 1e-6,
                "{direction:?}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(s.lights[2], Light::Point { .. }));
    assert!(s.warnings.iter().any(|w| w.contains("spot")));
}

#[test]
fn obj_fixture_loads() {
    let s = load_ok(&fixture("quad_and_triangle.obj"));
    assert_eq!(s.objects.len(), 2);
    assert_eq!(s.triangle_count(), 3);
}

// ---------------------------------------------------------------- bad inputs

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// A one-triangle glTF with an embedded buffer of `bytes` (base64) and an
/// accessor of `count` positions.
fn tiny_gltf(b64: &str, len: usize, count: usize, extra_material: &str) -> String {
    format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"name":"TriNode"}}],
        "meshes":[{{"name":"Tri","primitives":[{{"attributes":{{"POSITION":0}}{mat}}}]}}],
        "buffers":[{{"byteLength":{len},"uri":"data:application/octet-stream;base64,{b64}"}}],
        "bufferViews":[{{"buffer":0,"byteLength":{len}}}],
        "accessors":[{{"bufferView":0,"componentType":5126,"count":{count},"type":"VEC3"}}]{extra}}}"#,
        mat = if extra_material.is_empty() { "" } else { r#","material":0"# },
        extra = extra_material
    )
}

/// Base64 of three f32 positions (0,0,0) (1,0,0) (0,1,0).
const TRI_B64: &str = "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA";

#[test]
fn bad_inputs_give_clear_errors() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();

    // The tiny glTF itself is fine.
    let ok = write(d, "ok.gltf", &tiny_gltf(TRI_B64, 36, 3, ""));
    assert_eq!(load_ok(&ok).triangle_count(), 1);

    let e = err_of(&write(d, "broken.gltf", r#"{"asset": {"version": "2.0"}, "nodes": [ "#));
    assert!(e.contains("broken.gltf") && e.contains("glTF"), "{e}");

    let e = err_of(&write(d, "short.gltf", &tiny_gltf(TRI_B64, 36, 4, "")));
    assert!(
        e.contains("short.gltf") && e.contains("mesh \"Tri\" primitive 0") && e.contains("POSITION accessor 0"),
        "{e}"
    );

    let mat = r#","materials":[{"name":"Skin","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
        "textures":[{"source":0}],"images":[{"uri":"nothere.png"}]"#;
    let e = err_of(&write(d, "notex.gltf", &tiny_gltf(TRI_B64, 36, 3, mat)));
    assert!(e.contains("notex.gltf") && e.contains("nothere.png") && e.contains("Skin"), "{e}");

    let nan = "AADAfwAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"; // first x is NaN
    let e = err_of(&write(d, "nan.gltf", &tiny_gltf(nan, 36, 3, "")));
    assert!(e.contains("nan.gltf") && e.contains("\"Tri\"") && e.contains("NaN at vertex 0"), "{e}");

    // A missing material library is drawn with the default material, said
    // (as assimp and trimesh read it).
    let s = load_ok(&write(d, "nomtl.obj", "mtllib gone.mtl\nusemtl skin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    assert_eq!(s.triangle_count(), 1);
    assert!(
        s.warnings.iter().any(|w| w.contains("nomtl.obj: line 1") && w.contains("gone.mtl") && w.contains("default")),
        "{:?}",
        s.warnings
    );

    let e = err_of(&write(d, "range.obj", "g lid\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));
    assert!(e.contains("range.obj") && e.contains("\"lid\"") && e.contains("9"), "{e}");

    let e = err_of(&write(d, "nanv.obj", "g body\nv 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
    assert!(e.contains("nanv.obj") && e.contains("\"body\"") && e.contains("vertex 2") && e.contains("NaN"), "{e}");

    let e = err_of(&write(d, "empty.obj", "# nothing here\n"));
    assert!(e.contains("empty.obj") && e.contains("no triangles in the scene"), "{e}");

    // A missing texture of an MTL is drawn without, said (a glTF's missing
    // image above is an error: the glTF spec makes the file invalid).
    write(d, "m.mtl", "newmtl a\nmap_Kd missing_tex.png\n");
    let s = load_ok(&write(d, "notex.obj", "mtllib m.mtl\nusemtl a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    let said = s.warnings.join("\n");
    assert!(said.contains("m.mtl") && said.contains("missing_tex.png") && said.contains("material \"a\""), "{said}");

    // PLY: a binary body cut short, and a header claiming a huge count.
    let p = d.join("cut.ply");
    write_ply(&p, "binary_little_endian");
    let mut b = std::fs::read(&p).unwrap();
    b.truncate(b.len() - 40);
    std::fs::write(&p, b).unwrap();
    let e = err_of(&p);
    assert!(e.contains("cut.ply") && e.contains("element \"face\""), "{e}");

    let e = err_of(&write(
        d,
        "huge.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
    ));
    assert!(e.contains("huge.ply") && e.contains("element \"vertex\"") && e.contains("4000000000"), "{e}");

    let e = err_of(&write(
        d,
        "badidx.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
    ));
    assert!(e.contains("badidx.ply") && e.contains("vertex 7"), "{e}");

    let e = err_of(&write(d, "scene.fbx", "whatever"));
    assert!(e.contains("scene.fbx") && e.contains(".gltf") && e.contains(".ply"), "{e}");

    // A triangle limit refuses the scene before reading it, naming the object.
    let limits = LoadLimits { max_triangles: 0, ..LoadLimits::default() };
    let e = SceneSource::open_with_limits(&ok, limits).unwrap_err().to_string();
    assert!(e.contains("ok.gltf") && e.contains("\"Tri\"") && e.contains("limit"), "{e}");
}

/// Arbitrary damage to real files must give errors, never panics.
#[test]
fn damaged_files_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut sources: Vec<(String, Vec<u8>)> = Vec::new();
    let p = d.join("good.ply");
    write_ply(&p, "binary_big_endian");
    sources.push(("ply".into(), std::fs::read(&p).unwrap()));
    write_ply(&p, "ascii");
    sources.push(("ply".into(), std::fs::read(&p).unwrap()));
    sources.push(("gltf".into(), tiny_gltf(TRI_B64, 36, 3, "").into_bytes()));
    sources.push((
        "obj".into(),
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf -1 -2 -3\n".to_vec(),
    ));
    if let Some(shared) = data_dir_for_extra() {
        for f in [
            "gltf_khronos_BoxTextured/glTF-Binary/BoxTextured.glb",
            "gltf_khronos_AnimatedMorphCube/glTF-Binary/AnimatedMorphCube.glb",
            "gltf_khronos_BoxVertexColors/glTF-Embedded/BoxVertexColors.gltf",
            "mesh_cube_obj_vertexcolors/cube_with_vertexcolors.obj",
        ] {
            let ext = f.rsplit('.').next().unwrap().to_string();
            sources.push((ext, std::fs::read(shared.join(f)).unwrap()));
        }
    }
    let mut seed = 0x2545F4914F6CDD1Du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for (k, (ext, bytes)) in sources.iter().enumerate() {
        let rounds: usize = std::env::var("HOLO_FUZZ_ROUNDS").ok().and_then(|r| r.parse().ok()).unwrap_or(150);
        for round in 0..rounds {
            let mut b = bytes.clone();
            match round % 3 {
                0 => b.truncate((rnd() as usize) % (b.len() + 1)),
                1 => {
                    for _ in 0..4 {
                        let i = rnd() as usize % b.len();
                        b[i] = rnd() as u8;
                    }
                }
                _ => {
                    let i = rnd() as usize % b.len();
                    b[i] = b"0123456789-.e /\n"[rnd() as usize % 16];
                }
            }
            let p = d.join(format!("f{k}_{round}.{ext}"));
            std::fs::write(&p, &b).unwrap();
            let _ = load(&p);
        }
    }
}

/// Every number in a glTF's JSON set, one at a time, to a value far out of
/// range (an index past every list, a count past every buffer) must give an
/// error or a scene, never a panic.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn gltf_with_any_number_out_of_range_never_panics() {
    fn numbers(v: &serde_json::Value, path: &mut Vec<String>, out: &mut Vec<Vec<String>>) {
        match v {
            serde_json::Value::Number(_) => out.push(path.clone()),
            serde_json::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    path.push(i.to_string());
                    numbers(x, path, out);
                    path.pop();
                }
            }
            serde_json::Value::Object(m) => {
                for (k, x) in m {
                    path.push(k.clone());
                    numbers(x, path, out);
                    path.pop();
                }
            }
            _ => {}
        }
    }
    fn at<'a>(v: &'a mut serde_json::Value, path: &[String]) -> &'a mut serde_json::Value {
        path.iter().fold(v, |v, k| match v {
            serde_json::Value::Array(a) => &mut a[k.parse::<usize>().unwrap()],
            other => &mut other[k.as_str()],
        })
    }
    let dir = tempfile::tempdir().unwrap();
    let mut sources = vec![std::fs::read(fixture("modes_lights.gltf")).unwrap()];
    if let Some(shared) = data_dir_for_extra() {
        for f in [
            "gltf_khronos_BoxTextured/glTF-Embedded/BoxTextured.gltf",
            "gltf_khronos_SimpleMeshes/glTF-Embedded/SimpleMeshes.gltf",
        ] {
            sources.push(std::fs::read(shared.join(f)).unwrap());
        }
        // The morph cube with its .bin next to it.
        let d = shared.join("gltf_khronos_AnimatedMorphCube/glTF");
        std::fs::copy(d.join("AnimatedMorphCube.bin"), dir.path().join("AnimatedMorphCube.bin")).unwrap();
        sources.push(std::fs::read(d.join("AnimatedMorphCube.gltf")).unwrap());
    }
    for (k, src) in sources.iter().enumerate() {
        let json: serde_json::Value = serde_json::from_slice(src).unwrap();
        let mut paths = Vec::new();
        numbers(&json, &mut Vec::new(), &mut paths);
        for (i, p) in paths.iter().enumerate() {
            for bad in [serde_json::json!(999_999), serde_json::json!(4_000_000_000u64), serde_json::json!(-1)] {
                let mut j = json.clone();
                *at(&mut j, p) = bad;
                let f = dir.path().join(format!("n{k}_{i}.gltf"));
                std::fs::write(&f, serde_json::to_vec(&j).unwrap()).unwrap();
                if let Ok(s) = SceneSource::open(&f) {
                    let _ = s.scene_at(0.5);
                }
            }
        }
    }
}

fn base64(bytes: &[u8]) -> String {
    const A: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16 | (*c.get(1).unwrap_or(&0) as u32) << 8 | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                s.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

/// Materials (metallic-roughness mapping, texture transform, samplers,
/// normal map with generated tangents), an embedded PNG and a sparse accessor.
#[test]
fn gltf_materials_textures_and_sparse_accessor() {
    let f32s = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let mut buf = f32s(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]); // 0: positions, 36 bytes
    buf.extend(f32s(&[0.0, 1.0, 1.0, 1.0, 0.0, 0.0])); // 36: uv, 24 bytes
    buf.extend(f32s(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0])); // 60: normals, 36 bytes
    buf.extend([2u8, 0, 0, 0]); // 96: sparse index (u8) + padding
    buf.extend(f32s(&[0.0, 2.0, 0.0])); // 100: sparse value
    let png = common::png8(2, 2, 4, &[128, 128, 255, 255].repeat(4));
    let json = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_texture_transform"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "Leaf", "primitives": [{
            "attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 1, "NORMAL": 2},
            "material": 0}]}],
        "materials": [{
            "name": "Brass",
            "pbrMetallicRoughness": {
                "baseColorFactor": [1.0, 0.5, 0.25, 1.0], "metallicFactor": 0.5, "roughnessFactor": 0.5,
                "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform":
                    {"offset": [0.5, 0.0], "rotation": 0.1, "scale": [2.0, 2.0], "texCoord": 1}}}},
            "normalTexture": {"index": 1, "scale": 0.7},
            "emissiveFactor": [0.1, 0.2, 0.3],
            "doubleSided": true}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 0}],
        "samplers": [{"wrapS": 33071, "wrapT": 33648}],
        "images": [{"uri": format!("data:image/png;base64,{}", base64(&png)), "name": "grey"}],
        "buffers": [{"byteLength": buf.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&buf))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 24},
            {"buffer": 0, "byteOffset": 60, "byteLength": 36},
            {"buffer": 0, "byteOffset": 96, "byteLength": 1},
            {"buffer": 0, "byteOffset": 100, "byteLength": 12}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 2, 0],
             "sparse": {"count": 1, "indices": {"bufferView": 3, "componentType": 5121}, "values": {"bufferView": 4}}},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3"}]
    });
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("brass.gltf");
    std::fs::write(&p, serde_json::to_vec(&json).unwrap()).unwrap();
    let s = load_ok(&p);
    let o = &s.objects[0];
    assert_eq!(o.name, "Leaf");
    assert_eq!(o.positions[2], [0.0, 2.0, 0.0], "sparse substitution");
    let m = &o.material;
    assert_eq!(m.name, "Brass");
    assert_eq!(m.base_colour, [0.5, 0.25, 0.125, 1.0]);
    for (got, want) in m.specular.iter().zip([0.52, 0.27, 0.145]) {
        assert!((got - want).abs() < 1e-6, "{:?}", m.specular);
    }
    assert!((m.shininess - 30.0).abs() < 1e-3, "{}", m.shininess);
    assert_eq!(m.emissive, [0.1, 0.2, 0.3]);
    assert!(m.double_sided);
    assert_eq!(m.normal_scale, 0.7);
    let b = m.base_colour_texture.as_ref().unwrap();
    assert_eq!(b.uv_set, 1);
    assert_eq!(b.transform, holo::mesh::UvTransform { offset: [0.5, 0.0], rotation_rad: 0.1, scale: [2.0, 2.0] });
    use holo::mesh::Wrap;
    assert_eq!(s.textures[b.texture].wrap, [Wrap::ClampToEdge, Wrap::MirroredRepeat]);
    // The same image as sRGB colour and as a linear normal map: two textures.
    let n = m.normal_texture.as_ref().unwrap();
    assert_ne!(n.texture, b.texture);
    assert!((s.textures[b.texture].texels[0][0] - 0.2158605).abs() < 1e-4);
    assert!((s.textures[n.texture].texels[0][0] - 128.0 / 255.0).abs() < 1e-6);
    assert_eq!(s.textures[n.texture].wrap, [Wrap::Repeat; 2]);
    // Tangents generated from TEXCOORD_0: u grows along +x.
    assert_eq!(o.tangents.len(), 3);
    for t in &o.tangents {
        assert!((t[0] - 1.0).abs() < 1e-6 && t[1].abs() < 1e-6 && t[2].abs() < 1e-6, "{t:?}");
    }
}

/// A caller tells the kinds of failure apart by the error's variant: a file
/// the system cannot read, a scene file that cannot be used (naming it), a
/// value passed that is out of range.
#[test]
fn errors_keep_their_meaning() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.obj");
    match load(&missing) {
        Err(holo::Error::Io { path, source }) => {
            assert_eq!(path, missing);
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
        }
        other => panic!("a missing file is an I/O error: {other:?}"),
    }
    let d = dir.path();
    for (name, text) in [
        ("broken.gltf", r#"{"asset": {"version": "2.0"}, "nodes": [ "#),
        ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
        ("empty.obj", "# nothing\n"),
        ("bad.ply", "ply\nformat ascii 1.0\nend_header\n"),
        ("scene.fbx", "whatever"),
    ] {
        let p = write(d, name, text);
        match load(&p) {
            Err(holo::Error::Scene { path, problem }) => {
                assert_eq!(path, p);
                assert!(!problem.is_empty() && !problem.contains(name), "{name}: the path is a field: {problem}");
            }
            other => panic!("{name}: a scene problem: {other:?}"),
        }
    }
    // A lights file's bad line is a scene problem; a light given as a value is an argument.
    let lights = write(d, "lights.txt", "dir:0,0,-1\npoint:1,2\n");
    match holo::mesh::shade::read_lights(&lights, [0.0; 3]) {
        Err(holo::Error::Scene { path, problem }) => assert!(path == lights && problem.contains("line 2"), "{problem}"),
        other => panic!("a bad lights file: {other:?}"),
    }
    match holo::mesh::shade::parse_light("spot:1,2,3", [0.0; 3]) {
        Err(holo::Error::Argument { what: "light", problem }) => assert!(problem.contains("spot:1,2,3"), "{problem}"),
        other => panic!("a bad light: {other:?}"),
    }
    // A placement matrix that flattens the scene is the caller's value, not the scene's fault.
    let mut scene = load_ok(&write(d, "ok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"));
    let placement = holo::mesh::place::Placement { matrix: Some([[0.0; 4]; 4]), ..Default::default() };
    match holo::mesh::place::place(&mut scene, &holo::layout::mark3().geometry, &placement) {
        Err(holo::Error::Argument { what: "placement matrix", .. }) => {}
        other => panic!("a bad placement matrix: {other:?}"),
    }
    // Messages never name command-line options.
    let e = load(&write(d, "nan.obj", "v nan 0 0\n")).unwrap_err().to_string();
    assert!(!e.contains("--"), "{e}");
}

/// `KHR_mesh_quantization`: positions as normalised shorts, the node's scale
/// undoing the quantization, in a file that requires the extension. An
/// extension the loader does not read is an error when required, a warning
/// naming it when only used.
#[test]
fn quantized_positions_load_and_unknown_extensions_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let quantized = |extensions: &str| {
        format!(
            r#"{{"asset":{{"version":"2.0"}},{extensions}"scene":0,"scenes":[{{"nodes":[0]}}],
            "nodes":[{{"mesh":0,"scale":[2,3,1]}}],
            "meshes":[{{"name":"Q","primitives":[{{"attributes":{{"POSITION":0}}}}]}}],
            "buffers":[{{"byteLength":18,"uri":"data:application/octet-stream;base64,AAAAAAAA/38AAAAAAAD/fwAA"}}],
            "bufferViews":[{{"buffer":0,"byteLength":18}}],
            "accessors":[{{"bufferView":0,"componentType":5122,"normalized":true,"count":3,"type":"VEC3",
                "min":[0,0,0],"max":[32767,32767,0]}}]}}"#
        )
    };
    let q = write(
        d,
        "q.gltf",
        &quantized(r#""extensionsUsed":["KHR_mesh_quantization"],"extensionsRequired":["KHR_mesh_quantization"],"#),
    );
    let scene = load_ok(&q);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.objects[0].positions, vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 3.0, 0.0]]);
    let used = write(d, "used.gltf", &quantized(r#""extensionsUsed":["KHR_materials_sheen"],"#));
    let scene = load_ok(&used);
    assert!(
        scene.warnings.iter().any(|w| w.contains("used.gltf") && w.contains("KHR_materials_sheen")),
        "{:?}",
        scene.warnings
    );
    let required = write(
        d,
        "required.gltf",
        &quantized(
            r#""extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"],"#,
        ),
    );
    let e = err_of(&required);
    assert!(e.contains("required.gltf") && e.contains("KHR_draco_mesh_compression"), "{e}");
}

/// OBJ as the common readers (assimp, trimesh, tinyobjloader) accept it:
/// each variant loads to the triangles it means, and what is skipped or
/// missing is said, naming the file.
#[test]
fn obj_variants_the_common_readers_accept() {
    let dir = tempfile::tempdir().unwrap();
    let quad = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n";
    let cases: &[(&str, String, usize, &str)] = &[
        ("bom", format!("\u{feff}{quad}f 1 2 3\n"), 1, ""),
        ("negative indices", format!("{quad}f -4 -3 -2\n"), 1, ""),
        ("v//vn", format!("{quad}vn 0 0 1\nf 1//1 2//1 3//1\n"), 1, ""),
        ("n-gon", format!("{quad}v 0 1.5 0\nf 1 2 3 5 4\n"), 3, ""),
        ("vertex colours", "v -1 -1 0 1 0 0\nv 1 -1 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n".into(), 1, ""),
        ("w coordinate", "v -1 -1 0 1\nv 1 -1 0 1\nv 0 1 0 1\nf 1 2 3\n".into(), 1, ""),
        ("3-component vt", format!("{quad}vt 0 0 0\nvt 1 0 0\nvt 1 1 0\nf 1/1 2/2 3/3\n"), 1, ""),
        ("continued line", format!("{quad}f 1 2 \\\n 3\n"), 1, ""),
        ("comments at line ends", "v -1 -1 0 # a\nv 1 -1 0\nv 0 1 0\nf 1 2 3 # face\n".into(), 1, ""),
        ("tabs and spaces", "v\t-1\t-1\t0\nv  1 -1  0\n   v 0 1 0\nf\t1 2\t3\n".into(), 1, ""),
        ("number forms", "v -1e0 -1.0E+0 .0\nv +1 -1 0\nv 0 1. 0\nf 1 2 3\n".into(), 1, ""),
        ("trailing slashes", format!("{quad}f 1/ 2/ 3/\n"), 1, ""),
        (
            "groups, smoothing, lines, points",
            format!("{quad}o a\ng b\ns off\nl 1 2\np 1\nf 1 2 3\n"),
            1,
            "were ignored",
        ),
        ("unknown material", format!("{quad}usemtl nothing\nf 1 2 3\n"), 1, "material \"nothing\" (usemtl)"),
        ("two-corner face", format!("{quad}f 1 2\nf 1 2 3\n"), 1, "fewer than 3 corners"),
        (
            "missing texture",
            format!("mtllib m.mtl\n{quad}vt 0 0\nvt 1 0\nvt 1 1\nusemtl skin\nf 1/1 2/2 3/3\n"),
            1,
            "m.mtl: material \"skin\": map_Kd texture \"gone.png\" not found",
        ),
    ];
    std::fs::write(dir.path().join("m.mtl"), "newmtl skin\nKd 1 1 1\nmap_Kd gone.png\n").unwrap();
    for (name, text, triangles, warning) in cases {
        let path = dir.path().join(format!("{}.obj", name.replace([' ', '/', ','], "_")));
        std::fs::write(&path, text).unwrap();
        let scene = load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(scene.triangle_count(), *triangles, "{name}");
        let said = scene.warnings.join("\n");
        if warning.is_empty() {
            assert!(said.is_empty(), "{name}: {said}");
        } else {
            assert!(said.contains(warning), "{name}: {said}");
        }
    }
}

/// PLY triangle strips as old exporters wrote them (a `tristrips` element:
/// vertex indices, -1 restarting the strip): triangle i of a strip is
/// (a, b, c) for even i and (b, a, c) for odd i, so every triangle keeps the
/// strip's winding; triangles that repeat a vertex (the joins between
/// strips some exporters write) are dropped, and elements holo does not
/// read are named.
#[test]
fn ply_triangle_strips_keep_their_winding_and_restart() {
    let dir = tempfile::tempdir().unwrap();
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let strip: [i32; 11] = [0, 1, 2, 3, 4, -1, 5, 6, 7, 7, 6];
        let header = format!(
            "ply\nformat {format} 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n\
             element tristrips 1\nproperty list uchar int vertex_indices\nelement other 2\nproperty uchar k\nend_header\n"
        );
        let positions: [[f32; 3]; 8] = [
            [0., 0., 0.],
            [0., 1., 0.],
            [1., 0., 0.],
            [1., 1., 0.],
            [2., 0., 0.],
            [5., 0., 0.],
            [5., 1., 0.],
            [6., 0., 0.],
        ];
        let mut bytes = header.into_bytes();
        match format {
            "ascii" => {
                for p in positions {
                    bytes.extend(format!("{} {} {}\n", p[0], p[1], p[2]).bytes());
                }
                let list: Vec<String> = strip.iter().map(|i| i.to_string()).collect();
                bytes.extend(format!("{} {}\n1\n2\n", strip.len(), list.join(" ")).bytes());
            }
            _ => {
                let big = format == "binary_big_endian";
                for c in positions.iter().flatten() {
                    bytes.extend(if big { c.to_be_bytes() } else { c.to_le_bytes() });
                }
                bytes.push(strip.len() as u8);
                for i in strip {
                    bytes.extend(if big { i.to_be_bytes() } else { i.to_le_bytes() });
                }
                bytes.extend([1, 2]);
            }
        }
        let path = dir.path().join(format!("strip-{format}.ply"));
        std::fs::write(&path, bytes).unwrap();
        let scene = load_ok(&path);
        assert_eq!(scene.objects.len(), 1);
        // Strip 0 1 2 3 4: (0 1 2), (2 1 3), (2 3 4); strip 5 6 7 7 6:
        // (5 6 7), then (7 6 7) and (7 7 6) repeat a vertex.
        assert_eq!(scene.objects[0].triangles, vec![[0, 1, 2], [2, 1, 3], [2, 3, 4], [5, 6, 7]], "{format}");
        assert!(
            scene.warnings.iter().any(|w| w.contains("element \"other\"") && w.contains("skipped")),
            "{format}: {:?}",
            scene.warnings
        );
        assert!(!scene.warnings.iter().any(|w| w.contains("zero area")), "{format}: {:?}", scene.warnings);
    }
}
