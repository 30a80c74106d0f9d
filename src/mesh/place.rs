//! Placing a scene in the display's volume.
//!
//! By default the scene is fitted: rotated as asked, then scaled uniformly
//! and centred so its bounding box fills [`FIT_FILL`] of the volume the
//! layout shows well, centred on the middle of the emitter grid. That volume
//! is the emitter grid's width and height, and in depth the stereogram's
//! depth of field either side of the emitter plane: a point at distance
//! `Δz` from the emitter plane is drawn by neighbouring emitters at views
//! `Δθ` apart, so its image blurs over `Δz·Δθ`; beyond `Δz = p/Δθ` (emitter
//! pitch over view spacing) the blur exceeds one emitter. The depth is also
//! kept in front of the viewer line. An explicit 4×4 matrix replaces all this.

use super::{Light, Scene};
use crate::error::{Error, Result};
use crate::geometry::{millimetres_text, Geometry};
use crate::math::{
    cofactor3, det3, linear, mat3_apply, narrow, normalize_or, rotation_xyz, transform_point, transpose, unit, widen,
    Mat3, Mat4,
};

/// Fraction of the display volume a fitted scene fills.
pub const FIT_FILL: f64 = 0.9;

/// How to map the scene's world space onto display metres.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Placement {
    /// Rotation about x, then y, then z, degrees (applied before fitting).
    pub rotate_deg: [f64; 3],
    /// Display metres per scene unit, instead of the fitted scale.
    pub scale: Option<f64>,
    /// Offset in display metres added after centring.
    pub translate_m: [f64; 3],
    /// A 4×4 affine matrix from scene to display metres, row-major
    /// ([`Mat4`]); when given, the fields above are not used.
    pub matrix: Option<Mat4>,
}

/// What [`place`] did, for the user.
#[derive(Clone, Debug, PartialEq)]
pub struct Placed {
    /// The matrix applied (row-major, [`Mat4`]).
    pub matrix: Mat4,
    /// Display metres per scene unit (the cube root of the determinant).
    pub scale: f64,
    /// The scene's box in display metres after placement.
    pub bounds_m: ([f64; 3], [f64; 3]),
    /// The box the fit aimed at (emitter grid width and height, depth of field).
    pub volume_m: ([f64; 3], [f64; 3]),
}

impl std::fmt::Display for Placed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (lo, hi) = self.bounds_m;
        write!(
            f,
            "placed at {} display mm per scene unit: x {:+.1}..{:+.1} mm, y {:+.1}..{:+.1} mm, z {:+.1}..{:+.1} mm",
            millimetres_text(self.scale),
            lo[0] * 1e3,
            hi[0] * 1e3,
            lo[1] * 1e3,
            hi[1] * 1e3,
            lo[2] * 1e3,
            hi[2] * 1e3
        )
    }
}

/// The volume a geometry shows well (see the module text), as a box.
pub fn display_volume(g: &Geometry) -> ([f64; 3], [f64; 3]) {
    let x0 = g.emitter_x_m(0);
    let x1 = g.emitter_x_m(g.emitters.saturating_sub(1));
    let y0 = g.hololine_y_m(g.hololines.saturating_sub(1));
    let y1 = g.hololine_y_m(0);
    let views = g.views.count.max(2) as f64;
    let (a, b) = (g.views.first_theta_rad, g.views.last_theta_rad);
    let spacing_rad = ((b - a) / (views - 1.0)).abs().max(1e-9);
    let depth = g.emitter_pitch_m / spacing_rad;
    let z0 = g.emitter_z_m - depth;
    // Keep clear of the viewer line.
    let z1 = (g.emitter_z_m + depth).min(g.emitter_z_m + 0.5 * (g.viewer_distance_m - g.emitter_z_m));
    ([x0.min(x1), y0.min(y1), z0], [x0.max(x1), y0.max(y1), z1])
}

