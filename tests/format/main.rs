//! The .holo file and every file holo writes: round trips, frozen vectors, damaged and hostile inputs, pictures
//! (one tone mapping), the output discipline (atomic files, sets, checks before work).
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

mod bad_input;
mod full_parallax;
mod hogels;
mod output;
mod picture;
mod roundtrip;
mod seal;
mod sequence;
mod vectors;
