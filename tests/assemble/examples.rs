//! The numbered user examples of `examples/`, run end to end.
//!
//! `cargo test` builds every example but does not run it; each numbered
//! example keeps its work in a `run` function (its `main` only picks a new
//! folder), so this module includes the example files themselves and runs
//! them into a temporary folder here. Including them in this binary rather
//! than marking them `test = true` in Cargo.toml adds no test binary to link.

#[allow(dead_code)]
#[path = "../../examples/01_mesh_to_holo.rs"]
mod mesh_to_holo;

#[allow(dead_code)]
#[path = "../../examples/02_read_and_inspect.rs"]
mod read_and_inspect;

#[allow(dead_code)]
#[path = "../../examples/03_assemble_fringes.rs"]
mod assemble_fringes;

#[allow(dead_code)]
#[path = "../../examples/04_cameras_to_holo.rs"]
mod cameras_to_holo;

#[allow(dead_code)]
#[path = "../../examples/05_custom_layout.rs"]
mod custom_layout;

use std::error::Error;
use std::path::Path;

/// Run an example's `run` into a new temporary folder, which is kept as
/// long as the returned handle.
fn run_example<T>(run: fn(&Path) -> Result<T, Box<dyn Error>>) -> (tempfile::TempDir, T) {
    let folder = tempfile::tempdir().unwrap();
    let out = run(folder.path()).unwrap_or_else(|e| panic!("the example failed: {e}"));
    (folder, out)
}

#[test]
fn mesh_to_holo_then_read_and_inspect() {
    let (folder, file) = run_example(mesh_to_holo::run);
    assert!(holo::read(&file).unwrap().value_range().1 > 0.0, "the cow is lit");
    // The example refuses to replace what the first run wrote.
    assert!(mesh_to_holo::run(folder.path()).is_err());
    read_and_inspect::run(&file).unwrap();
    read_and_inspect::run(Path::new(read_and_inspect::FILE)).unwrap();
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn assemble_fringes() {
    let (_folder, fringes) = run_example(assemble_fringes::run);
    assert!(fringes.join(holo::assemble::output::FRINGE_SIDECAR).is_file());
}

#[test]
fn cameras_to_holo() {
    let (_folder, file) = run_example(cameras_to_holo::run);
    assert!(holo::read(&file).unwrap().value_range().1 > 0.5, "the wall is seen");
}

#[test]
fn custom_layout() {
    let (_folder, profile) = run_example(custom_layout::run);
    assert_eq!(holo::layout::Layout::load(&profile.to_string_lossy()).unwrap().geometry.hololines, 32);
}
