//! HoloFlicks (seed 001): holographic movies stored as frames of lit
//! micropolygons in world space, compressed with Deering's geometry
//! compression. [`container`] is the `.hflk` file (spec/holoflick.md).
//!
//! This file is a placeholder for the merge with the compressed-geometry codec.

pub mod container;
