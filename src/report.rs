//! What `holo info` and `holo demo` compute, as library calls with
//! serialisable results; the CLI only prints them.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::format::{FileInfo, HoloFile};
use crate::layout;
use crate::progress::{Labelled, Progress};
use crate::Result;

/// `holo info`: the headers plus, when asked, the value range of every frame.
#[derive(Clone, Debug, Serialize)]
pub struct Info {
    /// What the headers say.
    #[serde(flatten)]
    pub file: FileInfo,
    /// Uncompressed size of the samples, all frames.
    pub raw_bytes: u64,
    /// Smallest and largest sample of each frame (when values were read).
    pub value_ranges: Option<Vec<(f32, f32)>>,
}

/// Read the headers of `path` and, if `values`, every frame (verifying digests).
pub fn info(path: impl AsRef<Path>, values: bool) -> Result<Info> {
    let file = HoloFile::open(path)?;
    let value_ranges = if values {
        Some(
            (0..file.info().frames.len())
                .map(|i| file.read_frame(i).map(|m| m.value_range()))
                .collect::<Result<Vec<_>>>()?,
        )
    } else {
        None
    };
    Ok(Info { raw_bytes: file.info().raw_bytes(), file: file.info().clone(), value_ranges })
}

/// Whether two files hold the same content: same geometry, sample type and
/// frame digests (compression and data window may differ).
pub fn same_content(a: &Info, b: &Info) -> bool {
    let digests = |i: &Info| i.file.frames.iter().map(|f| f.digest.clone()).collect::<Vec<_>>();
    a.file.geometry == b.file.geometry
        && a.file.sample_type == b.file.sample_type
        && digests(a).iter().all(Option::is_some)
        && digests(a) == digests(b)
}

impl fmt::Display for Info {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let i = &self.file;
        let g = &i.geometry;
        let mm = |m: f64| m * 1e3;
        writeln!(f, "{}", i.path.display())?;
        writeln!(
            f,
            "  format        .holo {}.{} (OpenEXR), {} frame(s), pixel aspect ratio {}",
            i.version.0,
            i.version.1,
            i.frames.len(),
            i.pixel_aspect
        )?;
        writeln!(
            f,
            "  size          {} hololines × {} emitters × {} views, {:?} parallax",
            g.hololines, g.emitters, g.views.count, g.parallax
        )?;
        let colours: Vec<String> =
            g.channels.iter().map(|c| format!("{} {:.1} nm", c.name, c.wavelength_m * 1e9)).collect();
        writeln!(
            f,
            "  channels      {} ({} EXR channels, {:?})",
            colours.join(", "),
            g.views.count * g.channels.len(),
            i.sample_type
        )?;
        writeln!(
            f,
            "  emitters      pitch {:.4} mm, x from {:.4} to {:.4} mm, plane z = {:.4} mm",
            mm(g.emitter_pitch_m),
            mm(g.emitter_x_m(0)),
            mm(g.emitter_x_m(g.emitters - 1)),
            mm(g.emitter_z_m)
        )?;
        writeln!(
            f,
            "  hololines     pitch {:.4} mm, y from {:.4} to {:.4} mm",
            mm(g.hololine_pitch_m),
            mm(g.hololine_y_m(0)),
            mm(g.hololine_y_m(g.hololines - 1))
        )?;
        writeln!(
            f,
            "  views         {:.3}° … {:.3}°, uniform in {}",
            g.views.first_theta_rad.to_degrees(),
            g.views.last_theta_rad.to_degrees(),
            g.views.spacing.name()
        )?;
        writeln!(
            f,
            "  viewer        line at z = {:.1} mm, y = {:.1} mm",
            mm(g.viewer_distance_m),
            mm(g.viewer_height_m)
        )?;
        writeln!(
            f,
            "  radiometry    {}, radiance = sample × {} ({})",
            i.radiometry.encoding, i.radiometry.scale, i.radiometry.unit
        )?;
        let ratio = i.file_bytes as f64 / self.raw_bytes.max(1) as f64;
        writeln!(
            f,
            "  on disk       {} bytes, {:.1}% of {} raw bytes, compression {}",
            i.file_bytes,
            100.0 * ratio,
            self.raw_bytes,
            i.compression.name()
        )?;
        if let Some(fps) = i.frames_per_second {
            writeln!(f, "  frame rate    {}", frame_rate_text(fps.0.into(), fps.1.into()))?;
        }
        writeln!(f, "  written by    {}", i.software.as_deref().unwrap_or("(unknown)"))?;
        if let Some(s) = &i.source {
            writeln!(f, "  source        {s}")?;
        }
        for (k, frame) in i.frames.iter().enumerate() {
            let w = frame.data_window;
            write!(
                f,
                "  frame {:<7} data {}×{} at ({}, {}), {}",
                frame.number,
                w.width,
                w.height,
                w.x,
                w.y,
                frame.digest.as_deref().unwrap_or("no digest")
            )?;
            if let Some(r) = self.value_ranges.as_ref().and_then(|v| v.get(k)) {
                write!(f, ", values {} … {}", r.0, r.1)?;
            }
            writeln!(f)?;
        }
        for u in &i.unknown_attributes {
            writeln!(f, "  ignored       unknown attribute {u}")?;
        }
        Ok(())
    }
}

