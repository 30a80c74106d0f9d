//! Reconstruction: what the light leaving a fringe does, and what a viewer sees
//! (docs/optics.md §8).
//!
//! This layer sits after fringe assembly. Start at [`propagate`]: the 1-D
//! field on one hololine, its free-space propagation by the band-limited
//! angular spectrum method, and the angular spectrum of a window of it.

pub mod check;
pub mod coherent;
pub(crate) mod field;
pub mod files;
pub mod light_field;
pub mod picture;
pub mod propagate;
pub(crate) mod solve;
pub mod viewer;
