//! The `holo` binary as a user runs it, one test binary: each command
//! ([`commands`]) and the output discipline every command keeps ([`output`]).
//! One binary, so its slow tests (the demo, the interrupts) run side by side.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod commands;
mod farm;
mod first_use;
mod inputs;
mod output;
mod pictures;
mod reference;

const HOLO: &str = env!("CARGO_BIN_EXE_holo");

fn holo(args: &[&str], cwd: &Path) -> Output {
    Command::new(HOLO).args(args).current_dir(cwd).output().expect("run holo")
}

/// Standard output then standard error, for messages.
fn text(o: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr))
}

/// `o`, which must have succeeded.
fn ok(o: Output) -> Output {
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    o
}

fn fixture(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures").join(path)
}

/// The bundled textured mesh.
fn spot() -> String {
    fixture("mesh/spot/spot.obj").to_str().unwrap().to_string()
}

/// Mark III with `hololines` hololines, as a user would edit the profile.
fn small_profile(d: &Path, hololines: usize) -> PathBuf {
    let o = ok(holo(&["layout", "mark3"], d));
    let profile = String::from_utf8(o.stdout).unwrap().replace("hololines = 440", &format!("hololines = {hololines}"));
    let path = d.join("small.toml");
    std::fs::write(&path, profile).unwrap();
    path
}
