//! The movie path of the demo: three frames of the bundled morphing cube,
//! encoded for Mark III with coarse micropolygons (4× what the display
//! resolves: a demo, not a master), drawn into `.holo` frames, and each
//! frame seen by an eye in the middle of the viewing zone.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use holo::layout::Layout;
use holo::progress::{Labelled, Progress};
use holo::reconstruct::files::{view_file, EyeAt};
use holo::Result;

use super::eyes::{contact_sheet, PUPIL_M};

/// The bundled animated scene: Khronos' AnimatedMorphCube (CC0; fixtures/SOURCES.md).
const DEMO_MOVIE: &[u8] = include_bytes!("../../../../fixtures/mesh/AnimatedMorphCube.glb");

/// Frames of the animation taken.
const FRAMES: usize = 3;

/// The movie part of `holo demo`: the bundled animated glTF → a HoloFlick
/// for Mark III → `.holo` frames → what an eye in the middle sees of each.
#[derive(Clone, Debug, Serialize)]
pub struct DemoMovie {
    /// The bundled animated scene, written out.
    pub scene: PathBuf,
    /// The HoloFlick made from it.
    pub holoflick: PathBuf,
    /// Frames.
    pub frames: usize,
    /// Frames per second, as the `.holo` file stores it (a fraction).
    pub frames_per_second: Option<(i32, u32)>,
    /// Micropolygons over all frames.
    pub micropolygons: usize,
    /// Its size.
    pub holoflick_bytes: u64,
    /// The `.holo` file drawn from it.
    pub holo_file: PathBuf,
    /// What an eye in the middle sees of each frame, side by side.
    pub frames_picture: PathBuf,
    /// Seconds: encode, convert, assemble and view.
    pub seconds: [f64; 3],
}

/// The movie path into `dir`, for `layout`.
pub(super) fn demo_movie(dir: &Path, layout: &Layout, progress: &dyn Progress) -> Result<DemoMovie> {
    use holo::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
    use holo::holoflick::encode::{encode_holoflick, HoloFlickEncodeOptions};
    use holo::mesh::convert::SceneFramesOptions;
    std::fs::create_dir_all(dir).map_err(|e| holo::Error::Io { path: dir.to_path_buf(), source: e })?;
    let scene = dir.join("AnimatedMorphCube.glb");
    holo::output::write_bytes_beside(&scene, DEMO_MOVIE, true)?;
    let holoflick = dir.join("cube.hflk");
    let started = Instant::now();
    let options = HoloFlickEncodeOptions {
        micropolygon: 4.0,
        scene: SceneFramesOptions {
            placement: holo::mesh::place::Placement { rotate_deg: [20.0, -30.0, 0.0], ..Default::default() },
            frames: Some(0..FRAMES),
            frames_per_second: 0.5,
            ..SceneFramesOptions::default()
        },
        overwrite: true,
        ..HoloFlickEncodeOptions::default()
    };
    let encoded = encode_holoflick(&scene, &layout.geometry, &holoflick, &options, progress)?;
    let encode_seconds = started.elapsed().as_secs_f64();
    let holo_file = dir.join("cube.holo");
    let started = Instant::now();
    let mut convert = HoloFlickConvertOptions::default();
    convert.write.overwrite = true;
    convert_holoflick(&holoflick, &layout.geometry, &holo_file, &convert, progress)?;
    let convert_seconds = started.elapsed().as_secs_f64();
    let frames_per_second = holo::format::HoloFile::open(&holo_file)?.info().frames_per_second;

    // Each frame assembled in memory, as the display would receive it, and seen.
    let started = Instant::now();
    let eye =
        EyeAt { x_m: 0.0, y_m: layout.geometry.viewer_height_m, distance_m: None, pupil_m: PUPIL_M, coherent: false };
    let mut seen = Vec::new();
    for k in 0..encoded.pack.frames {
        let frame_progress = Labelled::new(progress, format!("frame {k}"));
        seen.extend(view_file(&holo_file, Some(layout), k, &[eye], &frame_progress)?);
    }
    let tiles: Vec<(String, &holo::reconstruct::picture::Picture)> =
        seen.iter().enumerate().map(|(k, p)| (format!("frame {k}"), p)).collect();
    let frames_picture = dir.join("frames.png");
    holo::output::write_bytes_beside(&frames_picture, &contact_sheet(&tiles, tiles.len(), 2).png()?, true)?;
    let view_seconds = started.elapsed().as_secs_f64();
    Ok(DemoMovie {
        scene,
        holoflick,
        frames: encoded.pack.frames,
        frames_per_second,
        micropolygons: encoded.micropolygons,
        holoflick_bytes: encoded.pack.file_bytes,
        holo_file,
        frames_picture,
        seconds: [encode_seconds, convert_seconds, view_seconds],
    })
}
