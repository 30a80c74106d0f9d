//! Helpers shared by the loaders: image decoding to linear RGBA texels,
//! and tangent generation for normal maps.

use std::io::Cursor;

use super::LoadLimits;
use crate::math::{cross, dot, length, scale, sub, widen};
use crate::mesh::{Texture, Wrap};
use crate::picture::decode::{decode as decode_picture, dimensions, DecodeError};
use crate::picture::{srgb_decode_f32, Bits};

/// Decode a PNG or JPEG image to linear RGBA texels. `srgb` says whether
/// the colour channels are sRGB-encoded (base colour, emissive) or already
/// linear (normal maps); alpha is always linear. The size is checked
/// against `limits` from the image header, before the texels are
/// allocated. The error is a phrase for the caller to put after the name of
/// the texture and material.
pub(crate) fn decode(
    bytes: &[u8],
    name: &str,
    srgb: bool,
    wrap: [Wrap; 2],
    limits: &LoadLimits,
) -> Result<Texture, String> {
    let fail = |e: DecodeError| match e {
        DecodeError::NotPngOrJpeg => "is not a PNG or JPEG image".to_string(),
        e => format!("cannot decode the image: {e}"),
    };
    let (w, h) = dimensions(Cursor::new(bytes)).map_err(fail)?;
    let texels_count = (w as u64) * (h as u64);
    if texels_count > limits.max_texture_texels as u64 {
        return Err(format!(
            "is {w}×{h} = {texels_count} texels, more than the limit of {} texels",
            limits.max_texture_texels
        ));
    }
    if texels_count == 0 {
        return Err("has no texels (width or height 0)".into());
    }
    let img = decode_picture(Cursor::new(bytes)).map_err(fail)?;
    let texels: Vec<[f32; 4]> = match img.bits() {
        Bits::Eight => {
            let lut: Vec<f32> =
                (0..256).map(|i| if srgb { srgb_decode_f32(i as f32 / 255.0) } else { i as f32 / 255.0 }).collect();
            img.rgba8()
                .chunks_exact(4)
                .map(|p| [lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize], p[3] as f32 / 255.0])
                .collect()
        }
        Bits::Sixteen => img
            .rgba_f32()
            .chunks_exact(4)
            .map(|p| {
                let [r, g, b, a] = [p[0], p[1], p[2], p[3]];
                if srgb {
                    [srgb_decode_f32(r), srgb_decode_f32(g), srgb_decode_f32(b), a]
                } else {
                    [r, g, b, a]
                }
            })
            .collect(),
    };
    Ok(Texture { name: name.to_string(), width: w, height: h, texels, wrap })
}

/// Per-vertex tangents for a normal map, from the texture coordinates.
///
/// Each triangle contributes `dP/du` and `dP/dv` (unnormalised, so larger
/// triangles weigh more) to its three vertices; each vertex's tangent is
/// then made orthogonal to its normal (Gram–Schmidt) and unit. The sign in
/// `w` follows glTF: the bitangent is `w · (N × T)` and points toward
/// *decreasing* `v` (texture up, since `v = 0` is the top row: glTF normal
/// maps have green pointing up in the image). Not MikkTSpace, but the same
/// frame wherever the UV mapping is smooth.
///
/// `positions`, `normals`, `uvs` are one per vertex; indices are assumed
/// checked by the caller.
pub(crate) fn generate_tangents(
    positions: &[[f64; 3]],
    normals: &[[f32; 3]],
    uvs: &[[f32; 2]],
    triangles: &[[u32; 3]],
) -> Vec<[f32; 4]> {
    let n = positions.len();
    let mut tan = vec![[0.0f64; 3]; n];
    let mut bit = vec![[0.0f64; 3]; n];
    for t in triangles {
        let [i0, i1, i2] = t.map(|i| i as usize);
        if i0 >= n || i1 >= n || i2 >= n || i0 >= uvs.len() || i1 >= uvs.len() || i2 >= uvs.len() {
            continue;
        }
        let e1 = sub(positions[i1], positions[i0]);
        let e2 = sub(positions[i2], positions[i0]);
        let (u0, v0) = (uvs[i0][0] as f64, uvs[i0][1] as f64);
        let (du1, dv1) = (uvs[i1][0] as f64 - u0, uvs[i1][1] as f64 - v0);
        let (du2, dv2) = (uvs[i2][0] as f64 - u0, uvs[i2][1] as f64 - v0);
        let det = du1 * dv2 - du2 * dv1;
        if det == 0.0 || !det.is_finite() {
            continue;
        }
        // dP/du and dP/dv, scaled by det's magnitude (area weighting).
        let s = det.signum();
        let dpdu = [(e1[0] * dv2 - e2[0] * dv1) * s, (e1[1] * dv2 - e2[1] * dv1) * s, (e1[2] * dv2 - e2[2] * dv1) * s];
        let dpdv = [(e2[0] * du1 - e1[0] * du2) * s, (e2[1] * du1 - e1[1] * du2) * s, (e2[2] * du1 - e1[2] * du2) * s];
        for i in [i0, i1, i2] {
            for k in 0..3 {
                tan[i][k] += dpdu[k];
                bit[i][k] += dpdv[k];
            }
        }
    }
    (0..n)
        .map(|i| {
            let nr = normals.get(i).copied().unwrap_or([0.0, 0.0, 1.0]);
            let nv = widen(nr);
            let mut t = sub(tan[i], scale(nv, dot(nv, tan[i])));
            let mut len = length(t);
            if len.is_nan() || len <= 1e-20 || !len.is_finite() {
                // No usable UV gradient: any unit vector orthogonal to N.
                let axis = if nv[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
                t = sub(axis, scale(nv, dot(nv, axis)));
                len = length(t);
                if len.is_nan() || len <= 0.0 {
                    t = [1.0, 0.0, 0.0];
                    len = 1.0;
                }
            }
            let t = scale(t, 1.0 / len);
            // Bitangent toward decreasing v: −dP/dv.
            let w = if dot(cross(nv, t), bit[i]) > 0.0 { -1.0 } else { 1.0 };
            [t[0] as f32, t[1] as f32, t[2] as f32, w]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_of_a_quad_is_plus_x() {
        // Quad in the xy plane facing +z; u along +x, v (down) along −y.
        let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let n = [[0.0, 0.0, 1.0f32]; 4];
        let uv = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0f32]];
        let t = generate_tangents(&p, &n, &uv, &[[0, 1, 2], [0, 2, 3]]);
        for x in t {
            assert!((x[0] - 1.0).abs() < 1e-6 && x[1].abs() < 1e-6 && x[2].abs() < 1e-6);
            assert_eq!(x[3], 1.0);
        }
    }
}
