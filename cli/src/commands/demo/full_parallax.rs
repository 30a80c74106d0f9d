//! The full-parallax step of the demo: the bundled cow rendered for Mark
//! III's emitter grid with vertical views as well (spec §8: a 2-D grid of
//! views from every emitter, a hogel), and what eyes above, level with and
//! below the viewer line see of that light field (`holo view --eye X,Y` of a
//! full-parallax file, [`holo::reconstruct::light_field`]), as a contact sheet.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use holo::geometry::Geometry;
use holo::progress::{Labelled, Progress};
use holo::reconstruct::light_field::{eye_view, EyePoint};
use holo::reconstruct::picture::Picture;
use holo::Result;

use super::eyes::{contact_sheet, PUPIL_M};

/// Vertical views: over the horizontal views' cone, as `--vertical-views`
/// gives them by default.
const VERTICAL_VIEWS: usize = 9;

/// The eyes above and below the viewer line, as a fraction of how far up
/// and down every emitter still has a view toward them.
const EYE_REACH: f64 = 0.8;

/// The sheet's tiles are what an eye sees shrunk this many times each way.
const SHEET_SHRINK: usize = 2;

/// What the full-parallax step made.
#[derive(Clone, Debug, Serialize)]
pub struct DemoFullParallax {
    /// The full-parallax `.holo` file.
    pub holo_file: PathBuf,
    /// Its emitter rows, emitters, views and vertical views.
    pub size: [usize; 4],
    /// Seconds spent rendering and writing it.
    pub convert_seconds: f64,
    /// The contact sheet of what the eyes see.
    pub eyes_sheet: PathBuf,
    /// The eyes' heights, millimetres, top first.
    pub eyes_y_mm: Vec<f64>,
    /// Their distance from the hologram plane, millimetres.
    pub eye_distance_mm: f64,
    /// Seconds spent reading the file and seeing it from the eyes.
    pub view_seconds: f64,
}

/// The bundled `scene` rendered full parallax on `horizontal` made full
/// parallax into `dir/demo-full-parallax.holo`, read back, and what eyes
/// above, level with and below the viewer line see of it in
/// `dir/eyes-full-parallax.png`.
pub fn demo_full_parallax(
    dir: &Path,
    scene: &Path,
    horizontal: &Geometry,
    rotate_deg: [f64; 3],
    progress: &dyn Progress,
) -> Result<DemoFullParallax> {
    use holo::mesh::convert::{convert_mesh, ConvertOptions};
    let g = horizontal.clone().with_centred_vertical_views(VERTICAL_VIEWS, None);
    let holo_file = dir.join("demo-full-parallax.holo");
    let mut options = ConvertOptions::default();
    options.write.overwrite = true;
    options.scene.placement.rotate_deg = rotate_deg;
    // One ray per view (two across each emitter): the views are 9 times
    // Mark III's, and the demo keeps to its time.
    options.render.supersample = holo::mesh::render::Supersample::new(2, 1);
    let started = Instant::now();
    convert_mesh(scene, &g, &holo_file, &options, &Labelled::new(progress, "full parallax"))?;
    let convert_seconds = started.elapsed().as_secs_f64();

    let started = Instant::now();
    let m = holo::format::HoloFile::open(&holo_file)?.read_frame(0)?;
    // How far up every emitter has a view toward an eye at the viewer's
    // distance (the highest vertical view from the lowest emitter row), and
    // down (the lowest from the top row).
    let vertical = g.vertical_views.as_ref().expect("made full parallax above");
    let span = g.viewer_distance_m - g.emitter_z_m;
    let up_m = g.hololine_y_m(g.hololines - 1) + span * vertical.theta_rad(vertical.count - 1).tan();
    let down_m = g.hololine_y_m(0) + span * vertical.theta_rad(0).tan();
    let y_v = g.viewer_height_m;
    let eyes_y_m = [y_v + EYE_REACH * (up_m - y_v), y_v, y_v - EYE_REACH * (y_v - down_m)];
    let pictures: Vec<Picture> = eyes_y_m
        .iter()
        .map(|&y| {
            let eye = EyePoint { centre_m: [0.0, y, g.viewer_distance_m], pupil_m: PUPIL_M };
            eye_view(&m, &eye).map(|(picture, _)| picture)
        })
        .collect::<Result<_>>()?;
    drop(m);
    let view_seconds = started.elapsed().as_secs_f64();
    let label = |y: f64| match y - y_v {
        d if d.abs() < 1e-9 => "eye level".to_string(),
        d => format!("eye {:.0} mm {}", d.abs() * 1e3, if d > 0.0 { "above" } else { "below" }),
    };
    let sheet: Vec<(String, &Picture)> = eyes_y_m.iter().zip(&pictures).map(|(&y, p)| (label(y), p)).collect();
    let eyes_sheet = dir.join("eyes-full-parallax.png");
    holo::output::write_bytes_beside(&eyes_sheet, &contact_sheet(&sheet, sheet.len(), SHEET_SHRINK).png()?, true)?;
    Ok(DemoFullParallax {
        holo_file,
        size: [g.hololines, g.emitters, g.views.count, vertical.count],
        convert_seconds,
        eyes_sheet,
        eyes_y_mm: eyes_y_m.iter().map(|y| y * 1e3).collect(),
        eye_distance_mm: g.viewer_distance_m * 1e3,
        view_seconds,
    })
}
