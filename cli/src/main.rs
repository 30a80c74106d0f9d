//! The `holo` command: parses arguments, calls the library, prints, and turns
//! outcomes into exit codes (0 ok, 1 error, 2 usage). All work happens in the
//! `holo` library, where tests call it too.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// `print!` to stdout through [`print_out`]: a closed stdout ends the process quietly.
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::print_out(format_args!($($arg)*))
    };
}

/// `println!` to stdout through [`print_out`]: a closed stdout ends the process quietly.
macro_rules! outln {
    ($($arg:tt)*) => {
        $crate::print_out(format_args!("{}\n", format_args!($($arg)*)))
    };
}

mod holoflick;
use holo::assemble::load_layout;
mod progress;
use holo::assemble::output::{assemble_file, AssembleOptions, FringeFormat, FRINGE_SIDECAR};
use holo::cameras::quilt::{QuiltOptions, QuiltSpec};
use holo::format::{Compression, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, Geometry};
use holo::pattern::{Pattern, PatternKind};
use holo::views::{ToneMapping, SIDECAR};

#[derive(Parser)]
#[command(name = "holo", version, about = "The .holo modulation-texture file for holographic stereogram displays", long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// Parsed once per run: the size of its largest variant does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    /// Show geometry, channels, frames, size and value range of .holo files
    /// (with two or more files, also whether they hold the same content).
    Info {
        /// The .holo files.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Read headers only: skip the value range and digest check.
        #[arg(long)]
        headers_only: bool,
    },
    /// Check every rule of the .holo spec, including each frame's digest;
    /// exits 1 and lists the violations if any file breaks one.
    Validate {
        /// The .holo files.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Write a display-engineering test pattern for a layout.
    Pattern {
        /// Display layout (built in: mark3, mark1).
        #[arg(long, default_value = "mark3")]
        layout: String,
        /// Which pattern: single-emitter, single-view, every-nth-emitter, view-ramp, colour-bars, checkerboard.
        #[arg(long, value_parser = parse_kind)]
        kind: PatternKind,
        /// Emitter lit by single-emitter (default: the centre).
        #[arg(long)]
        emitter: Option<usize>,
        /// View lit by single-view (default: the centre).
        #[arg(long)]
        view: Option<usize>,
        /// Spacing of every-nth-emitter.
        #[arg(long, default_value_t = 8)]
        every: usize,
        /// Square size of checkerboard, in hololines and emitters.
        #[arg(long, default_value_t = 8)]
        cell: usize,
        /// Radiance of a lit sample.
        #[arg(long, default_value_t = 1.0)]
        level: f32,
        /// Colour channels instead of the layout's own.
        #[arg(long, value_enum)]
        channels: Option<ChannelsArg>,
        #[command(flatten)]
        write: WriteArgs,
    },
    /// Write each view of a frame as a PNG (view_000.png, …) plus holo-views.json.
    ExportViews {
        /// The .holo file.
        file: PathBuf,
        /// Directory for the PNGs (created if needed).
        #[arg(long, short)]
        out: PathBuf,
        /// Frame (0-based, in file order).
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Bits per component.
        #[arg(long, default_value_t = 16, value_parser = clap::builder::ValueParser::new(parse_bits))]
        bits: u8,
        /// Sample value shown as full white, or `auto` for the frame's maximum.
        #[arg(long, default_value = "1")]
        white: String,
        /// Replace existing PNGs.
        #[arg(long)]
        force: bool,
    },
    /// Write a frame as a Looking Glass quilt (8-bit sRGB PNG): one view per
    /// camera on a horizontal rail facing the display, view 0 (leftmost) in the
    /// bottom-left tile, named NAME_qsCxRaA.png for the Looking Glass software.
    ExportQuilt {
        /// The .holo file.
        file: PathBuf,
        /// Output PNG (default: the quilt's conventional name next to FILE).
        #[arg(long, short, conflicts_with = "output_dir")]
        output: Option<PathBuf>,
        /// Directory for the quilt, under its conventional name (created if needed).
        #[arg(long)]
        output_dir: Option<PathBuf>,
        /// Frame (0-based, in file order).
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Quilt settings of a Looking Glass: portrait (8x6 tiles of 420x560),
        /// standard or 4k (5x9 of 819x455), go (11x6 of 372x682).
        #[arg(long, default_value = "portrait", value_parser = parse_preset)]
        preset: QuiltSpec,
        /// Tiles per row, instead of the preset's.
        #[arg(long)]
        columns: Option<usize>,
        /// Rows of tiles, instead of the preset's.
        #[arg(long)]
        rows: Option<usize>,
        /// Tile size in pixels, WxH, instead of the preset's.
        #[arg(long, value_parser = parse_tile)]
        tile: Option<(usize, usize)>,
        /// Width/height of a view as the display shows it, instead of the preset's.
        #[arg(long)]
        aspect: Option<f64>,
        /// Angle between the outermost views, degrees.
        #[arg(long, default_value_t = holo::cameras::quilt::DEFAULT_VIEW_CONE_DEG)]
        view_cone: f64,
        /// Sample value shown as full white, or `auto` for the quilt's 99.9th percentile.
        #[arg(long, default_value = "auto")]
        white: String,
        /// Replace an existing file.
        #[arg(long)]
        force: bool,
    },
    /// Build a .holo file from a directory of view PNGs (the inverse of export-views).
    ImportViews {
        /// Directory holding view_000.png, …
        dir: PathBuf,
        /// Geometry: a layout name or a JSON file (default: DIR/holo-views.json).
        #[arg(long)]
        geometry: Option<String>,
        /// Sample value of full white (default: the sidecar's, else 1).
        #[arg(long)]
        white: Option<f32>,
        #[command(flatten)]
        write: WriteArgs,
    },
    /// Convert content into a .holo file.
    #[command(subcommand)]
    Convert(ConvertCommand),
    /// HoloFlicks (.hflk) and Java 3D compressed geometry (.cg): info, pack, unpack.
    #[command(subcommand)]
    Holoflick(holoflick::HoloflickCommand),
    /// Assemble hologram fringes: one image per head (or colour layer) per
    /// frame, laid out as the layout's frame buffer expects.
    Assemble {
        /// The .holo file.
        file: PathBuf,
        /// Display layout: a built-in name (mark3) or a .toml/.json profile.
        #[arg(long, default_value = "mark3")]
        layout: String,
        /// Directory for the images and holo-fringes.json (created if needed).
        #[arg(long, short)]
        out: PathBuf,
        /// Frames to assemble: N, A..B (B excluded) or A..=B; default all.
        #[arg(long, value_parser = parse_frames)]
        frames: Option<std::ops::Range<usize>>,
        /// png or raw (8-bit, with the layout's offset and gain) or exr (float signal).
        #[arg(long, default_value = "png", value_parser = parse_fringe_format)]
        format: FringeFormat,
        /// When the file's geometry is not the layout's, resample it onto the
        /// layout (ray by ray) instead of refusing.
        #[arg(long)]
        resample: bool,
        /// Replace existing files.
        #[arg(long)]
        force: bool,
    },
    /// Recover a frame's modulation from its fringes (least squares, and
    /// through the optics by scalar diffraction) and print the error against
    /// the stored modulation.
    Check {
        /// The .holo file.
        file: PathBuf,
        /// Display layout: a built-in name or a .toml/.json profile (default:
        /// the fringes' own with --fringes, else mark3).
        #[arg(long)]
        layout: Option<String>,
        /// Frame index in the file.
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Check fringes `holo assemble` already wrote to this directory
        /// instead of assembling them (8-bit, in memory).
        #[arg(long)]
        fringes: Option<PathBuf>,
        /// Hololines to check: N, A..B or A..=B (default: all).
        #[arg(long, value_parser = parse_frames)]
        hololines: Option<std::ops::Range<usize>>,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Simulate the display by scalar diffraction and write the picture a
    /// viewer at the given eye position sees (focused on the emitters).
    View {
        /// A .holo file (assembled in memory) or a directory of fringes.
        input: PathBuf,
        /// Display layout for a .holo file (default mark3; a fringe directory names its own).
        #[arg(long)]
        layout: Option<String>,
        /// Eye position X[,Y] in millimetres on the viewer's side (X along
        /// the hololines, 0 = centre).
        #[arg(long, default_value = "0", value_parser = parse_eye, allow_hyphen_values = true)]
        eye: (f64, f64),
        /// Viewer distance in millimetres (default: the layout's).
        #[arg(long)]
        distance: Option<f64>,
        /// Pupil diameter in millimetres.
        #[arg(long, default_value_t = 4.0)]
        pupil: f64,
        /// Frame index (in the source .holo file).
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Brightness shown as full white (1 = a fully lit emitter).
        #[arg(long, default_value_t = 1.0)]
        white: f32,
        /// Output PNG.
        #[arg(long, short)]
        output: PathBuf,
        /// Replace an existing file.
        #[arg(long)]
        force: bool,
    },
    /// Print a layout profile (TOML, or JSON with --json): the numbers a
    /// layout uses, and a starting point for a custom profile.
    Layout {
        /// A built-in name or a profile file.
        name: String,
        /// Print JSON instead of TOML.
        #[arg(long)]
        json: bool,
    },
    /// Run the main job on built-in defaults and say where the results are.
    Demo {
        /// Directory for the demo's files (its own earlier files there are replaced).
        #[arg(long, default_value = "holo-demo")]
        out: PathBuf,
    },
}

#[derive(Subcommand)]
enum ConvertCommand {
    /// Draw a HoloFlick's lit micropolygons for every emitter and view of a
    /// layout, adding each frame's specular highlights per view.
    Holoflick {
        /// The .hflk file.
        file: PathBuf,
        /// Display layout: a built-in name or a .toml/.json profile.
        #[arg(long, default_value = "mark3")]
        layout: String,
        /// Frames to convert: N, A..B or A..=B (split a movie across machines); default all.
        #[arg(long, value_parser = parse_frames)]
        frames: Option<std::ops::Range<usize>>,
        /// Sub-rays per sample, EMITTERSxVIEWS (e.g. 2x2) or N for NxN.
        #[arg(long, default_value = "2x2", value_parser = parse_supersample)]
        supersample: holo::mesh::render::Supersample,
        /// Fit the content to the display even when it was made for it.
        #[arg(long)]
        fit: bool,
        #[command(flatten)]
        write: WriteArgs,
    },
    /// Render a glTF (.gltf/.glb), OBJ or PLY scene for every emitter and
    /// view of a layout (animated glTF: one frame per 1/fps).
    Mesh {
        /// The scene file.
        scene: PathBuf,
        /// Display layout: a built-in name or a .toml/.json profile.
        #[arg(long, default_value = "mark3")]
        layout: String,
        /// Frames to convert (animated glTF): N, A..B or A..=B; default all.
        #[arg(long, value_parser = parse_frames)]
        frames: Option<std::ops::Range<usize>>,
        /// Frames per second at which animations are sampled.
        #[arg(long, default_value_t = 30.0)]
        fps: f64,
        /// Sub-rays per sample, EMITTERSxVIEWS (e.g. 2x2) or N for NxN.
        #[arg(long, default_value = "2x2", value_parser = parse_supersample)]
        supersample: holo::mesh::render::Supersample,
        /// Specular lobe: blinn (N·H)^n or phong (R·V)^n.
        #[arg(long, default_value = "blinn", value_parser = parse_specular)]
        specular: holo::mesh::shade::SpecularModel,
        /// A light (repeatable): dir:DX,DY,DZ[:R,G,B], point:X,Y,Z[:R,G,B] (mm) or ambient:R,G,B.
        #[arg(long)]
        light: Vec<String>,
        /// A file of lights, one per line in --light's form.
        #[arg(long)]
        lights: Option<PathBuf>,
        /// Ignore the scene's own lights (glTF KHR_lights_punctual).
        #[arg(long)]
        no_scene_lights: bool,
        /// Rotation before fitting, degrees about x, y, z: RX,RY,RZ.
        #[arg(long, value_parser = parse_triple)]
        rotate: Option<[f64; 3]>,
        /// Display millimetres per scene unit, instead of fitting the scene to the display.
        #[arg(long)]
        scale: Option<f64>,
        /// Offset after centring, millimetres: X,Y,Z.
        #[arg(long, value_parser = parse_triple)]
        translate: Option<[f64; 3]>,
        /// A row-major 4x4 matrix (16 numbers, scene units to display metres) instead of fitting.
        #[arg(long, value_parser = parse_matrix)]
        matrix: Option<[[f64; 4]; 4]>,
        /// Render with the reference ray caster (slow; for checking).
        #[arg(long)]
        reference: bool,
        #[command(flatten)]
        write: WriteArgs,
    },
    /// Resample camera-array pictures (a rig file, an HCI or Stanford light
    /// field folder, a Middlebury _par.txt, a Looking Glass quilt or a
    /// folder of images on a rail) into every emitter and view of a layout.
    Cameras {
        /// The capture: rig file (.json/.toml), folder, _par.txt or quilt image.
        input: PathBuf,
        /// Display layout: a built-in name or a .toml/.json profile.
        #[arg(long, default_value = "mark3")]
        layout: String,
        /// Camera weighting: nearest, linear (barycentric) or natural (natural neighbour).
        #[arg(long, default_value = "linear")]
        blend: String,
        /// Focus distance from the cameras, in the rig's units (default: what the capture says).
        #[arg(long)]
        focus: Option<f64>,
        /// Display millimetres per rig unit (default: cameras at the viewer's distance).
        #[arg(long)]
        scale: Option<f64>,
        /// The rig point shown at the middle of the emitter plane, rig units: X,Y,Z (default: the focus point).
        #[arg(long, value_parser = parse_triple)]
        center: Option<[f64; 3]>,
        /// Scale so the middle camera's view at the focus fills the display's width.
        #[arg(long)]
        fill_width: bool,
        /// Ignore the rig's depth maps.
        #[arg(long)]
        no_depth: bool,
        /// Rays averaged across each emitter (default: from the pictures' resolution).
        #[arg(long)]
        taps: Option<usize>,
        /// Also write a PNG (emitters × hololines) of the fraction of views no camera sees.
        #[arg(long)]
        unseen_mask: Option<PathBuf>,
        /// Folder of images: distance between neighbouring cameras (rig units).
        #[arg(long)]
        baseline: Option<f64>,
        /// Folder or Stanford: focal length in pixels.
        #[arg(long)]
        focal_px: Option<f64>,
        /// Folder or Stanford: horizontal field of view in degrees.
        #[arg(long)]
        fov: Option<f64>,
        /// Quilt: angle between the first and last view, degrees.
        #[arg(long, default_value_t = 35.0)]
        view_cone: f64,
        /// Quilt: vertical field of view of each view, degrees.
        #[arg(long, default_value_t = 14.0)]
        quilt_fov: f64,
        /// Locate rays among the cameras by brute force (slow; for checking).
        #[arg(long)]
        reference: bool,
        #[command(flatten)]
        write: WriteArgs,
    },
}

#[derive(Args)]
struct WriteArgs {
    /// Output .holo file.
    #[arg(long, short)]
    output: PathBuf,
    /// Store f32 samples instead of f16.
    #[arg(long)]
    f32: bool,
    /// Compression: none, rle, zips, zip, piz (lossless), pxr24, b44, b44a, dwaa, dwab (lossy).
    #[arg(long, default_value = "zip", value_parser = parse_compression)]
    compression: Compression,
    /// Replace an existing output file.
    #[arg(long)]
    force: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum ChannelsArg {
    Rgb,
    Y,
}

fn parse_kind(s: &str) -> Result<PatternKind, String> {
    PatternKind::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = PatternKind::ALL.iter().map(|(_, n)| *n).collect();
        format!("unknown pattern kind {s:?}; choose one of {}", names.join(", "))
    })
}

