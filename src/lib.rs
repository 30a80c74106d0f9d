//! `holo`: the modulation texture of a holographic stereogram as a standard
//! file, and the conversions around it.
//!
//! A holographic stereogram display of horizontal parallax (the MIT Mark I to
//! Mark IV holovideo displays) draws each horizontal line of its image, a
//! *hololine*, as a row of *emitters*: points that each send a different
//! brightness into each direction of a fan of *views*. The brightness of every
//! (colour channel, hololine, emitter, view) is the *modulation texture*
//! (Smithwick et al., "Real-time shader rendering of holographic stereograms",
//! 2009, §3.2–§3.3; its §6 proposes it as the standard file of holographic
//! video; see `docs/references.md`). `holo` holds it in memory as a
//! [`Modulation`] over a [`Geometry`], stores it as a `.holo` file (OpenEXR
//! with typed attributes, specified in `spec/holo-format.md`), makes it from
//! meshes, camera arrays and HoloFlicks, and turns it into the *fringes*: the
//! frame-buffer images a display's acousto-optic modulator is driven with.
//!
//! A first program needs only [`prelude`]: `use holo::prelude::*;`.
//!
//! # Data flow
//!
//! ```text
//!  mesh scene   ─┐
//!  camera rig   ─┤                                       Layout (display profile)
//!  HoloFlick    ─┼─▶ Modulation ◀──▶ .holo file ──▶ Assembler ──▶ fringe images
//!  test pattern ─┤   (Geometry)      (format)        (assemble)     (PNG, raw, EXR)
//!  view PNGs    ─┘                                        │
//!                                                         ▼
//!                                     reconstruct: what an eye sees, recovery error
//! ```
//!
//! # Entry points
//!
//! | step | in memory | file to file |
//! |---|---|---|
//! | mesh → modulation | [`mesh::load::SceneSource::open`] → `scene_at`, [`mesh::place::place`], [`mesh::render::render`] | [`mesh::convert::convert_mesh`] |
//! | camera array → modulation | [`cameras::open_rig`], [`cameras::resample::resample_rig`] | [`cameras::convert::convert_camera_files`] |
//! | HoloFlick → modulation | [`holoflick::container::HoloFlickReader`] | [`holoflick::convert::convert_holoflick`] |
//! | test patterns, view pictures | [`pattern::Pattern::render`], [`views::import_views`] | [`pattern::write_pattern`], [`pictures::import_pictures_file`], [`views::export_views`] |
//! | hogel pictures (printers) | [`hogels::import_hogels`], [`hogels::export_hogels`] | [`pictures::import_pictures_file`], [`hogels::export_hogels_file`] |
//! | meshes → HoloFlicks | [`holoflick::container::HoloFlickWriter`] | [`holoflick::encode::encode_holoflick`], [`holoflick::tools::pack`] |
//! | the `.holo` file | [`write()`], [`read()`], [`format::HoloFile::open`] (one frame or region at a time), [`format::write_frames`] (streaming), [`validate()`] | |
//! | display profiles | [`layout::builtin`] (`mark3`, `mark1`, `mark1-hogel`, `mark2`, `mark4`), [`layout::Layout::load`] (TOML or JSON) | |
//! | modulation → fringes | [`assemble::Assembler::new`] → [`assemble`](assemble::Assembler::assemble) | [`assemble::output::assemble_file`] |
//! | what a viewer sees | [`reconstruct::check::check`], [`reconstruct::check::view`] | [`reconstruct::files::check_file`], [`reconstruct::files::view_file`] |
//!
//! The file-to-file calls all run through [`pipeline`], which checks the
//! output before any work, picks the frames, records provenance (in words,
//! and exactly: [`provenance`], which also gives a file's conversion back as
//! options to make it again) and gathers warnings. Every file is written through [`output`]: to a temporary beside
//! its destination, renamed into place only when complete, and never over an
//! existing file unless asked (`overwrite` in the options). A long call takes
//! a [`progress::Progress`] reporter, which also lets the caller cancel it
//! ([`progress::Silent`] when nothing is to be shown).
//!
//! # Units and conventions
//!
//! - Lengths are metres and angles radians, unless a name says otherwise:
//!   names end in their unit (`emitter_pitch_m`, `theta_rad`,
//!   `horizontal_fov_deg`, `focal_length_px`).
//! - Display coordinates: `x` right along a hololine, `y` up, `z` toward the
//!   viewer, the hologram plane at `z = 0` (see [`geometry`]).
//! - Samples are linear radiance (not sRGB-encoded), finite and
//!   non-negative: `f32` in memory, `f16` or `f32` on disk. Tone mapping to
//!   8- or 16-bit sRGB happens only when pictures are written ([`picture`]:
//!   one tone mapping and PNG encoder for every picture).
//! - Every fallible call returns [`Result`]; an [`Error`] is one sentence
//!   that names the file and the problem.
//!
//! # Example: a mesh to fringes
//!
//! A bundled mesh rendered for the MIT Mark I display, written as a `.holo`
//! file, read back, and assembled into the display's three 8-bit colour
//! layers:
//!
//! ```
//! use std::path::Path;
//!
//! use holo::assemble::Assembler;
//! use holo::mesh::load::SceneSource;
//! use holo::mesh::place::{place, Placement};
//! use holo::mesh::render::{render, RenderOptions, Supersample};
//! use holo::progress::Silent;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let layout = holo::layout::mark1(); // 242 emitters × 64 hololines × 5 views, RGB
//! let geometry = &layout.geometry;
//!
//! // A scene file (glTF/GLB, OBJ+MTL or PLY; this one ships with holo's
//! // sources), fitted into the display's volume (metres).
//! let mut scene = SceneSource::open(Path::new("fixtures/mesh/spot/spot.obj"))?.scene_at(0.0)?;
//! place(&mut scene, geometry, &Placement::default())?;
//!
//! // One frame of modulation: the radiance along every display ray.
//! let options = RenderOptions { supersample: Supersample::new(1, 1), ..RenderOptions::default() };
//! let (frame, _stats) = render(&scene, geometry, &options, &Silent)?;
//! assert_eq!(frame.geometry(), geometry);
//!
//! // The `.holo` file: written atomically, refused if it exists.
//! let folder = tempfile::tempdir()?;
//! let file = folder.path().join("spot.holo");
//! holo::write(&file, &frame, &holo::WriteOptions::default())?;
//! let stored = holo::read(&file)?; // f16 by default: 11 significant bits a sample
//!
//! // The fringes: one 2048 × 1024 layer per colour, as the frame buffer expects.
//! let (layers, stats) = Assembler::new(&layout)?.assemble::<u8>(&stored)?;
//! assert_eq!((layers.images.len(), layers.width, layers.height), (3, 2048, 1024));
//! println!("{} samples clipped", stats.clipped);
//! # Ok(())
//! # }
//! ```
//!
//! The numbered programs in `examples/` go further, each runnable with
//! `cargo run --example NAME`: `01_mesh_to_holo` (a scene file to a `.holo`
//! file in one call), `02_read_and_inspect` (geometry, frames and samples of a
//! file), `03_assemble_fringes` (a `.holo` file to a fringe folder),
//! `04_cameras_to_holo` (a camera array to a `.holo` file) and
//! `05_custom_layout` (a display profile of one's own).
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(unnameable_types)]

pub mod assemble;
pub mod cameras;
mod error;
pub mod farm;
pub mod format;
pub mod frame_rate;
pub mod geometry;
pub mod hogels;
pub mod holoflick;
pub mod layout;
pub mod math;
mod memory;
pub mod mesh;
mod modulation;
pub mod output;
pub mod parallax;
pub mod pattern;
pub mod picture;
pub mod pictures;
pub mod pipeline;
pub mod prelude;
pub mod progress;
pub mod provenance;
pub mod reconstruct;
pub mod report;
mod sampling;
pub mod signature;
pub mod simd;
mod validate;
pub mod views;

pub use error::{Error, OutputProblem, Result, SetProblem};
pub use format::{read, write, HoloFile, WriteOptions};
pub use geometry::Geometry;
pub use modulation::{full_to_horizontal, rows_beyond_vertical_views, Band, Modulation};
pub use validate::validate;
