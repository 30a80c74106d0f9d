//! Fringe assembly and reconstruction: files, frame-buffer layouts, physics, recovery; and the
//! numbered user examples of `examples/`, which end in fringes.
//!
//! One test binary for this stage of the data flow (each file a module), so a
//! clean build links a few binaries rather than one per file.

mod coherent;
mod examples;
mod files;
mod ghosts;
mod layouts;
mod physics;
mod reconstruct;
mod seams;
mod vectors;
