//! Meshes to modulation: loaders, renderers, camera pictures, writers.
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

#[path = "../common/mod.rs"]
mod common;

mod camera;
mod end_to_end;
mod load;
mod materials;
mod normals;
mod pipeline;
mod provenance;
mod render;
mod skin;
mod write;
