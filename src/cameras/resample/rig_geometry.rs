//! Where a capture goes on the display and how rays find their cameras:
//! the placement (framing, the display-aligned frame, a ring shown upright
//! about its axis), the camera surface (a rail's or grid's plane, or
//! directions about the scene's centre), the focus, and the eye map of
//! [`super::Parallax::Fit`].

use super::surface::Interpolator;
use super::{list_names, Framing, Parallax, Placement, PlacementRequest, Ray};
use crate::cameras::{Camera, Rig};
use crate::error::{Error, Result};
use crate::geometry::{millimetres_text, Geometry};
use crate::math::{
    add, cross, dot, length, mat3_transpose_apply, mean, normalize_or, principal_axes, scale, solve3, sub, Mat3, Plane,
};

/// The geometry of the rig that every ray uses: placement, camera surface,
/// focus plane.
pub struct RigGeometry {
    pub(super) placement: Placement,
    pub(super) surface: Surface,
    /// Eye positions to camera-surface points ([`Parallax::Fit`]); `None`:
    /// ray directions as they are.
    pub(super) eye_map: Option<EyeMap>,
    pub(super) cameras_on_surface: Interpolator,
    /// The focus plane (capture).
    pub(super) focus: Plane,
    /// Words for the report.
    pub(super) placement_words: String,
    /// The camera whose picture frames the display (the middle one).
    pub(super) frame_camera: usize,
    /// The middle camera's pixel at the focus, display metres.
    pub(super) pixel_at_focus_m: f64,
    /// Cameras that do not see the focus point.
    pub(super) warnings: Vec<String>,
}

pub(super) enum Surface {
    /// Rays are located where they cross this plane, in its unit axes `u`
    /// and `v`.
    Plane { plane: Plane, u: [f64; 3], v: [f64; 3] },
    /// Rays are located by their direction, cameras by theirs from
    /// `centre`: azimuth and elevation in the display-aligned frame.
    Directions { centre: [f64; 3] },
}

/// Where on the camera surface each eye position on the viewer line looks
/// from ([`Parallax::Fit`]). A display ray from emitter-plane `x` with slope
/// `sx` reaches the viewer line at eye position `e = x + D sx`; the capture
/// ray leaves the ray's focus-plane point toward the camera-surface point of
/// `e`, so every ray one eye sees comes from one place among the cameras
/// (for horizontal parallax, at the cameras' middle height). For full
/// parallax the eyes fill a rectangle of the viewer plane: a ray reaches the
/// eye at height `e_y = y + D s_y` too, and the cameras' vertical span is
/// taken across the eyes' heights the same way.
pub(super) struct EyeMap {
    /// Emitter plane to viewer line, display metres (`D`).
    pub(super) viewer_span_m: f64,
    /// Eye positions (display `x`, metres) from which some emitter is seen,
    /// lowest first.
    pub(super) eyes_m: [f64; 2],
    /// Full parallax: the eye heights (display `y`, metres) from which some
    /// emitter is seen, lowest first; `None` for horizontal parallax.
    pub(super) eyes_y_m: Option<[f64; 2]>,
    pub(super) target: EyeTarget,
}

pub(super) enum EyeTarget {
    /// A rail or grid: the cameras' range along the plane's `u` axis, taken
    /// across the eyes' range, at `v`; for full parallax the range along
    /// `v` (`v_across`, lowest eye first) across the eyes' heights instead.
    Plane { u: [f64; 2], v: f64, v_across: Option<[f64; 2]> },
    /// Cameras around the scene at `radius` from the surface's centre: the
    /// azimuth range (radians) taken across the eyes' range, or `None` for
    /// each eye's own azimuth from the display's middle; at `elevation`, or
    /// for full parallax the elevation range (`elevation_across`, lowest eye
    /// first) across the eyes' heights.
    Sphere { azimuth: Option<[f64; 2]>, elevation: f64, elevation_across: Option<[f64; 2]>, radius: f64 },
}

