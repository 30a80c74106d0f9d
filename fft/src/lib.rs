//! Complex f64 Fourier transforms, planned once per thread.
//!
//! holo reconstructs fringes with FFTs of a few lengths per hololine
//! (docs/optics.md §8). This crate is the one place that plans them, and it
//! exists as its own crate for build time, not for design: rustfft's planner
//! is generic, so every crate that calls it compiles every FFT algorithm
//! again (a third of the machine code of holo's library, twice over for its
//! unit tests). Behind these two non-generic functions the algorithms are
//! compiled once; callers run them through `dyn Fft<f64>`, which costs a
//! virtual call a transform.

use std::cell::RefCell;
use std::sync::Arc;

pub use rustfft::num_complex::Complex64;
pub use rustfft::Fft;
use rustfft::FftPlanner;

thread_local! {
    /// One planner per thread: planning a long FFT costs more than running
    /// it, and every hololine needs the same few lengths.
    static PLANNER: RefCell<FftPlanner<f64>> = RefCell::new(FftPlanner::new());
}

/// A forward FFT of `len` points (`X[k] = Σ x[n] e^{−2πi kn/len}`), planned
/// once per thread.
pub fn forward(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_forward(len))
}

/// An inverse FFT of `len` points, unnormalised (`x[n] = Σ X[k] e^{+2πi
/// kn/len}`, `len` times the input of [`forward`]), planned once per thread.
pub fn inverse(len: usize) -> Arc<dyn Fft<f64>> {
    PLANNER.with(|p| p.borrow_mut().plan_fft_inverse(len))
}
