//! What `holo farm` asks of a command it splits: its output, one per
//! frame; the decisions made once for the whole movie; and the command for
//! one frame. Below the commands that make frames and the farm that splits
//! them.

use std::ops::Range;
use std::path::PathBuf;

use holo::farm::FarmOutput;
use holo::math::Mat4;

use super::Failure;

/// A command that makes frames, as a farm splits it.
pub trait FrameJob {
    /// What it makes, one output per frame.
    fn output(&self) -> FarmOutput;
    /// Everything checked and decided once for the whole movie.
    fn decide(&self) -> Result<Decided, Failure>;
    /// Make frame `n` alone into `output` (replacing what is there),
    /// placed by `placement` when the movie was placed.
    fn for_frame(&mut self, n: usize, output: PathBuf, placement: Option<Mat4>);
}

/// What a farm decides before the split.
pub struct Decided {
    /// The movie's frames.
    pub frames: Range<usize>,
    /// The placement every chunk is given.
    pub placement: Option<Mat4>,
}