impl EyeMap {
    /// The fraction of the way across the eyes' range of the eye that ray
    /// `(x, sx)` reaches.
    pub(super) fn eye_fraction(&self, x: f64, sx: f64) -> f64 {
        let e = x + self.viewer_span_m * sx;
        (e - self.eyes_m[0]) / (self.eyes_m[1] - self.eyes_m[0])
    }

    /// Full parallax: the fraction of the way up the eyes' heights of the
    /// eye that ray `(y, sy)` reaches; `None` for horizontal parallax.
    pub(super) fn eye_fraction_y(&self, y: f64, sy: f64) -> Option<f64> {
        let [lo, hi] = self.eyes_y_m?;
        let e = y + self.viewer_span_m * sy;
        Some(if hi > lo { (e - lo) / (hi - lo) } else { 0.5 })
    }
}

impl RigGeometry {
    /// Work out the placement and the camera surface for `rig` shown on `g`.
    pub fn new(rig: &Rig, g: &Geometry, request: &PlacementRequest) -> Result<RigGeometry> {
        rig.check()?;
        let n = rig.cameras.len();
        let centres: Vec<[f64; 3]> = rig.cameras.iter().map(|c| c.pose.centre).collect();
        let mean_centre = mean(&centres);
        let mean_axis = mean(&rig.cameras.iter().map(|c| c.axis()).collect::<Vec<_>>());
        let axes_agree = length(mean_axis) > 0.7;
        let (axes, spread, extent) = principal_axes(&centres);
        // Display axes in capture coordinates: x along the cameras' mean
        // right, y against their mean down, z against their mean view.
        let right = mean(&rig.cameras.iter().map(|c| c.pose.rotation[0]).collect::<Vec<_>>());
        let down = mean(&rig.cameras.iter().map(|c| c.pose.rotation[1]).collect::<Vec<_>>());
        let ring = (!axes_agree && n >= 3 && spread[2] <= 0.25 * spread[1]).then(|| ring_frame(rig, axes[2], down));
        let (rotation, ring_words) = match ring {
            Some((rotation, words)) => (rotation, Some(words)),
            None => {
                let z_d = if axes_agree {
                    normalized(scale(mean_axis, -1.0))
                } else {
                    normalized(cross(right, scale(down, -1.0)))
                };
                let x_d = normalized(sub(right, scale(z_d, dot(right, z_d))));
                ([x_d, cross(z_d, x_d), z_d], None)
            }
        };
        let [x_d, y_d, z_d] = rotation;
        // Where the capture is in focus: on the mean axis at the focus
        // distance, or where inward-looking axes meet.
        let focus_distance = request.focus.or(rig.focus_distance);
        let (focus_point, focus_words) = if axes_agree {
            let f = focus_distance.ok_or_else(|| {
                Error::rig(
                    &rig.source,
                    "the capture does not say where it is in focus; give a focus distance (from the cameras, in the rig's units)",
                )
            })?;
            if !(f > 0.0 && f.is_finite()) {
                return Err(Error::argument("focus distance", format!("the focus distance must be positive, not {f}")));
            }
            (add(mean_centre, scale(normalized(mean_axis), f)), format!("focus {f:.4} units in front of the cameras"))
        } else {
            let p = axes_meet(&rig.cameras).ok_or_else(|| {
                Error::rig(&rig.source, "the cameras look in different directions whose axes do not meet")
            })?;
            (p, "focus where the camera axes meet".to_string())
        };
        // The surface.
        // A rail: the second spread tiny next to the first (calibrated rails
        // are straight to better than 1%); a plane likewise in the third.
        let surface = if n == 1 {
            Surface::Plane { plane: Plane { point: mean_centre, normal: z_d }, u: x_d, v: y_d }
        } else if extent == 0.0 {
            return Err(Error::rig(
                &rig.source,
                format!("cameras {} and {} are at the same place", rig.cameras[0].name, rig.cameras[1].name),
            ));
        } else if axes_agree && spread[1] <= 0.01 * spread[0] {
            // A rail: the plane through it, as square to the mean axis as it can be.
            let along = axes[0];
            let normal = normalized(sub(z_d, scale(along, dot(z_d, along))));
            Surface::Plane { plane: Plane { point: mean_centre, normal }, u: along, v: cross(normal, along) }
        } else if axes_agree && spread[2] <= 0.02 * spread[1] && dot(axes[2], z_d).abs() > 0.7 {
            let normal = if dot(axes[2], z_d) > 0.0 { axes[2] } else { scale(axes[2], -1.0) };
            let u = normalized(sub(x_d, scale(normal, dot(x_d, normal))));
            Surface::Plane { plane: Plane { point: mean_centre, normal }, u, v: cross(normal, u) }
        } else {
            Surface::Directions { centre: focus_point }
        };
        // Cameras around the scene: they are focused where their axes meet.
        let (focus_point, focus_words, surface) = match (&surface, axes_meet(&rig.cameras)) {
            (Surface::Directions { .. }, Some(p)) if request.focus.is_none() => {
                (p, "focus where the camera axes meet".to_string(), Surface::Directions { centre: p })
            }
            _ => (focus_point, focus_words, surface),
        };
        let points: Vec<[f64; 2]> = centres
            .iter()
            .map(|&c| match &surface {
                Surface::Plane { plane, u, v } => [dot(sub(c, plane.point), *u), dot(sub(c, plane.point), *v)],
                Surface::Directions { centre } => direction_coords(normalized(sub(c, *centre)), &rotation),
            })
            .collect();
        let mut cameras_on_surface = Interpolator::new(&points, rig)?;
        if g.vertical_views.is_some() && matches!(surface, Surface::Plane { .. }) {
            // Full parallax: an eye at an outer camera reads rays on both
            // sides of it; those beyond take the outer cameras' light.
            cameras_on_surface.cover_half_a_spacing_beyond();
        }
        refuse_a_rail_off_the_horizontal(rig, g, &surface, &cameras_on_surface, x_d)?;
        // Placement: the focus point at the middle of the emitter plane, and
        // by default the cameras as far from it as the viewer line is from
        // the emitter plane. Then a rail's vertical centre of projection is
        // the display's (HPO images are astigmatic, docs/optics.md §1.3), so content
        // off the focus plane keeps its vertical perspective. `fill_width`
        // instead fills the display's width with the middle camera's view.
        // The camera that frames the display: the one nearest the rig's
        // middle, or on a ring the one the display faces.
        let middle = if ring_words.is_some() {
            let facing = |i: usize| dot(normalized(sub(centres[i], focus_point)), z_d);
            (0..n).max_by(|&a, &b| facing(a).total_cmp(&facing(b)))
        } else {
            (0..n)
                .min_by(|&a, &b| length(sub(centres[a], mean_centre)).total_cmp(&length(sub(centres[b], mean_centre))))
        }
        .expect("cameras");
        let (scale_d, scale_words, focus_depth) = display_scale(rig, g, request, middle, focus_point)?;
        let cam = &rig.cameras[middle];
        let centre = request.centre.unwrap_or(focus_point);
        let placement = Placement { rotation, centre, scale: scale_d };
        let placement_words = format!(
            "{focus_words}; capture point ({:.4}, {:.4}, {:.4}) at the middle of the emitter plane; {scale_words}",
            centre[0], centre[1], centre[2]
        );
        let pixel_at_focus_m = focus_depth / cam.intrinsics.fx * scale_d;
        let (eye_map, parallax_words) = eye_map(rig, g, request, &surface, &points, [x_d, y_d]);
        let placement_words = match ring_words {
            Some(ring) => format!("{ring}; {placement_words}; {parallax_words}"),
            None => format!("{placement_words}; {parallax_words}"),
        };
        // Every camera should see the part of the scene the display shows.
        let blind: Vec<&str> = rig.cameras.iter().filter(|c| !c.sees(focus_point)).map(|c| c.name.as_str()).collect();
        if blind.len() == n {
            return Err(Error::rig(&rig.source, format!(
                "no camera sees the focus point ({:.4}, {:.4}, {:.4}) that the display would show (cameras {}); check the poses, the focus distance and the centre",
                focus_point[0],
                focus_point[1],
                focus_point[2],
                list_names(&blind)
            )));
        }
        let mut warnings = Vec::new();
        if !blind.is_empty() {
            warnings.push(format!("cameras {} do not see the focus point the display shows", list_names(&blind)));
        }
        Ok(RigGeometry {
            placement,
            surface,
            eye_map,
            cameras_on_surface,
            focus: Plane { point: focus_point, normal: z_d },
            placement_words,
            frame_camera: middle,
            pixel_at_focus_m,
            warnings,
        })
    }

