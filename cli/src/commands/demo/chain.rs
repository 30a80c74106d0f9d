//! `holo demo`: the whole chain on built-in defaults, told in pictures.
//!
//! The bundled cow is rendered for every Mark III emitter and view into a
//! `.holo` file (the light field), which is shown as a Looking Glass quilt;
//! the frame is assembled into the fringes the display is sent (held in
//! memory, as `holo assemble` would write them, and pictured: `fringe.rs`);
//! and what eyes across the whole viewing zone see of those fringes is
//! simulated by scalar diffraction ([`holo::reconstruct`]), as a labelled
//! contact sheet and an animated PNG of an eye moving (`canvas.rs`, with
//! labels in a built-in font, `font.rs`). The movie path (`movie.rs`) takes
//! the bundled animated glTF through a HoloFlick to `.holo` frames and shows
//! each frame as an eye sees it. Every picture has square pixels on the
//! display, so the scene is at its physical proportions.
//!
//! The fringe images themselves are not written (two of 4080 × 3386 a
//! frame, mostly the quantization's mid-grey): the text says how to make
//! them with `holo assemble`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use holo::assemble::Assembler;
use holo::layout;
use holo::progress::{Labelled, Progress};
use holo::reconstruct::check::{view, FrameRef};
use holo::reconstruct::picture::Picture;
use holo::reconstruct::viewer::Eye;
use holo::Result;

use super::canvas::{self, Canvas};
use super::eyes::{contact_sheet, labelled, PUPIL_M};
use super::fringe;
use super::full_parallax::{demo_full_parallax, DemoFullParallax};
use super::movie::{self, DemoMovie};

/// What `holo demo` made.
#[derive(Clone, Debug, Serialize)]
pub struct Demo {
    /// The folder of its files.
    pub dir: PathBuf,
    /// The bundled scene, written out so it can be looked at and converted again.
    pub scene: PathBuf,
    /// Triangles in it.
    pub triangles: usize,
    /// Where the scene was placed.
    pub placement: String,
    /// Seconds spent rendering it into modulation.
    pub convert_seconds: f64,
    /// The `.holo` file written.
    pub holo_file: PathBuf,
    /// Its hololines, emitters and views.
    pub size: [usize; 3],
    /// The layout's name (for the command that assembles the fringes).
    pub layout: String,
    /// The quilt of its views.
    pub quilt: PathBuf,
    /// Tiles in the quilt.
    pub quilt_tiles: usize,
    /// The picture of the assembled fringes.
    pub fringe_picture: PathBuf,
    /// Fringe images a frame (frame-buffer images), their width and height.
    pub fringe_images: (usize, usize, usize),
    /// The hololine and samples the fringe picture zooms into.
    pub fringe_zoom: (usize, std::ops::Range<usize>),
    /// Seconds spent assembling the frame.
    pub assemble_seconds: f64,
    /// The eyes' distance from the hologram plane, millimetres.
    pub eye_distance_mm: f64,
    /// The contact sheet of what eyes across the viewing zone see.
    pub eyes_sheet: PathBuf,
    /// Its eyes' x, millimetres, left to right.
    pub sheet_eyes_x_mm: Vec<f64>,
    /// The animated PNG of an eye sweeping across the viewing zone.
    pub eyes_moving: PathBuf,
    /// Its eyes' x, millimetres, in the order shown (there and back).
    pub moving_eyes_x_mm: Vec<f64>,
    /// Seconds spent simulating what the eyes see.
    pub view_seconds: f64,
    /// The full-parallax step: the cow with vertical views, seen from above and below.
    pub full_parallax: DemoFullParallax,
    /// The movie path: an animated scene through a HoloFlick.
    pub movie: DemoMovie,
    /// Seconds for the whole demo.
    pub seconds: f64,
}

/// The bundled scene: Spot the cow (Keenan Crane, public domain), decimated
/// to 500 triangles, with its texture (fixtures/SOURCES.md).
const DEMO_SCENE: [(&str, &[u8]); 3] = [
    ("spot.obj", include_bytes!("../../../../fixtures/mesh/spot/spot.obj")),
    ("spot.mtl", include_bytes!("../../../../fixtures/mesh/spot/spot.mtl")),
    ("spot_texture.png", include_bytes!("../../../../fixtures/mesh/spot/spot_texture.png")),
];