/// What `holo demo` made.
#[derive(Clone, Debug, Serialize)]
pub struct Demo {
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
    /// Its `info`.
    pub info: Info,
    /// The directory of assembled fringes.
    pub fringes: PathBuf,
    /// The fringe images (one per head).
    pub fringe_files: Vec<PathBuf>,
    /// The pictures viewers see, with the eye's x in millimetres.
    pub views: Vec<(f64, PathBuf)>,
    /// Seconds spent assembling the frame.
    pub assemble_seconds: f64,
    /// The movie path: an animated scene through a HoloFlick.
    pub movie: DemoMovie,
}

/// The movie part of `holo demo`: the bundled animated glTF → a HoloFlick
/// for Mark III → `.holo` frames → fringes, and one frame seen by a viewer.
#[derive(Clone, Debug, Serialize)]
pub struct DemoMovie {
    /// The bundled animated scene, written out.
    pub scene: PathBuf,
    /// The HoloFlick made from it.
    pub holoflick: PathBuf,
    /// Frames.
    pub frames: usize,
    /// Micropolygons over all frames.
    pub micropolygons: usize,
    /// Its size.
    pub holoflick_bytes: u64,
    /// The `.holo` file drawn from it.
    pub holo_file: PathBuf,
    /// The fringe images, every frame.
    pub fringe_files: Vec<PathBuf>,
    /// What a viewer in the middle sees of the middle frame.
    pub view: PathBuf,
    /// Seconds: encode, convert, assemble.
    pub seconds: [f64; 3],
}

/// The bundled scene: Spot the cow (Keenan Crane, public domain), decimated
/// to 500 triangles, with its texture (fixtures/SOURCES.md).
/// The bundled animated scene: Khronos' AnimatedMorphCube (CC0; fixtures/SOURCES.md).
const DEMO_MOVIE: &[u8] = include_bytes!("../fixtures/mesh/AnimatedMorphCube.glb");

const DEMO_SCENE: [(&str, &[u8]); 3] = [
    ("spot.obj", include_bytes!("../fixtures/mesh/spot/spot.obj")),
    ("spot.mtl", include_bytes!("../fixtures/mesh/spot/spot.mtl")),
    ("spot_texture.png", include_bytes!("../fixtures/mesh/spot/spot_texture.png")),
];

