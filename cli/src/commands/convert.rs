//! `holo convert mesh|cameras|holoflick`: content into a `.holo` file for a
//! layout.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use clap::{Args, Subcommand};
use holo::cameras::convert::{convert_camera_files, CameraConvertOptions};
use holo::cameras::quilt::{DEFAULT_VERTICAL_FOV_DEG, DEFAULT_VIEW_CONE_DEG};
use holo::cameras::read::{CameraHints, OpenOptions};
use holo::cameras::resample::{CameraOptions, Framing, Parallax, PlacementRequest, MAX_EMITTER_TAPS};
use holo::farm::FarmOutput;
use holo::holoflick::convert::HoloFlickSource;
use holo::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
use holo::math::Mat4;
use holo::mesh::convert::{convert_mesh, ConvertOptions, MeshRender, SceneFrames, SceneFramesOptions};
use holo::mesh::place::display_volume;
use holo::mesh::render::{Engine, RenderOptions, Supersample};
use holo::mesh::shade::{parse_light, read_lights, Lighting};
use holo::pipeline::decide;

use super::frame_job::{Decided, FrameJob};
use super::{check_output, inputs_exist, Failure, Outcome};
use crate::args::{
    self, layout_geometry, layout_help, BlendChoice, FramingChoice, ParallaxChoice, PlacementArgs, SpecularChoice,
    WriteArgs,
};
use crate::out::{note, say, warn};
use crate::progress::Reporter;

#[derive(Subcommand)]
pub enum ConvertCommand {
    Holoflick(HoloflickArgs),
    Mesh(MeshArgs),
    Cameras(CamerasArgs),
    Like(super::recorded::LikeArgs),
}

pub fn run(command: ConvertCommand) -> Outcome {
    match command {
        ConvertCommand::Holoflick(a) => holoflick(a),
        ConvertCommand::Mesh(a) => mesh(a),
        ConvertCommand::Cameras(a) => cameras(a),
        ConvertCommand::Like(a) => super::recorded::like(a),
    }
}

/// What every conversion shares: the display it is for, and the file written.
#[derive(Args)]
pub struct Target {
    #[arg(long, default_value = "mark3", help = layout_help(""))]
    layout: String,
    #[command(flatten)]
    write: WriteArgs,
    /// Print where the time went: seconds in each stage (open, place, decode, render, write), and per frame.
    #[arg(long)]
    timings: bool,
}

impl Target {
    /// The timings line, when asked for.
    fn say_timings(&self, timings: &holo::progress::Timings, frames: usize) {
        if self.timings {
            say!("timings: {}", timings.line(frames));
        }
    }
}

/// Sub-rays per sample, as `--supersample` and `--hololine-supersample` give them.
fn supersample((emitter, view): (usize, usize), hololine: usize) -> Supersample {
    Supersample { emitter, view, hololine }
}

/// Draw a HoloFlick's lit micropolygons for every emitter and view of a
/// layout, adding each frame's specular highlights per view.
#[derive(Args)]
pub struct HoloflickArgs {
    /// The .hflk file.
    file: PathBuf,
    #[command(flatten)]
    target: Target,
    /// Frames to convert: N, A..B or A..=B (split a movie across machines); default all.
    #[arg(long, value_parser = args::range())]
    frames: Option<Range<usize>>,
    /// Sub-rays per sample, EMITTERSxVIEWS (e.g. 2x2) or N for NxN; full parallax: VIEWS sub-views
    /// across each view in both directions.
    #[arg(long, default_value = "2x2", value_parser = args::by(64, true))]
    supersample: (usize, usize),
    /// Lines across each hololine's height, averaged (antialiases edges near the horizontal), 1 to 64.
    #[arg(long, default_value = "1", value_parser = args::whole(1, 64))]
    hololine_supersample: usize,
    /// Fit the content to the display even when it was made for it.
    #[arg(long)]
    fit: bool,
    #[command(flatten)]
    vertical: args::VerticalViewsArgs,
    /// A row-major 4x4 matrix (16 numbers, world to display metres) placing the content instead of
    /// deciding on the first frame converted (what holo farm gives every chunk).
    #[arg(long, value_name = "16 NUMBERS", value_parser = args::matrix(), allow_hyphen_values = true)]
    matrix: Option<[[f64; 4]; 4]>,
}

