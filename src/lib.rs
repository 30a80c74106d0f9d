//! `holo`: the modulation texture of a holographic stereogram as a standard
//! file, and the conversions around it.
//!
//! Start at [`Geometry`] and [`Modulation`] (the data), then [`format`](mod@format) (the
//! `.holo` file, spec/holo-format.md), [`layout`] (display profiles),
//! [`pattern`] (test patterns), [`views`] (PNG export and import) and
//! [`picture`] (the tone mapping and PNG encoding of every picture written).
#![deny(missing_docs)]

pub mod assemble;
pub mod cameras;
mod error;
pub mod format;
pub mod geometry;
pub mod holoflick;
pub mod layout;
pub mod mesh;
mod modulation;
pub mod pattern;
pub mod picture;
pub mod reconstruct;
pub mod report;
pub mod resample;
pub mod views;

pub use error::{Error, Result};
pub use format::{read, write, HoloFile, WriteOptions};
pub use geometry::Geometry;
pub use modulation::{Band, Modulation};