fn parse_frames(s: &str) -> Result<std::ops::Range<usize>, String> {
    let number = |t: &str| t.trim().parse::<usize>().map_err(|_| format!("{s:?} is not N, A..B or A..=B"));
    let range = if let Some((a, b)) = s.split_once("..=") {
        number(a)?..number(b)? + 1
    } else if let Some((a, b)) = s.split_once("..") {
        number(a)?..number(b)?
    } else {
        let n = number(s)?;
        n..n + 1
    };
    if range.is_empty() {
        return Err(format!("frames {s:?} is an empty range"));
    }
    Ok(range)
}

fn parse_preset(s: &str) -> Result<QuiltSpec, String> {
    QuiltSpec::preset(s).ok_or_else(|| {
        format!("unknown quilt preset {s:?}; choose one of {}", holo::cameras::quilt::PRESETS.join(", "))
    })
}

fn parse_tile(s: &str) -> Result<(usize, usize), String> {
    let n = |t: &str| t.trim().parse::<usize>().ok();
    match s.split_once(['x', 'X']) {
        Some((w, h)) => n(w).zip(n(h)).ok_or_else(|| format!("--tile {s:?} is not WIDTHxHEIGHT in pixels")),
        None => Err(format!("--tile {s:?} is not WIDTHxHEIGHT in pixels")),
    }
}