fn holoflick(a: HoloflickArgs) -> Outcome {
    let g = a.vertical.geometry(&a.target.layout)?;
    inputs_exist(&[&a.file])?;
    let _claim = check_output(&a.target.write.output, &[&a.file, Path::new(&a.target.layout)], a.target.write.force)?;
    let options = holoflick_options(&a);
    let started = Instant::now();
    let report = convert_holoflick(&a.file, &g, &a.target.write.output, &options, &Reporter::on_stderr())?;
    report.warnings.iter().for_each(warn);
    let w = report.work;
    say!(
        "converted frames {}..{} of {} into {} in {:.2} s",
        report.frames.start,
        report.frames.end,
        a.file.display(),
        report.path.display(),
        started.elapsed().as_secs_f64()
    );
    say!(
        "objects decoded {}, reused from key frames {}, skipped unseen {}; {} back faces dropped; {} segments rasterised, {} sub-rays shaded",
        w.decoded,
        w.reused,
        w.unseen_objects,
        w.back_faces,
        w.render.segments,
        w.render.shaded
    );
    a.target.say_timings(&report.timings, report.frames.len());
    Ok(ExitCode::SUCCESS)
}

/// The library's options for `a`.
fn holoflick_options(a: &HoloflickArgs) -> HoloFlickConvertOptions {
    HoloFlickConvertOptions {
        frames: a.frames.clone(),
        render: RenderOptions { supersample: supersample(a.supersample, a.hololine_supersample), ..Default::default() },
        write: a.target.write.options(String::new()),
        fit: a.fit,
        matrix: a.matrix,
    }
}

/// Render a glTF (.gltf/.glb), OBJ or PLY scene for every emitter and
/// view of a layout (animated glTF: one frame per 1/fps).
#[derive(Args)]
pub struct MeshArgs {
    /// The scene file.
    scene: PathBuf,
    #[command(flatten)]
    target: Target,
    /// Frames to convert (animated glTF): N, A..B or A..=B; default all.
    #[arg(long, value_parser = args::range())]
    frames: Option<Range<usize>>,
    /// Frames per second at which animations are sampled: a number, or an exact fraction such as 24000/1001.
    #[arg(long, default_value = "30", value_parser = args::frame_rate())]
    fps: f64,
    /// Sub-rays per sample, EMITTERSxVIEWS (e.g. 2x2) or N for NxN; full parallax: VIEWS sub-views
    /// across each view in both directions.
    #[arg(long, default_value = "2x2", value_parser = args::by(64, true))]
    supersample: (usize, usize),
    /// Lines across each hololine's height, averaged (antialiases edges near the horizontal), 1 to 64.
    #[arg(long, default_value = "1", value_parser = args::whole(1, 64))]
    hololine_supersample: usize,
    /// Specular lobe.
    #[arg(long, value_enum, default_value = "blinn")]
    specular: SpecularChoice,
    /// A light (repeatable): dir:DX,DY,DZ[:R,G,B], point:X,Y,Z[:R,G,B] or ambient:R,G,B. Lights given are
    /// added to the scene's own and replace the two default lights (dir:1,-1,-1 and ambient:0.08,0.08,0.08),
    /// which light only a scene given no lights: a side the given lights miss is then dark (a note says
    /// so). dir: a distant light travelling along DX,DY,DZ, the way its light goes (x right, y up, z toward
    /// the viewer: dir:0,0,-1 lights the scene's front); point: a light at X,Y,Z millimetres (display
    /// coordinates); ambient: radiance. R,G,B: irradiance at the scene (default π: a white surface facing
    /// the light has radiance 1).
    #[arg(long, value_name = "KIND:VALUES")]
    light: Vec<String>,
    /// A file of lights, one per line as --light takes them (# starts a comment); like --light, they
    /// replace the default lights.
    #[arg(long, value_name = "FILE")]
    lights: Option<PathBuf>,
    /// Ignore the scene's own lights (glTF KHR_lights_punctual).
    #[arg(long)]
    no_scene_lights: bool,
    #[command(flatten)]
    placement: PlacementArgs,
    /// Render with the reference ray caster (slow; for checking).
    #[arg(long)]
    reference: bool,
    #[command(flatten)]
    vertical: args::VerticalViewsArgs,
    /// Give objects without normals (scans, old exporters) smooth ones: edges
    /// between faces within DEG of each other are smoothed (30 is a common
    /// choice); without it they are shaded flat.
    #[arg(long, value_name = "DEG", value_parser = args::degrees_0_to_180())]
    smooth_normals: Option<f64>,
}

