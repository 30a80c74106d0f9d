//! Smooth vertex normals for objects that have none (scans, old exporters),
//! by the angle rule the common modelling tools use (Blender's auto smooth,
//! 3ds Max smoothing by angle): at each corner of a triangle, the normal is
//! the area-weighted mean of the face normals of every triangle sharing that
//! corner's position whose normal is within the threshold angle of this
//! triangle's; edges sharper than the threshold stay sharp. Corners that
//! end up with different normals get their own vertices.

use std::collections::HashMap;

use super::Object;
use crate::math::{cross, dot, sub, unit};

/// Give `object` smooth normals by the angle rule, if it has none; a
/// threshold of 180° smooths everything, 0° nothing. Returns whether it did.
pub fn smooth_normals(object: &mut Object, threshold_deg: f64) -> bool {
    if !object.normals.is_empty() || object.triangles.is_empty() {
        return false;
    }
    let cos_threshold = threshold_deg.clamp(0.0, 180.0).to_radians().cos();
    let p = &object.positions;
    // Twice each face's area times its unit normal, and the unit normal.
    let weighted: Vec<[f64; 3]> = object
        .triangles
        .iter()
        .map(|t| cross(sub(p[t[1] as usize], p[t[0] as usize]), sub(p[t[2] as usize], p[t[0] as usize])))
        .collect();
    let face: Vec<[f64; 3]> = weighted.iter().map(|w| unit(*w).unwrap_or([0.0, 0.0, 1.0])).collect();
    // Triangles around each position (vertices that share a position share
    // a surface, whatever their texture coordinates).
    let key = |v: u32| p[v as usize].map(f64::to_bits);
    let mut around: HashMap<[u64; 3], Vec<usize>> = HashMap::new();
    for (f, t) in object.triangles.iter().enumerate() {
        for &v in t {
            let list = around.entry(key(v)).or_default();
            if list.last() != Some(&f) {
                list.push(f);
            }
        }
    }
    // Each corner's normal; a new vertex per (vertex, normal) pair.
    let mut vertex_of: HashMap<(u32, [u32; 3]), u32> = HashMap::new();
    let mut source: Vec<u32> = Vec::new();
    let mut normals: Vec<[f32; 3]> = Vec::new();
    let mut triangles = Vec::with_capacity(object.triangles.len());
    for (f, t) in object.triangles.iter().enumerate() {
        let corner = |v: u32| {
            let mut sum = [0.0; 3];
            for &g in &around[&key(v)] {
                if dot(face[g], face[f]) >= cos_threshold - 1e-12 {
                    sum = [sum[0] + weighted[g][0], sum[1] + weighted[g][1], sum[2] + weighted[g][2]];
                }
            }
            unit(sum).unwrap_or(face[f]).map(|x| x as f32)
        };
        let mut new = [0u32; 3];
        for (k, &v) in t.iter().enumerate() {
            let n = corner(v);
            new[k] = *vertex_of.entry((v, n.map(f32::to_bits))).or_insert_with(|| {
                source.push(v);
                normals.push(n);
                (source.len() - 1) as u32
            });
        }
        triangles.push(new);
    }
    object.positions = pick(&source, &object.positions);
    if !object.colours.is_empty() {
        object.colours = pick(&source, &object.colours);
    }
    if !object.tangents.is_empty() {
        object.tangents = pick(&source, &object.tangents);
    }
    for set in &mut object.uv_sets {
        if !set.is_empty() {
            *set = pick(&source, set);
        }
    }
    object.normals = normals;
    object.triangles = triangles;
    true
}

/// `from[v]` for each `v` of `source`.
fn pick<T: Copy>(source: &[u32], from: &[T]) -> Vec<T> {
    source.iter().map(|&v| from[v as usize]).collect()
}
