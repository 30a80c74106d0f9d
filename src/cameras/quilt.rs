//! Looking Glass quilts: a frame of modulation as the pictures of a row of
//! cameras, tiled into one image, so a `.holo` file can be looked at on the
//! most common light-field display; and the same cameras
//! as a [`Rig`], so a quilt can be read back as a capture.
//!
//! **The quilt.** `columns × rows` tiles of `tile_width × tile_height`
//! pixels; view 0 is the leftmost camera and fills the *bottom-left* tile,
//! later views go left to right, then up a row, the last view top right. A
//! tile is shown stretched to the display's aspect `aspect` (width/height of
//! a view). The file name carries the layout the Looking Glass software
//! reads: `NAME_qs{columns}x{rows}a{aspect}.png` ([`quilt_file_name`]).
//!
//! **The cameras.** All views frame the same rectangle of the display's
//! emitter plane `z = z_e`: the emitters' and hololines' apertures (each
//! emitter and hololine half a pitch beyond its centre), widened to the
//! aspect `aspect` about its centre (bars above and below a wide display,
//! beside a tall one). The cameras sit on the display's viewer line
//! (`y = y_v`, `z = D`, a distance `s = D − z_e` from that plane), looking
//! toward `−z` with shifted sensors (sheared frustums, no toe-in); camera
//! `i` of `N` sees the rectangle's centre at the angle
//! `φ_i = (i/(N − 1) − ½) · view_cone`, so it is at
//! `x_i = x_centre + s · tan φ_i` (the HoloPlay / Looking Glass camera
//! rule: uniform in angle, leftmost first). On the viewer line, a camera's
//! ray through a point of the emitter plane is a ray of the display, so a
//! tile pixel is the modulation's sample there: hololine from the point's
//! `y`, emitter from its `x`, view from the direction
//! `θ = atan((x_i − x)/s)` through the file's view-spacing rule, each
//! interpolated linearly. Rays outside the emitters, hololines or views (by
//! more than half a pitch or half a view) are black.
//!
//! **Beyond the views.** The outer cameras see the far side of the display
//! along directions steeper than the file's last view: those pixels are
//! black, with a hard edge where the views end. That is what the display
//! itself shows an eye there (no light leaves an emitter beyond its views);
//! a fill from the outermost view would show light the file does not hold,
//! and a fade would hide where the file ends. [`export_quilt`] says which
//! tiles are so cut, and the view cone that shows every tile whole
//! ([`whole_tiles_view_cone_deg`]), at the cost of parallax.
//!
//! **Full parallax.** A quilt's cameras all sit on the viewer line, so a
//! full-parallax file is first made the horizontal-parallax frame it shows
//! there ([`full_to_horizontal`]): each emitter row's views in the vertical
//! direction toward the viewer line, linearly between the two nearest
//! vertical views, read band by band. Rows whose vertical views end more
//! than half a view short of that direction are black, and said.
//!
//! **Presets**: Looking Glass's quilt settings per device, from its
//! key-concepts page <https://lfdocs.lookingglassfactory.com/keyconcepts/quilts>
//! as the Looking Glass Blender add-on (Alice/LG, the `pylightio` quilt
//! formats: "Portrait, 48 Views", "4k Quilt, 45 Views", "Go, 66 Views") and
//! the `quiltwright` package (`QUILT_PRESETS`, citing that page) tabulate
//! them:
//!
//! | preset            | tiles  | tile    | quilt                   | aspect |
//! |-------------------|--------|---------|-------------------------|--------|
//! | `portrait`        | 8 × 6  | 420×560 | 3360×3360               | 0.75   |
//! | `standard` (`4k`) | 5 × 9  | 819×455 | 4096×4096 (4095 used)   | 1.6    |
//! | `go`              | 11 × 6 | 372×682 | 4092×4092               | 0.5625 |
//!
//! `standard` is the first-generation 8.9″ display's 4k quilt (its 2560×1600
//! screen gives the aspect 1.6, the `a1.6` of the add-on's example name
//! `quiltfilename_qs5x9a1.6.png`); the quilt written is 4095 × 4095, the
//! tiles without Looking Glass's unused last row and column. The view cone
//! (35°) and field of view (14°) defaults are HoloPlay's camera defaults.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::{look_rotation, Camera, ImageSource, Intrinsics, Pose, Rig};
use crate::error::{Error, Result};
use crate::geometry::{Geometry, Parallax, Views};
use crate::modulation::{full_to_horizontal, rows_beyond_vertical_views, Modulation};
use crate::picture::{encode_png, Bits, Colour, Tone, White};
use crate::sampling::linear_taps;

/// The layout of a quilt and the cameras that fill it.
#[derive(Clone, Debug, PartialEq)]
pub struct QuiltSpec {
    /// Tiles per row.
    pub columns: usize,
    /// Rows of tiles.
    pub rows: usize,
    /// Tile width in pixels.
    pub tile_width: usize,
    /// Tile height in pixels.
    pub tile_height: usize,
    /// Width over height of a view as displayed (a tile is stretched to it).
    pub aspect: f64,
    /// Angle between the outermost cameras' lines of sight to the centre
    /// of the framed rectangle, degrees.
    pub view_cone_deg: f64,
    /// Vertical field of view of a Looking Glass capture's cameras, degrees:
    /// with it, a quilt read as a rig puts its cameras at half the framed
    /// height over `tan(fov/2)` from the focal plane. An exported quilt's
    /// cameras are at the display's viewer distance instead, and
    /// [`QuiltReport::vertical_fov_deg`] gives the field of view they have.
    pub vertical_fov_deg: f64,
}

/// HoloPlay's default view cone, degrees.
pub const DEFAULT_VIEW_CONE_DEG: f64 = 35.0;
/// HoloPlay's default vertical field of view, degrees.
pub const DEFAULT_VERTICAL_FOV_DEG: f64 = 14.0;
/// Names of the presets, for messages and `--preset`.
pub const PRESETS: [&str; 3] = ["portrait", "standard", "go"];