    /// The placement chosen.
    pub fn placement(&self) -> &Placement {
        &self.placement
    }

    /// "rail", "grid", "directions (ring)", "single camera".
    pub(super) fn surface_words(&self, n: usize) -> String {
        let kind = match (&self.surface, &self.cameras_on_surface) {
            (_, Interpolator::Single) => "single camera",
            (Surface::Plane { .. }, Interpolator::Line { .. }) => "rail",
            (Surface::Plane { .. }, Interpolator::Triangles { .. }) => "planar grid",
            (Surface::Directions { .. }, Interpolator::Line { .. }) => "ring (by direction)",
            (Surface::Directions { .. }, Interpolator::Triangles { .. }) => "cameras around the scene (by direction)",
        };
        format!("{kind}, {n} cameras")
    }

    /// Capture-space origin and direction (toward the viewer) of display
    /// ray from `(x, y, z_e)` with direction `(sx, sy, 1)`, and, when the
    /// eye map chose it, the ray's point on the camera surface.
    pub(super) fn capture_ray(&self, x: f64, y: f64, sx: f64, sy: f64) -> ([f64; 3], [f64; 3], Option<[f64; 2]>) {
        let r = &self.placement.rotation;
        let origin = self.capture_point(x, y);
        let target = self.eye_point(x, y, sx, sy).and_then(|at| match (&self.eye_map, &self.surface) {
            (Some(EyeMap { target: EyeTarget::Plane { .. }, .. }), Surface::Plane { plane, u, v }) => {
                Some((add(plane.point, add(scale(*u, at[0]), scale(*v, at[1]))), at))
            }
            (Some(EyeMap { target: EyeTarget::Sphere { radius, .. }, .. }), Surface::Directions { centre }) => {
                let (a, elevation) = (at[0], at[1]);
                let (ce, se) = (elevation.cos(), elevation.sin());
                let toward = mat3_transpose_apply(r, [ce * a.sin(), se, ce * a.cos()]);
                Some((add(*centre, scale(toward, *radius)), at))
            }
            _ => None,
        });
        match target {
            Some((target, at)) => (origin, normalized(sub(target, origin)), Some(at)),
            None => (origin, normalized(mat3_transpose_apply(r, [sx, sy, 1.0])), None),
        }
    }