/// Eyes along the viewing zone simulated: the animation's frames one way.
/// Every eye costs about as much as another hololine pass of the
/// reconstruction's last step; this many keep the demo within its time.
const SWEEP_EYES: usize = 25;
/// Every this many of the sweep's eyes is a tile of the contact sheet (9).
const SHEET_EVERY: usize = 3;
/// Contact sheet tiles a row.
const SHEET_COLUMNS: usize = 3;
/// The sheet's tiles are what an eye sees shrunk this many times each way.
const SHEET_SHRINK: usize = 2;
/// Seconds each frame of the animation is shown.
const SWEEP_FRAME_SECONDS: f64 = 0.08;

/// The main job on built-in defaults: the bundled textured mesh rendered for
/// every Mark III emitter and view into `dir/demo.holo`, its quilt,
/// assembled into Mark III fringes (in memory, pictured in
/// `dir/fringe.png`), and reconstructed by scalar diffraction into what eyes
/// across the viewing zone see (`dir/eyes.png`, `dir/eyes-moving.png`); then
/// the movie path ([`DemoMovie`]). Each step's phases go to `progress`.
///
/// `dir` is new, empty, or an earlier demo's (marked by a `.holo-demo` file
/// in it, or, from before the marker, holding only the demo's own names
/// and the bundled scene), whose files are replaced; a folder holding other
/// files is refused, so no file the demo did not make is ever written over.
/// A demo that does not finish (an error, or a signal with
/// [`holo::output::install_interrupt_cleanup`]) leaves the folder as it
/// was: a new or empty one as such, an earlier demo's with the earlier
/// demo's files (moved aside while the demo runs,
/// [`holo::output::RunFolder::take_over`]).
pub fn demo(dir: impl AsRef<Path>, progress: &dyn Progress) -> Result<Demo> {
    let dir = dir.as_ref();
    if dir.join(MARKER).is_file() || made_by_an_earlier_demo(dir) {
        let folder = holo::output::RunFolder::take_over(dir, &WRITES)?;
        let demo = demo_in(dir, progress)?;
        if !dir.join(MARKER).is_file() {
            holo::output::write_bytes_beside(&dir.join(MARKER), MARKER_TEXT.as_bytes(), false)?;
        }
        folder.keep();
        return Ok(demo);
    }
    if std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_some()) {
        return Err(holo::Error::Output {
            path: dir.to_path_buf(),
            problem: holo::OutputProblem::WrongKind(
                "holds files that `holo demo` did not make (there is no .holo-demo in it); give -o a new or empty folder",
            ),
        });
    }
    let folder = holo::output::RunFolder::claim(dir)?;
    holo::output::write_bytes_beside(&dir.join(MARKER), MARKER_TEXT.as_bytes(), false)?;
    let demo = demo_in(dir, progress)?;
    folder.keep();
    Ok(demo)
}

/// What the demo writes into its folder: an earlier demo's files of these
/// names are replaced.
const WRITES: [&str; 9] = [
    "spot",
    "demo.holo",
    "demo_qs8x6a0.75.png",
    "fringe.png",
    "eyes.png",
    "eyes-moving.png",
    "demo-full-parallax.holo",
    "eyes-full-parallax.png",
    "movie",
];

/// The file that marks a folder as the demo's own: a later demo writes over
/// its files there.
const MARKER: &str = ".holo-demo";
const MARKER_TEXT: &str = "Made by `holo demo`: a later `holo demo` into this folder replaces its files.\n";

