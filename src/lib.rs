//! `holo`: the modulation texture of a holographic stereogram as a standard
//! file, and the conversions around it.
//!
//! Start at [`Geometry`] and [`Modulation`] (the data), then [`format`](mod@format) (the
//! `.holo` file, spec/holo-format.md), [`layout`] (display profiles),
//! [`pattern`] (test patterns), [`views`] (PNG export and import) and
//! [`picture`] (the tone mapping and PNG encoding of every picture written).
#![deny(missing_docs)]
#![deny(unsafe_op_in_unsafe_fn)]

pub mod assemble;
pub mod cameras;
mod error;
pub mod format;
pub mod geometry;
pub mod holoflick;
pub mod layout;
pub mod math;
pub mod mesh;
mod modulation;
pub mod output;
pub mod pattern;
pub mod picture;
pub mod pipeline;
pub mod progress;
pub mod reconstruct;
pub mod report;
pub mod resample;
mod sampling;
pub mod simd;
pub mod views;

pub use error::{Error, OutputProblem, Result, SetProblem};
pub use format::{read, write, HoloFile, WriteOptions};
pub use geometry::Geometry;
pub use modulation::{Band, Modulation};