/// The main job on built-in defaults: the bundled textured mesh rendered for
/// every Mark III emitter and view into `dir/demo.holo`, assembled into
/// Mark III fringes in `dir/fringes`, and reconstructed by scalar diffraction
/// into what viewers at three positions see (`dir/view-*.png`). An earlier
/// demo's files are replaced. Each step's phases go to `progress`.
pub fn demo(dir: impl AsRef<Path>, progress: &dyn Progress) -> Result<Demo> {
    use crate::assemble::output::{assemble_file, AssembleOptions, FringeFormat};
    use crate::mesh::convert::{convert_mesh, ConvertOptions};
    use crate::reconstruct::files::{view_file, EyeAt};
    let dir = dir.as_ref();
    let scene_dir = dir.join("spot");
    std::fs::create_dir_all(&scene_dir).map_err(|e| crate::Error::io(&scene_dir, e))?;
    for (name, bytes) in DEMO_SCENE {
        let path = scene_dir.join(name);
        crate::output::write_bytes_beside(&path, bytes, true)?;
    }
    let scene = scene_dir.join("spot.obj");
    let layout = layout::mark3();
    let holo_file = dir.join("demo.holo");
    let mut options = ConvertOptions::default();
    options.write.overwrite = true;
    // Turn the cow to show its side and face.
    options.scene.placement.rotate_deg = [0.0, -60.0, 0.0];
    let started = std::time::Instant::now();
    let converted = convert_mesh(&scene, &layout.geometry, &holo_file, &options, &Labelled::new(progress, "mesh"))?;
    let convert_seconds = started.elapsed().as_secs_f64();
    let info = info(&holo_file, true)?;
    let fringes = dir.join("fringes");
    let started = std::time::Instant::now();
    let assembled = assemble_file(
        &holo_file,
        &layout,
        &fringes,
        &AssembleOptions { frames: None, format: FringeFormat::Png, overwrite: true, resample: false },
        &Labelled::new(progress, "fringes"),
    )?;
    let assemble_seconds = started.elapsed().as_secs_f64();
    let eyes_mm = [-40.0, 0.0, 40.0];
    let eyes: Vec<EyeAt> =
        eyes_mm.iter().map(|x| EyeAt { x_m: x * 1e-3, y_m: 0.0, distance_m: None, pupil_m: 4e-3 }).collect();
    let pictures = view_file(&fringes, None, 0, &eyes, &Labelled::new(progress, "views"))?;
    let mut views = Vec::new();
    for (x, picture) in eyes_mm.iter().zip(&pictures) {
        let path = dir.join(format!("view-x{x:+.0}mm.png"));
        picture.write_png(&path, 1.0, true)?;
        views.push((*x, path));
    }
    let movie = demo_movie(&dir.join("movie"), &layout, &Labelled::new(progress, "movie"))?;
    Ok(Demo {
        scene,
        triangles: converted.triangles,
        placement: converted.placed.to_string(),
        convert_seconds,
        holo_file,
        info,
        fringes,
        fringe_files: assembled.files,
        views,
        assemble_seconds,
        movie,
    })
}

/// The movie path of the demo: three frames of the bundled morphing cube,
/// encoded for Mark III with coarse micropolygons (4× what the display
/// resolves: a demo, not a master), drawn, assembled and one of them seen.
fn demo_movie(dir: &Path, layout: &layout::Layout, progress: &dyn Progress) -> Result<DemoMovie> {
    use crate::assemble::output::{assemble_file, AssembleOptions, FringeFormat};
    use crate::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
    use crate::holoflick::encode::{encode_holoflick, HoloFlickEncodeOptions};
    use crate::mesh::convert::SceneFramesOptions;
    use crate::reconstruct::files::{view_file, EyeAt};
    std::fs::create_dir_all(dir).map_err(|e| crate::Error::io(dir, e))?;
    let scene = dir.join("AnimatedMorphCube.glb");
    crate::output::write_bytes_beside(&scene, DEMO_MOVIE, true)?;
    let holoflick = dir.join("cube.hflk");
    let started = std::time::Instant::now();
    let options = HoloFlickEncodeOptions {
        micropolygon: 4.0,
        scene: SceneFramesOptions {
            placement: crate::mesh::place::Placement { rotate_deg: [20.0, -30.0, 0.0], ..Default::default() },
            frames: Some(0..3),
            frames_per_second: 0.5,
            ..SceneFramesOptions::default()
        },
        overwrite: true,
        ..HoloFlickEncodeOptions::default()
    };
    let encoded = encode_holoflick(&scene, &layout.geometry, &holoflick, &options, progress)?;
    let encode_seconds = started.elapsed().as_secs_f64();
    let holo_file = dir.join("cube.holo");
    let started = std::time::Instant::now();
    let mut convert = HoloFlickConvertOptions::default();
    convert.write.overwrite = true;
    convert_holoflick(&holoflick, &layout.geometry, &holo_file, &convert, progress)?;
    let convert_seconds = started.elapsed().as_secs_f64();
    let fringes = dir.join("fringes");
    let started = std::time::Instant::now();
    let assembled = assemble_file(
        &holo_file,
        layout,
        &fringes,
        &AssembleOptions { frames: None, format: FringeFormat::Png, overwrite: true, resample: false },
        progress,
    )?;
    let assemble_seconds = started.elapsed().as_secs_f64();
    let eye = EyeAt { x_m: 0.0, y_m: 0.0, distance_m: None, pupil_m: 4e-3 };
    let picture = view_file(&fringes, None, 1, &[eye], progress)?;
    let view = dir.join("view-frame1-x+0mm.png");
    if let Some(p) = picture.first() {
        p.write_png(&view, 1.0, true)?;
    }
    Ok(DemoMovie {
        scene,
        holoflick,
        frames: encoded.pack.frames,
        micropolygons: encoded.micropolygons,
        holoflick_bytes: encoded.pack.file_bytes,
        holo_file,
        fringe_files: assembled.files,
        view,
        seconds: [encode_seconds, convert_seconds, assemble_seconds],
    })
}

