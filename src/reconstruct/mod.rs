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
pub mod picture;
pub mod propagate;
pub(crate) mod solve;
pub mod viewer;

use std::cell::RefCell;
use std::sync::Arc;

use rustfft::{Fft, FftPlanner};

thread_local! {
    /// One planner per thread: planning a long FFT costs more than running
    /// it, and every hololine needs the same few lengths.
    static PLANNER: RefCell<FftPlanner<f64>> = RefCell::new(FftPlanner::new());
}

/// A forward FFT of `len` points, planned once per thread.
pub(crate) fn fft_forward(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_forward(len))
}

/// An inverse (unnormalised) FFT of `len` points, planned once per thread.
pub(crate) fn fft_inverse(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_inverse(len))
}
