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

use std::path::Path;

#[test]
fn mesh_to_holo_then_read_and_inspect() {
    let folder = tempfile::tempdir().unwrap();
    let file = mesh_to_holo::run(folder.path()).unwrap();
    let frame = holo::read(&file).unwrap();
    assert!(frame.value_range().1 > 0.0, "the cow is lit");
    // The example refuses to replace what the first run wrote.
    assert!(mesh_to_holo::run(folder.path()).is_err());
    read_and_inspect::run(&file).unwrap();
    read_and_inspect::run(Path::new(read_and_inspect::FILE)).unwrap();
}

#[test]
fn assemble_fringes() {
    let folder = tempfile::tempdir().unwrap();
    assemble_fringes::run(folder.path()).unwrap();
    assert!(folder.path().join("fringes").join(holo::assemble::output::FRINGE_SIDECAR).is_file());
}

#[test]
fn cameras_to_holo() {
    let folder = tempfile::tempdir().unwrap();
    let file = cameras_to_holo::run(folder.path()).unwrap();
    let frame = holo::read(&file).unwrap();
    assert!(frame.value_range().1 > 0.5, "the wall is seen");
}

#[test]
fn custom_layout() {
    let folder = tempfile::tempdir().unwrap();
    custom_layout::run(folder.path()).unwrap();
}