fn parse_eye(s: &str) -> Result<(f64, f64), String> {
    let number = |t: &str| t.trim().parse::<f64>().ok().filter(|x| x.is_finite());
    let bad = || format!("--eye {s:?} is not X or X,Y in millimetres");
    match s.split_once(',') {
        Some((x, y)) => Ok((number(x).ok_or_else(bad)?, number(y).ok_or_else(bad)?)),
        None => Ok((number(s).ok_or_else(bad)?, 0.0)),
    }
}

fn parse_supersample(s: &str) -> Result<holo::mesh::render::Supersample, String> {
    let n = |t: &str| t.trim().parse::<usize>().ok().filter(|&n| (1..=64).contains(&n));
    let bad = || format!("--supersample {s:?} is not N or EXV with factors 1 to 64");
    let (e, v) = match s.split_once(['x', 'X']) {
        Some((a, b)) => (n(a).ok_or_else(bad)?, n(b).ok_or_else(bad)?),
        None => {
            let k = n(s).ok_or_else(bad)?;
            (k, k)
        }
    };
    Ok(holo::mesh::render::Supersample { emitter: e, view: v })
}

fn parse_specular(s: &str) -> Result<holo::mesh::shade::SpecularModel, String> {
    match s {
        "blinn" => Ok(holo::mesh::shade::SpecularModel::Blinn),
        "phong" => Ok(holo::mesh::shade::SpecularModel::Phong),
        _ => Err(format!("--specular {s:?}: choose blinn or phong")),
    }
}

