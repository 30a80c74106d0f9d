//! HoloFlicks (DESIGN.md §6): streams of frames of compressed geometry.
//!
//! So far this holds the geometry codec, [`cg`]: Michael Deering's
//! compressed geometry exactly as Java 3D 1.5.2 reads and writes it (stream
//! format 1.0.2) and Java 3D's `.cg` resource files. Start reading at
//! [`cg::encode`] and [`cg::decode`].

pub mod cg;