/// The largest quilt made, in pixels (16384 × 16384).
const MAX_PIXELS: usize = 1 << 28;

impl QuiltSpec {
    fn new(columns: usize, rows: usize, tile_width: usize, tile_height: usize, aspect: f64) -> QuiltSpec {
        QuiltSpec {
            columns,
            rows,
            tile_width,
            tile_height,
            aspect,
            view_cone_deg: DEFAULT_VIEW_CONE_DEG,
            vertical_fov_deg: DEFAULT_VERTICAL_FOV_DEG,
        }
    }

    /// Looking Glass Portrait: 8 × 6 tiles of 420 × 560 (3360 × 3360), aspect 0.75.
    pub fn portrait() -> QuiltSpec {
        QuiltSpec::new(8, 6, 420, 560, 0.75)
    }

    /// The first-generation 8.9″ Looking Glass's 4k quilt: 5 × 9 tiles of
    /// 819 × 455 (4095 × 4095 of its 4096 × 4096), aspect 1.6.
    pub fn standard() -> QuiltSpec {
        QuiltSpec::new(5, 9, 819, 455, 1.6)
    }

    /// Looking Glass Go: 11 × 6 tiles of 372 × 682 (4092 × 4092), aspect 0.5625.
    pub fn go() -> QuiltSpec {
        QuiltSpec::new(11, 6, 372, 682, 0.5625)
    }

    /// A preset by name ([`PRESETS`]; `4k` is `standard`).
    pub fn preset(name: &str) -> Option<QuiltSpec> {
        match name.to_ascii_lowercase().as_str() {
            "portrait" => Some(QuiltSpec::portrait()),
            "standard" | "4k" => Some(QuiltSpec::standard()),
            "go" => Some(QuiltSpec::go()),
            _ => None,
        }
    }

    /// Number of views (tiles).
    pub fn views(&self) -> usize {
        self.columns * self.rows
    }

    /// Quilt width in pixels.
    pub fn width(&self) -> usize {
        self.columns * self.tile_width
    }

    /// Quilt height in pixels.
    pub fn height(&self) -> usize {
        self.rows * self.tile_height
    }

    /// Pixel column and row of the top-left corner of view `i`'s tile
    /// (view 0 bottom left, then left to right, rows upward).
    pub fn tile_origin(&self, i: usize) -> (usize, usize) {
        let (column, row_up) = (i % self.columns, i / self.columns);
        (column * self.tile_width, (self.rows - 1 - row_up) * self.tile_height)
    }

    /// What is wrong with the numbers, if anything.
    pub fn problem(&self) -> Option<String> {
        for (what, n) in [
            ("columns", self.columns),
            ("rows", self.rows),
            ("tile width", self.tile_width),
            ("tile height", self.tile_height),
        ] {
            if n == 0 {
                return Some(format!("the quilt has 0 {what}; it needs at least 1"));
            }
        }
        let fits = |a: usize, b: usize| a.checked_mul(b).filter(|&n| n <= MAX_PIXELS);
        let size =
            fits(self.columns, self.tile_width).zip(fits(self.rows, self.tile_height)).and_then(|(w, h)| fits(w, h));
        if size.is_none() {
            return Some(format!(
                "a quilt of {} × {} tiles of {} × {} pixels is larger than the limit of {MAX_PIXELS} pixels",
                self.columns, self.rows, self.tile_width, self.tile_height
            ));
        }
        if !(self.aspect.is_finite() && self.aspect > 0.0) {
            return Some(format!("the aspect {} must be a positive width/height ratio", self.aspect));
        }
        if !(self.view_cone_deg.is_finite() && self.view_cone_deg >= 0.0 && self.view_cone_deg < 180.0) {
            return Some(format!("the view cone {}° must be from 0° to less than 180°", self.view_cone_deg));
        }
        if !(self.vertical_fov_deg.is_finite() && self.vertical_fov_deg > 0.0 && self.vertical_fov_deg < 180.0) {
            return Some(format!("the field of view {}° must be between 0° and 180°", self.vertical_fov_deg));
        }
        None
    }
}

/// `{stem}_qs{columns}x{rows}a{aspect}.png`, the aspect printed as the
/// Looking Glass software does: shortest decimal, at most 4 places
/// (`a0.75`, `a1.6`, `a0.5625`).
pub fn quilt_file_name(stem: &str, spec: &QuiltSpec) -> String {
    let aspect = format!("{:.4}", spec.aspect);
    let aspect = aspect.trim_end_matches('0').trim_end_matches('.');
    format!("{stem}_qs{}x{}a{aspect}.png", spec.columns, spec.rows)
}

/// Where the cameras are and what they frame.
#[derive(Clone, Debug)]
struct Framing {
    /// Left and right `x` of the framed rectangle.
    x: [f64; 2],
    /// Bottom and top `y`.
    y: [f64; 2],
    /// Distance from the cameras to the rectangle.
    s: f64,
    /// `y` and `z` of every camera.
    eye_yz: [f64; 2],
    /// `x` of each camera, view 0 first.
    eye_x: Vec<f64>,
}