fn parse_numbers(s: &str, n: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("{s:?} is not {n} comma-separated numbers"))?;
    if v.len() != n {
        return Err(format!("{s:?} has {} numbers, not {n}", v.len()));
    }
    Ok(v)
}

fn parse_triple(s: &str) -> Result<[f64; 3], String> {
    let v = parse_numbers(s, 3)?;
    Ok([v[0], v[1], v[2]])
}

fn parse_matrix(s: &str) -> Result<[[f64; 4]; 4], String> {
    let v = parse_numbers(s, 16)?;
    let mut m = [[0.0; 4]; 4];
    for (i, x) in v.into_iter().enumerate() {
        m[i / 4][i % 4] = x;
    }
    Ok(m)
}

fn parse_fringe_format(s: &str) -> Result<FringeFormat, String> {
    FringeFormat::from_name(s).ok_or_else(|| format!("unknown fringe format {s:?}; choose png, raw or exr"))
}

fn parse_compression(s: &str) -> Result<Compression, String> {
    Compression::from_name(s).ok_or_else(|| {
        let names: Vec<&str> = Compression::ALL.iter().map(|c| c.name()).collect();
        format!("unknown compression {s:?}; choose one of {}", names.join(", "))
    })
}

/// Write to stdout. Rust ignores SIGPIPE, so a reader that goes away (as
/// `head` does) shows up here as a broken pipe: the listing was cut short
/// on purpose, and the process ends quietly with success, as it would by
/// SIGPIPE. Any other failure to write is an error.
fn print_out(args: std::fmt::Arguments) {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_fmt(args).and_then(|()| stdout.flush()) {
        Ok(()) => {}
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            holo::output::remove_temporaries();
            std::process::exit(0);
        }
        Err(e) => {
            holo::output::remove_temporaries();
            eprintln!("holo: error: cannot write to standard output: {e}");
            std::process::exit(1);
        }
    }
}