fn mesh(a: MeshArgs) -> Outcome {
    let g = a.vertical.geometry(&a.target.layout)?;
    let options = mesh_options(&a, &g)?;
    inputs_exist(&[&a.scene])?;
    let mut read = vec![a.scene.as_path(), Path::new(&a.target.layout)];
    read.extend(a.lights.as_deref());
    let _claim = check_output(&a.target.write.output, &read, a.target.write.force)?;
    let started = Instant::now();
    let report = convert_mesh(&a.scene, &g, &a.target.write.output, &options, &Reporter::on_stderr())?;
    report.warnings.iter().for_each(warn);
    for w in &report.written.warnings {
        warn(format_args!("{}: {w}", report.path.display()));
    }
    say!(
        "converted {} ({} triangles in {} objects) into {} frame(s) of {} in {:.2} s",
        a.scene.display(),
        report.triangles,
        report.objects,
        report.frames.len(),
        report.path.display(),
        started.elapsed().as_secs_f64()
    );
    say!("{}", report.placed);
    say!(
        "{} light(s); {} segments rasterised, {} sub-rays shaded",
        report.lights.len(),
        report.stats.segments,
        report.stats.shaded
    );
    // The lights given are all the lights (the scene has none of its own, or
    // they are ignored): the two default ones are not used.
    let given = options.render.lighting.lights.len();
    if given > 0 && report.lights.len() == given {
        note(format_args!(
            "the lights given replace the default ones (--light {}); give those too to keep them",
            Lighting::DEFAULT_SPECS.join(" --light ")
        ));
    }
    a.target.say_timings(&report.timings, report.frames.len());
    Ok(ExitCode::SUCCESS)
}

/// The library's options for `a` on the display `g`.
fn mesh_options(a: &MeshArgs, g: &holo::Geometry) -> Result<ConvertOptions, Failure> {
    // Point lights are given relative to the middle of the display.
    let (lo, hi) = display_volume(g);
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), g.emitter_z_m];
    let mut user_lights = match &a.lights {
        Some(path) => read_lights(path, centre)?,
        None => Vec::new(),
    };
    for spec in &a.light {
        user_lights.push(parse_light(spec, centre)?);
    }
    Ok(ConvertOptions {
        scene: SceneFramesOptions {
            placement: a.placement.placement(),
            frames: a.frames.clone(),
            frames_per_second: a.fps,
            smooth_normals_deg: a.smooth_normals,
        },
        render: RenderOptions {
            supersample: supersample(a.supersample, a.hololine_supersample),
            lighting: Lighting { lights: user_lights, model: a.specular.0 },
            scene_lights: !a.no_scene_lights,
            default_lights: true,
            engine: if a.reference { Engine::Reference } else { Engine::Fast },
        },
        write: a.target.write.options(String::new()),
    })
}

