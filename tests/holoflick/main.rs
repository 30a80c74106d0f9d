//! HoloFlicks: the container, the geometry shader (dicing, baking, pre-lit
//! micropolygons, culling), objects, tools, and conversion to modulation.
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

#[path = "../common/mod.rs"]
mod common;

mod bake;
mod cg_real;
mod container;
mod convert;
mod cull;
mod dice;
mod micro;
mod objects;
mod provenance;
mod tools;