    /// The point on the camera surface that the eye map gives the display
    /// ray from `(x, y)` with slopes `(sx, sy)` (the eye it reaches), or
    /// `None` without an eye map. (`y` and `sy` matter for full parallax
    /// only: a horizontal-parallax eye map keeps the cameras' middle height.)
    pub(super) fn eye_point(&self, x: f64, y: f64, sx: f64, sy: f64) -> Option<[f64; 2]> {
        let map = self.eye_map.as_ref()?;
        let t = map.eye_fraction(x, sx);
        let across = |range: &[f64; 2], t: f64| range[0] + t * (range[1] - range[0]);
        // Up the eyes' heights (full parallax only), a form exact at both
        // ends: the outermost rays land exactly on the corner cameras, where
        // a rounding would put them outside the cameras' hull.
        let up = |range: &[f64; 2], t: f64| range[0] * (1.0 - t) + range[1] * t;
        match (&map.target, &self.surface) {
            (EyeTarget::Plane { u, v, v_across }, Surface::Plane { .. }) => {
                let v = match (v_across, map.eye_fraction_y(y, sy)) {
                    (Some(range), Some(t_y)) => up(range, t_y),
                    _ => *v,
                };
                Some([across(u, t), v])
            }
            (EyeTarget::Sphere { azimuth, elevation, elevation_across, .. }, Surface::Directions { .. }) => {
                let a = match azimuth {
                    Some(range) => across(range, t),
                    None => (x / map.viewer_span_m + sx).atan(),
                };
                let elevation = match (elevation_across, map.eye_fraction_y(y, sy)) {
                    (Some(range), Some(t_y)) => up(range, t_y),
                    _ => *elevation,
                };
                Some([a, elevation])
            }
            // The map is made for its surface.
            _ => None,
        }
    }

