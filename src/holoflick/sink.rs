//! HoloFlicks as the output of a [`crate::pipeline::run`]: a `.hflk` file
//! ([`HoloFlickSink`]) or, for one frame, a Java 3D `.cg` file ([`CgSink`]).

use std::path::{Path, PathBuf};

use super::container::{
    write_cg_file, Frame, HoloFlickWriter, ObjectRecord, ViewerCouch, WriteOptions, WriteReport as ContainerReport,
};
use crate::pipeline::{Job, Sink};
use crate::{Error, Result};

/// How `pack` and `encode` write: the frame rate, `software` and `source` text.
pub(crate) fn writer_options(frames_per_second: (u32, u32), source: String, overwrite: bool) -> WriteOptions {
    WriteOptions {
        frames_per_second,
        text: vec![("software".into(), format!("holo {}", env!("CARGO_PKG_VERSION"))), ("source".into(), source)],
        overwrite,
    }
}

/// `n / d` for a frame rate (exact for integers and for 24000/1001-style rates).
pub(crate) fn frame_rate_fraction(fps: f64) -> (u32, u32) {
    for d in [1u32, 1001, 1000, 100] {
        let n = fps * d as f64;
        if (n - n.round()).abs() < 1e-6 && n.round() >= 1.0 && n.round() <= u32::MAX as f64 {
            return (n.round() as u32, d);
        }
    }
    ((fps * 1000.0).round().max(1.0) as u32, 1000)
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

/// A HoloFlick file (`.hflk`, spec/holoflick.md) as the output of a run; its
/// `source` text is the run's provenance.
#[derive(Clone, Debug)]
pub struct HoloFlickSink {
    path: PathBuf,
    overwrite: bool,
}

impl HoloFlickSink {
    /// Write `path`, replacing an existing file only when `overwrite`.
    pub fn new(path: &Path, overwrite: bool) -> Self {
        HoloFlickSink { path: path.to_path_buf(), overwrite }
    }
}

impl Sink<Frame> for HoloFlickSink {
    type Written = ContainerReport;

    fn path(&self) -> &Path {
        &self.path
    }

    fn overwrite(&self) -> bool {
        self.overwrite
    }

    fn write(self, job: &Job, render: &mut dyn FnMut(usize, &mut Frame) -> Result<()>) -> Result<ContainerReport> {
        let rate = job.frames_per_second.unwrap_or((30, 1));
        let mut writer =
            HoloFlickWriter::create(&self.path, &writer_options(rate, job.provenance.clone(), self.overwrite))?;
        for number in job.frames.clone() {
            let mut frame = empty_frame();
            render(number, &mut frame)?;
            writer.add_frame(&frame)?;
        }
        Ok(writer.finish()?)
    }
}

/// A Java 3D `.cg` file as the output of a run of one frame: the frame's
/// objects as they are stored (no transforms, no lights: the file cannot
/// hold them).
#[derive(Clone, Debug)]
pub struct CgSink {
    path: PathBuf,
    overwrite: bool,
}

/// What a `.cg` file got.
#[derive(Clone, Debug, Default)]
pub struct CgWritten {
    /// The file's size.
    pub file_bytes: u64,
    /// Each object's `model = normalised × (1/scale) + centre` as (centre,
    /// 1/scale): a `.cg` file cannot hold it.
    pub transforms: Vec<([f64; 3], f64)>,
    /// Each object's colour scale (`1/s` was applied to colours above 1).
    pub radiance_scales: Vec<f64>,
}

impl CgSink {
    /// Write `path`, replacing an existing file only when `overwrite`.
    pub fn new(path: &Path, overwrite: bool) -> Self {
        CgSink { path: path.to_path_buf(), overwrite }
    }
}

impl Sink<Frame> for CgSink {
    type Written = CgWritten;

    fn path(&self) -> &Path {
        &self.path
    }

    fn overwrite(&self) -> bool {
        self.overwrite
    }

    fn write(self, job: &Job, render: &mut dyn FnMut(usize, &mut Frame) -> Result<()>) -> Result<CgWritten> {
        if job.frames.len() != 1 {
            return Err(Error::Usage(format!(
                "{}: a .cg file holds one frame's objects; {} frames given (write a .hflk)",
                self.path.display(),
                job.frames.len()
            )));
        }
        let mut frame = empty_frame();
        render(job.frames.start, &mut frame)?;
        let mut written = CgWritten::default();
        let mut blocks = Vec::new();
        for o in frame.objects {
            // The first frame of a run is a key frame: every object is stored.
            let ObjectRecord::Stored(g) = o else {
                return Err(Error::Usage(format!("{}: internal: a reference in a .cg frame", self.path.display())));
            };
            let m = g.world_from_object;
            written.transforms.push(([m[0][3], m[1][3], m[2][3]], m[0][0]));
            written.radiance_scales.push(g.radiance_scale);
            blocks.push(g.block);
        }
        written.file_bytes = write_cg_file(&self.path, &blocks, self.overwrite)?;
        Ok(written)
    }
}