/// A library error as the one sentence the user reads; a refusal to
/// replace something says how to ask for it.
fn error_text(e: holo::Error) -> String {
    match &e {
        holo::Error::Output { problem: holo::OutputProblem::Exists | holo::OutputProblem::SetExists(_), .. } => {
            format!("{e} (use --force to replace it)")
        }
        _ => e.to_string(),
    }
}

/// Refuse, before any work, an output that exists (without `force`), whose
/// folder is missing, or that is one of `inputs`, where an input folder
/// stands for itself and every file in it.
fn check_output(output: &Path, inputs: &[&Path], force: bool) -> Result<(), String> {
    let mut read: Vec<PathBuf> = Vec::new();
    for input in inputs {
        read.push(input.to_path_buf());
        if let Ok(entries) = std::fs::read_dir(input) {
            read.extend(entries.flatten().map(|e| e.path()));
        }
    }
    let read: Vec<&Path> = read.iter().map(PathBuf::as_path).collect();
    holo::output::check_output(output, &read, force).map_err(error_text)
}

fn main() -> ExitCode {
    // First, so an interrupt at any later point removes what is half written.
    if let Err(e) = holo::output::install_interrupt_cleanup() {
        eprintln!(
            "holo: warning: cannot watch for interrupts ({e}); an interrupted write may leave hidden temporary files"
        );
    }
    let cli = Cli::parse();
    // A panic is a bug; still, the user gets one sentence, not a backtrace.
    std::panic::set_hook(Box::new(|info| {
        eprintln!("holo: internal error ({info}); please report it");
    }));
    match std::panic::catch_unwind(|| run(cli)) {
        Ok(Ok(code)) => code,
        Ok(Err(message)) => {
            eprintln!("holo: error: {message}");
            ExitCode::from(1)
        }
        Err(_) => ExitCode::from(1),
    }
}

type Outcome = Result<ExitCode, String>;