    /// The display ray's point on the camera surface, or `None` when it
    /// misses it.
    pub(super) fn ray_surface_point(&self, ray: Ray) -> Option<[f64; 2]> {
        if let Some(at) = self.eye_point(ray.x, ray.y, ray.sx, ray.sy) {
            return Some(at);
        }
        let (origin, dir, _) = self.capture_ray(ray.x, ray.y, ray.sx, ray.sy);
        self.surface_point(origin, dir)
    }

    /// The ray's point on the camera surface, or `None` when it misses it.
    pub(super) fn surface_point(&self, origin: [f64; 3], dir: [f64; 3]) -> Option<[f64; 2]> {
        match &self.surface {
            Surface::Plane { plane, u, v } => {
                let p = sub(plane.crossing(origin, dir)?, plane.point);
                Some([dot(p, *u), dot(p, *v)])
            }
            Surface::Directions { .. } => Some(direction_coords(dir, &self.placement.rotation)),
        }
    }

    /// The capture point the placement puts at emitter-plane point `(x, y)`
    /// (on the focus plane when the centre is the focus point).
    pub(super) fn capture_point(&self, x: f64, y: f64) -> [f64; 3] {
        let p = &self.placement;
        add(p.centre, mat3_transpose_apply(&p.rotation, [x / p.scale, y / p.scale, 0.0]))
    }

    /// Whether emitter-plane point `(x, y)` shows a part of the capture's
    /// frame: its capture point inside the middle camera's picture.
    pub(super) fn in_frame(&self, rig: &Rig, x: f64, y: f64) -> bool {
        rig.cameras[self.frame_camera].sees(self.capture_point(x, y))
    }

    /// Whether the placement's centre, and so every ray's origin, lies on
    /// the focus plane (to 1e-12 of the centre's distance from the capture's
    /// origin, or of the focus plane's).
    pub(super) fn centre_on_focus_plane(&self) -> bool {
        let off = dot(sub(self.placement.centre, self.focus.point), self.focus.normal).abs();
        off <= 1e-12 * length(self.placement.centre).max(length(self.focus.point)).max(1e-300)
    }

    /// Where the ray crosses the focus plane.
    pub(super) fn focus_on_ray(&self, origin: [f64; 3], dir: [f64; 3]) -> Option<[f64; 3]> {
        self.focus.crossing(origin, dir)
    }
}

