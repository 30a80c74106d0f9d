//! `holo holoflick …`: thin wrappers over `holo::holoflick::tools`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Subcommand};
use holo::holoflick::cg::EncodeOptions;
use holo::holoflick::container::ViewerCouch;
use holo::holoflick::tools::{info, pack, unpack, PackOptions};

use crate::{check_output, error_text};

#[derive(Subcommand)]
pub enum HoloflickCommand {
    /// Describe a HoloFlick (.hflk) or Java 3D compressed-geometry (.cg) file:
    /// frames, objects, triangles, bytes per triangle.
    Info {
        /// The file.
        file: PathBuf,
    },
    /// Pack meshes (glTF, OBJ, PLY; one frame each, an animated glTF one
    /// frame per 1/fps) into a HoloFlick, or into a Java 3D .cg file when
    /// the output ends in .cg (one frame's objects, without their transforms).
    Pack {
        /// The mesh files, one frame each (in order).
        #[arg(required = true)]
        meshes: Vec<PathBuf>,
        /// Output: NAME.hflk or NAME.cg.
        #[arg(short, long)]
        output: PathBuf,
        #[command(flatten)]
        bits: Bits,
        /// Frame rate, and the rate animations are sampled at.
        #[arg(long, default_value_t = 30.0)]
        fps: f64,
        /// Frames of an animation to keep: N, A..B or A..=B.
        #[arg(long, value_parser = crate::parse_frames)]
        frames: Option<std::ops::Range<usize>>,
        /// The viewer's couch, XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX in metres
        /// (default: a box in front of the scene, +z).
        #[arg(long, value_parser = parse_couch)]
        couch: Option<ViewerCouch>,
        /// A key frame every N frames.
        #[arg(long, default_value_t = 30)]
        key_interval: usize,
        /// Replace an existing output.
        #[arg(long)]
        force: bool,
    },
    /// Make a HoloFlick for a display from a glTF, OBJ or PLY scene (the
    /// geometry shader of Deering's HoloFlicks): place it, dice it into micropolygons
    /// sized for the display, bake ambient and diffuse light (and shadows)
    /// into vertex colours, keep specular as materials; animated glTF gives
    /// one frame per 1/fps.
    Encode {
        /// The scene file.
        scene: PathBuf,
        /// Output: NAME.hflk.
        #[arg(short, long)]
        output: PathBuf,
        /// Display layout: a built-in name or a .toml/.json profile.
        #[arg(long, default_value = "mark3")]
        layout: String,
        /// Micropolygon edge as a multiple of what the display resolves at its depth.
        #[arg(long, default_value_t = 1.0)]
        micropolygon: f64,
        /// Keep micropolygons flat (do not bend them onto the surface the normals describe).
        #[arg(long)]
        flat: bool,
        /// Bake shadows of the scene's lights.
        #[arg(long)]
        shadows: bool,
        #[command(flatten)]
        bits: Bits,
        /// Frame rate, and the rate animations are sampled at.
        #[arg(long, default_value_t = 30.0)]
        fps: f64,
        /// Frames of an animation: N, A..B or A..=B; default all.
        #[arg(long, value_parser = crate::parse_frames)]
        frames: Option<std::ops::Range<usize>>,
        /// A key frame every N frames.
        #[arg(long, default_value_t = 30)]
        key_interval: usize,
        /// Replace an existing output.
        #[arg(long)]
        force: bool,
    },
    /// Write one frame of a HoloFlick (or the objects of a .cg file) as a
    /// mesh: .glb (glTF, unlit vertex colours) or .ply.
    Unpack {
        /// The .hflk or .cg file.
        file: PathBuf,
        /// Which frame.
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Output: NAME.glb or NAME.ply.
        #[arg(short, long)]
        output: PathBuf,
        /// Replace an existing output.
        #[arg(long)]
        force: bool,
    },
}

/// Quantization of compressed geometry.
#[derive(Args)]
pub struct Bits {
    /// Bits per position component (1–16).
    #[arg(long, default_value_t = 16)]
    position_bits: u32,
    /// Bits per colour component (2–16).
    #[arg(long, default_value_t = 9)]
    colour_bits: u32,
    /// Bits of the normal grid (0–6).
    #[arg(long, default_value_t = 6)]
    normal_bits: u32,
}