/// Map the scene into display metres in place, lights included (point
/// light intensities are scaled so the irradiance they give the scene is
/// what it was in scene units).
pub fn place(scene: &mut Scene, g: &Geometry, placement: &Placement) -> Result<Placed> {
    let volume = display_volume(g);
    scene.bounds().ok_or_else(|| Error::scene(&scene.source, "no triangles in the scene"))?;
    let matrix = match placement.matrix {
        Some(m) => m,
        None => {
            let r = rotation(placement.rotate_deg);
            // Box of the rotated scene.
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for o in &scene.objects {
                for t in &o.triangles {
                    for &i in t {
                        let p = mat3_apply(&r, o.positions[i as usize]);
                        for k in 0..3 {
                            lo[k] = lo[k].min(p[k]);
                            hi[k] = hi[k].max(p[k]);
                        }
                    }
                }
            }
            let s = match placement.scale {
                Some(s) => s,
                None => {
                    let mut s = f64::INFINITY;
                    for k in 0..3 {
                        let extent = hi[k] - lo[k];
                        if extent.is_infinite() {
                            return Err(Error::scene(
                                &scene.source,
                                format!(
                                    "its coordinates run from {:e} to {:e}, a span too large to compute with",
                                    lo[k], hi[k]
                                ),
                            ));
                        }
                        if extent > 0.0 {
                            s = s.min(FIT_FILL * (volume.1[k] - volume.0[k]) / extent);
                        }
                    }
                    if !s.is_finite() {
                        1.0
                    } else {
                        s
                    }
                }
            };
            let target = [0.5 * (volume.0[0] + volume.1[0]), 0.5 * (volume.0[1] + volume.1[1]), g.emitter_z_m];
            let mut m = [[0.0; 4]; 4];
            for row in 0..3 {
                for col in 0..3 {
                    m[row][col] = s * r[row][col];
                }
                let centre = 0.5 * (lo[row] + hi[row]);
                m[row][3] = target[row] - s * centre + placement.translate_m[row];
            }
            m[3][3] = 1.0;
            m
        }
    };
    // A matrix the caller gave is the caller's value; one placement computed
    // is the scene's doing (its coordinates), and names it.
    check_matrix(&matrix).map_err(|problem| match placement.matrix {
        Some(_) => Error::argument("placement matrix", problem),
        None => Error::scene(&scene.source, problem),
    })?;
    apply(scene, &matrix);
    let scale = LinearPart::of(&matrix).scale;
    let placed_bounds = scene.bounds().unwrap_or(([0.0; 3], [0.0; 3]));
    // Each hololine sees the scene only where its plane `y = y_j` cuts it
    // (horizontal parallax): a scene that falls between two hololines, or
    // above or below them all, is drawn by none and comes out black.
    let (y_lo, y_hi) = (placed_bounds.0[1], placed_bounds.1[1]);
    if !(0..g.hololines).any(|j| (y_lo..=y_hi).contains(&g.hololine_y_m(j))) {
        scene.warnings.push(format!(
            "{}: placed, the scene spans y {:+.4} … {:+.4} mm, which no hololine crosses (they are {:.4} mm apart, \
             from {:+.2} to {:+.2} mm): it will come out black; scale or move it, or check its units",
            scene.source,
            y_lo * 1e3,
            y_hi * 1e3,
            g.hololine_pitch_m * 1e3,
            g.hololine_y_m(g.hololines - 1) * 1e3,
            g.hololine_y_m(0) * 1e3,
        ));
    }
    if let Some(outside) = leaves_volume(placed_bounds, g) {
        scene.warnings.push(format!(
            "{}: placed, the scene leaves the display's volume: {outside}; scale it down or move it",
            scene.source
        ));
    }
    Ok(Placed { matrix, scale, bounds_m: placed_bounds, volume_m: volume })
}

/// The volume a scene should stay in, as a box: across, the emitters' and
/// hololines' extent (each half a pitch beyond its centre), where a point
/// outside is drawn by no emitter or hololine and cut off; in depth, the
/// depth of field of [`display_volume`], beyond which a point blurs over
/// more than an emitter.
pub fn display_extent(g: &Geometry) -> ([f64; 3], [f64; 3]) {
    let (volume_lo, volume_hi) = display_volume(g);
    let (pe, pj) = (g.emitter_pitch_m / 2.0, g.hololine_pitch_m / 2.0);
    let (x0, x1) = (g.emitter_x_m(0), g.emitter_x_m(g.emitters.saturating_sub(1)));
    let (y0, y1) = (g.hololine_y_m(g.hololines.saturating_sub(1)), g.hololine_y_m(0));
    ([x0.min(x1) - pe, y0.min(y1) - pj, volume_lo[2]], [x0.max(x1) + pe, y0.max(y1) + pj, volume_hi[2]])
}