/// Resample camera-array pictures (a rig file, an HCI or Stanford light
/// field folder, a Middlebury _par.txt, a Looking Glass quilt or a
/// folder of images on a rail) into every emitter and view of a layout.
#[derive(Args)]
pub struct CamerasArgs {
    /// The capture: rig file (.json/.toml), folder, _par.txt or quilt image.
    input: PathBuf,
    #[command(flatten)]
    target: Target,
    /// Camera weighting.
    #[arg(long, value_enum, default_value = "linear")]
    blend: BlendChoice,
    /// Focus distance from the cameras, in the rig's units (default: what the capture says).
    #[arg(long, value_parser = args::positive())]
    focus: Option<f64>,
    /// Display millimetres per rig unit (default: from --framing).
    #[arg(long = "scale", value_name = "MM", value_parser = args::positive_millimetres())]
    scale_m: Option<f64>,
    /// The rig point shown at the middle of the emitter plane, rig units: X,Y,Z (default: the focus point).
    #[arg(long, value_parser = args::triple("X,Y,Z in rig units"), allow_hyphen_values = true)]
    center: Option<[f64; 3]>,
    /// How big the capture is shown: fit (all the middle camera saw at the focus, as large as fits),
    /// fill (covering the display, the overflow cut), width (filling the display's width),
    /// viewer (the cameras at the viewer's distance).
    #[arg(long, value_enum, default_value = "fit")]
    framing: FramingChoice,
    /// Same as --framing width.
    #[arg(long, conflicts_with = "framing")]
    fill_width: bool,
    /// How the capture's directions meet the display's views: fit (the cameras' span across the
    /// eye positions that see the display) or true (as captured; rays no camera saw stay black).
    #[arg(long, value_enum, default_value = "fit")]
    parallax: ParallaxChoice,
    /// Ignore the rig's depth maps.
    #[arg(long)]
    no_depth: bool,
    /// Rays averaged across each emitter, 1 to 64 (default: from the pictures' resolution).
    #[arg(long, value_parser = args::whole(1, MAX_EMITTER_TAPS))]
    taps: Option<usize>,
    /// Also write a PNG (emitters × hololines) of the fraction of views no camera sees.
    #[arg(long)]
    unseen_mask: Option<PathBuf>,
    /// Folder of images: distance between neighbouring cameras (rig units).
    #[arg(long, value_parser = args::positive())]
    baseline: Option<f64>,
    /// Folder or Stanford: focal length in pixels.
    #[arg(long, value_parser = args::positive(), conflicts_with = "fov_deg")]
    focal_px: Option<f64>,
    /// Folder or Stanford: horizontal field of view in degrees.
    #[arg(long = "fov", value_name = "DEG", value_parser = args::angle_below_180_degrees())]
    fov_deg: Option<f64>,
    /// Quilt: angle between the first and last view, degrees.
    #[arg(long = "view-cone", value_name = "DEG", default_value_t = DEFAULT_VIEW_CONE_DEG, value_parser = args::angle_below_180_degrees())]
    view_cone_deg: f64,
    /// Quilt: vertical field of view of each view, degrees.
    #[arg(long = "quilt-fov", value_name = "DEG", default_value_t = DEFAULT_VERTICAL_FOV_DEG, value_parser = args::angle_below_180_degrees())]
    quilt_fov_deg: f64,
    /// Locate rays among the cameras by brute force (slow; for checking).
    #[arg(long)]
    reference: bool,
    #[command(flatten)]
    vertical: args::VerticalViewsArgs,
}

