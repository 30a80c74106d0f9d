//! A camera array to a `.holo` file.
//!
//! ```text
//! cargo run --example 04_cameras_to_holo
//! ```
//!
//! Builds a rig in memory: nine pinhole cameras on a horizontal rail, 1 m in
//! front of a painted wall, each with the picture it would take of it. The
//! rig's pictures are then resampled into one frame of modulation for the
//! MIT Mark I display (every display ray takes its radiance from the cameras
//! nearest to it) and written as `wall.holo` in a new folder under the
//! system's temporary folder, which it prints. A real capture is opened the
//! same way with `holo::cameras::open_rig` (a rig file, an HCI, Stanford or
//! Middlebury capture, a quilt or a folder of images) and converted with
//! `holo::cameras::convert::convert_camera_files`.

use std::error::Error;
use std::path::{Path, PathBuf};

use holo::cameras::image::Picture;
use holo::cameras::resample::{resample_rig, CameraOptions, CameraView};
use holo::cameras::{look_rotation, Camera, ImageSource, Intrinsics, Pose, Rig};
use holo::progress::Silent;

/// Pixels across and down each picture.
const WIDTH: usize = 192;
const HEIGHT: usize = 128;

fn main() -> Result<(), Box<dyn Error>> {
    // Kept after the run, so the file can be looked at.
    let folder = tempfile::Builder::new().prefix("holo-example-").tempdir()?.keep();
    let file = run(&folder)?;
    println!("wrote {}", file.display());
    Ok(())
}

/// The wall's linear RGB radiance at `(x, y)` (metres on the plane `z = 0`):
/// 1 cm squares, coloured by column.
fn wall(x: f64, y: f64) -> [f32; 3] {
    let (column, row) = ((x / 0.01).floor() as i64, (y / 0.01).floor() as i64);
    let bright = if (column + row).rem_euclid(2) == 0 { 0.9 } else { 0.2 };
    let hue = column.rem_euclid(3) as usize;
    let mut rgb = [0.1 * bright; 3];
    rgb[hue] = bright;
    rgb
}

/// Camera `k` of `n`, on the rail `z = 1 m`, looking at the wall (`−z`),
/// its sensor shifted so that the wall's centre is the picture's centre.
fn camera(k: usize, n: usize) -> Camera {
    let x = 0.04 * (k as f64 - (n - 1) as f64 / 2.0);
    let mut camera = Camera {
        name: format!("cam{k}"),
        // The pictures are made in memory; the name is for messages.
        image: ImageSource::File(format!("cam{k}.png").into()),
        width: WIDTH,
        height: HEIGHT,
        // A narrow field of view (under 4° across, 6 cm of the wall): the
        // display shows about 3 cm of it.
        intrinsics: Intrinsics::centred(WIDTH, HEIGHT, 3000.0, 3000.0),
        // Picture `+y` (down) is the world's `−y`.
        pose: Pose { rotation: look_rotation([0.0, 0.0, -1.0], [0.0, -1.0, 0.0]), centre: [x, 0.0, 1.0] },
        depth: None,
    };
    camera.centre_on([0.0, 0.0, 0.0]);
    camera
}

/// What `camera` sees of the wall: one ray through each pixel's centre.
fn photograph(camera: &Camera) -> CameraView {
    let rgb = (0..WIDTH * HEIGHT)
        .map(|i| {
            let d = camera.ray((i % WIDTH) as f64, (i / WIDTH) as f64);
            let t = -camera.pose.centre[2] / d[2]; // where the ray meets z = 0
            wall(camera.pose.centre[0] + t * d[0], camera.pose.centre[1] + t * d[1])
        })
        .collect();
    CameraView { picture: Picture { width: WIDTH, height: HEIGHT, rgb }, depth_z: None }
}

/// Resample the rig into `folder/wall.holo`; returns the file's path.
pub fn run(folder: &Path) -> Result<PathBuf, Box<dyn Error>> {
    let n = 9;
    let cameras: Vec<Camera> = (0..n).map(|k| camera(k, n)).collect();
    let views: Vec<CameraView> = cameras.iter().map(photograph).collect();
    let rig = Rig {
        source: "a painted wall (in memory)".into(),
        cameras,
        metres_per_unit: 1.0,
        // The wall is 1 m from the cameras: the display shows it in focus
        // on its emitter plane.
        focus_distance: Some(1.0),
        // The pictures hold linear radiance, not sRGB-encoded values.
        linear: true,
    };

    let layout = holo::layout::mark1();
    let (frame, report) = resample_rig(&rig, &views, &layout.geometry, &CameraOptions::default(), &Silent)?;
    println!("{}; {}", report.surface, report.placement);
    println!("{} of {} rays seen by no camera", report.unseen, report.rays);

    let file = folder.join("wall.holo");
    let options = holo::WriteOptions { source: "examples/04_cameras_to_holo".into(), ..Default::default() };
    holo::write(&file, &frame, &options)?;
    Ok(file)
}