impl Framing {
    fn new(g: &Geometry, spec: &QuiltSpec) -> Framing {
        let (pe, pj) = (g.emitter_pitch_m, g.hololine_pitch_m);
        let left = g.emitter_left_x_m - pe / 2.0;
        let right = g.emitter_x_m(g.emitters - 1) + pe / 2.0;
        let top = g.hololine_top_y_m + pj / 2.0;
        let bottom = g.hololine_y_m(g.hololines - 1) - pj / 2.0;
        let (cx, cy) = ((left + right) / 2.0, (top + bottom) / 2.0);
        let (mut w, mut h) = (right - left, top - bottom);
        if w / h > spec.aspect {
            h = w / spec.aspect;
        } else {
            w = h * spec.aspect;
        }
        let s = g.viewer_distance_m - g.emitter_z_m;
        let n = spec.views();
        let cone = spec.view_cone_deg.to_radians();
        let eye_x = (0..n)
            .map(|i| {
                let phi = if n > 1 { (i as f64 / (n - 1) as f64 - 0.5) * cone } else { 0.0 };
                cx + s * phi.tan()
            })
            .collect();
        Framing {
            x: [cx - w / 2.0, cx + w / 2.0],
            y: [cy - h / 2.0, cy + h / 2.0],
            s,
            eye_yz: [g.viewer_height_m, g.viewer_distance_m],
            eye_x,
        }
    }

    /// The point of the framed rectangle at tile pixel `(u, v)` (centres at
    /// integers, `(0, 0)` top left).
    fn point(&self, spec: &QuiltSpec, u: f64, v: f64) -> (f64, f64) {
        let x = self.x[0] + (u + 0.5) / spec.tile_width as f64 * (self.x[1] - self.x[0]);
        let y = self.y[1] - (v + 0.5) / spec.tile_height as f64 * (self.y[1] - self.y[0]);
        (x, y)
    }

    /// Camera `i` as a pinhole camera whose picture is its tile of `file`.
    fn camera(&self, spec: &QuiltSpec, i: usize, file: &Path) -> Camera {
        let (w, h) = (spec.tile_width as f64, spec.tile_height as f64);
        let (fw, fh) = (self.x[1] - self.x[0], self.y[1] - self.y[0]);
        let (ex, [ey, ez]) = (self.eye_x[i], self.eye_yz);
        let (x, y) = spec.tile_origin(i);
        Camera {
            name: format!("view {i}"),
            image: ImageSource::Tile {
                file: file.to_path_buf(),
                x,
                y,
                width: spec.tile_width,
                height: spec.tile_height,
            },
            width: spec.tile_width,
            height: spec.tile_height,
            // u = w (x − x_left)/W − ½ and v = h (y_top − y)/H − ½ on the plane.
            intrinsics: Intrinsics {
                fx: self.s * w / fw,
                fy: self.s * h / fh,
                cx: w * (ex - self.x[0]) / fw - 0.5,
                cy: h * (self.y[1] - ey) / fh - 0.5,
            },
            pose: Pose { rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]), centre: [ex, ey, ez] },
            depth: None,
        }
    }
}

/// The cameras of a quilt of `spec` exported from a file of geometry `g`,
/// as a rig whose pictures are the tiles of `file` (display metres, sRGB
/// pictures, in focus at the emitter plane).
pub fn quilt_rig(g: &Geometry, spec: &QuiltSpec, file: &Path) -> Result<Rig> {
    check(g, spec).map_err(|e| e.naming(file))?;
    let f = Framing::new(g, spec);
    Ok(Rig {
        source: file.display().to_string(),
        cameras: (0..spec.views()).map(|i| f.camera(spec, i, file)).collect(),
        metres_per_unit: 1.0,
        focus_distance: Some(f.s),
        linear: false,
    })
}

fn check(g: &Geometry, spec: &QuiltSpec) -> Result<()> {
    if let Some(p) = spec.problem() {
        return Err(Error::argument("quilt", format!("cannot make a quilt: {p}")));
    }
    let problems = g.problems();
    if !problems.is_empty() {
        return Err(Error::argument("geometry", format!("invalid geometry: {}", problems.join("; "))));
    }
    Ok(())
}

/// A quilt in linear radiance.
#[derive(Clone, Debug, PartialEq)]
pub struct Quilt {
    /// Its layout.
    pub spec: QuiltSpec,
    /// Width in pixels (`columns × tile_width`).
    pub width: usize,
    /// Height in pixels (`rows × tile_height`).
    pub height: usize,
    /// The modulation had one channel (`Y`): the three components are equal.
    pub grey: bool,
    /// Linear RGB, row by row from the top; a colour the modulation lacks is 0.
    pub rgb: Vec<[f32; 3]>,
    /// Pixels whose ray the modulation does not hold (black).
    pub outside: u64,
    /// Per tile (view 0 first), its pixels that show the emitters from
    /// beyond the file's views: black, where the rest of the tile is lit.
    pub beyond_views: Vec<u64>,
}