fn cameras(a: CamerasArgs) -> Outcome {
    let write = &a.target.write;
    let g = a.vertical.geometry(&a.target.layout)?;
    inputs_exist(&[&a.input])?;
    let _claim = check_output(&write.output, &[&a.input, Path::new(&a.target.layout)], write.force)?;
    let _mask_claim =
        a.unseen_mask.as_ref().map(|mask| check_output(mask, &[&a.input, &write.output], write.force)).transpose()?;
    let mut open = OpenOptions::default();
    open.folder.baseline = a.baseline;
    let camera = CameraHints { focal_length_px: a.focal_px, horizontal_fov_deg: a.fov_deg, focus_distance: a.focus };
    open.folder.camera = camera.clone();
    open.stanford.camera = camera;
    open.quilt.view_cone_deg = a.view_cone_deg;
    open.quilt.vertical_fov_deg = a.quilt_fov_deg;
    let placement = PlacementRequest {
        scale: a.scale_m,
        centre: a.center,
        focus: a.focus,
        framing: if a.fill_width { Framing::FillWidth } else { a.framing.0 },
        parallax: a.parallax.0,
    };
    let options = CameraConvertOptions {
        resample: CameraOptions {
            blend: a.blend.0,
            placement,
            use_depth: !a.no_depth,
            want_mask: false,
            reference: a.reference,
            emitter_taps: a.taps,
        },
        open,
        unseen_png: a.unseen_mask,
        write: write.options(String::new()),
    };
    let started = Instant::now();
    let report = convert_camera_files(&a.input, &g, &write.output, &options, &Reporter::on_stderr())
        .map_err(with_capture_flags)?;
    report.resample.warnings.iter().chain(&report.written.warnings).for_each(warn);
    let r = &report.resample;
    let (input, output, seconds) = (a.input.display(), report.path.display(), started.elapsed().as_secs_f64());
    say!("converted {input} ({}) into {output} in {seconds:.2} s", r.surface);
    say!("placement: {}", r.placement);
    a.target.say_timings(&report.timings, 1);
    let percent = |n: u64| 100.0 * n as f64 / r.rays.max(1) as f64;
    let inside = r.unseen - r.unseen_outside_frame;
    say!(
        "{} rays, {} taps per emitter; {} ({:.1}%) seen by no camera and left black: {:.1}% outside the capture's frame, {:.1}% inside it",
        r.rays,
        r.emitter_taps,
        r.unseen,
        percent(r.unseen),
        percent(r.unseen_outside_frame),
        percent(inside)
    );
    // What would fix many unseen rays, by cause.
    if percent(r.unseen_outside_frame) >= 10.0 && a.scale_m.is_none() {
        say!("the capture's frame does not have the display's shape: --framing fill covers the display (cutting the capture's overflowing edges)");
    }
    if percent(inside) >= 10.0 {
        match a.parallax.0 {
            Parallax::True => say!(
                "the cameras did not look along many of the display's views: --parallax fit spreads them across the viewer's positions"
            ),
            Parallax::Fit => say!(
                "the cameras do not see many points the display shows (outside their pictures, or hidden by their depth maps): check --focus and --center, or --no-depth"
            ),
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What a capture's files do not say, by the words the library's sentences
/// name it with, and the flags that give it.
const CAPTURE_FLAGS: [(&str, &str); 4] = [
    ("the baseline", "--baseline"),
    ("focal length", "--focal-px or --fov"),
    ("field of view", "--focal-px or --fov"),
    ("the focus distance", "--focus"),
];

/// A capture refused for something only the user can give, with the flags
/// that give it (the library names quantities, the command line its flags).
fn with_capture_flags(e: holo::Error) -> Failure {
    let mut flags: Vec<&str> = Vec::new();
    if let holo::Error::Rig { problem, .. } = &e {
        for (words, flag) in CAPTURE_FLAGS {
            if problem.contains(words) && !flags.contains(&flag) {
                flags.push(flag);
            }
        }
    }
    match flags.as_slice() {
        [] => Failure::from(e),
        _ => Failure(format!("{e} ({})", flags.join("; "))),
    }
}

/// A conversion as `holo farm` splits it: one file of the numbered sequence
/// per frame, the movie placed once.
impl Target {
    fn farm_output(&self) -> FarmOutput {
        FarmOutput::Sequence(self.write.output.clone())
    }

    /// Write frame `n` alone into `output`, replacing what is there (a
    /// frame the farm found missing or damaged).
    fn one_frame(&mut self, output: PathBuf) {
        self.write.output = output;
        self.write.force = true;
    }
}

impl FrameJob for MeshArgs {
    fn output(&self) -> FarmOutput {
        self.target.farm_output()
    }

    fn decide(&self) -> Result<Decided, Failure> {
        let g = self.vertical.geometry(&self.target.layout)?;
        let options = mesh_options(self, &g)?;
        let mut source = SceneFrames::open(&self.scene, &g, &options.scene, MeshRender::new(&options))?;
        let (frames, placement) = decide(&mut source, self.frames.clone())?;
        Ok(Decided { frames, placement })
    }

    fn for_frame(&mut self, n: usize, output: PathBuf, placement: Option<Mat4>) {
        self.frames = Some(n..n + 1);
        self.placement.matrix = placement.or(self.placement.matrix);
        self.target.one_frame(output);
    }
}

impl FrameJob for HoloflickArgs {
    fn output(&self) -> FarmOutput {
        self.target.farm_output()
    }

    fn decide(&self) -> Result<Decided, Failure> {
        let g = self.vertical.geometry(&self.target.layout)?;
        let options = holoflick_options(self);
        let mut source = HoloFlickSource::open(&self.file, &g, &options)?;
        let (frames, placement) = decide(&mut source, self.frames.clone())?;
        // Drawn as stored (the identity), every chunk decides alike; a fit
        // made on the movie's first frame is handed to every chunk.
        Ok(Decided { frames, placement: placement.filter(|m| *m != holo::math::IDENTITY4) })
    }

    fn for_frame(&mut self, n: usize, output: PathBuf, placement: Option<Mat4>) {
        self.frames = Some(n..n + 1);
        self.matrix = placement.or(self.matrix);
        self.target.one_frame(output);
    }
}

impl FrameJob for CamerasArgs {
    fn output(&self) -> FarmOutput {
        self.target.farm_output()
    }

    /// A capture is one frame.
    fn decide(&self) -> Result<Decided, Failure> {
        layout_geometry(&self.target.layout)?;
        if !self.input.exists() {
            return Err(Failure(format!("{}: no such file or folder", self.input.display())));
        }
        Ok(Decided { frames: 0..1, placement: None })
    }

    fn for_frame(&mut self, _: usize, output: PathBuf, _: Option<Mat4>) {
        self.target.one_frame(output);
    }
}