/// Collinear cameras are a rail, which samples parallax along its line
/// only: across the display's horizontal parallax it works, but a line
/// running up and down would give every view of a hololine the same camera.
/// Such a rig needs cameras off the line (a grid).
pub(super) fn refuse_a_rail_off_the_horizontal(
    rig: &Rig,
    g: &Geometry,
    surface: &Surface,
    cameras_on_surface: &Interpolator,
    x_d: [f64; 3],
) -> Result<()> {
    if let Interpolator::Line { axis, sorted, .. } = cameras_on_surface {
        let horizontal = match surface {
            Surface::Plane { u, v, .. } => dot(add(scale(*u, axis[0]), scale(*v, axis[1])), x_d).abs(),
            Surface::Directions { .. } => axis[0].abs(),
        };
        if horizontal < std::f64::consts::FRAC_1_SQRT_2 || g.parallax == crate::geometry::Parallax::Full {
            let (first, last) = (sorted[0].1, sorted[sorted.len() - 1].1);
            return Err(Error::rig(
                &rig.source,
                format!(
                    "cameras {} to {} are collinear, on a line {:.0}° from the display's horizontal{}: \
                 a rail gives parallax only along its line, so these cameras cannot fill the display's views; \
                 add cameras off the line (a grid) or turn the rail across the horizontal parallax",
                    rig.cameras[first].name,
                    rig.cameras[last].name,
                    horizontal.clamp(0.0, 1.0).acos().to_degrees(),
                    if g.parallax == crate::geometry::Parallax::Full {
                        " and the display has full parallax"
                    } else {
                        ""
                    }
                ),
            ));
        }
    }
    Ok(())
}

/// Display metres per capture unit: given, or the cameras as far from the
/// focus as the viewer line is from the emitter plane, or (`fill_width`)
/// camera `middle`'s view filling the display's width. With its description
/// and camera `middle`'s depth of the focus point.
pub(super) fn display_scale(
    rig: &Rig,
    g: &Geometry,
    request: &PlacementRequest,
    middle: usize,
    focus_point: [f64; 3],
) -> Result<(f64, String, f64)> {
    let cam = &rig.cameras[middle];
    let focus_depth = dot(sub(focus_point, cam.pose.centre), cam.axis()).abs();
    let view_width = cam.width as f64 / cam.intrinsics.fx * focus_depth;
    let view_height = cam.height as f64 / cam.intrinsics.fy * focus_depth;
    let display_width = g.emitters as f64 * g.emitter_pitch_m;
    let display_height = g.hololines as f64 * g.hololine_pitch_m;
    let viewer_span = g.viewer_distance_m - g.emitter_z_m;
    let no_viewer_line = viewer_span.is_nan() || viewer_span <= 0.0;
    let (scale_d, scale_words) = match request.scale {
        Some(s) if s > 0.0 && s.is_finite() => (s, format!("scale {} display mm per capture unit (given)", millimetres_text(s))),
        Some(s) => return Err(Error::argument("scale", format!("the scale must be a positive number of display metres per capture unit, not {s}"))),
        None if matches!(request.framing, Framing::Fit | Framing::Fill) => {
            let (width_fits, height_fits) = (display_width / view_width, display_height / view_height);
            let (s, verb) = if request.framing == Framing::Fit {
                (width_fits.min(height_fits), "fits")
            } else {
                (width_fits.max(height_fits), "covers")
            };
            (
                s,
                format!(
                    "scale {} display mm per capture unit: camera {}'s view at the focus ({view_width:.4} × {view_height:.4} units) {verb} the display's {:.1} × {:.1} mm",
                    millimetres_text(s),
                    cam.name,
                    display_width * 1e3,
                    display_height * 1e3
                ),
            )
        }
        None if request.framing == Framing::FillWidth || no_viewer_line => (
            display_width / view_width,
            format!(
                "scale {} display mm per capture unit: camera {}'s view at the focus ({view_width:.4} units wide) fills the display's {:.1} mm",
                millimetres_text(display_width / view_width),
                cam.name,
                display_width * 1e3
            ),
        ),
        None => {
            let s = viewer_span / focus_depth;
            (
                s,
                format!(
                    "scale {} display mm per capture unit: the cameras ({focus_depth:.4} units from the focus) at the viewer's {:.0} mm; camera {}'s view at the focus spans {:.1} mm of the display's {:.1} mm",
                    millimetres_text(s),
                    viewer_span * 1e3,
                    cam.name,
                    view_width * s * 1e3,
                    display_width * 1e3
                ),
            )
        }
    };
    Ok((scale_d, scale_words, focus_depth))
}