/// Resample one frame of modulation into a quilt (see the module's text for
/// the cameras and the interpolation).
pub fn quilt_from_modulation(m: &Modulation, spec: &QuiltSpec) -> Result<Quilt> {
    let g = m.geometry();
    check(g, spec)?;
    let f = Framing::new(g, spec);
    let (width, height) = (spec.width(), spec.height());
    // Where each channel goes: R, G, B to their component, Y to all three.
    let slots: Vec<(usize, Vec<usize>)> = g
        .channels
        .iter()
        .enumerate()
        .map(|(c, ch)| {
            let to = match ch.name.as_str() {
                "R" => vec![0],
                "G" => vec![1],
                "B" => vec![2],
                _ => vec![0, 1, 2],
            };
            (c, to)
        })
        .collect();
    let grey = g.channels.len() == 1 && g.channels[0].name == "Y";
    let rows: Vec<(Vec<[f32; 3]>, u64, Vec<u64>)> = (0..height)
        .into_par_iter()
        .map(|py| {
            let mut row = vec![[0f32; 3]; width];
            let mut outside = 0u64;
            // Per tile of this row.
            let mut beyond = vec![0u64; spec.columns];
            let row_up = spec.rows - 1 - py / spec.tile_height;
            let v = (py % spec.tile_height) as f64;
            for (px, out) in row.iter_mut().enumerate() {
                let i = row_up * spec.columns + px / spec.tile_width;
                let u = (px % spec.tile_width) as f64;
                let (x, y) = f.point(spec, u, v);
                let theta = g.ray_slope_x_toward(x, f.eye_x[i]).atan();
                let tj = linear_taps((g.hololine_top_y_m - y) / g.hololine_pitch_m, g.hololines);
                let te = linear_taps((x - g.emitter_left_x_m) / g.emitter_pitch_m, g.emitters);
                let tv = if g.views.count == 1 {
                    linear_taps(0.0, 1)
                } else {
                    linear_taps(g.views.index_at(theta), g.views.count)
                };
                let (Some(tj), Some(te), Some(tv)) = (tj, te, tv) else {
                    outside += 1;
                    beyond[px / spec.tile_width] += u64::from(tj.is_some() && te.is_some());
                    continue;
                };
                for (c, to) in &slots {
                    let mut value = 0f32;
                    for (j, wj) in tj {
                        for (e, we) in te {
                            let w = wj * we;
                            if w == 0.0 {
                                continue;
                            }
                            let views = m.views_of(*c, j, e);
                            value += w * (tv[0].1 * views[tv[0].0] + tv[1].1 * views[tv[1].0]);
                        }
                    }
                    for &k in to {
                        out[k] = value;
                    }
                }
            }
            (row, outside, beyond)
        })
        .collect();
    let mut quilt = Quilt {
        spec: spec.clone(),
        width,
        height,
        grey,
        rgb: Vec::with_capacity(width * height),
        outside: 0,
        beyond_views: vec![0; spec.views()],
    };
    for (py, (row, outside, beyond)) in rows.into_iter().enumerate() {
        quilt.rgb.extend(row);
        quilt.outside += outside;
        let row_up = spec.rows - 1 - py / spec.tile_height;
        for (column, n) in beyond.into_iter().enumerate() {
            quilt.beyond_views[row_up * spec.columns + column] += n;
        }
    }
    Ok(quilt)
}

impl Quilt {
    /// The sample value `white` chooses as full white among every component
    /// of every pixel (letterbox bars and rays outside the file included).
    pub fn white_level(&self, white: White) -> f32 {
        white.level(self.rgb.iter().flatten().copied())
    }

    /// The quilt as an 8-bit sRGB PNG (grey for a grey quilt), tone-mapped
    /// as every picture is ([`crate::picture`]): sample value `white` is full white.
    pub fn png(&self, white: f32) -> Result<Vec<u8>> {
        let tone = Tone::new(white, Bits::Eight)?;
        let colour = if self.grey { Colour::Grey } else { Colour::Rgb };
        encode_png(self.width, self.height, colour, &tone, None, |x, y| self.rgb[y * self.width + x])
    }

    /// Write [`Quilt::png`] to `path`; an existing file is kept unless `overwrite`.
    pub fn write_png(&self, path: &Path, white: f32, overwrite: bool) -> Result<()> {
        let png = self.png(white).map_err(|e| e.naming(path))?;
        crate::output::write_bytes_beside(path, &png, overwrite)
    }
}

/// How [`export_quilt`] tone-maps and writes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct QuiltOptions {
    /// The sample value shown as white, chosen among the quilt's pixels.
    pub white: White,
    /// Replace an existing output file.
    pub overwrite: bool,
}

/// What [`export_quilt`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct QuiltReport {
    /// The PNG written.
    pub path: PathBuf,
    /// Its width in pixels.
    pub width: usize,
    /// Its height in pixels.
    pub height: usize,
    /// Number of views (tiles).
    pub views: usize,
    /// The sample value shown as white.
    pub white: f32,
    /// Pixels whose ray the file does not hold (black).
    pub outside: u64,
    /// The framed rectangle of the emitter plane, metres: left, right, bottom, top.
    pub frame_m: [f64; 4],
    /// The cameras' distance from it, metres.
    pub distance_m: f64,
    /// The vertical field of view the cameras have, degrees.
    pub vertical_fov_deg: f64,
    /// Tiles that look from beyond the file's views, or views no tile
    /// shows: said, with the view cone that fits.
    pub warnings: Vec<String>,
}

/// The view cone, degrees, that fits a file's views: a quilt's cameras are
/// symmetric about the axis, so the cone reaches out to the nearer of the
/// first and last view (all of a symmetric file's views, no tile beyond
/// them).
pub fn view_cone_deg_for(views: &Views) -> f64 {
    2.0 * views.first_theta_rad.abs().min(views.last_theta_rad.abs()).to_degrees()
}

/// The tiles whose centre looks from beyond `views`: black, or nearly.
fn black_tiles(views: &Views, spec: &QuiltSpec) -> Vec<usize> {
    let n = spec.views();
    let half_rad = spec.view_cone_deg.to_radians() / 2.0;
    let phi = |i: usize| if n > 1 { (i as f64 / (n - 1) as f64 - 0.5) * 2.0 * half_rad } else { 0.0 };
    let span = views.count as f64 - 0.5;
    (0..n).filter(|&i| !(-0.5..=span).contains(&views.index_at(phi(i)))).collect()
}

/// What a quilt of `spec` leaves out of `views`, or shows beyond them.
fn view_cone_warnings(views: &Views, spec: &QuiltSpec) -> Vec<String> {
    let n = spec.views();
    let half_rad = spec.view_cone_deg.to_radians() / 2.0;
    let black = black_tiles(views, spec).len();
    let left_out = (0..views.count).filter(|&k| views.theta_rad(k).abs() > half_rad + 1e-12).count();
    let range = format!(
        "the file's views run from {:+.1}° to {:+.1}°",
        views.first_theta_rad.to_degrees(),
        views.last_theta_rad.to_degrees()
    );
    let fit = view_cone_deg_for(views);
    let mut warnings = Vec::new();
    if black > 0 {
        warnings.push(format!(
            "{black} of {n} tiles look from beyond the file's views and are black: {range}, the quilt spans \
             {:.1}°; a view cone of {fit:.1}° fits them",
            spec.view_cone_deg
        ));
    }
    if left_out > 0 {
        warnings.push(format!(
            "{left_out} of the file's {} views lie outside the quilt's {:.1}° and are not shown: {range}",
            views.count, spec.view_cone_deg
        ));
    }
    warnings
}

