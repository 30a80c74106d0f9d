//! `holo holoflick info|pack|encode|unpack`: thin wrappers over
//! `holo::holoflick::tools` and `holo::holoflick::encode`.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Subcommand};
use holo::holoflick::cg::EncodeOptions;
use holo::holoflick::container::ViewerCouch;
use holo::holoflick::encode::{encode_holoflick, HoloFlickEncodeOptions, DEFAULT_MICROPOLYGON};
use holo::holoflick::tools::{info, pack, unpack, PackOptions, PackReport};
use holo::mesh::convert::SceneFramesOptions;

use super::{check_output, inputs_exist, Outcome};
use crate::args::{self, layout_help, PlacementArgs};
use crate::out::{put, say, warn};
use crate::progress::Reporter;

// Parsed once per run: the size of its largest variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
pub enum HoloflickCommand {
    /// Describe a HoloFlick (.hflk) or Java 3D compressed-geometry (.cg) file:
    /// frames, objects, triangles, bytes per triangle.
    Info {
        /// The file.
        file: PathBuf,
    },
    Pack(PackArgs),
    Encode(EncodeArgs),
    /// Write one frame of a HoloFlick (or the objects of a .cg file) as a
    /// mesh: .glb (glTF, unlit vertex colours) or .ply.
    Unpack {
        /// The .hflk or .cg file.
        file: PathBuf,
        /// Which frame.
        #[arg(long, default_value = "0", value_parser = args::at_least(0))]
        frame: usize,
        /// Output: NAME.glb or NAME.ply.
        #[arg(short, long)]
        output: PathBuf,
        /// Replace an existing output.
        #[arg(long)]
        force: bool,
    },
}

