//! The .holo file: round trips, frozen vectors, damaged and hostile inputs.
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

mod bad_input;
mod roundtrip;
mod vectors;