/// The widest view cone, degrees, whose every tile shows all the emitters
/// from within the file's views (none partly black), or `None` when no cone
/// does (the views are too narrow for the display's width at the viewer's
/// distance). The rightmost camera sees the leftmost emitter edge at the
/// steepest angle, the leftmost camera the rightmost edge.
pub fn whole_tiles_view_cone_deg(g: &Geometry) -> Option<f64> {
    let views = &g.views;
    if views.count <= 1 {
        return None;
    }
    let s = g.viewer_distance_m - g.emitter_z_m;
    let pe = g.emitter_pitch_m / 2.0;
    let (left, right) = (g.emitter_left_x_m - pe, g.emitter_x_m(g.emitters - 1) + pe);
    let centre = (left + right) / 2.0;
    // The directions the file holds, each view half an interval either side.
    let (lo, hi) = (views.theta_at(-0.5), views.theta_at(views.count as f64 - 0.5));
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    let right_camera = (hi.tan() - (centre - left) / s).atan();
    let left_camera = (lo.tan() + (right - centre) / s).atan();
    let half = right_camera.min(-left_camera);
    (half > 0.0).then(|| 2.0 * half.to_degrees())
}

/// `views` (sorted) as runs: `0–7 and 40–47`.
fn runs_text(views: &[usize]) -> String {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for &v in views {
        match runs.last_mut() {
            Some((_, end)) if *end + 1 == v => *end = v,
            _ => runs.push((v, v)),
        }
    }
    let text: Vec<String> =
        runs.iter().map(|&(a, b)| if a == b { a.to_string() } else { format!("{a}–{b}") }).collect();
    match text.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => text.join(""),
    }
}

/// Tiles that show part of the display from beyond the file's views: black
/// there, with a hard edge where the views end, as the display itself shows
/// that part of its picture to an eye there (no light); said with the view
/// cone that shows every tile whole. Tiles wholly beyond the views are said
/// by [`view_cone_warnings`].
fn partly_black_warning(quilt: &Quilt, g: &Geometry, black_centres: &[usize]) -> Option<String> {
    let spec = &quilt.spec;
    let partly: Vec<usize> =
        (0..spec.views()).filter(|i| quilt.beyond_views[*i] > 0 && !black_centres.contains(i)).collect();
    if partly.is_empty() {
        return None;
    }
    let most = partly.iter().map(|&i| quilt.beyond_views[i]).max().unwrap_or(0);
    let share = 100.0 * most as f64 / (spec.tile_width * spec.tile_height) as f64;
    let fix = match whole_tiles_view_cone_deg(g) {
        // Rounded down, so the cone said is one that does.
        Some(cone) => format!(
            "a view cone of {:.1}° or less shows every tile whole, with less parallax",
            (cone * 10.0).floor() / 10.0
        ),
        None => "no view cone shows every tile whole: the file's views are too narrow for the display's width".into(),
    };
    Some(format!(
        "{} of {} tiles see part of the display from beyond the file's views, which hold no light there: views {} \
         are black there, with a hard edge (up to {share:.0}% of a tile); {fix}",
        partly.len(),
        spec.views(),
        runs_text(&partly)
    ))
}

/// The horizontal-parallax frame that frame `frame` of the full-parallax
/// `file` shows along its viewer line ([`full_to_horizontal`]), read band
/// `band_rows` at a time (its digests checked), so memory is the result and
/// a band, not the full-parallax frame: a quilt's cameras all sit on the
/// viewer line.
fn horizontal_frame(file: &crate::format::HoloFile, frame: usize, band_rows: usize) -> Result<Modulation> {
    let g = file.geometry();
    let mut out = Modulation::zeros(Geometry { parallax: Parallax::Horizontal, vertical_views: None, ..g.clone() })?;
    file.read_frame_in_bands(frame, band_rows, |rows, band| {
        let band = full_to_horizontal(&band)?;
        for c in 0..g.channels.len() {
            let line = band.hololine(c, 0).len();
            let at = out.index(c, rows.start, 0, 0);
            out.samples_mut()[at..at + rows.len() * line]
                .copy_from_slice(&band.samples()[c * rows.len() * line..][..rows.len() * line]);
        }
        Ok(())
    })?;
    Ok(out)
}

/// The emitter rows of a full-parallax file that send no view toward the
/// viewer line, where the quilt's cameras are: black in every tile.
fn rows_beyond_warning(g: &Geometry) -> Option<String> {
    let rows = rows_beyond_vertical_views(g);
    (!rows.is_empty()).then(|| {
        format!(
            "{} of {} emitter rows send no view toward the viewer line (height {} mm at {} mm), where the quilt's \
             cameras are: their vertical views end more than half a view short of it; rows {} are black in every tile",
            rows.len(),
            g.hololines,
            crate::geometry::millimetres_text(g.viewer_height_m),
            crate::geometry::millimetres_text(g.viewer_distance_m),
            runs_text(&rows)
        )
    })
}