pub fn run(command: HoloflickCommand) -> Outcome {
    match command {
        HoloflickCommand::Info { file } => put!("{}", info(&file)?),
        HoloflickCommand::Pack(a) => return run_pack(a),
        HoloflickCommand::Encode(a) => return run_encode(a),
        HoloflickCommand::Unpack { file, frame, output, force } => {
            inputs_exist(&[&file])?;
            let _claim = check_output(&output, &[&file], force)?;
            let triangles = unpack(&file, frame, &output, force)?;
            say!("wrote {} ({triangles} triangles of frame {frame})", output.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// What packing and encoding share: quantization, frames, key frames.
#[derive(Args)]
pub struct MovieArgs {
    /// Bits per position component.
    #[arg(long, default_value = "16", value_parser = args::whole(1, 16))]
    position_bits: usize,
    /// Bits per colour component.
    #[arg(long, default_value = "9", value_parser = args::whole(2, 16))]
    colour_bits: usize,
    /// Bits of the normal grid.
    #[arg(long, default_value = "6", value_parser = args::whole(0, 6))]
    normal_bits: usize,
    /// Frame rate, and the rate animations are sampled at: a number, or an exact fraction such as 24000/1001.
    #[arg(long, default_value = "30", value_parser = args::frame_rate())]
    fps: f64,
    /// Frames of an animation to keep: N, A..B or A..=B; default all.
    #[arg(long, value_parser = args::range())]
    frames: Option<Range<usize>>,
    /// A key frame every N frames (1 or more; 1: every frame a key frame).
    #[arg(long, default_value = "30", value_parser = args::at_least(1))]
    key_interval: usize,
    /// Replace an existing output.
    #[arg(long)]
    force: bool,
}

impl MovieArgs {
    /// The quantization asked for (each count checked against its range).
    fn encode(&self) -> EncodeOptions {
        EncodeOptions {
            position_bits: self.position_bits as u32,
            color_bits: self.colour_bits as u32,
            normal_bits: self.normal_bits as u32,
            alpha: true,
        }
    }
}

/// Pack meshes (glTF, OBJ, PLY; one frame each, an animated glTF one
/// frame per 1/fps) into a HoloFlick, or into a Java 3D .cg file when
/// the output ends in .cg (one frame's objects, without their transforms).
#[derive(Args)]
pub struct PackArgs {
    /// The mesh files, one frame each (in order).
    #[arg(required = true)]
    meshes: Vec<PathBuf>,
    /// Output: NAME.hflk or NAME.cg.
    #[arg(short, long)]
    output: PathBuf,
    /// The viewer's couch, XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX in metres
    /// (default: a box in front of the scene, +z).
    #[arg(long, value_parser = args::couch(), allow_hyphen_values = true)]
    couch: Option<ViewerCouch>,
    #[command(flatten)]
    movie: MovieArgs,
}

fn run_pack(a: PackArgs) -> Outcome {
    let m = &a.movie;
    let read: Vec<&Path> = a.meshes.iter().map(PathBuf::as_path).collect();
    inputs_exist(&read)?;
    let _claim = check_output(&a.output, &read, m.force)?;
    let options = PackOptions {
        encode: m.encode(),
        frames_per_second: m.fps,
        frames: m.frames.clone(),
        couch: a.couch,
        key_interval: m.key_interval,
        overwrite: m.force,
    };
    let report = pack(&a.meshes, &a.output, &options, &Reporter::on_stderr())?;
    report.warnings.iter().for_each(warn);
    say_packed(&report, "triangle", report.triangles);
    for (i, (c, s)) in report.cg_transforms.iter().enumerate() {
        say!("  object {i}: model = normalised × {s:.6e} + ({:.6}, {:.6}, {:.6})", c[0], c[1], c[2]);
    }
    Ok(ExitCode::SUCCESS)
}

/// Make a HoloFlick for a display from a glTF, OBJ or PLY scene (the
/// geometry shader of Deering's HoloFlicks): place it, dice it into
/// micropolygons sized for the display, bake ambient and diffuse light (and
/// shadows) into vertex colours, keep specular as materials; animated glTF
/// gives one frame per 1/fps.
#[derive(Args)]
pub struct EncodeArgs {
    /// The scene file.
    scene: PathBuf,
    /// Output: NAME.hflk.
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, default_value = "mark3", help = layout_help(""))]
    layout: String,
    /// Micropolygon edge as a multiple of what the display resolves at its depth (1: finest that
    /// shows; flat, untextured faces under directional light are left whole at any size).
    #[arg(long, default_value_t = DEFAULT_MICROPOLYGON, value_parser = args::positive())]
    micropolygon: f64,
    /// Keep micropolygons flat (do not bend them onto the surface the normals describe).
    #[arg(long)]
    flat: bool,
    /// Bake shadows of the scene's lights.
    #[arg(long)]
    shadows: bool,
    /// Give objects without normals smooth ones: edges between faces within
    /// DEG of each other are smoothed; without it they are shaded flat.
    #[arg(long, value_name = "DEG", value_parser = args::degrees_0_to_180())]
    smooth_normals: Option<f64>,
    #[command(flatten)]
    placement: PlacementArgs,
    #[command(flatten)]
    vertical: args::VerticalViewsArgs,
    #[command(flatten)]
    movie: MovieArgs,
}

fn run_encode(a: EncodeArgs) -> Outcome {
    let g = a.vertical.geometry(&a.layout)?;
    inputs_exist(&[&a.scene])?;
    let _claim = check_output(&a.output, &[&a.scene, Path::new(&a.layout)], a.movie.force)?;
    let m = &a.movie;
    let options = HoloFlickEncodeOptions {
        micropolygon: a.micropolygon,
        smooth: !a.flat,
        shadows: a.shadows,
        encode: m.encode(),
        scene: SceneFramesOptions {
            placement: a.placement.placement(),
            frames: m.frames.clone(),
            frames_per_second: m.fps,
            smooth_normals_deg: a.smooth_normals,
        },
        key_interval: m.key_interval,
        overwrite: m.force,
    };
    let report = encode_holoflick(&a.scene, &g, &a.output, &options, &Reporter::on_stderr())?;
    report.pack.warnings.iter().for_each(warn);
    say_packed(&report.pack, "micropolygon", report.micropolygons);
    say!("{}", report.placed);
    Ok(ExitCode::SUCCESS)
}

/// What a HoloFlick written holds: `count` `elements` (triangles or
/// micropolygons) in its frames, and their cost in stream bytes.
fn say_packed(p: &PackReport, element: &str, count: usize) {
    let (path, bytes, frames) = (p.path.display(), p.file_bytes, p.frames);
    let per_element = p.stream_bytes as f64 / p.triangles.max(1) as f64;
    say!(
        "wrote {path} ({bytes} bytes): {frames} frames, {} objects stored, {} from key frames, {count} {element}s, \
         {per_element:.2} stream bytes/{element}",
        p.stored,
        p.references
    );
}