impl fmt::Display for Demo {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.info)?;
        writeln!(
            f,
            "\nThe demo rendered {} ({} triangles) for every Mark III emitter and view in {:.2} s\n  ({}),\ninto {},",
            self.scene.display(),
            self.triangles,
            self.convert_seconds,
            self.placement,
            self.holo_file.display()
        )?;
        writeln!(
            f,
            "assembled it into Mark III fringes in {:.2} s ({}),",
            self.assemble_seconds,
            self.fringe_files.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(", ")
        )?;
        writeln!(f, "and simulated the display by scalar diffraction. What a viewer at 600 mm sees:")?;
        for (x, path) in &self.views {
            writeln!(f, "  eye at x = {x:+.0} mm: {}", path.display())?;
        }
        let m = &self.movie;
        writeln!(
            f,
            "The movie: {} ({} frames) became the HoloFlick {} ({} micropolygons, {} bytes) in {:.2} s,",
            m.scene.display(),
            m.frames,
            m.holoflick.display(),
            m.micropolygons,
            m.holoflick_bytes,
            m.seconds[0]
        )?;
        writeln!(
            f,
            "drawn into {} in {:.2} s, assembled into {} fringe images in {:.2} s; frame 1 seen from the middle: {}",
            m.holo_file.display(),
            m.seconds[1],
            m.fringe_files.len(),
            m.seconds[2],
            m.view.display()
        )?;
        writeln!(f, "Each view is also a picture in any OpenEXR viewer, or as PNGs:")?;
        writeln!(
            f,
            "  holo export-views {} -o {}",
            self.holo_file.display(),
            self.holo_file.with_file_name("views").display()
        )
    }
}

/// A frame rate stored as the fraction `numerator / denominator` frames a
/// second, as a number with its unit: `24 frames/s`, `0.5 frames/s`; a
/// fraction that is not a whole number of thousandths is given as well,
/// `23.976 frames/s (24000/1001)`.
pub fn frame_rate_text(numerator: i64, denominator: u64) -> String {
    if denominator == 0 {
        return format!("{numerator}/0 frames/s (no rate)");
    }
    let rate = numerator as f64 / denominator as f64;
    if (i128::from(numerator) * 1000) % i128::from(denominator) == 0 {
        let text = format!("{rate:.3}");
        format!("{} frames/s", text.trim_end_matches('0').trim_end_matches('.'))
    } else {
        format!("{rate:.3} frames/s ({numerator}/{denominator})")
    }
}

#[cfg(test)]
mod tests {
    use super::frame_rate_text;

    #[test]
    fn frame_rates_are_numbers_with_units() {
        for (n, d, text) in [
            (24, 1, "24 frames/s"),
            (1, 2, "0.5 frames/s"),
            (2997, 100, "29.97 frames/s"),
            (24000, 1001, "23.976 frames/s (24000/1001)"),
            (30000, 1001, "29.970 frames/s (30000/1001)"),
            (1, 3, "0.333 frames/s (1/3)"),
        ] {
            assert_eq!(frame_rate_text(n, d), text);
        }
    }
}
