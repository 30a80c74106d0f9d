//! HoloFlicks (Deering, *HoloFlicks*; spec/holoflick.md): holographic movies stored as frames
//! of lit micropolygons in world space.
//!
//! - [`cg`]: Michael Deering's compressed geometry exactly as Java 3D 1.5.2
//!   reads and writes it (stream format 1.0.2) and Java 3D's `.cg` resource
//!   files: the workspace crate `holo-cg` (folder `cg/`), which stands alone,
//!   re-exported here. Start reading at [`cg::encode`] and [`cg::decode`].
//! - [`container`]: the `.hflk` file (spec/holoflick.md): frames of geometry
//!   blocks with their transforms, specular lights and materials, bindings,
//!   the viewer's couch and key frames.
//! - [`shader`]: the geometry shader: a scene diced into micropolygons for a
//!   display, its view-independent light baked in, and what a frame does not
//!   need culled.

pub use holo_cg as cg;
pub mod container;
pub mod convert;
pub mod encode;
pub mod objects;
pub mod shader;
pub mod sink;
pub mod tools;
