//! Every modulation ray from the cameras' pictures.
//!
//! A ray `(j, e, v)` of the display (docs/optics.md §1.3) is carried into the
//! capture's space by the [`Placement`]. There it is located among the
//! cameras on the rig's *camera surface*: for a rail or a planar grid whose
//! cameras look across their plane, the point where the ray crosses that
//! plane (the two-plane light field of Levoy and Hanrahan); for a ring or
//! any rig whose cameras look inward, the ray's direction (azimuth and
//! elevation in the display-aligned frame), compared with each camera's
//! direction from the scene centre. The cameras' points on that surface are
//! triangulated once (`spade`; a line of cameras is a 1-D list), and the
//! ray's point gets weights by the chosen [`Blend`]. Each weighted camera
//! then looks at the ray's *focus point* — where the ray crosses the focus
//! plane (Isaksen, McMillan and Gortler's dynamic reparameterisation), or,
//! with depth maps, the surface point found along the ray — and its picture
//! is sampled there (bilinear). Each sample averages such rays across its
//! emitter's aperture, the display's own filter (as the mesh renderer's
//! emitter supersampling): an isotropic picture prefilter would blur
//! vertically, which a hololine does not.
//! Cameras that do not see the point (outside their picture, behind them, or
//! hidden according to their own depth map) drop out and the others'
//! weights are renormalised. Rays outside the cameras' surface hull, or seen
//! by none, are zero and counted: nothing is invented.
//!
//! The fast path walks a hololine emitter by emitter, every view of an
//! emitter in turn, and uses what stays the same. Without depth maps and with
//! the placement's centre on the focus plane (the default), a ray's focus
//! point is its origin whatever its direction, so the views of an emitter
//! share one lookup per camera (`SharedFocus`). At one view the ray's
//! point on the camera surface moves evenly along the hololine, so each view
//! keeps the triangle (or nearest camera) of its last ray and walks only
//! when a ray leaves it. With the parallax fitted across the eyes a ray's
//! weights do not depend on its hololine, so natural-neighbour weights, the
//! costliest, are found once for all hololines (`RayWeights`).
//! `CameraOptions::reference` turns all of this off: every ray on its own,
//! located by brute force; tests compare the two.

use std::borrow::Cow;

use spade::handles::FixedVertexHandle;
use spade::{DelaunayTriangulation, Point2, PositionInTriangulation, Triangulation};

use super::image::Picture;
use super::{Camera, Rig};
use crate::geometry::{channel_weights, millimetres_text, Geometry};
use crate::math::{add, cross, det3, dot, length, mat3_transpose_apply, normalize_or, scale, sub, Mat3, Plane};
use crate::progress::Progress;
use crate::{Band, Error, Modulation, Result};

/// How the cameras around a ray are weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Blend {
    /// The nearest camera on the camera surface.
    Nearest,
    /// Linear along a rail, barycentric in the cameras' Delaunay triangle.
    Linear,
    /// Sibson's natural-neighbour coordinates (linear along a rail).
    NaturalNeighbour,
}

impl Blend {
    /// Every weighting.
    pub const ALL: [Blend; 3] = [Blend::Nearest, Blend::Linear, Blend::NaturalNeighbour];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Blend::Nearest => "nearest",
            Blend::Linear => "linear",
            Blend::NaturalNeighbour => "natural",
        }
    }

    /// Parse a command-line name.
    pub fn parse(s: &str) -> Result<Blend> {
        match s {
            "nearest" => Ok(Blend::Nearest),
            "linear" | "barycentric" => Ok(Blend::Linear),
            "natural" | "natural-neighbour" | "natural-neighbor" => Ok(Blend::NaturalNeighbour),
            _ => {
                Err(Error::argument("blending", format!("unknown blending {s:?}: expected nearest, linear or natural")))
            }
        }
    }
}

/// How the capture's space sits in the display's: display point
/// `P_d = scale · R (P_c − centre) + (0, 0, z_e)`, with `R`'s rows the
/// display's `x`, `y`, `z` axes in capture coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Capture to display rotation (rows: display axes in capture
    /// coordinates; row-major, [`Mat3`]).
    pub rotation: Mat3,
    /// The capture point shown at the middle of the emitter plane.
    pub centre: [f64; 3],
    /// Display metres per capture unit.
    pub scale: f64,
}

/// How big the capture is shown: which display metres per capture unit
/// (unless the user gives the scale).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Framing {
    /// The middle camera's view at the focus fits the emitter plane, its
    /// shape kept: everything the capture saw is shown, as large as it fits.
    #[default]
    Fit,
    /// The middle camera's view at the focus covers the emitter plane, its
    /// shape kept: no border, the capture's overflowing edges cut.
    Fill,
    /// The middle camera's view at the focus fills the display's width
    /// (its top and bottom may be cut).
    FillWidth,
    /// The cameras as far from the focus as the viewer line is from the
    /// emitter plane: the capture's own perspective, whatever it frames.
    CamerasAtViewer,
}

impl Framing {
    /// Every framing.
    pub const ALL: [Framing; 4] = [Framing::Fit, Framing::Fill, Framing::FillWidth, Framing::CamerasAtViewer];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Framing::Fit => "fit",
            Framing::Fill => "fill",
            Framing::FillWidth => "width",
            Framing::CamerasAtViewer => "viewer",
        }
    }
}

/// How the capture's directions meet the display's views.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Parallax {
    /// Each eye position on the viewer line sees what one point of the
    /// camera surface saw: the cameras' span across the eye positions from
    /// which the display is seen (a narrow rig's parallax enlarged, a wide
    /// one's reduced); a ring much wider than the display's views keeps its
    /// true angles around its middle camera.
    #[default]
    Fit,
    /// The display's ray directions, rotated and scaled into the capture, as
    /// they are: where the cameras did not look, rays are unseen.
    True,
}

impl Parallax {
    /// Both kinds.
    pub const ALL: [Parallax; 2] = [Parallax::Fit, Parallax::True];

    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Parallax::Fit => "fit",
            Parallax::True => "true",
        }
    }
}

/// What the user asked for (each `None`: chosen from the rig).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlacementRequest {
    /// Display metres per capture unit.
    pub scale: Option<f64>,
    /// The capture point to show at the middle of the emitter plane.
    pub centre: Option<[f64; 3]>,
    /// Focus distance from the cameras, capture units.
    pub focus: Option<f64>,
    /// How big the capture is shown when `scale` is not given.
    pub framing: Framing,
    /// How the capture's directions meet the display's views.
    pub parallax: Parallax,
}

/// Options of [`resample_rig`].
#[derive(Clone, Debug, PartialEq)]
pub struct CameraOptions {
    /// Camera weighting.
    pub blend: Blend,
    /// Placement and focus.
    pub placement: PlacementRequest,
    /// Use the cameras' depth maps where they have them.
    pub use_depth: bool,
    /// Return a mask of the rays no camera sees.
    pub want_mask: bool,
    /// Locate every ray among the cameras by brute force (the slow,
    /// obviously correct reference the tests and benchmarks compare with).
    pub reference: bool,
    /// Rays averaged across each emitter's aperture (the mesh renderer's
    /// emitter supersampling); `None`: as many as the middle camera has
    /// pixels across an emitter at the focus (1 to 16).
    pub emitter_taps: Option<usize>,
}

