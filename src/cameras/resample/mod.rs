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

pub use self::rig_geometry::RigGeometry;
use self::surface::Scratch;
use super::image::Picture;
use super::{Camera, Rig};
use crate::error::{Error, Result};
use crate::geometry::{channel_weights, Geometry};
use crate::math::{add, dot, length, scale, sub, Mat3};
use crate::modulation::{Band, Modulation};
use crate::progress::Progress;

mod rig_geometry;
mod surface;

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
    /// pixels across an emitter at the focus (1 to 16). For full parallax
    /// as many again up it (`n × n`; by default from the hololine pitch).
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
    /// tan θ of every (horizontal) view.
    slopes: Vec<f64>,
    /// Full parallax: tan φ of every vertical view (spec §8); `None` for
    /// horizontal parallax, whose rays go toward the viewer line.
    vertical_slopes: Option<Vec<f64>>,
    /// Offsets across an emitter's aperture of the rays averaged, metres.
    tap_x_m: Vec<f64>,
    /// Their offsets up the aperture: `[0]` for horizontal parallax (a
    /// hololine has no height to average over); for full parallax an
    /// emitter is a cell as tall as the hololine pitch, sampled as across.
    tap_y_m: Vec<f64>,
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
        let offsets = |pitch_m: f64, taps: usize| -> Vec<f64> {
            (0..taps).map(|k| pitch_m * ((k as f64 + 0.5) / taps as f64 - 0.5)).collect()
        };
        let tap_y_m = match &g.vertical_views {
            None => vec![0.0],
            Some(_) => {
                let taps = options
                    .emitter_taps
                    .unwrap_or_else(|| ((g.hololine_pitch_m / geo.pixel_at_focus_m).ceil() as usize).clamp(1, 16));
                offsets(g.hololine_pitch_m, taps)
            }
        };
        Ok(RigResampler {
            views,
            weights: channel_weights(&names),
            slopes: (0..g.views.count).map(|k| g.ray_slope_x(k as f64)).collect(),
            vertical_slopes: g
                .vertical_views
                .as_ref()
                .map(|vertical| (0..vertical.count).map(|k| vertical.theta_at(k as f64).tan()).collect()),
            tap_x_m: offsets(g.emitter_pitch_m, taps),
            tap_y_m,
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
    /// blending, an eye map, the fast path, horizontal parallax (a full-
    /// parallax eye's height depends on the hololine) and not too many rays.
    fn with_ray_weights(mut self) -> Self {
        use rayon::prelude::*;
        let (g, taps) = (&self.g, self.tap_x_m.len());
        let rays = g.emitters * taps * g.views.count;
        let worth = self.options.blend == Blend::NaturalNeighbour
            && self.vertical_slopes.is_none()
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
        let (e, v, c) = (g.emitters, g.views_per_emitter(), g.channels.len());
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

    /// Per view (every view of an emitter, [`Geometry::view_index`] order),
    /// the ray's point on the camera surface as an affine function of
    /// emitter-plane `x` along the line at height `y`, when the
    /// directions are as captured: rays of one view along a hololine then
    /// differ only in their origin, which moves along a line, so their
    /// crossings of a camera plane step evenly and their directions stay.
    /// Fitted from the hololine's first and last rays. Empty when the focus
    /// point is not shared (rays are then found one by one) or an eye map
    /// gives the points (by its own affine arithmetic, as cheap as a step
    /// and exactly the reference's: its outermost rays land exactly on the
    /// end cameras, where a rounding would lose them).
    fn surface_steps(&self, y: f64) -> Vec<Option<SurfaceStep>> {
        let g = &self.g;
        let first = g.emitter_x_m(0) + self.tap_x_m[0];
        let last = g.emitter_x_m(g.emitters - 1) + self.tap_x_m[self.tap_x_m.len() - 1];
        if !(self.shared_focus && self.geo.eye_map.is_none() && last > first) {
            return Vec::new();
        }
        (0..g.views_per_emitter())
            .map(|vi| {
                let (sx, sy) = self.slopes_of(vi, y);
                let point = |x: f64| self.geo.ray_surface_point(Ray { x, y, sx, sy });
                let (a, b) = (point(first)?, point(last)?);
                let per_m = [(b[0] - a[0]) / (last - first), (b[1] - a[1]) / (last - first)];
                Some(SurfaceStep { x0: first, at_x0: a, per_m })
            })
            .collect()
    }

    /// The slopes `(dx/dz, dy/dz)` of view `vi` (an index among an emitter's
    /// views) for rays leaving the emitter plane at height `y`: toward the
    /// viewer line for horizontal parallax, at the vertical view's `φ` for
    /// full parallax (the one ray geometry, [`Geometry::ray_at_views`]).
    fn slopes_of(&self, vi: usize, y: f64) -> (f64, f64) {
        match &self.vertical_slopes {
            None => (self.slopes[vi], self.g.ray_slope_y(y)),
            Some(vertical) => {
                let (h, k) = self.g.view_of_index(vi);
                (self.slopes[h], vertical[k])
            }
        }
    }

    /// Fill hololine `j`'s `rows` (one per channel, emitter-major) and, when
    /// `mask` is not empty, mark its unseen rays; returns those.
    fn fill_hololine(&self, j: usize, rows: &mut [&mut [f32]], mask: &mut [bool]) -> Unseen {
        let g = &self.g;
        let v = g.views_per_emitter();
        let y_line = g.hololine_y_m(j);
        let mut unseen = Unseen::default();
        let (mut w, mut scratch) = (Vec::new(), Scratch::new(v));
        // Per view: the radiance summed over the emitter's taps, and the taps that saw.
        let mut sums = vec![([0.0f64; 3], 0usize); v];
        let mut shared = SharedFocus { point: [0.0; 3], samples: vec![None; self.rig.cameras.len()] };
        // Per row of taps up the aperture (one for horizontal parallax): its
        // height, and each view's slopes and steps along it.
        let tap_rows: Vec<TapRow> = self
            .tap_y_m
            .iter()
            .map(|dy| {
                let y = y_line + dy;
                TapRow { y, slopes: (0..v).map(|vi| self.slopes_of(vi, y)).collect(), steps: self.surface_steps(y) }
            })
            .collect();
        for ei in 0..g.emitters {
            let x = g.emitter_x_m(ei);
            sums.fill(([0.0; 3], 0));
            for ((ti, dx), TapRow { y, slopes, steps }) in
                tap_rows.iter().flat_map(|row| self.tap_x_m.iter().enumerate().map(move |tap| (tap, row)))
            {
                let (x, y) = (x + dx, *y);
                if self.shared_focus {
                    shared.point = self.geo.capture_point(x, y);
                    shared.samples.fill(None);
                }
                for (vi, &(sx, sy)) in slopes.iter().enumerate() {
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
            let in_frame = self.geo.in_frame(&self.rig, x, y_line);
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
            emitter_taps: self.tap_x_m.len() * self.tap_y_m.len(),
            warnings: self.warnings.clone(),
            surface: self.geo.surface_words(self.rig.cameras.len()),
            rays: (g.hololines * g.emitters * g.views_per_emitter()) as u64,
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

/// A row of rays across an emitter's aperture at height `y`: each view's
/// slopes `(dx/dz, dy/dz)` and [`SurfaceStep`].
struct TapRow {
    y: f64,
    slopes: Vec<(f64, f64)>,
    steps: Vec<Option<SurfaceStep>>,
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