/// The display frame for cameras on a ring around the scene (`normal`: the
/// normal of the plane of their centres): up along the ring's axis, toward
/// the cameras' mean up when they agree on it, else toward the rig's `+y`
/// (the convention of most capture software: a ring of rolled cameras, as
/// Middlebury's, agrees on no up); the display faces the middle of an arc,
/// or the first camera of a closed ring. Rows: display `x`, `y`, `z`.
pub(super) fn ring_frame(rig: &Rig, normal: [f64; 3], mean_down: [f64; 3]) -> (Mat3, String) {
    let up_hint = scale(mean_down, -1.0);
    let (y_d, up_words) = if dot(normal, up_hint).abs() >= 0.5 {
        (if dot(normal, up_hint) > 0.0 { normal } else { scale(normal, -1.0) }, "the cameras' up")
    } else {
        (if normal[1] >= 0.0 { normal } else { scale(normal, -1.0) }, "the rig's +y")
    };
    let centres: Vec<[f64; 3]> = rig.cameras.iter().map(|c| c.pose.centre).collect();
    let centre = axes_meet(&rig.cameras).unwrap_or_else(|| mean(&centres));
    let flat: Vec<[f64; 3]> = centres
        .iter()
        .map(|&c| {
            let d = sub(c, centre);
            normalized(sub(d, scale(y_d, dot(d, y_d))))
        })
        .collect();
    let middle = mean(&flat);
    let (z_d, facing) = if length(middle) >= 0.5 {
        (normalized(middle), "the middle of the arc".to_string())
    } else {
        (flat[0], format!("camera {}", rig.cameras[0].name))
    };
    (
        [cross(y_d, z_d), y_d, z_d],
        format!("cameras on a ring: up along its axis ({up_words}), the display facing {facing}"),
    )
}