/// Where the box `bounds` leaves [`display_extent`], in words (millimetres,
/// each side that is out); `None` when it stays inside.
fn leaves_volume(bounds: ([f64; 3], [f64; 3]), g: &Geometry) -> Option<String> {
    let (lo, hi) = display_extent(g);
    // Less than a micrometre out is rounding, not a scene that is too large.
    const SLACK_M: f64 = 1e-6;
    let mut sides = Vec::new();
    for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
        // Across, a point beyond the emitters or hololines is cut off; in depth, blurred.
        let (below, above, what) = match k {
            2 => ("behind the", "in front of the", "the views resolve (blurred)"),
            _ => ("beyond the display's edge at", "beyond the display's edge at", "(cut off)"),
        };
        if bounds.0[k] < lo[k] - SLACK_M {
            sides.push(format!("{axis} from {:+.1} mm, {below} {:+.1} mm {what}", bounds.0[k] * 1e3, lo[k] * 1e3));
        }
        if bounds.1[k] > hi[k] + SLACK_M {
            sides.push(format!("{axis} up to {:+.1} mm, {above} {:+.1} mm {what}", bounds.1[k] * 1e3, hi[k] * 1e3));
        }
    }
    (!sides.is_empty()).then(|| sides.join("; "))
}

/// What makes a placement matrix unusable, if anything.
fn check_matrix(m: &Mat4) -> std::result::Result<(), String> {
    if m.iter().flatten().any(|v| !v.is_finite()) {
        return Err("the placement matrix has a NaN or infinite entry (are the scene's coordinates too large?)".into());
    }
    if m[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err("the placement matrix must be affine: its last row must be 0 0 0 1".into());
    }
    // Singular or nearly so, whatever the scale: the determinant of the rows
    // made unit length (a scene in units of 1e300 is placed by a matrix of
    // 1e-300s, whose own determinant underflows to zero).
    let rows = linear(m).map(|row| {
        // Divided by the largest entry first, so squaring cannot underflow.
        let k = row.iter().fold(0f64, |a, x| a.max(x.abs()));
        unit(row.map(|x| x / k)).unwrap_or([0.0; 3])
    });
    let det = det3(&rows).abs();
    if det.is_nan() || det <= 1e-12 {
        return Err("the placement matrix is singular (it flattens the scene)".into());
    }
    Ok(())
}

/// Apply an affine matrix (row-major, [`Mat4`]) to positions, normals
/// (inverse transpose), tangents and lights; a mirroring matrix reverses the
/// winding so front faces stay counter-clockwise.
pub fn apply(scene: &mut Scene, m: &Mat4) {
    let lin = linear(m);
    let LinearPart { det, scale, cofactors } = LinearPart::of(m);
    // The cofactor matrix is the inverse transpose times det; with det's sign
    // turned it maps normals to the right side, and normalising removes |det|.
    let sign = if det < 0.0 { -1.0 } else { 1.0 };
    let normal_map = cofactors.map(|row| row.map(|c| c * sign));
    let xform_normal = |n: [f64; 3]| -> [f64; 3] {
        // `+ 0.0` turns −0 components into +0, as placement always has: the
        // signs of zero components reach the `.cg` normal codes.
        normalize_or(mat3_apply(&normal_map, n).map(|x| x + 0.0), [0.0, 0.0, 1.0])
    };
    for o in &mut scene.objects {
        for p in &mut o.positions {
            *p = transform_point(m, *p);
        }
        for n in &mut o.normals {
            *n = narrow(xform_normal(widen(*n)));
        }
        for t in &mut o.tangents {
            let v = normalize_or(mat3_apply(&lin, widen([t[0], t[1], t[2]])), [1.0, 0.0, 0.0]);
            *t = [v[0] as f32, v[1] as f32, v[2] as f32, if det < 0.0 { -t[3] } else { t[3] }];
        }
        if det < 0.0 {
            for t in &mut o.triangles {
                t.swap(1, 2);
            }
        }
    }
    let area_scale = scale.powi(2);
    for l in &mut scene.lights {
        match l {
            Light::Point { position, intensity, .. } => {
                *position = transform_point(m, *position);
                for c in intensity.iter_mut() {
                    *c = (*c as f64 * area_scale) as f32;
                }
            }
            Light::Directional { direction, .. } => {
                *direction = normalize_or(mat3_apply(&lin, *direction), [0.0, 0.0, -1.0]);
            }
            Light::Ambient { .. } => {}
        }
    }
}

/// What placement needs of an affine matrix's linear part `A`.
struct LinearPart {
    /// det A, or a number of its sign where it under- or overflows.
    det: f64,
    /// The uniform scale |det A|^⅓.
    scale: f64,
    /// The cofactor matrix, up to a positive factor.
    cofactors: Mat3,
}