impl Default for CameraOptions {
    fn default() -> Self {
        CameraOptions {
            blend: Blend::Linear,
            placement: PlacementRequest::default(),
            use_depth: true,
            want_mask: false,
            reference: false,
            emitter_taps: None,
        }
    }
}

/// A camera's picture and (optionally) depth map, ready to sample.
#[derive(Clone, Debug)]
pub struct CameraView {
    /// The picture, linear RGB.
    pub picture: Picture,
    /// Camera `z` (world units) per pixel, top row first, where the rig
    /// gives a depth map (`INFINITY` where the map says nothing is there).
    pub depth_z: Option<Vec<f32>>,
}

/// What a resampling did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraReport {
    /// The placement used, in words (what was chosen and why).
    pub placement: String,
    /// Display metres per capture unit, as used.
    pub scale: f64,
    /// The capture point at the middle of the emitter plane, as used.
    pub centre: [f64; 3],
    /// The camera surface: "rail", "grid" or "directions" and the camera count.
    pub surface: String,
    /// Rays averaged across each emitter's aperture.
    pub emitter_taps: usize,
    /// Rays resampled (hololines × emitters × views).
    pub rays: u64,
    /// Rays no camera sees (left zero).
    pub unseen: u64,
    /// Of those, the rays of emitters outside the capture's frame (the
    /// middle camera's picture at the focus): the borders a framing that
    /// keeps the capture's shape leaves on a display of another shape.
    pub unseen_outside_frame: u64,
    /// Per ray (hololine, emitter, view order), `true` where unseen, on request.
    pub mask: Option<Vec<bool>>,
    /// Things the user should know (cameras listed twice, ...).
    pub warnings: Vec<String>,
}

/// The most rays averaged across one emitter. The automatic choice, one
/// ray per picture pixel the emitter spans at the focus, stops at 16; past
/// 64 a picture is sampled finer than any capture resolves across one
/// emitter, and the cost (linear in the taps) only grows.
pub const MAX_EMITTER_TAPS: usize = 64;

/// The geometry of the rig that every ray uses: placement, camera surface,
/// focus plane.
pub struct RigGeometry {
    placement: Placement,
    surface: Surface,
    /// Eye positions to camera-surface points ([`Parallax::Fit`]); `None`:
    /// ray directions as they are.
    eye_map: Option<EyeMap>,
    cameras_on_surface: Interpolator,
    /// The focus plane (capture).
    focus: Plane,
    /// Words for the report.
    placement_words: String,
    /// The camera whose picture frames the display (the middle one).
    frame_camera: usize,
    /// The middle camera's pixel at the focus, display metres.
    pixel_at_focus_m: f64,
    /// Cameras that do not see the focus point.
    warnings: Vec<String>,
}

enum Surface {
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
/// (for horizontal parallax, at the cameras' middle height).
struct EyeMap {
    /// Emitter plane to viewer line, display metres (`D`).
    viewer_span_m: f64,
    /// Eye positions (display `x`, metres) from which some emitter is seen,
    /// lowest first.
    eyes_m: [f64; 2],
    target: EyeTarget,
}

enum EyeTarget {
    /// A rail or grid: the cameras' range along the plane's `u` axis, taken
    /// across the eyes' range, at `v`.
    Plane { u: [f64; 2], v: f64 },
    /// Cameras around the scene at `radius` from the surface's centre: the
    /// azimuth range (radians) taken across the eyes' range, or `None` for
    /// each eye's own azimuth from the display's middle; at `elevation`.
    Sphere { azimuth: Option<[f64; 2]>, elevation: f64, radius: f64 },
}

impl EyeMap {
    /// The fraction of the way across the eyes' range of the eye that ray
    /// `(x, sx)` reaches.
    fn eye_fraction(&self, x: f64, sx: f64) -> f64 {
        let e = x + self.viewer_span_m * sx;
        (e - self.eyes_m[0]) / (self.eyes_m[1] - self.eyes_m[0])
    }
}

/// Rays no camera sees, over the hololines filled so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Unseen {
    /// Every ray left zero.
    pub rays: u64,
    /// Those of emitters outside the capture's frame.
    pub outside_frame: u64,
}

impl std::ops::AddAssign for Unseen {
    fn add_assign(&mut self, other: Unseen) {
        self.rays += other.rays;
        self.outside_frame += other.outside_frame;
    }
}

/// A worker's reusable state for [`Interpolator::weights`].
#[derive(Default)]
struct Scratch {
    weights: Vec<(FixedVertexHandle, f64)>,
    /// The vertex to start the next walk from.
    hint: usize,
    /// The triangle each view's last ray fell in. Along a hololine at one
    /// view a ray's point on the camera surface moves by a small, constant
    /// step from emitter to emitter, so it usually stays in its triangle:
    /// the weights are stepped (evaluated from the triangle's affine
    /// barycentric functions) and spade's walk runs only when a ray leaves
    /// the triangle.
    triangles: Vec<Option<Triangle>>,
    /// The worker's copy of the cameras' triangulation ([`Blend::NaturalNeighbour`]).
    triangulation: Option<DelaunayTriangulation<Point2<f64>>>,
    /// The vertex nearest each view's last ray ([`Blend::Nearest`]).
    nearest: Vec<usize>,
    /// Which of `triangles` and `nearest` the next ray uses (its view).
    view: usize,
}

impl Scratch {
    /// Scratch for rays of `views` views.
    fn new(views: usize) -> Scratch {
        Scratch { triangles: vec![None; views], nearest: vec![0; views], ..Scratch::default() }
    }
}

/// A Delaunay triangle with its barycentric coordinates as affine functions
/// of the surface point: `λ_k(q) = a_k + b_k q_x + c_k q_y`.
#[derive(Clone, Copy, Debug)]
struct Triangle {
    cameras: [usize; 3],
    affine: [[f64; 3]; 3],
}

impl Triangle {
    /// The triangle of vertices `p` (counter-clockwise or not; not
    /// degenerate) for cameras `cameras`.
    fn new(p: [[f64; 2]; 3], cameras: [usize; 3]) -> Triangle {
        let det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        // λ1 = ((q − p0) × (p2 − p0)) / det, λ2 = ((p1 − p0) × (q − p0)) / det.
        let (b1, c1) = ((p[2][1] - p[0][1]) / det, -(p[2][0] - p[0][0]) / det);
        let (b2, c2) = (-(p[1][1] - p[0][1]) / det, (p[1][0] - p[0][0]) / det);
        let a1 = -(p[0][0] * b1 + p[0][1] * c1);
        let a2 = -(p[0][0] * b2 + p[0][1] * c2);
        Triangle { cameras, affine: [[1.0 - a1 - a2, -b1 - b2, -c1 - c2], [a1, b1, c1], [a2, b2, c2]] }
    }

    /// The barycentric coordinates of `q`.
    fn coordinates(&self, q: [f64; 2]) -> [f64; 3] {
        self.affine.map(|[a, b, c]| a + b * q[0] + c * q[1])
    }
}

