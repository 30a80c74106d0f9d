//! The `holo` binary as a user runs it, one test binary: each command
//! ([`commands`]), the output discipline every command keeps ([`output`]) and the
//! command line's parts one by one ([`parts`]).
//! One binary, so its slow tests (the demo, the interrupts) run side by side.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod commands;
mod farm;
mod first_use;
mod inputs;
mod output;
mod parts;
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

/// `holo args` in `cwd` under a cap of `memory_mib` MiB of address space (a
/// runaway allocation then fails at once instead of exhausting the machine),
/// stopped if it runs past `seconds`: its output, or a panic saying it ran
/// on.
fn holo_bounded(args: &[&str], cwd: &Path, seconds: u64, memory_mib: u64) -> Output {
    let mut child = Command::new("sh")
        .args(["-c", &format!("ulimit -v {}; exec \"$@\"", memory_mib * 1024), "sh", HOLO])
        .args(args)
        .current_dir(cwd)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("run holo");
    let started = std::time::Instant::now();
    while child.try_wait().expect("wait for holo").is_none() {
        if started.elapsed().as_secs() >= seconds {
            let _ = child.kill();
            let o = child.wait_with_output().expect("wait for holo");
            panic!("holo {args:?} still ran after {seconds} s: {}", text(&o));
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().expect("wait for holo")
}