impl LinearPart {
    /// Computed as placement always has (the determinant expanded along the
    /// first column: the point lights' intensity scale depends on its last
    /// bit, and the `.cg` normal codes on the cofactors'), unless that under-
    /// or overflows, as it does for a scene in units of 1e300 placed by a
    /// matrix of 1e-302s: then on `A / k`, `k` its largest entry, since
    /// det(kA) = k³ det A and cof(kA) = k² cof A.
    fn of(m: &Mat4) -> LinearPart {
        let lin = linear(m);
        let det = det3(&transpose(&lin));
        let cofactors = cofactor3(&lin);
        let fine = |x: f64| x == 0.0 || (x.is_normal() && x.abs() < 1e300);
        if det.is_normal() && cofactors.iter().flatten().all(|&c| fine(c)) {
            return LinearPart { det, scale: det.abs().cbrt(), cofactors };
        }
        let k = lin.iter().flatten().fold(0f64, |a, x| a.max(x.abs()));
        let a = lin.map(|row| row.map(|x| x / k));
        let det_a = det3(&transpose(&a));
        LinearPart { det: det_a, scale: k * det_a.abs().cbrt(), cofactors: cofactor3(&a) }
    }
}

/// Rotation about x, then y, then z (degrees), row-major.
pub fn rotation(deg: [f64; 3]) -> Mat3 {
    rotation_xyz(deg.map(f64::to_radians))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{mono_channel, Views};
    use crate::mesh::Object;

    /// 20 hololines and 40 emitters of 1 mm, 9 views over ±10°, the
    /// emitter plane 10 mm in front of the hologram, the viewer at 500 mm.
    fn display() -> Geometry {
        Geometry::centred(20, 40, Views::tan_spaced(9, -0.17, 0.17), 1e-3, 1e-3, 0.01, 0.5, mono_channel())
    }

    /// A unit cube (two triangles a face are not needed: its corners give the box).
    fn cube() -> Scene {
        let positions = (0..8).map(|i| [(i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64]).collect();
        let object =
            Object { name: "cube".into(), positions, triangles: vec![[0, 1, 2], [5, 6, 7]], ..Object::default() };
        Scene { source: "cube.obj".into(), objects: vec![object], ..Scene::default() }
    }

    #[test]
    fn scales_are_said_in_millimetres_as_typed() {
        let mut scene = cube();
        let placed = place(&mut scene, &display(), &Placement { scale: Some(0.01), ..Placement::default() }).unwrap();
        assert!(placed.to_string().starts_with("placed at 10 display mm per scene unit: x -5.0..+5.0 mm"), "{placed}");
    }

    #[test]
    fn a_scene_placed_beyond_the_display_is_said_fitted_ones_are_not() {
        let g = display();
        let (lo, hi) = display_extent(&g);
        // 40 × 20 mm of emitters and hololines; the depth of field 23.5 mm either side of the emitter plane.
        assert!((lo[0] + 0.020).abs() < 1e-12 && (hi[1] - 0.010).abs() < 1e-12, "{lo:?} {hi:?}");
        let mut fitted = cube();
        place(&mut fitted, &g, &Placement::default()).unwrap();
        assert!(fitted.warnings.is_empty(), "{:?}", fitted.warnings);
        let mut inside = cube();
        place(&mut inside, &g, &Placement { scale: Some(0.015), ..Placement::default() }).unwrap();
        assert!(inside.warnings.is_empty(), "{:?}", inside.warnings);
        // 60 mm a unit: wider and taller than the display, deeper than it resolves.
        let mut large = cube();
        place(&mut large, &g, &Placement { scale: Some(0.06), ..Placement::default() }).unwrap();
        let w = large.warnings.join("\n");
        assert_eq!(large.warnings.len(), 1, "{w}");
        for side in [
            "x from -30.0 mm, beyond the display's edge at -20.0 mm (cut off)",
            "x up to +30.0 mm",
            "y up to +30.0 mm, beyond the display's edge at +10.0 mm (cut off)",
            "z from -20.0 mm, behind the -13.5 mm the views resolve (blurred)",
        ] {
            assert!(w.contains(side), "{side}: {w}");
        }
        assert!(w.starts_with("cube.obj: placed, the scene leaves the display's volume"), "{w}");
        // Moved up alone: only the top is said.
        let mut moved = cube();
        let up = Placement { scale: Some(0.01), translate_m: [0.0, 0.008, 0.0], ..Placement::default() };
        place(&mut moved, &g, &up).unwrap();
        let w = moved.warnings.join("\n");
        assert!(
            w.contains("y up to +13.0 mm, beyond the display's edge at +10.0 mm (cut off)") && !w.contains("x "),
            "{w}"
        );
    }
}
