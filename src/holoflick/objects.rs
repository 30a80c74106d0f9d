//! Mesh objects in and out of HoloFlick geometry objects: what `pack`,
//! `unpack` and the converters share.
//!
//! In: an object's triangles (world metres, per-vertex normals and linear
//! colours) are compressed ([`super::cg::encode`]) in the stream's
//! normalised frame; the transform back to world metres and the colours'
//! scale travel beside the block (spec/holoflick.md §6.4). Out: a block is
//! decoded and mapped back: positions by `world_from_object`, normals by its
//! inverse transpose, colours times `radiance_scale`.

use super::cg::{self, EncodeOptions, EncodeStats};
use super::container::{Descriptor, GeometryBlock, GeometryObject, Matrix4, SpecularLight};
use super::shader::dice::with_flat_normals;
use crate::error::{Error, Result};
use crate::math::{det3, inverse_transpose3, linear, mat3_apply, narrow, transform_point, unit, widen};
use crate::mesh::{Light, Material, Object};

/// Compress one mesh object as geometry object `id`. Objects without
/// normals are shaded flat (one vertex per corner, the face normal); colours
/// above 1 (radiance) are scaled into the stream's range, the scale kept in
/// `radiance_scale`. Without colours the block carries none (the material's
/// base colour is not baked in: that is a converter's choice).
pub fn encode_object(id: u32, o: &Object, options: &EncodeOptions) -> Result<(GeometryObject, EncodeStats)> {
    let o = with_flat_normals(o);
    // Colours up to 1 go as they are (the stream's largest, 1 − 2^(1 − bits),
    // takes 1, as in Java 3D); brighter radiance is scaled so the brightest
    // component lands on that largest value.
    let top = 1.0 - 2f64.powi(1 - options.color_bits.clamp(2, 16) as i32);
    let brightest = o.colours.iter().flat_map(|c| c[..3].iter()).fold(0.0f32, |a, &b| a.max(b)) as f64;
    if !brightest.is_finite() {
        return Err(Error::argument("object", format!("object \"{}\": a vertex colour is not finite", o.name)));
    }
    let radiance_scale = if brightest > 1.0 { brightest / top } else { 1.0 };
    let colours: Vec<[f32; 4]> = o
        .colours
        .iter()
        .map(|c| [c[0], c[1], c[2]].map(|x| (x as f64 / radiance_scale).max(0.0) as f32))
        .zip(&o.colours)
        .map(|(rgb, c)| [rgb[0], rgb[1], rgb[2], c[3].clamp(0.0, 1.0)])
        .collect();
    let mesh = cg::Mesh {
        positions: &o.positions,
        normals: (!o.normals.is_empty()).then_some(&o.normals[..]),
        colors: (!colours.is_empty()).then_some(&colours[..]),
        triangles: &o.triangles,
    };
    // The codec knows no object names: the message gains the object's here.
    let encoded =
        cg::encode(&mesh, options).map_err(|e| Error::argument("object", format!("object \"{}\": {e}", o.name)))?;
    let descriptor = Descriptor::from_cg_header(&encoded.header);
    let block = GeometryBlock::new(descriptor, &encoded.bytes)
        .map_err(|m| Error::argument("object", format!("object \"{}\": {m}", o.name)))?;
    let s = 1.0 / encoded.scale;
    let c = encoded.center;
    let world_from_object = [[s, 0.0, 0.0, c[0]], [0.0, s, 0.0, c[1]], [0.0, 0.0, s, c[2]], [0.0, 0.0, 0.0, 1.0]];
    Ok((GeometryObject { id, world_from_object, radiance_scale, block }, encoded.stats))
}

/// Decode a block and map it to world space as a mesh object named `name`
/// (triangles only, each with its own three vertices). The material is
/// pre-lit ([`Material::prelit`]): the colours are the light the geometry
/// shader baked. Points and lines are skipped (counted in the second value).
pub fn decode_object(
    name: &str,
    block: &GeometryBlock,
    world_from_object: &Matrix4,
    radiance_scale: f64,
) -> Result<(Object, usize)> {
    let (o, skipped) = decode_block(name, block)?;
    Ok((to_world(&o, world_from_object, radiance_scale)?, skipped))
}

/// Decode a block as it is: positions in the stream's normalised frame,
/// colours as stored (what a converter caches for objects reused from key
/// frames; [`to_world`] places it).
pub fn decode_block(name: &str, block: &GeometryBlock) -> Result<(Object, usize)> {
    let mut o = Object::default();
    let skipped = decode_block_into(name, block, &mut o)?;
    Ok((o, skipped))
}

