//! Camera arrays to modulation: rigs read, resampled, ground truth, real captures.
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

#[path = "../common/mod.rs"]
mod common;

mod ground_truth;
mod hci_export;
mod provenance;
mod read;
mod real;
mod resample;