/// The eye map of [`Parallax::Fit`] for the cameras at `points` on
/// `surface`, and its words; `None` for [`Parallax::True`], one camera, or a
/// display without a viewer line.
pub(super) fn eye_map(
    rig: &Rig,
    g: &Geometry,
    request: &PlacementRequest,
    surface: &Surface,
    points: &[[f64; 2]],
    [x_d, y_d]: [[f64; 3]; 2],
) -> (Option<EyeMap>, String) {
    let viewer_span_m = g.viewer_distance_m - g.emitter_z_m;
    if request.parallax == Parallax::True {
        return (None, "ray directions as captured (true parallax)".into());
    }
    if points.len() < 2 || !(viewer_span_m > 0.0 && viewer_span_m.is_finite()) {
        return (None, "ray directions as captured".into());
    }
    let (xs, slopes) = (
        [g.emitter_x_m(0), g.emitter_x_m(g.emitters - 1)],
        [g.ray_slope_x(0.0), g.ray_slope_x((g.views.count - 1) as f64)],
    );
    let eyes_m = [
        xs[0].min(xs[1]) + viewer_span_m * slopes[0].min(slopes[1]),
        xs[0].max(xs[1]) + viewer_span_m * slopes[0].max(slopes[1]),
    ];
    let range =
        |k: usize| points.iter().fold([f64::INFINITY, f64::NEG_INFINITY], |r, p| [r[0].min(p[k]), r[1].max(p[k])]);
    // Full parallax: the eyes' heights likewise, from the vertical views.
    let eyes_y_m = g.vertical_views.as_ref().map(|vertical| {
        let ys = [g.hololine_y_m(0), g.hololine_y_m(g.hololines - 1)];
        let slopes = [vertical.theta_at(0.0).tan(), vertical.theta_at((vertical.count - 1) as f64).tan()];
        [
            ys[0].min(ys[1]) + viewer_span_m * slopes[0].min(slopes[1]),
            ys[0].max(ys[1]) + viewer_span_m * slopes[0].max(slopes[1]),
        ]
    });
    let mut eyes_words =
        format!("eyes from {:+.0} to {:+.0} mm at {:.0} mm", eyes_m[0] * 1e3, eyes_m[1] * 1e3, viewer_span_m * 1e3);
    if let Some([lo, hi]) = eyes_y_m {
        eyes_words = format!("{eyes_words}, {:+.0} to {:+.0} mm high", lo * 1e3, hi * 1e3);
    }
    match surface {
        Surface::Plane { u: u_axis, v: v_axis, .. } => {
            let [lo, hi] = range(0);
            let v = range(1);
            // Left eyes see from the left cameras: u oriented along display x;
            // and lower eyes from the lower cameras: v along display y.
            let u = if dot(*u_axis, x_d) >= 0.0 { [lo, hi] } else { [hi, lo] };
            let v_across = eyes_y_m.map(|_| if dot(*v_axis, y_d) >= 0.0 { v } else { [v[1], v[0]] });
            let words = match v_across {
                None => format!("parallax fitted: the cameras' {:.4} units across the {eyes_words}", hi - lo),
                Some(_) => format!(
                    "parallax fitted: the cameras' {:.4} × {:.4} units across the {eyes_words}",
                    hi - lo,
                    v[1] - v[0]
                ),
            };
            let target = EyeTarget::Plane { u, v: 0.5 * (v[0] + v[1]), v_across };
            (Some(EyeMap { viewer_span_m, eyes_m, eyes_y_m, target }), words)
        }
        Surface::Directions { centre } => {
            let [lo, hi] = range(0);
            let el = range(1);
            let eye_azimuth = [(eyes_m[0] / viewer_span_m).atan(), (eyes_m[1] / viewer_span_m).atan()];
            let eye_span = eye_azimuth[1] - eye_azimuth[0];
            let radius =
                rig.cameras.iter().map(|c| length(sub(c.pose.centre, *centre))).sum::<f64>() / rig.cameras.len() as f64;
            let (azimuth, words) = if hi - lo <= 2.0 * eye_span {
                (
                    Some([lo, hi]),
                    format!(
                        "parallax fitted: the cameras' {:.1}° across the {eyes_words} ({:.1}°)",
                        (hi - lo).to_degrees(),
                        eye_span.to_degrees()
                    ),
                )
            } else {
                (
                    None,
                    format!(
                        "true angles: the cameras span {:.0}°, more than twice the {eyes_words} ({:.1}°)",
                        (hi - lo).to_degrees(),
                        eye_span.to_degrees()
                    ),
                )
            };
            // Elevation grows upward (direction_coords), as the eyes' heights do.
            let elevation_across = eyes_y_m.map(|_| el);
            let target = EyeTarget::Sphere { azimuth, elevation: 0.5 * (el[0] + el[1]), elevation_across, radius };
            (Some(EyeMap { viewer_span_m, eyes_m, eyes_y_m, target }), words)
        }
    }
}

/// Where the cameras' axes come closest to meeting (least squares), if
/// they are not all parallel.
pub(super) fn axes_meet(cameras: &[Camera]) -> Option<[f64; 3]> {
    // Σ (I − a aᵀ) p = Σ (I − a aᵀ) c.
    let mut m = [[0.0; 3]; 3];
    let mut r = [0.0; 3];
    for cam in cameras {
        let a = cam.axis();
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 } - a[i] * a[j];
                m[i][j] += e;
                r[i] += e * cam.pose.centre[j];
            }
        }
    }
    solve3(m, r)
}

/// Azimuth (toward display `x`) and elevation (toward display `y`) of a
/// unit direction, in the display-aligned frame `rotation`.
pub(super) fn direction_coords(d: [f64; 3], rotation: &[[f64; 3]; 3]) -> [f64; 2] {
    let (x, y, z) = (dot(d, rotation[0]), dot(d, rotation[1]), dot(d, rotation[2]));
    [x.atan2(z), y.clamp(-1.0, 1.0).asin()]
}

/// `a · (1/|a|)`; NaN for a zero vector, which the placement's checks
/// then report, rather than a made-up direction.
pub(super) fn normalized(a: [f64; 3]) -> [f64; 3] {
    normalize_or(a, [f64::NAN; 3])
}
