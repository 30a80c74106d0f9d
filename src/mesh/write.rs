//! Writing triangle meshes with per-vertex normals and colours, so decoded
//! geometry (a HoloFlick frame, a `.cg` file) can be looked at in the tools
//! people have: binary glTF (`.glb`, glTF 2.0) or binary PLY (`.ply`).
//!
//! Colours are written as they are stored, linear RGBA: glTF `COLOR_0` is
//! linear by definition; PLY gets 8-bit sRGB-encoded `red green blue` and
//! linear `alpha` (what MeshLab and Blender expect, and what
//! [`super::load`] decodes back). glTF materials are unlit
//! (`KHR_materials_unlit`): the colours of lit micropolygons already hold
//! their light.
//!
//! Like every writer here, the file is written beside the destination and
//! renamed into place; an existing file is kept unless `overwrite`.

use std::path::Path;

use super::Object;
use crate::error::{Error, Result};
use crate::picture::{Bits, Tone};

/// Vertex colours in PLY are bytes, encoded as an 8-bit sRGB picture's.
const SRGB_8: Tone = Tone::unit(Bits::Eight);

/// The format, from the file name's extension (`.glb` or `.ply`).
pub fn write_mesh(path: &Path, objects: &[Object], overwrite: bool) -> Result<()> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    let bytes = match ext.as_str() {
        "glb" => glb_bytes(path, objects)?,
        "ply" => ply_bytes(path, objects)?,
        _ => return Err(Error::unsupported(path, "cannot tell the mesh format; the name must end in .glb or .ply")),
    };
    crate::format::write_bytes_beside(path, &bytes, overwrite)
}

/// Check what every writer needs: attribute lists empty or one per vertex,
/// indices in range, finite positions, and a u32 vertex count.
fn check(path: &Path, objects: &[Object]) -> Result<()> {
    let mut total = 0u64;
    for o in objects {
        let n = o.positions.len();
        let bad = |what: &str| Error::scene(path, format!("object \"{}\": {what}", o.name));
        if !o.normals.is_empty() && o.normals.len() != n {
            return Err(bad(&format!("{} normals for {n} vertices", o.normals.len())));
        }
        if !o.colours.is_empty() && o.colours.len() != n {
            return Err(bad(&format!("{} colours for {n} vertices", o.colours.len())));
        }
        if let Some(t) = o.triangles.iter().find(|t| t.iter().any(|&i| i as usize >= n)) {
            return Err(bad(&format!("triangle {t:?} names a vertex past the {n} there are")));
        }
        if o.positions.iter().flatten().any(|x| !x.is_finite()) {
            return Err(bad("a vertex position is not finite"));
        }
        total += n as u64;
    }
    if total > u32::MAX as u64 {
        return Err(Error::unsupported(path, format!("{total} vertices; at most 2³² − 1 fit")));
    }
    Ok(())
}

