//! The geometry shader of HoloFlicks: a scene made into lit micropolygons
//! for one display, and the work a frame does not need. [`dice`] cuts every
//! surface into micropolygons no larger than the display resolves at their
//! depth; [`bake`] puts the view-independent light into their vertex
//! colours; [`micro`] does both and leaves pre-lit materials that keep only
//! what varies with the view; [`cull`] finds what no ray of the display
//! meets and faces turned away from the viewer's couch. The mesh renderers
//! ([`crate::mesh`]) draw the result.

pub mod bake;
pub mod cull;
pub mod dice;
pub mod micro;