impl Bits {
    fn options(&self) -> EncodeOptions {
        EncodeOptions {
            position_bits: self.position_bits,
            color_bits: self.colour_bits,
            normal_bits: self.normal_bits,
            alpha: true,
        }
    }
}

fn parse_couch(s: &str) -> Result<ViewerCouch, String> {
    let v: Vec<f64> =
        s.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|e| format!("{s:?}: {e}"))?;
    if v.len() != 6 || v.iter().any(|x| !x.is_finite()) || (0..3).any(|k| v[k] > v[k + 3]) {
        return Err(format!("{s:?}: give six finite numbers XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX with each min ≤ max"));
    }
    Ok(ViewerCouch { min_m: [v[0], v[1], v[2]], max_m: [v[3], v[4], v[5]] })
}

pub fn run(command: HoloflickCommand) -> Result<ExitCode, String> {
    match command {
        HoloflickCommand::Info { file } => {
            out!("{}", info(&file).map_err(error_text)?);
        }
        HoloflickCommand::Pack { meshes, output, bits, fps, frames, couch, key_interval, force } => {
            let read: Vec<&std::path::Path> = meshes.iter().map(PathBuf::as_path).collect();
            check_output(&output, &read, force)?;
            let options = PackOptions {
                encode: bits.options(),
                frames_per_second: fps,
                frames,
                couch,
                key_interval,
                overwrite: force,
            };
            let report =
                pack(&meshes, &output, &options, &crate::progress::Reporter::on_stderr()).map_err(error_text)?;
            for w in &report.warnings {
                eprintln!("holo: warning: {w}");
            }
            outln!(
                "wrote {} ({} bytes): {} frames, {} objects stored, {} from key frames, {} triangles, {:.2} stream bytes/triangle",
                report.path.display(),
                report.file_bytes,
                report.frames,
                report.stored,
                report.references,
                report.triangles,
                report.stream_bytes as f64 / report.triangles.max(1) as f64
            );
            for (i, (c, s)) in report.cg_transforms.iter().enumerate() {
                outln!("  object {i}: model = normalised × {s:.6e} + ({:.6}, {:.6}, {:.6})", c[0], c[1], c[2]);
            }
        }
        HoloflickCommand::Encode {
            scene,
            output,
            layout,
            micropolygon,
            flat,
            shadows,
            bits,
            fps,
            frames,
            key_interval,
            force,
        } => {
            use holo::holoflick::encode::{encode_holoflick, HoloFlickEncodeOptions};
            check_output(&output, &[&scene, std::path::Path::new(&layout)], force)?;
            let g = crate::layout_geometry(&layout)?;
            let options = HoloFlickEncodeOptions {
                micropolygon,
                smooth: !flat,
                shadows,
                encode: bits.options(),
                frames_per_second: fps,
                frames,
                key_interval,
                overwrite: force,
                ..HoloFlickEncodeOptions::default()
            };
            let report = encode_holoflick(&scene, &g, &output, &options, &crate::progress::Reporter::on_stderr())
                .map_err(error_text)?;
            let p = &report.pack;
            for w in &p.warnings {
                eprintln!("holo: warning: {w}");
            }
            outln!(
                "wrote {} ({} bytes): {} frames, {} micropolygons, {} objects stored, {} from key frames, {:.2} stream bytes/micropolygon",
                p.path.display(),
                p.file_bytes,
                p.frames,
                report.micropolygons,
                p.stored,
                p.references,
                p.stream_bytes as f64 / p.triangles.max(1) as f64
            );
            outln!("{}", report.placed);
        }
        HoloflickCommand::Unpack { file, frame, output, force } => {
            check_output(&output, &[&file], force)?;
            let triangles = unpack(&file, frame, &output, force).map_err(error_text)?;
            outln!("wrote {} ({triangles} triangles of frame {frame})", output.display());
        }
    }
    Ok(ExitCode::SUCCESS)
}