/// A binary glTF 2.0 file: one mesh per object (one triangle primitive with
/// POSITION, NORMAL and COLOR_0 when present, u32 indices), one node each.
fn glb_bytes(path: &Path, objects: &[Object]) -> Result<Vec<u8>> {
    check(path, objects)?;
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes, mut nodes) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // One buffer view per attribute, each 4-byte aligned (every component is 4 bytes).
    let mut push_view = |bin: &mut Vec<u8>, data: &[u8], target: u32| -> usize {
        views.push(
            serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": data.len(), "target": target}),
        );
        bin.extend_from_slice(data);
        views.len() - 1
    };
    const ARRAY_BUFFER: u32 = 34962;
    const ELEMENT_ARRAY_BUFFER: u32 = 34963;
    const FLOAT: u32 = 5126;
    const UNSIGNED_INT: u32 = 5125;
    for (k, o) in objects.iter().enumerate() {
        let n = o.positions.len();
        let positions: Vec<[f32; 3]> = o.positions.iter().map(|p| p.map(|x| x as f32)).collect();
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for p in &positions {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        if n == 0 {
            (lo, hi) = ([0.0; 3], [0.0; 3]);
        }
        let mut attributes = serde_json::Map::new();
        let view = push_view(&mut bin, &f32_bytes(positions.iter().flatten()), ARRAY_BUFFER);
        accessors.push(serde_json::json!({"bufferView": view, "componentType": FLOAT, "count": n, "type": "VEC3", "min": lo, "max": hi}));
        attributes.insert("POSITION".into(), (accessors.len() - 1).into());
        if !o.normals.is_empty() {
            let view = push_view(&mut bin, &f32_bytes(o.normals.iter().flatten()), ARRAY_BUFFER);
            accessors.push(serde_json::json!({"bufferView": view, "componentType": FLOAT, "count": n, "type": "VEC3"}));
            attributes.insert("NORMAL".into(), (accessors.len() - 1).into());
        }
        if !o.colours.is_empty() {
            let view = push_view(&mut bin, &f32_bytes(o.colours.iter().flatten()), ARRAY_BUFFER);
            accessors.push(serde_json::json!({"bufferView": view, "componentType": FLOAT, "count": n, "type": "VEC4"}));
            attributes.insert("COLOR_0".into(), (accessors.len() - 1).into());
        }
        let indices: Vec<u8> = o.triangles.iter().flatten().flat_map(|i| i.to_le_bytes()).collect();
        let view = push_view(&mut bin, &indices, ELEMENT_ARRAY_BUFFER);
        accessors.push(serde_json::json!({"bufferView": view, "componentType": UNSIGNED_INT, "count": o.triangles.len() * 3, "type": "SCALAR"}));
        meshes.push(serde_json::json!({
            "name": o.name,
            "primitives": [{"attributes": attributes, "indices": accessors.len() - 1, "material": 0, "mode": 4}]
        }));
        nodes.push(serde_json::json!({"name": o.name, "mesh": k}));
    }
    let json = serde_json::json!({
        "asset": {"version": "2.0", "generator": format!("holo {}", env!("CARGO_PKG_VERSION"))},
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{"nodes": (0..objects.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": [{"name": "vertex colours", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 1.0, 1.0, 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}, "doubleSided": false, "extensions": {"KHR_materials_unlit": {}}}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    let mut json = serde_json::to_vec(&json).map_err(|e| Error::encode(path, "JSON", e))?;
    // Chunks are 4-byte aligned: JSON padded with spaces, BIN with zeros.
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let total = u32::try_from(total)
        .map_err(|_| Error::unsupported(path, format!("{total} bytes; a .glb holds at most 4 GiB")))?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    Ok(out)
}

fn f32_bytes<'a>(values: impl Iterator<Item = &'a f32>) -> Vec<u8> {
    values.flat_map(|x| x.to_le_bytes()).collect()
}

/// A binary little-endian PLY: every object's vertices in one list (float
/// position and normal, 8-bit sRGB colour with linear alpha), faces as
/// `uchar`-counted `int` lists.
fn ply_bytes(path: &Path, objects: &[Object]) -> Result<Vec<u8>> {
    check(path, objects)?;
    let normals = objects.iter().any(|o| !o.normals.is_empty());
    let colours = objects.iter().any(|o| !o.colours.is_empty());
    let vertices: usize = objects.iter().map(|o| o.positions.len()).sum();
    let faces: usize = objects.iter().map(|o| o.triangles.len()).sum();
    let mut out = Vec::new();
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by holo {}\nelement vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\n",
        env!("CARGO_PKG_VERSION")
    );
    if normals {
        header.push_str("property float nx\nproperty float ny\nproperty float nz\n");
    }
    if colours {
        header.push_str("property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n");
    }
    header.push_str(&format!("element face {faces}\nproperty list uchar int vertex_indices\nend_header\n"));
    out.extend_from_slice(header.as_bytes());
    let byte = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    for o in objects {
        for (i, p) in o.positions.iter().enumerate() {
            p.iter().for_each(|x| out.extend_from_slice(&(*x as f32).to_le_bytes()));
            if normals {
                let n = o.normals.get(i).copied().unwrap_or([0.0; 3]);
                n.iter().for_each(|x| out.extend_from_slice(&x.to_le_bytes()));
            }
            if colours {
                let c = o.colours.get(i).copied().unwrap_or([1.0; 4]);
                // Alpha is linear.
                let srgb = |x: f32| SRGB_8.code(x) as u8;
                out.extend_from_slice(&[srgb(c[0]), srgb(c[1]), srgb(c[2]), byte(c[3] as f64)]);
            }
        }
    }
    let mut first = 0u32;
    for o in objects {
        for t in &o.triangles {
            out.push(3);
            t.iter().for_each(|i| out.extend_from_slice(&(first + i).to_le_bytes()));
        }
        first += o.positions.len() as u32;
    }
    Ok(out)
}