fn run(cli: Cli) -> Outcome {
    match cli.command {
        Command::Info { files, json, headers_only } => info(&files, json, !headers_only),
        Command::Validate { files, json } => validate(&files, json),
        Command::Pattern { layout, kind, emitter, view, every, cell, level, channels, write } => {
            check_output(&write.output, &[Path::new(&layout)], write.force)?;
            let mut geometry = layout_geometry(&layout)?;
            match channels {
                Some(ChannelsArg::Rgb) => geometry.channels = rgb_channels(),
                Some(ChannelsArg::Y) => geometry.channels = mono_channel(),
                None => {}
            }
            let pattern = Pattern { kind, emitter, view, every, cell, level };
            let options = write.options(format!("{} layout={layout}", pattern.describe()));
            let progress = progress::Reporter::on_stderr();
            let run = holo::pattern::write_pattern(&pattern, &geometry, &write.output, options, &progress)
                .map_err(error_text)?;
            wrote(&run.written, &write)
        }
        Command::ExportViews { file, out, frame, bits, white, force } => {
            let holo_file = holo::HoloFile::open(&file).map_err(error_text)?;
            let views = holo_file.geometry().views.count;
            let names: Vec<String> = (0..views).map(|v| holo::views::view_file_name(v, views)).collect();
            holo::output::check_set_output(&out, SIDECAR, &names, &[&file], force).map_err(error_text)?;
            let m = holo_file.read_frame(frame).map_err(error_text)?;
            let white = if white == "auto" {
                let max = m.value_range().1;
                if max > 0.0 {
                    max
                } else {
                    1.0
                }
            } else {
                white.parse::<f32>().map_err(|_| format!("--white {white:?} is not a number or `auto`"))?
            };
            let written =
                holo::views::export_views(&m, &out, &ToneMapping { white, bits }, force).map_err(error_text)?;
            outln!("wrote {} view PNGs and {} to {}", written.len() - 1, SIDECAR, out.display());
            Ok(ExitCode::SUCCESS)
        }
        Command::ExportQuilt {
            file,
            output,
            output_dir,
            frame,
            preset,
            columns,
            rows,
            tile,
            aspect,
            view_cone,
            white,
            force,
        } => {
            let mut spec = preset;
            spec.columns = columns.unwrap_or(spec.columns);
            spec.rows = rows.unwrap_or(spec.rows);
            if let Some((w, h)) = tile {
                (spec.tile_width, spec.tile_height) = (w, h);
            }
            spec.aspect = aspect.unwrap_or(spec.aspect);
            spec.view_cone_deg = view_cone;
            let white = match white.as_str() {
                "auto" => None,
                w => Some(w.parse::<f32>().map_err(|_| format!("--white {w:?} is not a number or `auto`"))?),
            };
            let name = || {
                let stem = file.file_stem().map_or("quilt".into(), |s| s.to_string_lossy().into_owned());
                holo::cameras::quilt::quilt_file_name(&stem, &spec)
            };
            let out = match (output, output_dir) {
                (Some(path), _) => path,
                (None, Some(dir)) => {
                    // The folder is made only for an input that opens.
                    holo::HoloFile::open(&file).map_err(error_text)?;
                    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
                    dir.join(name())
                }
                (None, None) => file.with_file_name(name()),
            };
            check_output(&out, &[&file], force)?;
            let report = holo::cameras::quilt::export_quilt(
                &file,
                frame,
                &spec,
                &out,
                &QuiltOptions { white, overwrite: force },
            )
            .map_err(error_text)?;
            outln!(
                "wrote {}: a {}×{} quilt of {} views ({}×{} tiles of {}×{}) of frame {frame} of {}, white = {}",
                report.path.display(),
                report.width,
                report.height,
                report.views,
                spec.columns,
                spec.rows,
                spec.tile_width,
                spec.tile_height,
                file.display(),
                report.white
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::ImportViews { dir, geometry, white, write } => {
            let sidecar_path = dir.join(SIDECAR);
            let sidecar = sidecar_path
                .exists()
                .then(|| holo::views::read_sidecar(&sidecar_path))
                .transpose()
                .map_err(error_text)?;
            let g = match (&geometry, &sidecar) {
                (Some(name), _) => layout_geometry(name)?,
                (None, Some(s)) => s.geometry.clone(),
                (None, None) => {
                    return Err(format!(
                        "{}: no {SIDECAR} here; say which geometry with --geometry LAYOUT|FILE.json",
                        dir.display()
                    ))
                }
            };
            // Every file of the folder counts as an input here, not only the pictures.
            check_output(&write.output, &[dir.as_path()], write.force)?;
            let mut tone = sidecar.map(|s| s.tone).unwrap_or_default();
            if let Some(w) = white {
                tone.white = w;
            }
            let progress = progress::Reporter::on_stderr();
            let options = write.options(String::new());
            let run = holo::views::import_views_file(&dir, &g, &tone, &write.output, options, &progress)
                .map_err(error_text)?;
            wrote(&run.written, &write)
        }
        Command::Assemble { file, layout, out, frames, format, resample, force } => {
            let layout = load_layout(&layout).map_err(error_text)?;
            let options = AssembleOptions { frames, format, overwrite: force, resample };
            let started = std::time::Instant::now();
            let report =
                assemble_file(&file, &layout, &out, &options, &progress::Reporter::on_stderr()).map_err(error_text)?;
            let seconds = started.elapsed().as_secs_f64();
            outln!(
                "assembled {} frame(s) of {} for {} in {seconds:.2} s: {} files and {FRINGE_SIDECAR} in {}",
                report.frames.len(),
                file.display(),
                layout.name,
                report.files.len() - 1,
                out.display()
            );
            if let Some(r) = report.resampled {
                outln!(
                    "resampled onto {} by rays: {} of {} samples had no ray in the file and are black",
                    layout.name,
                    r.outside,
                    r.total
                );
            }
            if report.stats.clipped > 0 {
                eprintln!(
                    "holo: warning: {} samples clipped by the 8-bit quantization (the modulation is brighter than \
                     the layout's gain allows; scale it down)",
                    report.stats.clipped
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Check { file, layout, frame, fringes, hololines, json } => {
            let layout = match (&layout, &fringes) {
                (Some(name), _) => Some(load_layout(name).map_err(error_text)?),
                (None, Some(_)) => None,
                (None, None) => Some(load_layout("mark3").map_err(error_text)?),
            };
            let options = holo::reconstruct::files::CheckOptions { frame, fringes, hololines };
            let checked = holo::reconstruct::files::check_file(
                &file,
                layout.as_ref(),
                &options,
                &progress::Reporter::on_stderr(),
            )
            .map_err(error_text)?;
            if json {
                outln!("{}", serde_json::to_string_pretty(&checked).map_err(|e| e.to_string())?);
            } else {
                out!("{checked}");
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::View { input, layout, eye, distance, pupil, frame, white, output, force } => {
            let layout = match layout {
                Some(name) => Some(load_layout(&name).map_err(error_text)?),
                None if holo::reconstruct::files::is_fringe_dir(&input) => None,
                None => Some(load_layout("mark3").map_err(error_text)?),
            };
            if !(pupil.is_finite() && pupil > 0.0) || distance.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
                return Err(format!("--pupil {pupil} and --distance must be positive millimetres"));
            }
            check_output(&output, &[&input], force)?;
            let at = holo::reconstruct::files::EyeAt {
                x_m: eye.0 * 1e-3,
                y_m: eye.1 * 1e-3,
                distance_m: distance.map(|d| d * 1e-3),
                pupil_m: pupil * 1e-3,
            };
            let pictures = holo::reconstruct::files::view_file(
                &input,
                layout.as_ref(),
                frame,
                &[at],
                &progress::Reporter::on_stderr(),
            )
            .map_err(error_text)?;
            pictures[0].write_png(&output, white, force).map_err(error_text)?;
            outln!(
                "wrote {}: what an eye at x = {} mm sees of {} ({} × {} emitters × hololines)",
                output.display(),
                eye.0,
                input.display(),
                pictures[0].emitters,
                pictures[0].hololines
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Holoflick(command) => holoflick::run(command),
        Command::Layout { name, json } => {
            let layout = load_layout(&name).map_err(error_text)?;
            if json {
                outln!("{}", serde_json::to_string_pretty(&layout).map_err(|e| e.to_string())?);
            } else {
                out!("{}", layout.to_toml());
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Convert(ConvertCommand::Holoflick { file, layout, frames, supersample, fit, write }) => {
            use holo::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
            check_output(&write.output, &[&file, Path::new(&layout)], write.force)?;
            let g = layout_geometry(&layout)?;
            let options = HoloFlickConvertOptions {
                frames,
                render: holo::mesh::render::RenderOptions { supersample, ..Default::default() },
                write: write.options(String::new()),
                fit,
            };
            let started = std::time::Instant::now();
            let report = convert_holoflick(&file, &g, &write.output, &options, &progress::Reporter::on_stderr())
                .map_err(error_text)?;
            for w in &report.warnings {
                eprintln!("holo: warning: {w}");
            }
            let w = report.work;
            outln!(
                "converted frames {}..{} of {} into {} in {:.2} s",
                report.frames.start,
                report.frames.end,
                file.display(),
                report.path.display(),
                started.elapsed().as_secs_f64()
            );
            outln!(
                "objects decoded {}, reused from key frames {}, skipped unseen {}; {} back faces dropped; {} segments rasterised, {} sub-rays shaded",
                w.decoded, w.reused, w.unseen_objects, w.back_faces, w.render.segments, w.render.shaded
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Convert(ConvertCommand::Mesh {
            scene,
            layout,
            frames,
            fps,
            supersample,
            specular,
            light,
            lights,
            no_scene_lights,
            rotate,
            scale,
            translate,
            matrix,
            reference,
            write,
        }) => {
            use holo::mesh::convert::{convert_mesh, ConvertOptions};
            use holo::mesh::place::{display_volume, Placement};
            use holo::mesh::render::{Engine, RenderOptions};
            let mut read = vec![scene.as_path(), Path::new(&layout)];
            read.extend(lights.as_deref());
            check_output(&write.output, &read, write.force)?;
            let g = layout_geometry(&layout)?;
            let (lo, hi) = display_volume(&g);
            let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), g.emitter_z_m];
            let mut user_lights = Vec::new();
            if let Some(path) = &lights {
                user_lights.extend(holo::mesh::shade::read_lights(path, centre).map_err(error_text)?);
            }
            for spec in &light {
                user_lights.push(holo::mesh::shade::parse_light(spec, centre)?);
            }
            if let Some(s) = scale {
                if !(s.is_finite() && s > 0.0) {
                    return Err(format!("--scale {s}: give a positive number of millimetres per scene unit"));
                }
            }
            let options = ConvertOptions {
                placement: Placement {
                    rotate_deg: rotate.unwrap_or([0.0; 3]),
                    scale: scale.map(|s| s * 1e-3),
                    translate_m: translate.map_or([0.0; 3], |t| [t[0] * 1e-3, t[1] * 1e-3, t[2] * 1e-3]),
                    matrix,
                },
                render: RenderOptions {
                    supersample,
                    lighting: holo::mesh::shade::Lighting { lights: user_lights, model: specular },
                    scene_lights: !no_scene_lights,
                    default_lights: true,
                    engine: if reference { Engine::Reference } else { Engine::Fast },
                },
                frames,
                fps,
                write: write.options(String::new()),
            };
            let started = std::time::Instant::now();
            let report = convert_mesh(&scene, &g, &write.output, &options, &progress::Reporter::on_stderr())
                .map_err(error_text)?;
            for w in &report.warnings {
                eprintln!("holo: warning: {w}");
            }
            for w in &report.written.warnings {
                eprintln!("holo: warning: {}: {w}", report.path.display());
            }
            outln!(
                "converted {} ({} triangles in {} objects) into {} frame(s) of {} in {:.2} s",
                scene.display(),
                report.triangles,
                report.objects,
                report.frames.len(),
                report.path.display(),
                started.elapsed().as_secs_f64()
            );
            outln!("{}", report.placed);
            outln!(
                "{} light(s); {} segments rasterised, {} sub-rays shaded",
                report.lights.len(),
                report.stats.segments,
                report.stats.shaded
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Convert(ConvertCommand::Cameras {
            input,
            layout,
            blend,
            focus,
            scale,
            center,
            fill_width,
            no_depth,
            taps,
            unseen_mask,
            baseline,
            focal_px,
            fov,
            view_cone,
            quilt_fov,
            reference,
            write,
        }) => {
            use holo::cameras::convert::{convert_camera_files, CameraConvertOptions};
            use holo::cameras::read::OpenOptions;
            use holo::cameras::resample::{Blend, CameraOptions, PlacementRequest};
            check_output(&write.output, &[&input, Path::new(&layout)], write.force)?;
            if let Some(mask) = &unseen_mask {
                check_output(mask, &[&input, &write.output], write.force)?;
            }
            let g = layout_geometry(&layout)?;
            let mut open = OpenOptions::default();
            open.folder.baseline = baseline;
            open.folder.focal_length_px = focal_px;
            open.folder.horizontal_fov_deg = fov;
            open.folder.focus_distance = focus;
            open.stanford.focal_length_px = focal_px;
            open.stanford.horizontal_fov_deg = fov;
            open.stanford.focus_distance = focus;
            open.quilt.view_cone_deg = view_cone;
            open.quilt.vertical_fov_deg = quilt_fov;
            if let Some(s) = scale {
                if !(s.is_finite() && s > 0.0) {
                    return Err(format!("--scale {s}: give a positive number of display millimetres per rig unit"));
                }
            }
            let options = CameraConvertOptions {
                resample: CameraOptions {
                    blend: Blend::parse(&blend).map_err(error_text)?,
                    placement: PlacementRequest { scale: scale.map(|s| s * 1e-3), centre: center, focus, fill_width },
                    use_depth: !no_depth,
                    want_mask: false,
                    reference,
                    emitter_taps: taps,
                },
                unseen_png: unseen_mask,
                write: write.options(String::new()),
            };
            let started = std::time::Instant::now();
            let report =
                convert_camera_files(&input, &open, &g, &write.output, &options, &progress::Reporter::on_stderr())
                    .map_err(error_text)?;
            for w in report.resample.warnings.iter().chain(&report.written.warnings) {
                eprintln!("holo: warning: {w}");
            }
            let r = &report.resample;
            outln!(
                "converted {} ({}) into {} in {:.2} s",
                input.display(),
                r.surface,
                report.path.display(),
                started.elapsed().as_secs_f64()
            );
            outln!("placement: {}", r.placement);
            outln!(
                "{} rays, {} taps per emitter; {} ({:.1}%) seen by no camera and left black",
                r.rays,
                r.emitter_taps,
                r.unseen,
                100.0 * r.unseen as f64 / r.rays.max(1) as f64
            );
            Ok(ExitCode::SUCCESS)
        }
        Command::Demo { out } => {
            let demo = holo::report::demo(&out, &progress::Reporter::on_stderr()).map_err(error_text)?;
            out!("{demo}");
            Ok(ExitCode::SUCCESS)
        }
    }
}

/// A built-in layout's geometry, a layout profile's, or a geometry JSON file.
fn layout_geometry(name: &str) -> Result<Geometry, String> {
    let path = Path::new(name);
    if path.extension().is_some_and(|e| e == "json") && path.exists() {
        if let Ok(g) = holo::views::read_geometry_json(path) {
            return Ok(g);
        }
    }
    load_layout(name).map(|l| l.geometry).map_err(error_text)
}

impl WriteArgs {
    /// The write options these arguments ask for, with provenance `source`
    /// (empty: the converter writes its own).
    fn options(&self, source: String) -> WriteOptions {
        WriteOptions {
            sample_type: if self.f32 { SampleType::F32 } else { SampleType::F16 },
            compression: self.compression,
            source,
            overwrite: self.force,
            ..WriteOptions::default()
        }
    }
}

/// What writing a `.holo` file did, said as every command that writes one says it.
fn wrote(report: &holo::format::WriteReport, args: &WriteArgs) -> Outcome {
    for w in &report.warnings {
        eprintln!("holo: warning: {}: {w}", args.output.display());
    }
    outln!("wrote {} ({} bytes, {})", report.path.display(), report.file_bytes, report.digests[0]);
    Ok(ExitCode::SUCCESS)
}

fn info(files: &[PathBuf], json: bool, values: bool) -> Outcome {
    let infos =
        files.iter().map(|f| holo::report::info(f, values)).collect::<Result<Vec<_>, _>>().map_err(error_text)?;
    let same = (infos.len() > 1).then(|| infos.windows(2).all(|w| holo::report::same_content(&w[0], &w[1])));
    if json {
        let value = serde_json::json!({ "files": infos, "same_content": same });
        outln!("{}", serde_json::to_string_pretty(&value).map_err(|e| e.to_string())?);
    } else {
        for i in &infos {
            out!("{i}");
        }
        if let Some(same) = same {
            outln!("same content: {}", if same { "yes (equal geometry, sample type and frame digests)" } else { "no" });
        }
    }
    Ok(ExitCode::SUCCESS)
}

fn validate(files: &[PathBuf], json: bool) -> Outcome {
    let mut all_valid = true;
    let mut reports = Vec::new();
    for f in files {
        let (valid, violations, warnings) = match holo::format::validate(f) {
            Ok(v) => (v.is_valid(), v.violations, v.warnings),
            Err(e) => (false, vec![e.to_string()], vec![]),
        };
        all_valid &= valid;
        if json {
            reports
                .push(serde_json::json!({ "file": f, "valid": valid, "violations": violations, "warnings": warnings }));
            continue;
        }
        if valid {
            outln!("{}: valid", f.display());
        } else {
            outln!("{}: INVALID, {} violation(s)", f.display(), violations.len());
        }
        for v in &violations {
            outln!("  violation: {v}");
        }
        for w in &warnings {
            outln!("  warning: {w}");
        }
    }
    if json {
        outln!("{}", serde_json::to_string_pretty(&reports).map_err(|e| e.to_string())?);
    }
    Ok(if all_valid { ExitCode::SUCCESS } else { ExitCode::from(1) })
}

fn parse_bits(s: &str) -> Result<u8, String> {
    match s {
        "8" => Ok(8),
        "16" => Ok(16),
        _ => Err(format!("{s:?} bits: choose 8 or 16")),
    }
}