/// Read frame `frame` of `holo_path` and write its quilt to `out_path` (an
/// 8-bit sRGB PNG). The output is refused before any work if it exists and
/// `options.overwrite` is not set, if its folder is missing, or if it is the
/// input.
pub fn export_quilt(
    holo_path: &Path,
    frame: usize,
    spec: &QuiltSpec,
    out_path: &Path,
    options: &QuiltOptions,
) -> Result<QuiltReport> {
    if let Some(p) = spec.problem() {
        return Err(Error::argument("quilt", format!("{}: cannot make a quilt: {p}", out_path.display())));
    }
    if let Some(problem) = options.white.problem() {
        return Err(Error::argument("white level", format!("{}: {problem}", out_path.display())));
    }
    let _claim = crate::output::check_output(out_path, &[holo_path], options.overwrite)?;
    let file = crate::format::HoloFile::open(holo_path)?;
    let m = match file.geometry().vertical_views {
        None => file.read_frame(frame)?,
        Some(_) => horizontal_frame(&file, frame, crate::views::band_rows(file.geometry()))?,
    };
    let quilt = quilt_from_modulation(&m, spec)?;
    let white = quilt.white_level(options.white);
    quilt.write_png(out_path, white, options.overwrite)?;
    let f = Framing::new(m.geometry(), spec);
    let views = &m.geometry().views;
    let mut warnings = view_cone_warnings(views, spec);
    warnings.extend(partly_black_warning(&quilt, m.geometry(), &black_tiles(views, spec)));
    warnings.extend(rows_beyond_warning(file.geometry()));
    Ok(QuiltReport {
        path: out_path.to_path_buf(),
        width: quilt.width,
        height: quilt.height,
        views: spec.views(),
        white,
        outside: quilt.outside,
        frame_m: [f.x[0], f.x[1], f.y[0], f.y[1]],
        distance_m: f.s,
        vertical_fov_deg: (2.0 * ((f.y[1] - f.y[0]) / (2.0 * f.s)).atan()).to_degrees(),
        warnings,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{mono_channel, rgb_channels, ViewSpacing, Views};

    /// 30 hololines of 0.5 mm, 40 emitters of 0.5 mm (20 × 15 mm), viewer at
    /// 500 mm, emitter plane 5 mm in front of the hologram.
    fn geometry(views: Views) -> Geometry {
        let mut g = Geometry::centred(30, 40, views, 0.5e-3, 0.5e-3, 0.005, 0.5, rgb_channels());
        g.viewer_height_m = 0.002;
        g
    }

    /// 4 × 3 tiles of odd sizes (their centre pixels look at the framed
    /// rectangle's centre).
    fn spec() -> QuiltSpec {
        QuiltSpec { columns: 4, rows: 3, tile_width: 41, tile_height: 31, aspect: 1.2, ..QuiltSpec::portrait() }
    }

    fn by_view(g: Geometry) -> Modulation {
        Modulation::from_fn(g, |c, _, _, v| 0.05 + 0.07 * v as f32 + 0.001 * c as f32).unwrap()
    }

    fn centre(q: &Quilt, i: usize) -> [f32; 3] {
        let (x, y) = q.spec.tile_origin(i);
        q.rgb[(y + q.spec.tile_height / 2) * q.width + x + q.spec.tile_width / 2]
    }

    #[test]
    fn a_full_parallax_frame_read_in_bands_is_its_row_of_views_toward_the_viewer_line() {
        let g = geometry(Views::tan_spaced(3, -0.2, 0.2)).with_vertical_views(Views::tan_spaced(3, -0.03, 0.03));
        let m = Modulation::from_fn(g, |c, j, e, v| 0.01 * (1 + c + 2 * j + 3 * e + 5 * v) as f32).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("full.holo");
        crate::format::write(&path, &m, &crate::format::WriteOptions::default()).unwrap();
        let file = crate::format::HoloFile::open(&path).unwrap();
        let whole = full_to_horizontal(&file.read_frame(0).unwrap()).unwrap();
        for band_rows in [1, 7, 30] {
            assert_eq!(horizontal_frame(&file, 0, band_rows).unwrap(), whole, "bands of {band_rows}");
        }
    }

    #[test]
    fn each_tile_centre_shows_its_view_bottom_left_first() {
        let s = spec();
        let half = s.view_cone_deg.to_radians() / 2.0;
        let views = Views { count: 12, first_theta_rad: -half, last_theta_rad: half, spacing: ViewSpacing::Angle };
        let q = quilt_from_modulation(&by_view(geometry(views)), &s).unwrap();
        assert_eq!((q.width, q.height, q.grey), (164, 93, false));
        for i in 0..12 {
            let got = centre(&q, i);
            for c in 0..3 {
                let want = 0.05 + 0.07 * i as f32 + 0.001 * c as f32;
                assert!((got[c] - want).abs() < 1e-5, "view {i} channel {c}: {got:?} vs {want}");
            }
        }
        // View 0 is the bottom-left tile, view 4 the left tile of the row above.
        assert_eq!(s.tile_origin(0), (0, 62));
        assert_eq!(s.tile_origin(3), (123, 62));
        assert_eq!(s.tile_origin(4), (0, 31));
        assert_eq!(s.tile_origin(11), (123, 0));
    }

    #[test]
    fn views_are_found_by_the_spacing_rule() {
        // Cameras at 12 angles over ±17.5°, views spaced otherwise: each tile
        // centre is the view ramp at the inverse of the spacing rule, black
        // beyond the views.
        let s = spec();
        let n = s.views();
        let list: Vec<f64> = [-0.2, -0.15, -0.02, 0.01, 0.09, 0.2].to_vec();
        for views in [
            Views::tan_spaced(9, -0.2, 0.25),
            Views { count: 7, first_theta_rad: -0.25, last_theta_rad: 0.15, spacing: ViewSpacing::Sin },
            Views {
                count: 6,
                first_theta_rad: -0.2,
                last_theta_rad: 0.2,
                spacing: ViewSpacing::Explicit(list.clone()),
            },
        ] {
            let q = quilt_from_modulation(&by_view(geometry(views.clone())), &s).unwrap();
            for i in 0..n {
                let phi = (i as f64 / (n - 1) as f64 - 0.5) * s.view_cone_deg.to_radians();
                let f = views.index_at(phi);
                let got = centre(&q, i)[0];
                if f < -0.5 - 1e-9 || f > views.count as f64 - 0.5 + 1e-9 {
                    assert_eq!(got, 0.0, "{:?} view {i}", views.spacing);
                } else {
                    let want = 0.05 + 0.07 * f.clamp(0.0, (views.count - 1) as f64) as f32;
                    assert!((got - want).abs() < 1e-5, "{:?} view {i}: {got} vs {want}", views.spacing);
                }
                // The inverse is right: the rule maps it back.
                assert!((views.theta_at(f) - phi).abs() < 1e-12, "{:?} {phi}", views.spacing);
            }
        }
    }

    #[test]
    fn the_emitter_plane_has_no_parallax_and_the_frame_is_letterboxed() {
        // One lit emitter, every view: all cameras see it in the same tile column.
        let s =
            QuiltSpec { columns: 3, rows: 2, tile_width: 80, tile_height: 120, aspect: 0.75, ..QuiltSpec::portrait() };
        let g = geometry(Views::tan_spaced(32, -0.4, 0.4));
        let m = Modulation::from_fn(g.clone(), |_, _, e, _| f32::from(e == 13)).unwrap();
        let q = quilt_from_modulation(&m, &s).unwrap();
        // 20 mm wide at aspect 0.75: 26.7 mm tall, taller than the 15 mm of hololines.
        let f = Framing::new(&g, &s);
        assert!(((f.x[1] - f.x[0]) - 0.020).abs() < 1e-12 && ((f.y[1] - f.y[0]) - 0.020 / 0.75).abs() < 1e-12);
        // Tile column u looks at x = (u + ½)/4 − 10 mm, between emitters
        // (x + 9.75 mm)/0.5 mm; emitter 13 is lit.
        for i in 0..6 {
            let (x0, y0) = s.tile_origin(i);
            let at = |u: usize, v: usize| q.rgb[(y0 + v) * q.width + x0 + u][1];
            for u in 0..80 {
                let fe = ((u as f32 + 0.5) / 4.0 - 10.0 + 9.75) / 0.5;
                let want = (1.0 - (fe - 13.0).abs()).max(0.0);
                assert!((at(u, 60) - want).abs() < 1e-5, "tile {i} column {u}: {}", at(u, 60));
            }
            // Letterbox bars above and below the 15 mm of hololines.
            assert!(at(26, 60) > 0.7);
            assert_eq!(at(26, 2), 0.0);
            assert_eq!(at(26, 117), 0.0);
        }
        assert!(q.outside > 0);
    }

    #[test]
    fn the_rig_cameras_see_the_plane_where_the_quilt_puts_it() {
        let s =
            QuiltSpec { columns: 3, rows: 2, tile_width: 40, tile_height: 36, aspect: 1.6, ..QuiltSpec::standard() };
        let g = geometry(Views::tan_spaced(8, -0.3, 0.3));
        let rig = quilt_rig(&g, &s, Path::new("q.png")).unwrap();
        assert!(rig.problem().is_none(), "{:?}", rig.problem());
        let f = Framing::new(&g, &s);
        for (i, cam) in rig.cameras.iter().enumerate() {
            for (u, v) in [(0.0, 0.0), (17.0, 5.0), (39.0, 35.0)] {
                let (x, y) = f.point(&s, u, v);
                let (px, z) = cam.project([x, y, g.emitter_z_m]).unwrap();
                assert!((px[0] - u).abs() < 1e-9 && (px[1] - v).abs() < 1e-9, "camera {i}: {px:?} vs {u} {v}");
                assert!((z - f.s).abs() < 1e-12);
            }
            let ImageSource::Tile { x, y, .. } = cam.image else { panic!() };
            assert_eq!((x, y), s.tile_origin(i));
        }
        // The outermost cameras see the centre at ±cone/2.
        let c = (f.x[0] + f.x[1]) / 2.0;
        let angle = |i: usize| ((rig.cameras[i].pose.centre[0] - c) / f.s).atan().to_degrees();
        assert!((angle(0) + 17.5).abs() < 1e-9 && (angle(5) - 17.5).abs() < 1e-9);
    }

    #[test]
    fn grey_files_give_grey_quilts_and_the_tone_mapping_is_that_of_the_views() {
        let dir = tempfile::tempdir().unwrap();
        let mut g = geometry(Views::tan_spaced(12, -0.3, 0.3));
        g.channels = mono_channel();
        let m = Modulation::from_fn(g, |_, j, _, _| 0.2 + 0.01 * j as f32).unwrap();
        let q = quilt_from_modulation(&m, &spec()).unwrap();
        assert!(q.grey && q.rgb.iter().all(|p| p[0] == p[1] && p[1] == p[2]));
        let path = dir.path().join("g.png");
        q.write_png(&path, 0.5, false).unwrap();
        let img = crate::picture::decode::open(&path).unwrap();
        assert_eq!((img.channels, img.bits()), (1, Bits::Eight));
        let grey = img.grey8();
        let (x, y) = spec().tile_origin(5);
        let (u, v) = (x + 20, y + 15);
        let want = q.rgb[v * q.width + u][0];
        let code = grey[v * img.width + u];
        assert_eq!(code, Tone::new(0.5, Bits::Eight).unwrap().code(want) as u8);
        // Not overwritten.
        let err = q.write_png(&path, 0.5, false).unwrap_err().to_string();
        assert!(err.contains("g.png") && err.contains("already exists"), "{err}");
        // Auto white: the 99.9th percentile.
        let mut q2 = q.clone();
        q2.rgb = (0..1000).map(|i| [i as f32; 3]).collect();
        assert_eq!(q2.white_level(White::Auto), 998.0);
        assert_eq!(q2.white_level(White::Max), 999.0);
        q2.rgb = vec![[0.0; 3]; 10];
        assert_eq!(q2.white_level(White::Auto), 1.0);
    }

    #[test]
    fn tiles_that_see_the_display_from_beyond_the_views_are_said() {
        let dir = tempfile::tempdir().unwrap();
        // 48 views over ±0.3 rad: the display's 20 mm at 495 mm span more than half a view.
        let g = geometry(Views::tan_spaced(48, -0.3, 0.3));
        let m = by_view(g.clone());
        let holo = dir.path().join("ramp.holo");
        crate::format::write(&holo, &m, &crate::format::WriteOptions::default()).unwrap();
        // The cone that fits the views: the outer cameras look at the display's
        // centre along the outermost views, at its far side beyond them.
        let fitting = QuiltSpec { view_cone_deg: view_cone_deg_for(&g.views), ..spec() };
        let q = quilt_from_modulation(&m, &fitting).unwrap();
        let cut: Vec<usize> = (0..12).filter(|&i| q.beyond_views[i] > 0).collect();
        assert!(cut.contains(&0) && cut.contains(&11) && !cut.contains(&5) && !cut.contains(&6), "{cut:?}");
        // Cut where the views end: tile 0's left emitters are lit, its right ones black.
        let (x0, y0) = fitting.tile_origin(0);
        let mid = (y0 + fitting.tile_height / 2) * q.width;
        assert!(q.rgb[mid + x0 + 2][0] > 0.0 && q.rgb[mid + x0 + fitting.tile_width - 3][0] == 0.0);
        let out = dir.path().join("q.png");
        let report = export_quilt(&holo, 0, &fitting, &out, &QuiltOptions::default()).unwrap();
        let w = report.warnings.join("\n");
        let said = format!("{} of 12 tiles see part of the display from beyond the file's views", cut.len());
        assert!(w.contains(&said) && w.contains(&format!("views {}", runs_text(&cut))), "{w}");
        let cone = whole_tiles_view_cone_deg(&g).unwrap();
        assert!(w.contains(&format!("a view cone of {:.1}° or less", (cone * 10.0).floor() / 10.0)), "{w}");
        // That cone shows every tile whole; a wider one cuts the outer tiles.
        assert!(cone < fitting.view_cone_deg);
        let whole = quilt_from_modulation(&m, &QuiltSpec { view_cone_deg: cone, ..fitting.clone() }).unwrap();
        assert!(whole.beyond_views.iter().all(|&n| n == 0), "{:?}", whole.beyond_views);
        let wider = quilt_from_modulation(&m, &QuiltSpec { view_cone_deg: cone + 0.5, ..fitting }).unwrap();
        assert!(wider.beyond_views[0] > 0 && wider.beyond_views[11] > 0 && wider.beyond_views[5] == 0);
        assert_eq!(runs_text(&[0, 1, 2, 3, 8, 10, 11]), "0–3, 8 and 10–11");
        assert_eq!(runs_text(&[4]), "4");
    }

    #[test]
    fn file_names_follow_the_looking_glass_convention() {
        assert_eq!(quilt_file_name("scene", &QuiltSpec::portrait()), "scene_qs8x6a0.75.png");
        assert_eq!(quilt_file_name("scene", &QuiltSpec::standard()), "scene_qs5x9a1.6.png");
        assert_eq!(quilt_file_name("a.b", &QuiltSpec::go()), "a.b_qs11x6a0.5625.png");
        let odd = QuiltSpec { aspect: 16.0 / 9.0, ..QuiltSpec::portrait() };
        assert_eq!(quilt_file_name("x", &odd), "x_qs8x6a1.7778.png");
        let one = QuiltSpec { aspect: 1.0, ..QuiltSpec::portrait() };
        assert_eq!(quilt_file_name("x", &one), "x_qs8x6a1.png");
        let p = QuiltSpec::portrait();
        assert_eq!((p.width(), p.height(), p.views()), (3360, 3360, 48));
        assert_eq!(QuiltSpec::preset("4K"), Some(QuiltSpec::standard()));
        assert!(PRESETS.iter().all(|n| QuiltSpec::preset(n).is_some()));
        assert_eq!(QuiltSpec::preset("nope"), None);
    }

    #[test]
    fn bad_requests_get_clear_errors() {
        let dir = tempfile::tempdir().unwrap();
        let holo = dir.path().join("ramp.holo");
        let m = by_view(geometry(Views::tan_spaced(5, -0.1, 0.1)));
        crate::format::write(&holo, &m, &crate::format::WriteOptions::default()).unwrap();
        let out = dir.path().join("q.png");
        let options = QuiltOptions::default();
        let err = export_quilt(&dir.path().join("missing.holo"), 0, &spec(), &out, &options).unwrap_err().to_string();
        assert!(err.contains("missing.holo"), "{err}");
        let zero = QuiltSpec { columns: 0, ..spec() };
        let err = export_quilt(&holo, 0, &zero, &out, &options).unwrap_err().to_string();
        assert!(err.contains("0 columns") && err.contains("q.png"), "{err}");
        let err = export_quilt(&holo, 3, &spec(), &out, &options).unwrap_err().to_string();
        assert!(err.contains("ramp.holo") && err.contains("no frame 3"), "{err}");
        assert!(!out.exists());
        let report = export_quilt(&holo, 0, &spec(), &out, &options).unwrap();
        assert_eq!((report.width, report.height, report.views), (164, 93, 12));
        assert!(report.white > 0.0 && report.outside > 0);
        let err = export_quilt(&holo, 0, &spec(), &out, &options).unwrap_err().to_string();
        assert!(err.contains("already exists"), "{err}");
        let again = QuiltOptions { overwrite: true, white: White::Value(1.0) };
        assert_eq!(export_quilt(&holo, 0, &spec(), &out, &again).unwrap().white, 1.0);
        for bad in [
            QuiltSpec { aspect: 0.0, ..spec() },
            QuiltSpec { view_cone_deg: f64::NAN, ..spec() },
            QuiltSpec { tile_width: 1 << 20, tile_height: 1 << 20, ..spec() },
            QuiltSpec { columns: usize::MAX, ..spec() },
        ] {
            assert!(bad.problem().is_some(), "{bad:?}");
            assert!(quilt_from_modulation(&m, &bad).is_err());
        }
    }
}
