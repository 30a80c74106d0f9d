//! HoloFlicks: the container, objects, tools, and conversion to modulation.
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

#[path = "../common/mod.rs"]
mod common;

mod cg_real;
mod container;
mod convert;
mod objects;
mod provenance;
mod tools;