/// Whether `dir` is what a demo from before the marker left: nothing but
/// the demo's own names in it (and the `fringes` its text suggests), and
/// the bundled scene's bytes in `spot/`.
fn made_by_an_earlier_demo(dir: &Path) -> bool {
    const NAMES: [&str; 8] =
        ["spot", "demo.holo", "demo_qs8x6a0.75.png", "fringe.png", "eyes.png", "eyes-moving.png", "movie", "fringes"];
    let Ok(entries) = std::fs::read_dir(dir) else { return false };
    let only_ours = entries.into_iter().all(|e| e.is_ok_and(|e| NAMES.iter().any(|n| e.file_name() == *n)));
    only_ours
        && DEMO_SCENE.iter().all(|(name, bytes)| std::fs::read(dir.join("spot").join(name)).is_ok_and(|b| b == *bytes))
}

fn demo_in(dir: &Path, progress: &dyn Progress) -> Result<Demo> {
    use holo::mesh::convert::{convert_mesh, ConvertOptions};
    let started_demo = Instant::now();
    let scene_dir = dir.join("spot");
    std::fs::create_dir_all(&scene_dir).map_err(|e| holo::Error::Io { path: scene_dir.clone(), source: e })?;
    for (name, bytes) in DEMO_SCENE {
        holo::output::write_bytes_beside(&scene_dir.join(name), bytes, true)?;
    }
    let scene = scene_dir.join("spot.obj");
    let layout = layout::mark3();
    let g = &layout.geometry;
    let holo_file = dir.join("demo.holo");
    let mut options = ConvertOptions::default();
    options.write.overwrite = true;
    // Turn the cow to show its side and face.
    let rotate_deg = [0.0, -60.0, 0.0];
    options.scene.placement.rotate_deg = rotate_deg;
    let started = Instant::now();
    let converted = convert_mesh(&scene, g, &holo_file, &options, &Labelled::new(progress, "mesh"))?;
    let convert_seconds = started.elapsed().as_secs_f64();

    let (quilt, quilt_tiles) = quilt(&holo_file)?;

    let m = holo::format::HoloFile::open(&holo_file)?.read_frame(0)?;
    let started = Instant::now();
    let assembler = Assembler::new(&layout)?;
    let (images, _) = assembler.assemble::<u8>(&m)?;
    let assemble_seconds = started.elapsed().as_secs_f64();
    let eyes_x_m = viewing_zone_eyes_x_m(&m, SWEEP_EYES);
    drop(m);
    let fringe = fringe::fringe_picture(&assembler, &images)?;
    let fringe_picture = dir.join("fringe.png");
    holo::output::write_bytes_beside(&fringe_picture, &fringe.canvas.png()?, true)?;

    let started = Instant::now();
    let eyes: Vec<Eye> = eyes_x_m
        .iter()
        .map(|&x_m| Eye { x_m, y_m: g.viewer_height_m, z_m: g.viewer_distance_m, pupil_m: PUPIL_M, coherent: false })
        .collect();
    let pictures = view(&assembler, FrameRef::Bytes(&images), &eyes, &Labelled::new(progress, "eyes"))?;
    drop(images);
    let view_seconds = started.elapsed().as_secs_f64();
    let label = |x_m: f64| format!("eye x = {:+.0} mm", x_m * 1e3);

    let sheet: Vec<(String, &Picture)> =
        eyes_x_m.iter().zip(&pictures).step_by(SHEET_EVERY).map(|(&x, p)| (label(x), p)).collect();
    let eyes_sheet = dir.join("eyes.png");
    holo::output::write_bytes_beside(&eyes_sheet, &contact_sheet(&sheet, SHEET_COLUMNS, SHEET_SHRINK).png()?, true)?;

    // There and back, the ends shown once.
    let order: Vec<usize> = (0..eyes.len()).chain((1..eyes.len().saturating_sub(1)).rev()).collect();
    let frames: Vec<Canvas> = order.iter().map(|&k| labelled(&pictures[k], 1, &label(eyes_x_m[k]))).collect();
    let eyes_moving = dir.join("eyes-moving.png");
    holo::output::write_bytes_beside(&eyes_moving, &canvas::apng(&frames, SWEEP_FRAME_SECONDS, 0)?, true)?;

    let full_parallax = demo_full_parallax(dir, &scene, g, rotate_deg, progress)?;
    let movie = movie::demo_movie(&dir.join("movie"), &layout, &Labelled::new(progress, "movie"))?;
    let fb = &layout.fringe.as_ref().expect("Mark III has a fringe side").frame_buffer;
    let mm = |x: &f64| x * 1e3;
    Ok(Demo {
        dir: dir.to_path_buf(),
        scene,
        triangles: converted.triangles,
        placement: converted.placed.to_string(),
        convert_seconds,
        holo_file,
        size: [g.hololines, g.emitters, g.views.count],
        layout: layout.name.clone(),
        quilt,
        quilt_tiles,
        fringe_picture,
        fringe_images: (fb.image_names.len(), fb.width, fb.height),
        fringe_zoom: (fringe.hololine, fringe.samples),
        assemble_seconds,
        eye_distance_mm: g.viewer_distance_m * 1e3,
        sheet_eyes_x_mm: eyes_x_m.iter().step_by(SHEET_EVERY).map(mm).collect(),
        eyes_sheet,
        moving_eyes_x_mm: order.iter().map(|&k| mm(&eyes_x_m[k])).collect(),
        eyes_moving,
        view_seconds,
        full_parallax,
        movie,
        seconds: started_demo.elapsed().as_secs_f64(),
    })
}