/// Barycentric weights of `p` in its Delaunay triangle (two on an edge,
/// one on a vertex, none outside the hull), located by a walk from vertex
/// `hint`, which is moved to a vertex of the triangle found. Returns the
/// triangle when `p` is inside one.
fn barycentric_with_hint(
    t: &DelaunayTriangulation<Point2<f64>>,
    p: Point2<f64>,
    hint: &mut usize,
    out: &mut Vec<(FixedVertexHandle, f64)>,
) -> Option<[FixedVertexHandle; 3]> {
    out.clear();
    let start = FixedVertexHandle::from_index((*hint).min(t.num_vertices() - 1));
    match t.locate_with_hint(p, start) {
        PositionInTriangulation::OnVertex(v) => {
            *hint = v.index();
            out.push((v, 1.0));
        }
        PositionInTriangulation::OnEdge(e) => {
            let e = t.directed_edge(e);
            let (a, b) = (e.from(), e.to());
            *hint = a.fix().index();
            let (pa, pb) = (a.position(), b.position());
            let (dx, dy) = (pb.x - pa.x, pb.y - pa.y);
            let s = (((p.x - pa.x) * dx + (p.y - pa.y) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            out.push((a.fix(), 1.0 - s));
            out.push((b.fix(), s));
        }
        PositionInTriangulation::OnFace(f) => {
            let v = t.face(f).vertices();
            *hint = v[0].fix().index();
            let q = v.map(|v| v.position());
            let det = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
            let l1 = ((p.x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (p.y - q[0].y)) / det;
            let l2 = ((q[1].x - q[0].x) * (p.y - q[0].y) - (p.x - q[0].x) * (q[1].y - q[0].y)) / det;
            out.extend([(v[0].fix(), 1.0 - l1 - l2), (v[1].fix(), l1), (v[2].fix(), l2)]);
            return Some(v.map(|v| v.fix()));
        }
        PositionInTriangulation::OutsideOfConvexHull(e) => *hint = t.directed_edge(e).from().fix().index(),
        PositionInTriangulation::NoTriangulation => {}
    }
    None
}

/// The vertex of `t` nearest `q` (the first by index among equals), walked
/// to from vertex `start`: a vertex no Delaunay neighbour of which is nearer
/// is the nearest of all (its Voronoi cell is bounded by its neighbours').
fn nearest_vertex(t: &DelaunayTriangulation<Point2<f64>>, start: usize, q: [f64; 2]) -> usize {
    let key = |v: FixedVertexHandle| {
        let p = t.vertex(v).position();
        ((q[0] - p.x).powi(2) + (q[1] - p.y).powi(2), v.index())
    };
    let mut best = FixedVertexHandle::from_index(start.min(t.num_vertices() - 1));
    let mut best_key = key(best);
    loop {
        let nearer = t.vertex(best).out_edges().map(|e| e.to().fix()).map(|v| (key(v), v)).fold(None, |a, b| match a {
            Some((ka, _)) if ka <= b.0 => a,
            _ => Some(b),
        });
        match nearer {
            Some((k, v)) if k < best_key => (best, best_key) = (v, k),
            _ => return best.index(),
        }
    }
}

/// Cameras' points on the surface and the weights of a query point.
/// [`Interpolator::weights`] locates the point by binary search or by
/// spade's walk; [`Interpolator::weights_reference`] by trying every
/// interval or triangle, the slow and obvious way the tests compare with.
enum Interpolator {
    /// One camera: it takes every ray.
    Single,
    /// Cameras on a line: their coordinate along `axis` from `origin`, sorted, with camera indices.
    Line { origin: [f64; 2], axis: [f64; 2], sorted: Vec<(f64, usize)> },
    /// Scattered: the Delaunay triangulation; vertex `k` is camera `cameras[k]`.
    Triangles { triangulation: DelaunayTriangulation<Point2<f64>>, cameras: Vec<usize> },
}

/// The coordinate of `p` along the line through `origin` with unit
/// direction `axis`: how cameras on a line are sorted and rays located
/// among them.
fn along_line(p: [f64; 2], origin: [f64; 2], axis: [f64; 2]) -> f64 {
    (p[0] - origin[0]) * axis[0] + (p[1] - origin[1]) * axis[1]
}

/// The weights at coordinate `s` on a line of the neighbouring cameras `a`
/// and `b` (coordinate, camera index) around it: the nearest, or both in
/// proportion (natural-neighbour weights on a line are linear).
fn pair_weights(a: (f64, usize), b: (f64, usize), s: f64, blend: Blend, out: &mut Vec<(usize, f64)>) {
    let t = ((s - a.0) / (b.0 - a.0)).clamp(0.0, 1.0);
    match blend {
        Blend::Nearest => out.push((if t < 0.5 { a.1 } else { b.1 }, 1.0)),
        Blend::Linear | Blend::NaturalNeighbour => {
            out.push((a.1, 1.0 - t));
            out.push((b.1, t));
        }
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
        let cameras_on_surface = Interpolator::new(&points, rig)?;
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
        let (eye_map, parallax_words) = eye_map(rig, g, request, &surface, &points, x_d);
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
    fn surface_words(&self, n: usize) -> String {
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
    fn capture_ray(&self, x: f64, y: f64, sx: f64, sy: f64) -> ([f64; 3], [f64; 3], Option<[f64; 2]>) {
        let r = &self.placement.rotation;
        let origin = self.capture_point(x, y);
        let target = self.eye_point(x, sx).and_then(|at| match (&self.eye_map, &self.surface) {
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
    /// ray from `x` with slope `sx` (the eye it reaches), or `None` without
    /// an eye map.
    fn eye_point(&self, x: f64, sx: f64) -> Option<[f64; 2]> {
        let map = self.eye_map.as_ref()?;
        let t = map.eye_fraction(x, sx);
        match (&map.target, &self.surface) {
            (EyeTarget::Plane { u, v }, Surface::Plane { .. }) => Some([u[0] + t * (u[1] - u[0]), *v]),
            (EyeTarget::Sphere { azimuth, elevation, .. }, Surface::Directions { .. }) => {
                let a = match azimuth {
                    Some(range) => range[0] + t * (range[1] - range[0]),
                    None => (x / map.viewer_span_m + sx).atan(),
                };
                Some([a, *elevation])
            }
            // The map is made for its surface.
            _ => None,
        }
    }

    /// The display ray's point on the camera surface, or `None` when it
    /// misses it.
    fn ray_surface_point(&self, ray: Ray) -> Option<[f64; 2]> {
        if let Some(at) = self.eye_point(ray.x, ray.sx) {
            return Some(at);
        }
        let (origin, dir, _) = self.capture_ray(ray.x, ray.y, ray.sx, ray.sy);
        self.surface_point(origin, dir)
    }

    /// The ray's point on the camera surface, or `None` when it misses it.
    fn surface_point(&self, origin: [f64; 3], dir: [f64; 3]) -> Option<[f64; 2]> {
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
    fn capture_point(&self, x: f64, y: f64) -> [f64; 3] {
        let p = &self.placement;
        add(p.centre, mat3_transpose_apply(&p.rotation, [x / p.scale, y / p.scale, 0.0]))
    }

    /// Whether emitter-plane point `(x, y)` shows a part of the capture's
    /// frame: its capture point inside the middle camera's picture.
    fn in_frame(&self, rig: &Rig, x: f64, y: f64) -> bool {
        rig.cameras[self.frame_camera].sees(self.capture_point(x, y))
    }

    /// Whether the placement's centre, and so every ray's origin, lies on
    /// the focus plane (to 1e-12 of the centre's distance from the capture's
    /// origin, or of the focus plane's).
    fn centre_on_focus_plane(&self) -> bool {
        let off = dot(sub(self.placement.centre, self.focus.point), self.focus.normal).abs();
        off <= 1e-12 * length(self.placement.centre).max(length(self.focus.point)).max(1e-300)
    }

    /// Where the ray crosses the focus plane.
    fn focus_on_ray(&self, origin: [f64; 3], dir: [f64; 3]) -> Option<[f64; 3]> {
        self.focus.crossing(origin, dir)
    }
}

impl Interpolator {
    /// [`Interpolator::weights`] found by brute force: every pair of
    /// neighbours on a line, every Delaunay triangle (barycentric
    /// coordinates in f64 from the vertices), every camera for the nearest.
    /// Natural-neighbour weights have no second implementation here and
    /// come from spade.
    fn weights_reference(&self, q: [f64; 2], blend: Blend, out: &mut Vec<(usize, f64)>, scratch: &mut Scratch) {
        out.clear();
        match self {
            Interpolator::Single => out.push((0, 1.0)),
            Interpolator::Line { origin, axis, sorted } => {
                let s = along_line(q, *origin, *axis);
                for pair in sorted.windows(2) {
                    let (a, b) = (pair[0], pair[1]);
                    if s >= a.0 && s <= b.0 {
                        pair_weights(a, b, s, blend, out);
                        return;
                    }
                }
            }
            Interpolator::Triangles { triangulation, cameras } => {
                if blend == Blend::NaturalNeighbour {
                    return self.weights(q, blend, out, scratch);
                }
                for face in triangulation.inner_faces() {
                    let v = face.vertices();
                    let p = v.map(|v| [v.position().x, v.position().y]);
                    let det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
                    let l1 = ((q[0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (q[1] - p[0][1])) / det;
                    let l2 = ((p[1][0] - p[0][0]) * (q[1] - p[0][1]) - (q[0] - p[0][0]) * (p[1][1] - p[0][1])) / det;
                    let l0 = 1.0 - l1 - l2;
                    let eps = -1e-12;
                    if l0 >= eps && l1 >= eps && l2 >= eps {
                        let ids = v.map(|v| cameras[v.fix().index()]);
                        if blend == Blend::Nearest {
                            let d = |i: usize| {
                                (q[0] - triangulation.vertex(FixedVertexHandle::from_index(i)).position().x).powi(2)
                                    + (q[1] - triangulation.vertex(FixedVertexHandle::from_index(i)).position().y)
                                        .powi(2)
                            };
                            let best = (0..cameras.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).expect("cameras");
                            out.push((cameras[best], 1.0));
                        } else {
                            out.extend(
                                [(ids[0], l0.max(0.0)), (ids[1], l1.max(0.0)), (ids[2], l2.max(0.0))]
                                    .into_iter()
                                    .filter(|w| w.1 > 0.0),
                            );
                        }
                        return;
                    }
                }
            }
        }
    }

    fn new(points: &[[f64; 2]], rig: &Rig) -> Result<Interpolator> {
        let n = points.len();
        if n == 1 {
            return Ok(Interpolator::Single);
        }
        // Coincident points first: every method needs them distinct.
        let extent = points.iter().flat_map(|p| p.iter()).fold(0.0f64, |a, &b| a.max(b.abs()));
        for a in 0..n {
            for b in a + 1..n {
                let d = ((points[a][0] - points[b][0]).powi(2) + (points[a][1] - points[b][1]).powi(2)).sqrt();
                if d <= 1e-9 * extent.max(1e-300) {
                    return Err(Error::rig(
                        &rig.source,
                        format!(
                            "cameras {} and {} are at the same place on the camera surface (the same position{})",
                            rig.cameras[a].name,
                            rig.cameras[b].name,
                            if extent > 0.0 { " or direction" } else { "" }
                        ),
                    ));
                }
            }
        }
        // Collinear: a 1-D list along the principal direction.
        let c =
            [points.iter().map(|p| p[0]).sum::<f64>() / n as f64, points.iter().map(|p| p[1]).sum::<f64>() / n as f64];
        let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
        for p in points {
            let (x, y) = (p[0] - c[0], p[1] - c[1]);
            sxx += x * x;
            sxy += x * y;
            syy += y * y;
        }
        let tr = sxx + syy;
        let det = sxx * syy - sxy * sxy;
        let l1 = tr / 2.0 + (tr * tr / 4.0 - det).max(0.0).sqrt();
        let l2 = (tr - l1).max(0.0);
        if l2 <= 1e-10 * l1 {
            let axis = if sxy.abs() > 1e-300 || sxx >= syy {
                let a = if sxy.abs() > 1e-300 { [l1 - syy, sxy] } else { [1.0, 0.0] };
                let l = (a[0] * a[0] + a[1] * a[1]).sqrt();
                [a[0] / l, a[1] / l]
            } else {
                [0.0, 1.0]
            };
            let mut sorted: Vec<(f64, usize)> =
                points.iter().enumerate().map(|(i, &p)| (along_line(p, c, axis), i)).collect();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            return Ok(Interpolator::Line { origin: c, axis, sorted });
        }
        let mut triangulation = DelaunayTriangulation::<Point2<f64>>::new();
        let mut cameras: Vec<usize> = Vec::with_capacity(n);
        for (i, p) in points.iter().enumerate() {
            let h: FixedVertexHandle = triangulation
                .insert(Point2::new(p[0], p[1]))
                .map_err(|e| Error::rig(&rig.source, format!("camera {}: {e:?}", rig.cameras[i].name)))?;
            if h.index() != cameras.len() {
                return Err(Error::rig(
                    &rig.source,
                    format!(
                        "cameras {} and {} are at the same place on the camera surface",
                        rig.cameras[cameras[h.index()]].name,
                        rig.cameras[i].name
                    ),
                ));
            }
            cameras.push(i);
        }
        Ok(Interpolator::Triangles { triangulation, cameras })
    }

    /// Camera weights at `q` (summing to 1), empty outside the cameras' hull.
    fn weights(&self, q: [f64; 2], blend: Blend, out: &mut Vec<(usize, f64)>, scratch: &mut Scratch) {
        out.clear();
        match self {
            Interpolator::Single => out.push((0, 1.0)),
            Interpolator::Line { origin, axis, sorted } => {
                let s = along_line(q, *origin, *axis);
                let (first, last) = (sorted[0].0, sorted[sorted.len() - 1].0);
                if !(s >= first && s <= last) {
                    return;
                }
                // The last camera at or before s.
                let i = sorted.partition_point(|&(x, _)| x <= s).saturating_sub(1).min(sorted.len() - 2);
                pair_weights(sorted[i], sorted[i + 1], s, blend, out);
            }
            Interpolator::Triangles { triangulation, cameras } => {
                let p = Point2::new(q[0], q[1]);
                if !(q[0].is_finite() && q[1].is_finite()) {
                    return;
                }
                // spade's weights (by vertex) as camera weights, zeros left out.
                let from_spade = |weights: &[(FixedVertexHandle, f64)], out: &mut Vec<(usize, f64)>| {
                    out.extend(weights.iter().filter(|w| w.1 > 0.0).map(|&(h, w)| (cameras[h.index()], w)))
                };
                if blend == Blend::NaturalNeighbour {
                    // On the worker's own copy: spade's walks start from the
                    // last vertex it found, kept in the triangulation, which
                    // threads sharing one would keep taking from each other.
                    let own = scratch.triangulation.get_or_insert_with(|| triangulation.clone());
                    own.natural_neighbor().get_weights(p, &mut scratch.weights);
                    return from_spade(&scratch.weights, out);
                }
                // Barycentric in the triangle of this view's last ray, usually;
                // else located by walking from the last ray's vertex (spade's
                // own hint is shared between threads).
                let cached = match scratch.triangles.get(scratch.view) {
                    Some(Some(t)) => Some((t.cameras, t.coordinates(q))).filter(|(_, l)| l.iter().all(|&l| l >= 0.0)),
                    _ => None,
                };
                let found = cached.or_else(|| {
                    let face = barycentric_with_hint(triangulation, p, &mut scratch.hint, &mut scratch.weights)?;
                    let at = face.map(|v| {
                        let p = triangulation.vertex(v).position();
                        [p.x, p.y]
                    });
                    let t = Triangle::new(at, face.map(|v| cameras[v.index()]));
                    if let Some(slot) = scratch.triangles.get_mut(scratch.view) {
                        *slot = Some(t);
                    }
                    Some((t.cameras, t.coordinates(q)))
                });
                match found {
                    Some((ids, l)) => out.extend(ids.into_iter().zip(l).filter(|w| w.1 > 0.0)),
                    // On an edge or a vertex, or outside the hull (none).
                    None => from_spade(&scratch.weights, out),
                }
                if blend == Blend::Nearest && !out.is_empty() {
                    // Inside the hull: the nearest camera, walked to from this
                    // view's last one.
                    let start = scratch.nearest.get(scratch.view).copied().unwrap_or(0);
                    let v = nearest_vertex(triangulation, start, q);
                    if let Some(slot) = scratch.nearest.get_mut(scratch.view) {
                        *slot = v;
                    }
                    out.clear();
                    out.push((cameras[v], 1.0));
                }
            }
        }
    }
}

/// Resample the rig's pictures (`views`, one per camera, in the rig's
/// order) into one frame of modulation on `g`, reporting the phase
/// `hololines` to `progress`.
pub fn resample_rig(
    rig: &Rig,
    views: &[CameraView],
    g: &Geometry,
    options: &CameraOptions,
    progress: &dyn Progress,
) -> Result<(Modulation, CameraReport)> {
    let resampler = RigResampler::new(rig, views, g, options)?;
    let mut frame = Band::zeros(g.clone(), 0..g.hololines)?;
    progress.phase("hololines", g.hololines as u64);
    let (unseen, mask) = resampler.fill(&mut frame, progress);
    Ok((frame.into_modulation()?, resampler.report(unseen, options.want_mask.then_some(mask))))
}

/// A rig made ready to resample: cameras listed twice dropped, the placement
/// and camera surface found, the emitter taps chosen. It fills any band of
/// hololines, so a frame can be made (and written) a band at a time.
pub struct RigResampler<'a> {
    rig: Cow<'a, Rig>,
    views: Vec<&'a CameraView>,
    g: Geometry,
    options: CameraOptions,
    geo: RigGeometry,
    warnings: Vec<String>,
    /// Channel weights of linear RGB, per channel.
    weights: Vec<[f64; 3]>,
    /// tan θ of every view.
    slopes: Vec<f64>,
    /// Offsets across an emitter's aperture of the rays averaged, metres.
    tap_x_m: Vec<f64>,
    /// Hololines done so far (for progress).
    done: std::sync::atomic::AtomicUsize,
    /// Every ray's focus point is its origin ([`SharedFocus`]): no depth map
    /// is used and the placement's centre is on the focus plane. Never for
    /// the reference, which finds every ray's focus point on its own.
    shared_focus: bool,
    /// Natural-neighbour weights of every (emitter, ray across it, view),
    /// found once for all hololines when an eye map makes them the same on
    /// every hololine ([`RayWeights`]).
    ray_weights: Option<RayWeights>,
}

/// The camera weights of every (emitter, tap, view) ray, `(emitter · taps +
/// tap) · views + view`, shared by all hololines. With an eye map a ray's
/// point on the camera surface depends only on the eye it reaches, so on
/// its emitter-plane `x` and slope `sx`, not on its hololine; natural-
/// neighbour weights, the costliest (spade finds the point's neighbours and
/// their stolen Voronoi areas for each), are then found 440 times less
/// often on Mark III. The others are cheap enough per ray and not kept.
struct RayWeights {
    /// Ray `r`'s weights are `cameras[start[r]..start[r + 1]]` with `weights`.
    start: Vec<u32>,
    cameras: Vec<u32>,
    weights: Vec<f64>,
}

impl RayWeights {
    /// The most rays kept: about 60 MB of weights (a ray has 3 to 8
    /// natural neighbours, 12 bytes each).
    const MAX_RAYS: usize = 800_000;

    /// The weights of ray `r`, into `out`.
    fn get(&self, r: usize, out: &mut Vec<(usize, f64)>) {
        let (a, b) = (self.start[r] as usize, self.start[r + 1] as usize);
        out.clear();
        out.extend(self.cameras[a..b].iter().zip(&self.weights[a..b]).map(|(&c, &w)| (c as usize, w)));
    }
}

impl<'a> RigResampler<'a> {
    /// Check and prepare `rig` with its pictures `views` (one per camera, in
    /// the rig's order) for `g`.
    pub fn new(rig: &'a Rig, views: &'a [CameraView], g: &Geometry, options: &CameraOptions) -> Result<Self> {
        if views.len() != rig.cameras.len() {
            return Err(Error::rig(&rig.source, format!("{} pictures for {} cameras", views.len(), rig.cameras.len())));
        }
        // A camera listed twice (same position and orientation: Middlebury's
        // temple ring has its first view again at 360°) is used once.
        let mut warnings = Vec::new();
        let mut keep: Vec<usize> = Vec::with_capacity(rig.cameras.len());
        for (i, cam) in rig.cameras.iter().enumerate() {
            match keep.iter().find(|&&k| same_pose(&rig.cameras[k], cam)) {
                Some(&k) => warnings.push(format!(
                    "cameras {} and {} have the same position and orientation; only {} is used",
                    rig.cameras[k].name, cam.name, rig.cameras[k].name
                )),
                None => keep.push(i),
            }
        }
        let (rig, views): (Cow<'a, Rig>, Vec<&'a CameraView>) = if keep.len() == rig.cameras.len() {
            (Cow::Borrowed(rig), views.iter().collect())
        } else {
            let unique = Rig { cameras: keep.iter().map(|&i| rig.cameras[i].clone()).collect(), ..rig.clone() };
            (Cow::Owned(unique), keep.iter().map(|&i| &views[i]).collect())
        };
        let geo = RigGeometry::new(&rig, g, &options.placement)?;
        warnings.extend(geo.warnings.iter().cloned());
        let names: Vec<&str> = g.channels.iter().map(|c| c.name.as_str()).collect();
        // Each sample averages rays across its emitter's aperture, point-sampling
        // the pictures: the display's own filter (the mesh renderer's emitter
        // supersampling), not a blur the display does not have.
        let taps = match options.emitter_taps {
            Some(n) if !(1..=MAX_EMITTER_TAPS).contains(&n) => {
                return Err(Error::argument(
                    "emitter taps",
                    format!("the emitter taps must be 1 to {MAX_EMITTER_TAPS}, not {n}"),
                ))
            }
            Some(n) => n,
            None => ((g.emitter_pitch_m / geo.pixel_at_focus_m).ceil() as usize).clamp(1, 16),
        };
        let depth_maps = options.use_depth && views.iter().any(|v| v.depth_z.is_some());
        let shared_focus = !(options.reference || depth_maps) && geo.centre_on_focus_plane();
        Ok(RigResampler {
            views,
            weights: channel_weights(&names),
            slopes: (0..g.views.count).map(|k| g.ray_slope_x(k as f64)).collect(),
            tap_x_m: (0..taps).map(|k| g.emitter_pitch_m * ((k as f64 + 0.5) / taps as f64 - 0.5)).collect(),
            rig,
            g: g.clone(),
            options: options.clone(),
            geo,
            warnings,
            done: std::sync::atomic::AtomicUsize::new(0),
            shared_focus,
            ray_weights: None,
        }
        .with_ray_weights())
    }

    /// Find [`RayWeights`] when they are worth keeping: natural-neighbour
    /// blending, an eye map, the fast path, and not too many rays.
    fn with_ray_weights(mut self) -> Self {
        use rayon::prelude::*;
        let (g, taps) = (&self.g, self.tap_x_m.len());
        let rays = g.emitters * taps * g.views.count;
        let worth = self.options.blend == Blend::NaturalNeighbour
            && self.shared_focus
            && self.geo.eye_map.is_some()
            && rays <= RayWeights::MAX_RAYS;
        if !worth {
            return self;
        }
        // Any hololine: the weights do not depend on it.
        let (y, sy) = (g.hololine_y_m(0), g.ray_slope_y(g.hololine_y_m(0)));
        let per_emitter: Vec<Vec<Vec<(usize, f64)>>> = (0..g.emitters)
            .into_par_iter()
            .map(|ei| {
                let (mut scratch, mut out) = (Scratch::new(g.views.count), Vec::with_capacity(taps * g.views.count));
                for dx in &self.tap_x_m {
                    for (vi, &sx) in self.slopes.iter().enumerate() {
                        scratch.view = vi;
                        let mut w = Vec::new();
                        if let Some(q) = self.geo.ray_surface_point(Ray { x: g.emitter_x_m(ei) + dx, y, sx, sy }) {
                            self.geo.cameras_on_surface.weights(q, self.options.blend, &mut w, &mut scratch);
                        }
                        out.push(w);
                    }
                }
                out
            })
            .collect();
        let mut table = RayWeights { start: vec![0], cameras: Vec::new(), weights: Vec::new() };
        for w in per_emitter.iter().flatten() {
            table.cameras.extend(w.iter().map(|&(c, _)| c as u32));
            table.weights.extend(w.iter().map(|&(_, w)| w));
            table.start.push(table.cameras.len() as u32);
        }
        self.ray_weights = Some(table);
        self
    }

    /// Fill `band` (of this resampler's geometry), hololines in parallel;
    /// `progress` is advanced by the hololines done across bands (the caller
    /// begins the phase, of the geometry's hololines). Returns
    /// the rays no camera sees (left zero) and, when the options ask for a
    /// mask, which they are (band's hololine, emitter, view order).
    pub fn fill(&self, band: &mut Band, progress: &dyn Progress) -> (Unseen, Vec<bool>) {
        use rayon::prelude::*;
        let g = &self.g;
        let lines = band.hololines();
        let (e, v, c) = (g.emitters, g.views.count, g.channels.len());
        let mut rows: Vec<Vec<&mut [f32]>> = lines.clone().map(|_| Vec::with_capacity(c)).collect();
        for (i, row) in band.samples_mut().chunks_exact_mut(e * v).enumerate() {
            rows[i % lines.len()].push(row);
        }
        let want_mask = self.options.want_mask;
        let per_line: Vec<(Unseen, Vec<bool>)> = rows
            .into_par_iter()
            .zip(lines.clone())
            .map(|(mut rows, j)| {
                let mut mask = if want_mask { vec![false; e * v] } else { Vec::new() };
                let unseen = self.fill_hololine(j, &mut rows, &mut mask);
                let n = self.done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress.advance(n as u64);
                (unseen, mask)
            })
            .collect();
        let mut unseen = Unseen::default();
        per_line.iter().for_each(|l| unseen += l.0);
        (unseen, per_line.into_iter().flat_map(|l| l.1).collect())
    }

    /// Per view, the ray's point on the camera surface as an affine function
    /// of emitter-plane `x` along hololine `y` (ray slope `sy`), when the
    /// directions are as captured: rays of one view along a hololine then
    /// differ only in their origin, which moves along a line, so their
    /// crossings of a camera plane step evenly and their directions stay.
    /// Fitted from the hololine's first and last rays. Empty when the focus
    /// point is not shared (rays are then found one by one) or an eye map
    /// gives the points (by its own affine arithmetic, as cheap as a step
    /// and exactly the reference's: its outermost rays land exactly on the
    /// end cameras, where a rounding would lose them).
    fn surface_steps(&self, y: f64, sy: f64) -> Vec<Option<SurfaceStep>> {
        let g = &self.g;
        let first = g.emitter_x_m(0) + self.tap_x_m[0];
        let last = g.emitter_x_m(g.emitters - 1) + self.tap_x_m[self.tap_x_m.len() - 1];
        if !(self.shared_focus && self.geo.eye_map.is_none() && last > first) {
            return Vec::new();
        }
        let point = |x: f64, sx: f64| self.geo.ray_surface_point(Ray { x, y, sx, sy });
        self.slopes
            .iter()
            .map(|&sx| {
                let (a, b) = (point(first, sx)?, point(last, sx)?);
                let per_m = [(b[0] - a[0]) / (last - first), (b[1] - a[1]) / (last - first)];
                Some(SurfaceStep { x0: first, at_x0: a, per_m })
            })
            .collect()
    }

    /// Fill hololine `j`'s `rows` (one per channel, emitter-major) and, when
    /// `mask` is not empty, mark its unseen rays; returns those.
    fn fill_hololine(&self, j: usize, rows: &mut [&mut [f32]], mask: &mut [bool]) -> Unseen {
        let g = &self.g;
        let v = g.views.count;
        let y = g.hololine_y_m(j);
        let sy = g.ray_slope_y(y);
        let mut unseen = Unseen::default();
        let (mut w, mut scratch) = (Vec::new(), Scratch::new(v));
        // Per view: the radiance summed over the emitter's taps, and the taps that saw.
        let mut sums = vec![([0.0f64; 3], 0usize); v];
        let mut shared = SharedFocus { point: [0.0; 3], samples: vec![None; self.rig.cameras.len()] };
        let steps = self.surface_steps(y, sy);
        for ei in 0..g.emitters {
            let x = g.emitter_x_m(ei);
            sums.fill(([0.0; 3], 0));
            for (ti, dx) in self.tap_x_m.iter().enumerate() {
                let x = x + dx;
                if self.shared_focus {
                    shared.point = self.geo.capture_point(x, y);
                    shared.samples.fill(None);
                }
                for (vi, &sx) in self.slopes.iter().enumerate() {
                    scratch.view = vi;
                    let ray = Ray { x, y, sx, sy };
                    let rgb = if let Some(table) = &self.ray_weights {
                        table.get((ei * self.tap_x_m.len() + ti) * v + vi, &mut w);
                        self.shared_blend(&w, &mut shared)
                    } else if self.shared_focus {
                        match steps.get(vi).copied().flatten() {
                            Some(step) => Some(step.at(x)),
                            None => self.geo.ray_surface_point(ray),
                        }
                        .and_then(|q| {
                            self.geo.cameras_on_surface.weights(q, self.options.blend, &mut w, &mut scratch);
                            self.shared_blend(&w, &mut shared)
                        })
                    } else {
                        self.ray_radiance(ray, &mut w, &mut scratch)
                    };
                    if let Some(rgb) = rgb {
                        let (sum, seen) = &mut sums[vi];
                        for k in 0..3 {
                            sum[k] += rgb[k];
                        }
                        *seen += 1;
                    }
                }
            }
            let in_frame = self.geo.in_frame(&self.rig, x, y);
            for (vi, &(sum, seen)) in sums.iter().enumerate() {
                let at = ei * v + vi;
                if seen > 0 {
                    let rgb = sum.map(|s| s / seen as f64);
                    for (row, wc) in rows.iter_mut().zip(&self.weights) {
                        row[at] = (wc[0] * rgb[0] + wc[1] * rgb[1] + wc[2] * rgb[2]) as f32;
                    }
                } else {
                    for row in rows.iter_mut() {
                        row[at] = 0.0;
                    }
                    unseen.rays += 1;
                    unseen.outside_frame += u64::from(!in_frame);
                    if !mask.is_empty() {
                        mask[at] = true;
                    }
                }
            }
        }
        unseen
    }

    /// Capture coordinates to display metres (row-major, points as columns):
    /// `P_d = scale · R (P_c − centre) + (0, 0, z_e)`, the placement of the
    /// focus plane's points. (With [`Parallax::Fit`] the rays' directions are
    /// mapped apart from it, by the eye map.)
    pub fn display_from_capture(&self) -> crate::math::Mat4 {
        let p = self.geo.placement();
        let mut m = crate::math::IDENTITY4;
        for (i, row) in p.rotation.iter().enumerate() {
            let shift = if i == 2 { self.g.emitter_z_m } else { 0.0 };
            m[i] = [p.scale * row[0], p.scale * row[1], p.scale * row[2], shift - p.scale * dot(*row, p.centre)];
        }
        m
    }

    /// The report of a resampling that left `unseen` rays unseen.
    pub fn report(&self, unseen: Unseen, mask: Option<Vec<bool>>) -> CameraReport {
        let g = &self.g;
        CameraReport {
            placement: self.geo.placement_words.clone(),
            scale: self.geo.placement.scale,
            centre: self.geo.placement.centre,
            emitter_taps: self.tap_x_m.len(),
            warnings: self.warnings.clone(),
            surface: self.geo.surface_words(self.rig.cameras.len()),
            rays: (g.hololines * g.emitters * g.views.count) as u64,
            unseen: unseen.rays,
            unseen_outside_frame: unseen.outside_frame,
            mask,
        }
    }
}

/// A display ray: from emitter-plane point `(x, y)` (metres) with slopes
/// `(sx, sy)` (`dx/dz`, `dy/dz`).
#[derive(Clone, Copy, Debug)]
struct Ray {
    x: f64,
    y: f64,
    sx: f64,
    sy: f64,
}

/// A ray's point on the camera surface along a hololine at one view:
/// `at_x0 + (x − x0)·per_m`.
#[derive(Clone, Copy, Debug)]
struct SurfaceStep {
    x0: f64,
    at_x0: [f64; 2],
    per_m: [f64; 2],
}

impl SurfaceStep {
    fn at(&self, x: f64) -> [f64; 2] {
        let d = x - self.x0;
        [self.at_x0[0] + d * self.per_m[0], self.at_x0[1] + d * self.per_m[1]]
    }
}

/// The focus point that every view of one emitter-plane point looks at, and
/// each camera's picture sampled there once (`None`: not yet; `Some(None)`:
/// the camera does not see it). Rays leave the emitter plane from points of
/// the focus plane whenever the placement's centre is on it (the default),
/// so without depth maps a ray's focus point is its origin, whatever its
/// direction: the 96 views of an emitter share about two dozen camera
/// lookups instead of making three each.
struct SharedFocus {
    point: [f64; 3],
    samples: Vec<Option<Option<[f32; 3]>>>,
}

impl RigResampler<'_> {
    /// Linear RGB along one display ray, or `None` when no camera sees it:
    /// the ray located among the cameras, its focus point found (moved to
    /// the surface by the depth maps when used), each weighted camera's
    /// picture sampled there.
    fn ray_radiance(&self, ray: Ray, w: &mut Vec<(usize, f64)>, scratch: &mut Scratch) -> Option<[f64; 3]> {
        let (geo, options) = (&self.geo, &self.options);
        let (origin, dir, on_surface) = geo.capture_ray(ray.x, ray.y, ray.sx, ray.sy);
        let q = match on_surface {
            Some(q) => q,
            None => geo.surface_point(origin, dir)?,
        };
        if options.reference {
            geo.cameras_on_surface.weights_reference(q, options.blend, w, scratch);
        } else {
            geo.cameras_on_surface.weights(q, options.blend, w, scratch);
        }
        if w.is_empty() {
            return None;
        }
        let mut point = geo.focus_on_ray(origin, dir)?;
        if options.use_depth {
            point = refine_with_depth(&self.rig, &self.views, w, origin, dir, point);
        }
        blend_samples(w, |ci| camera_sample(&self.rig, &self.views, options, ci, point))
    }

    /// [`RigResampler::ray_radiance`] of a ray with camera weights `w` whose
    /// focus point is `shared.point`, the cameras' samples there remembered
    /// in `shared`.
    fn shared_blend(&self, w: &[(usize, f64)], shared: &mut SharedFocus) -> Option<[f64; 3]> {
        let point = shared.point;
        blend_samples(w, |ci| {
            *shared.samples[ci].get_or_insert_with(|| camera_sample(&self.rig, &self.views, &self.options, ci, point))
        })
    }
}

/// Camera `ci`'s picture at world point `point`, or `None` where the camera
/// does not see it (behind it, outside its picture, or hidden by a nearer
/// surface in its depth map when depth maps are used).
fn camera_sample(
    rig: &Rig,
    views: &[&CameraView],
    options: &CameraOptions,
    ci: usize,
    point: [f64; 3],
) -> Option<[f32; 3]> {
    let cam = &rig.cameras[ci];
    let (px, z) = cam.project(point)?;
    if options.use_depth && !visible_in(cam, views[ci], px, z) {
        return None;
    }
    views[ci].picture.sample(px[0], px[1])
}

/// The weights `w`' blend of each camera's `sample`, over the cameras that
/// see (the others' weights renormalised away); `None` when none does.
fn blend_samples(w: &[(usize, f64)], mut sample: impl FnMut(usize) -> Option<[f32; 3]>) -> Option<[f64; 3]> {
    let (mut sum, mut total) = ([0.0f64; 3], 0.0);
    for &(ci, wi) in w {
        let Some(rgb) = sample(ci) else { continue };
        for k in 0..3 {
            sum[k] += wi * rgb[k] as f64;
        }
        total += wi;
    }
    (total > 0.0).then(|| sum.map(|s| s / total))
}

/// The surface point along the ray according to the depth map of the
/// most-weighted camera that has one: a few fixed-point steps from the
/// focus point (project, read the depth, move to that depth along the ray).
fn refine_with_depth(
    rig: &Rig,
    views: &[&CameraView],
    w: &[(usize, f64)],
    origin: [f64; 3],
    dir: [f64; 3],
    start: [f64; 3],
) -> [f64; 3] {
    let Some(&(ci, _)) = w.iter().filter(|(ci, _)| views[*ci].depth_z.is_some()).max_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return start;
    };
    let cam = &rig.cameras[ci];
    let depth = views[ci].depth_z.as_ref().expect("filtered");
    let axis = cam.axis();
    let along = dot(dir, axis);
    if along.abs() < 1e-12 {
        return start;
    }
    let mut p = start;
    for _ in 0..8 {
        let Some((px, _)) = cam.project(p) else { return p };
        let Some(z) = depth_at(cam, depth, px) else { return p };
        if !z.is_finite() {
            return p;
        }
        // The point of the ray whose camera z is `z`.
        let t = (z - dot(sub(origin, cam.pose.centre), axis)) / along;
        let next = add(origin, scale(dir, t));
        let moved = length(sub(next, p));
        p = next;
        if moved <= 1e-9 * z.abs().max(1e-300) {
            break;
        }
    }
    p
}

/// The depth map's camera `z` at the pixel nearest `px`.
fn depth_at(cam: &Camera, depth: &[f32], px: [f64; 2]) -> Option<f64> {
    let (u, v) = (px[0].round(), px[1].round());
    if !(u >= 0.0 && v >= 0.0 && u < cam.width as f64 && v < cam.height as f64) {
        return None;
    }
    Some(depth[v as usize * cam.width + u as usize] as f64)
}

/// The point at camera depth `z` projecting to `px` is what the camera
/// saw (not hidden behind a nearer surface), by its own depth map: within
/// 1% of the depth (and two pixels' worth of the slope) of the map.
fn visible_in(cam: &Camera, view: &CameraView, px: [f64; 2], z: f64) -> bool {
    let Some(depth) = &view.depth_z else { return true };
    match depth_at(cam, depth, px) {
        Some(d) => z <= d * 1.01 + 1e-12,
        None => false,
    }
}

/// Up to five names, then how many more.
fn list_names(names: &[&str]) -> String {
    let mut s = names.iter().take(5).copied().collect::<Vec<_>>().join(", ");
    if names.len() > 5 {
        s.push_str(&format!(" and {} more", names.len() - 5));
    }
    s
}

/// Two cameras at one place looking the same way (to calibration precision).
fn same_pose(a: &Camera, b: &Camera) -> bool {
    let scale = length(a.pose.centre).max(length(b.pose.centre)).max(1e-300);
    length(sub(a.pose.centre, b.pose.centre)) <= 1e-9 * scale
        && (0..3).all(|i| length(sub(a.pose.rotation[i], b.pose.rotation[i])) <= 1e-9)
}

fn mean(v: &[[f64; 3]]) -> [f64; 3] {
    let n = v.len().max(1) as f64;
    let mut m = [0.0; 3];
    for p in v {
        for k in 0..3 {
            m[k] += p[k] / n;
        }
    }
    m
}

/// The principal axes of points (unit, by decreasing spread), the
/// standard deviations along them, and the largest distance from their mean.
fn principal_axes(points: &[[f64; 3]]) -> ([[f64; 3]; 3], [f64; 3], f64) {
    let m = mean(points);
    let mut cov = [[0.0; 3]; 3];
    let mut extent = 0.0f64;
    for p in points {
        let d = sub(*p, m);
        extent = extent.max(length(d));
        for a in 0..3 {
            for b in 0..3 {
                cov[a][b] += d[a] * d[b] / points.len() as f64;
            }
        }
    }
    let (vectors, values) = symmetric_eigen(cov);
    (vectors, values.map(|x| x.max(0.0).sqrt()), extent)
}

/// Eigenvectors (rows, unit) and eigenvalues of a symmetric 3 × 3 matrix,
/// by decreasing eigenvalue: cyclic Jacobi rotations, f64, to convergence.
fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([[f64; 3]; 3], [f64; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..64 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let (c, s) = (1.0 / (t * t + 1.0).sqrt(), t / (t * t + 1.0).sqrt());
            // A ← Jᵀ A J with J the rotation in the (p, q) plane.
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            for k in 0..3 {
                a[p][k] = c * rp[k] - s * rq[k];
                a[q][k] = s * rp[k] + c * rq[k];
            }
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    // Columns of v are the eigenvectors.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let vectors = order.map(|i| [v[0][i], v[1][i], v[2][i]]);
    (vectors, order.map(|i| a[i][i]))
}

/// Collinear cameras are a rail, which samples parallax along its line
/// only: across the display's horizontal parallax it works, but a line
/// running up and down would give every view of a hololine the same camera.
/// Such a rig needs cameras off the line (a grid).
fn refuse_a_rail_off_the_horizontal(
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
fn display_scale(
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
fn ring_frame(rig: &Rig, normal: [f64; 3], mean_down: [f64; 3]) -> (Mat3, String) {
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
fn eye_map(
    rig: &Rig,
    g: &Geometry,
    request: &PlacementRequest,
    surface: &Surface,
    points: &[[f64; 2]],
    x_d: [f64; 3],
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
    let eyes_words =
        format!("eyes from {:+.0} to {:+.0} mm at {:.0} mm", eyes_m[0] * 1e3, eyes_m[1] * 1e3, viewer_span_m * 1e3);
    match surface {
        Surface::Plane { u: u_axis, .. } => {
            let [lo, hi] = range(0);
            let v = range(1);
            // Left eyes see from the left cameras: u oriented along display x.
            let u = if dot(*u_axis, x_d) >= 0.0 { [lo, hi] } else { [hi, lo] };
            let words = format!("parallax fitted: the cameras' {:.4} units across the {eyes_words}", hi - lo);
            (Some(EyeMap { viewer_span_m, eyes_m, target: EyeTarget::Plane { u, v: 0.5 * (v[0] + v[1]) } }), words)
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
            let target = EyeTarget::Sphere { azimuth, elevation: 0.5 * (el[0] + el[1]), radius };
            (Some(EyeMap { viewer_span_m, eyes_m, target }), words)
        }
    }
}

/// Where the cameras' axes come closest to meeting (least squares), if
/// they are not all parallel.
fn axes_meet(cameras: &[Camera]) -> Option<[f64; 3]> {
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

fn solve3(m: [[f64; 3]; 3], r: [f64; 3]) -> Option<[f64; 3]> {
    let det = det3(&m);
    let scale_m = m.iter().flatten().fold(0.0f64, |a, &b| a.max(b.abs()));
    if det.is_nan() || det.abs() <= 1e-9 * scale_m.powi(3) {
        return None;
    }
    // Cramer's rule, columns replaced by r.
    let col = |k: usize| -> f64 {
        let mut c = m;
        for i in 0..3 {
            c[i][k] = r[i];
        }
        det3(&c) / det
    };
    Some([col(0), col(1), col(2)])
}

/// Azimuth (toward display `x`) and elevation (toward display `y`) of a
/// unit direction, in the display-aligned frame `rotation`.
fn direction_coords(d: [f64; 3], rotation: &[[f64; 3]; 3]) -> [f64; 2] {
    let (x, y, z) = (dot(d, rotation[0]), dot(d, rotation[1]), dot(d, rotation[2]));
    [x.atan2(z), y.clamp(-1.0, 1.0).asin()]
}

/// `a · (1/|a|)`; NaN for a zero vector, which the placement's checks
/// then report, rather than a made-up direction.
fn normalized(a: [f64; 3]) -> [f64; 3] {
    normalize_or(a, [f64::NAN; 3])
}
