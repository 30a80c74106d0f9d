//! HoloFlicks as the output of a [`crate::pipeline::run`]: a `.hflk` file
//! or, for one frame, a Java 3D `.cg` file ([`HoloFlickSink`]).

use std::path::{Path, PathBuf};

use super::container::{write_cg_file, Frame, HoloFlickWriteOptions, HoloFlickWriter, ObjectRecord, ViewerCouch};
use crate::error::{Error, Result};
use crate::pipeline::{Job, Sink};

/// How `pack` and `encode` write: the frame rate, `software` and `source` text.
pub(crate) fn writer_options(frames_per_second: (u32, u32), source: String, overwrite: bool) -> HoloFlickWriteOptions {
    HoloFlickWriteOptions {
        frames_per_second,
        text: vec![("software".into(), format!("holo {}", env!("CARGO_PKG_VERSION"))), ("source".into(), source)],
        overwrite,
    }
}

/// An empty frame for a source to fill.
fn empty_frame() -> Frame {
    Frame {
        key_frame: false,
        couch: ViewerCouch { min_m: [0.0; 3], max_m: [0.0; 3] },
        lights: Vec::new(),
        materials: Vec::new(),
        bindings: Vec::new(),
        objects: Vec::new(),
    }
}

/// HoloFlick frames as the output of a run: a HoloFlick file (`.hflk`,
/// spec/holoflick.md; its `source` text the run's provenance) or, when the
/// name ends in `.cg`, a Java 3D `.cg` file of one frame's objects as they
/// are stored (no transforms, no lights: the file cannot hold them).
#[derive(Clone, Debug)]
pub struct HoloFlickSink {
    path: PathBuf,
    overwrite: bool,
}

/// What a [`HoloFlickSink`] wrote.
#[derive(Clone, Debug, Default)]
pub struct HoloFlickWritten {
    /// The file's size.
    pub file_bytes: u64,
    /// For a `.cg` file, each object's `model = normalised × (1/scale) +
    /// centre` as (centre, 1/scale), and its colour scale (`1/s` was applied
    /// to colours above 1): a `.cg` file cannot hold them.
    pub cg: Option<CgObjects>,
}

/// What a `.cg` file could not hold of its objects.
#[derive(Clone, Debug, Default)]
pub struct CgObjects {
    /// (centre, 1/scale) of each object.
    pub transforms: Vec<([f64; 3], f64)>,
    /// The colour scale of each object.
    pub radiance_scales: Vec<f64>,
}

impl HoloFlickSink {
    /// Write `path`, replacing an existing file only when `overwrite`.
    pub fn new(path: &Path, overwrite: bool) -> Self {
        HoloFlickSink { path: path.to_path_buf(), overwrite }
    }

    /// Whether the output is a Java 3D `.cg` file.
    pub fn is_cg(&self) -> bool {
        self.path.extension().is_some_and(|e| e.eq_ignore_ascii_case("cg"))
    }

    /// The one frame of a `.cg` file.
    fn write_cg(self, job: &Job, render: &mut dyn FnMut(usize, &mut Frame) -> Result<()>) -> Result<HoloFlickWritten> {
        if job.frames.len() != 1 {
            return Err(Error::unsupported(
                &self.path,
                format!("a .cg file holds one frame's objects; {} frames given (write a .hflk)", job.frames.len()),
            ));
        }
        let mut frame = empty_frame();
        render(job.frames.start, &mut frame)?;
        let mut cg = CgObjects::default();
        let mut blocks = Vec::new();
        for o in frame.objects {
            // The first frame of a run is a key frame: every object is stored.
            let ObjectRecord::Stored(g) = o else {
                return Err(Error::unsupported(&self.path, "internal: a reference in a .cg frame"));
            };
            let m = g.world_from_object;
            cg.transforms.push(([m[0][3], m[1][3], m[2][3]], m[0][0]));
            cg.radiance_scales.push(g.radiance_scale);
            blocks.push(g.block);
        }
        let file_bytes = write_cg_file(&self.path, &blocks, self.overwrite)?;
        Ok(HoloFlickWritten { file_bytes, cg: Some(cg) })
    }
}

impl Sink<Frame> for HoloFlickSink {
    type Written = HoloFlickWritten;

    fn path(&self) -> &Path {
        &self.path
    }

    fn overwrite(&self) -> bool {
        self.overwrite
    }

    /// (A `.cg` file, one frame, says so itself when it is asked for more.)
    fn max_frames(&self) -> (u64, &'static str) {
        (super::container::MAX_FRAMES, "a HoloFlick")
    }

    fn write(self, job: &Job, render: &mut dyn FnMut(usize, &mut Frame) -> Result<()>) -> Result<HoloFlickWritten> {
        if self.is_cg() {
            return self.write_cg(job, render);
        }
        let rate = job.frames_per_second.unwrap_or((30, 1));
        let mut writer =
            HoloFlickWriter::create(&self.path, &writer_options(rate, job.provenance.clone(), self.overwrite))?;
        for number in job.frames.clone() {
            let mut frame = empty_frame();
            render(number, &mut frame)?;
            writer.add_frame(&frame)?;
        }
        Ok(HoloFlickWritten { file_bytes: writer.finish()?.file_bytes, cg: None })
    }
}