/// [`decode_block`] into `o`, whose lists are emptied and refilled: a player
/// that hands each frame the last frame's objects fills memory it has
/// already touched, instead of tens of megabytes of fresh pages a frame.
pub fn decode_block_into(name: &str, block: &GeometryBlock, o: &mut Object) -> Result<usize> {
    let header = block.descriptor().cg_header();
    let mut lists = std::mem::take(o);
    lists.uv_sets.clear();
    lists.positions.clear();
    lists.normals.clear();
    lists.tangents.clear();
    lists.colours.clear();
    lists.triangles.clear();
    *o = Object {
        name: name.to_string(),
        material: Material { name: name.to_string(), prelit: true, specular: [0.0; 3], ..Material::default() },
        ..lists
    };
    // The streaming decoder (constant memory, the fast path); each triangle
    // gets its own three vertices: the renderers work per triangle, and
    // sharing vertices would cost a hash per corner.
    let mut skipped = 0;
    let (mut with_normals, mut with_colours) = (true, true);
    cg::decode_with(&header, block.stream(), |p| match p {
        cg::Primitive::Triangle(t) => {
            let first = o.positions.len() as u32;
            for v in t {
                o.positions.push(v.position.map(f64::from));
                match v.normal {
                    Some(n) => o.normals.push(n),
                    None => with_normals = false,
                }
                match v.color {
                    Some(c) => o.colours.push(c),
                    None => with_colours = false,
                }
            }
            o.triangles.push([first, first + 1, first + 2]);
        }
        _ => skipped += 1,
    })
    .map_err(|e| Error::argument("compressed geometry", format!("object {name}: {e}")))?;
    // Vertices may lack normals or colours in part of a block (a list
    // without them): keep the lists whole or empty.
    if !with_normals || o.normals.len() != o.positions.len() {
        o.normals.clear();
    }
    if !with_colours || o.colours.len() != o.positions.len() {
        o.colours.clear();
    }
    Ok(skipped)
}

/// A decoded block (normalised frame, stored colours) in world space:
/// positions by `world_from_object`, normals by its inverse transpose,
/// colours times `radiance_scale`; a mirroring transform turns the winding.
pub fn to_world(o: &Object, world_from_object: &Matrix4, radiance_scale: f64) -> Result<Object> {
    let mut out = Object::default();
    to_world_into(o, world_from_object, radiance_scale, &mut out)?;
    Ok(out)
}

/// [`to_world`] into `out`, whose lists are refilled: a player hands it the
/// last frame's objects, so a frame's tens of megabytes go into memory
/// already touched rather than fresh pages.
pub fn to_world_into(o: &Object, world_from_object: &Matrix4, radiance_scale: f64, out: &mut Object) -> Result<()> {
    let m = world_from_object;
    let lin = linear(m);
    let normal_matrix = inverse_transpose3(&lin).ok_or_else(|| {
        Error::argument("object transform", format!("object {}: its transform cannot be inverted", o.name))
    })?;
    out.name.clone_from(&o.name);
    out.material.clone_from(&o.material);
    out.positions.clear();
    out.positions.extend(o.positions.iter().map(|&p| transform_point(m, p)));
    out.normals.clear();
    out.normals.extend(o.normals.iter().map(|&n| unit(mat3_apply(&normal_matrix, widen(n))).map_or([0.0; 3], narrow)));
    out.tangents.clone_from(&o.tangents);
    out.uv_sets.clone_from(&o.uv_sets);
    let s = radiance_scale as f32;
    out.colours.clear();
    out.colours.extend(o.colours.iter().map(|c| [c[0] * s, c[1] * s, c[2] * s, c[3]]));
    out.triangles.clone_from(&o.triangles);
    // A mirroring transform turns the winding (spec §6.4).
    if det3(&lin) < 0.0 {
        out.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    Ok(())
}

/// A HoloFlick specular light as the mesh renderer's light.
pub fn mesh_light(l: &SpecularLight) -> Light {
    match *l {
        SpecularLight::Directional { direction, irradiance } => {
            Light::Directional { direction, irradiance: irradiance.map(|x| x as f32), name: "specular".into() }
        }
        SpecularLight::Point { position_m, intensity } => {
            Light::Point { position: position_m, intensity: intensity.map(|x| x as f32), name: "specular".into() }
        }
    }
}