/// `count` eye positions on the viewer line, evenly spaced left to right
/// over the whole stretch from which every lit emitter of `m` is seen
/// within the views: the first and last eyes see the scene's near edge in
/// the first and last views. Beyond it the far side of the scene would be
/// seen outside the views, where no light was steered. With nothing lit,
/// or a scene wider than that stretch allows, the stretch from which the
/// middle of the emitter plane is seen in the views.
pub fn viewing_zone_eyes_x_m(m: &holo::Modulation, count: usize) -> Vec<f64> {
    let g = m.geometry();
    let lit = |e: usize| {
        (0..g.channels.len()).any(|c| (0..g.hololines).any(|j| m.views_of(c, j, e).iter().any(|&v| v > 0.0)))
    };
    let first = (0..g.emitters).find(|&e| lit(e));
    let last = (0..g.emitters).rev().find(|&e| lit(e));
    let last_view = g.views.count.saturating_sub(1) as f64;
    // Where the light of an emitter at `x_m` reaches the viewer line in the first and last views.
    let reach = |x_m: f64| {
        let [a, b] = [0.0, last_view].map(|v| g.ray_at(x_m, g.viewer_height_m, v).at_z(g.viewer_distance_m)[0]);
        (a.min(b), a.max(b))
    };
    let centre = reach(0.5 * (g.emitter_x_m(0) + g.emitter_x_m(g.emitters - 1)));
    let (left, right) = match (first, last) {
        (Some(a), Some(b)) => {
            let ((l1, r1), (l2, r2)) = (reach(g.emitter_x_m(a)), reach(g.emitter_x_m(b)));
            if l1.max(l2) < r1.min(r2) {
                (l1.max(l2), r1.min(r2))
            } else {
                centre
            }
        }
        _ => centre,
    };
    match count {
        0 => vec![],
        1 => vec![0.5 * (left + right)],
        n => (0..n).map(|k| left + (right - left) * k as f64 / (n - 1) as f64).collect(),
    }
}

/// The demo file's quilt, at `holo export-quilt`'s defaults (Looking Glass
/// Portrait, spanning the file's own views): its path and tiles.
fn quilt(holo_file: &Path) -> Result<(PathBuf, usize)> {
    use holo::cameras::quilt::{export_quilt, quilt_file_name, view_cone_deg_for, QuiltOptions, QuiltSpec};
    let mut spec = QuiltSpec::portrait();
    spec.view_cone_deg = view_cone_deg_for(&holo::format::HoloFile::open(holo_file)?.info().geometry.views);
    let path = holo_file.with_file_name(quilt_file_name("demo", &spec));
    let report =
        export_quilt(holo_file, 0, &spec, &path, &QuiltOptions { overwrite: true, ..QuiltOptions::default() })?;
    Ok((report.path, report.views))
}
