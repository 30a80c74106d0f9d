//! The output discipline as a user meets it: interrupts leave nothing half
//! written, sets of files are replaced whole and refused when mixed, a full
//! disk truncates nothing, an output never replaces its input, a closed pipe
//! ends a listing quietly, and refusals come before any work.

use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

use holo::geometry::{mono_channel, Geometry, Views};
use holo::{Modulation, WriteOptions};

use super::{fixture, holo, ok, small_profile, text, HOLO};

/// Hidden files in `dir`: temporaries and spools left behind.
fn hidden(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect()
}

/// Every file of `dir` (and of its folders, as `folder/name`) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap().map(|e| e.unwrap()) {
        let name = e.file_name().to_string_lossy().into_owned();
        if e.file_type().unwrap().is_dir() {
            files.extend(snapshot(&e.path()).into_iter().map(|(n, b)| (format!("{name}/{n}"), b)));
        } else {
            files.insert(name, std::fs::read(e.path()).unwrap());
        }
    }
    files
}

/// Wait until a hidden file whose name holds `suffix` is in `dir` (the
/// child is then mid-write); panics with the child's messages if it ends
/// first.
fn wait_for_hidden(child: &mut Child, dir: &Path, suffix: &str) {
    let started = Instant::now();
    loop {
        // (The folder may not be there yet: the child makes it.)
        if std::fs::read_dir(dir).into_iter().flatten().flatten().any(|e| {
            e.file_name().to_string_lossy().starts_with('.') && e.file_name().to_string_lossy().contains(suffix)
        }) {
            return;
        }
        if let Some(status) = child.try_wait().unwrap() {
            let mut messages = String::new();
            std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut messages).unwrap();
            panic!("the child ended ({status}) before writing a {suffix} file: {messages}");
        }
        assert!(started.elapsed() < Duration::from_secs(300), "no {suffix} file after 300 s");
        std::thread::sleep(Duration::from_millis(1));
    }
}

fn spawn(args: &[&str], cwd: &Path) -> Child {
    Command::new(HOLO)
        .args(args)
        .current_dir(cwd)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start holo")
}

/// Send `signal` (a name as `kill` takes it) to the child and wait for it.
fn interrupt(child: Child, signal: &str) -> (Option<i32>, String) {
    signal_child(&child, signal);
    let out = child.wait_with_output().unwrap();
    (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// Sends `child` the signal named `signal` (`INT`, `STOP`, `CONT`, ...).
fn signal_child(child: &Child, signal: &str) {
    let pid = child.id().to_string();
    assert!(Command::new("kill").args([&format!("-{signal}"), &pid]).status().unwrap().success());
}

/// A movie of `frames` frames of noise for the layout profile at `profile`
/// (assembled, long enough that a test can act while it runs).
fn noise_movie(profile: &Path, path: &Path, frames: usize) {
    let g = holo::layout::Layout::load(profile.to_str().unwrap()).unwrap().geometry;
    holo::format::write_frames(path, &g, frames, &WriteOptions::default(), |i| {
        let m = Modulation::from_fn(g.clone(), |_, j, e, v| noise((i * 7919 + j * 131 + e * 17 + v) as u64))?;
        Ok(std::borrow::Cow::Owned(m))
    })
    .unwrap();
}

/// A noise value in [0, 1) from a position, the same every run.
fn noise(k: u64) -> f32 {
    let mut x = k.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x5DEE_CE66;
    x ^= x >> 29;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 32;
    (x % 1_000_000) as f32 / 1_000_000.0
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn interrupts_remove_temporaries_keep_the_previous_file_and_say_which_signal() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark3", "--kind", "view-ramp", "-o", "ramp.holo"], d));
    ok(holo(&["export-quilt", "ramp.holo", "-o", "ramp_qs8x6a0.75.png"], d));
    let glb = fixture("mesh/AnimatedMorphCube.glb");
    let spot = fixture("mesh/spot/spot.obj");
    let (glb, spot) = (glb.to_str().unwrap(), spot.to_str().unwrap());
    let mesh: &[&str] =
        &["convert", "mesh", glb, "--frames", "0..4", "--f32", "--compression", "none", "-o", "out.holo", "--force"];
    let cameras: &[&str] = &["convert", "cameras", "ramp_qs8x6a0.75.png", "-o", "out.holo", "--force"];
    let encode: &[&str] = &["holoflick", "encode", spot, "-o", "out.hflk", "--force"];
    // Every signal on one command, and SIGINT on the others: the signals
    // reach one handler, the temporaries differ by command.
    let every_signal: &[(&str, i32)] = &[("INT", 130), ("TERM", 143), ("HUP", 129)];
    let interrupt_only: &[(&str, i32)] = &[("INT", 130)];
    for (args, output, mid_write, signals) in [
        (mesh, "out.holo", ".partial", every_signal),
        (cameras, "out.holo", ".spool", interrupt_only),
        (encode, "out.hflk", ".partial", interrupt_only),
    ] {
        for &(signal, code) in signals {
            let previous = format!("the previous {output}, kept through SIG{signal}").into_bytes();
            std::fs::write(d.join(output), &previous).unwrap();
            let mut child = spawn(args, d);
            wait_for_hidden(&mut child, d, mid_write);
            let (status, messages) = interrupt(child, signal);
            assert_eq!(status, Some(code), "{args:?} on SIG{signal}: {messages}");
            assert_eq!(hidden(d), Vec::<String>::new(), "{args:?} on SIG{signal} left temporaries");
            assert_eq!(std::fs::read(d.join(output)).unwrap(), previous, "{args:?} on SIG{signal}");
        }
    }
}

#[test]
fn the_demo_writes_over_no_file_of_yours_and_an_interrupted_demo_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A folder of your own files, one of them named as a demo file: refused
    // before any work, and left as it was.
    let mine = d.join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("demo.holo"), "my own demo.holo").unwrap();
    std::fs::write(mine.join("notes.txt"), "my notes").unwrap();
    // Only demo names, but a scene in spot/ that is not the demo's: yours too.
    let named = d.join("named");
    std::fs::create_dir_all(named.join("spot")).unwrap();
    std::fs::write(named.join("demo.holo"), "my own demo.holo").unwrap();
    std::fs::write(named.join("spot/spot.obj"), "v 0 0 0\n").unwrap();
    for folder in ["mine", "named"] {
        let before = snapshot(&d.join(folder));
        let o = holo(&["demo", "-o", folder], d);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(text(&o).contains(folder) && text(&o).contains("did not make"), "{}", text(&o));
        assert!(snapshot(&d.join(folder)) == before, "the refused demo changed {folder}");
        assert_eq!(std::fs::read(d.join(folder).join("demo.holo")).unwrap(), b"my own demo.holo");
    }
    // Interrupted mid-run, a new folder is gone again and an empty one is empty again.
    for (name, existed) in [("new", false), ("empty", true)] {
        let folder = d.join(name);
        if existed {
            std::fs::create_dir(&folder).unwrap();
        }
        let mut child = spawn(&["demo", "-o", name], d);
        // While it renders the scene into demo.holo (the scene's files are written).
        wait_for_hidden(&mut child, &folder, ".demo.holo.");
        assert!(folder.join("spot/spot.obj").is_file());
        let (status, messages) = interrupt(child, "INT");
        assert_eq!(status, Some(130), "{messages}");
        if existed {
            assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 0, "{name}: {messages}");
        } else {
            assert!(!folder.exists(), "{name}: {messages}");
        }
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn an_interrupted_assemble_keeps_the_previous_set_and_a_mixed_set_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = small_profile(d, 2);
    let p = profile.to_str().unwrap();
    ok(holo(&["pattern", "--layout", p, "--kind", "colour-bars", "-o", "a.holo"], d));
    ok(holo(&["pattern", "--layout", p, "--kind", "checkerboard", "--cell", "3", "-o", "c.holo"], d));
    // Another file, long enough that an interrupt finds it mid-set.
    let g = holo::layout::Layout::load(p).unwrap().geometry;
    let frames = 200;
    holo::format::write_frames(d.join("b.holo"), &g, frames, &WriteOptions::default(), |i| {
        let m = Modulation::from_fn(g.clone(), |_, j, e, v| noise((i * 7919 + j * 131 + e * 17 + v) as u64))?;
        Ok(std::borrow::Cow::Owned(m))
    })
    .unwrap();
    ok(holo(&["assemble", "a.holo", "--layout", p, "-o", "fringes"], d));
    let fringes = d.join("fringes");
    let before = snapshot(&fringes);
    let checked = ok(holo(&["check", "a.holo", "--fringes", "fringes", "--json"], d));

    let mut child = spawn(&["assemble", "b.holo", "--layout", p, "-o", "fringes", "--force"], d);
    wait_for_hidden(&mut child, &fringes, ".partial");
    let (status, messages) = interrupt(child, "INT");
    assert_eq!(status, Some(130), "{messages}");
    assert_eq!(hidden(&fringes), Vec::<String>::new());
    assert!(snapshot(&fringes) == before, "the interrupted run changed the previous set");
    // The set is still a's, whole: checked as before; b is refused.
    let again = ok(holo(&["check", "a.holo", "--fringes", "fringes", "--json"], d));
    let report = |o: &Output| serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()["signal"].clone();
    assert_eq!(report(&again), report(&checked));
    let o = holo(&["check", "b.holo", "--fringes", "fringes"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    // Interrupted into a new folder whose parents it made: none is left.
    let mut child = spawn(&["assemble", "b.holo", "--layout", p, "-o", "made/for/new"], d);
    wait_for_hidden(&mut child, &d.join("made/for/new"), ".partial");
    let (status, messages) = interrupt(child, "INT");
    assert_eq!(status, Some(130), "{messages}");
    assert!(!d.join("made").exists(), "{messages}");

    // A set mixed by hand: one image replaced by another file's.
    ok(holo(&["assemble", "c.holo", "--layout", p, "-o", "other"], d));
    std::fs::copy(d.join("other/frame0000-head1.png"), fringes.join("frame0000-head1.png")).unwrap();
    for args in [&["check", "a.holo", "--fringes", "fringes"][..], &["view", "fringes", "-o", "v.png"]] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(
            text(&o).contains("frame0000-head1.png") && text(&o).contains("not the file of this set"),
            "{}",
            text(&o)
        );
    }
    // A set whose sidecar is gone (an interrupt between taking the old set
    // apart and putting the new one in place) is not a set.
    std::fs::remove_file(d.join("other/holo-fringes.json")).unwrap();
    let o = holo(&["view", "other", "-o", "w.png"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("holo-fringes.json"), "{}", text(&o));
}

/// A small file whose view 5 is noise (a PNG of some kilobytes) and whose
/// other views are flat (PNGs of a few hundred bytes), or all noise.
fn views_file(d: &Path, name: &str, all_noise: bool) {
    let g = Geometry::centred(32, 64, Views::tan_spaced(16, -0.2, 0.2), 1.3e-4, 2.4e-4, 0.027, 0.6, mono_channel());
    let m = Modulation::from_fn(
        g,
        |_, j, e, v| {
            if all_noise || v == 5 {
                noise((j * 64 + e) as u64 * 16 + v as u64)
            } else {
                0.5
            }
        },
    )
    .unwrap();
    holo::write(d.join(name), &m, &WriteOptions::default()).unwrap();
}

/// Every file a failed export left in `views` (temporaries too), and those
/// under a final name that are not whole PNGs.
fn left_behind(views: &Path) -> (Vec<PathBuf>, Vec<PathBuf>) {
    let left: Vec<PathBuf> =
        std::fs::read_dir(views).map(|r| r.flatten().map(|e| e.path()).collect()).unwrap_or_default();
    let truncated = left
        .iter()
        .filter(|p| {
            !p.file_name().unwrap().to_string_lossy().starts_with('.') && holo::picture::decode::open(p).is_err()
        })
        .cloned()
        .collect();
    (left, truncated)
}

/// What a failed export must leave: no file under its final name that is
/// not whole, and here none at all (no PNG is in place before all are
/// complete, the sidecar comes last), nor any temporary.
fn assert_nothing_left((left, truncated): (Vec<PathBuf>, Vec<PathBuf>)) {
    assert_eq!(truncated, Vec::<PathBuf>::new(), "truncated under their final names");
    assert_eq!(left, Vec::<PathBuf>::new(), "left by an export that failed");
}

#[test]
fn an_export_whose_writes_fail_truncates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    views_file(d, "one-noisy.holo", false);
    views_file(d, "noisy.holo", true);
    // A file-size limit (2 KiB) the noisy view's PNG exceeds: the write
    // fails mid-way through the views, as on a full disk.
    let o = Command::new("sh")
        .args([
            "-c",
            "trap '' XFSZ; ulimit -f 4; exec \"$@\"",
            "sh",
            HOLO,
            "export-views",
            "one-noisy.holo",
            "-o",
            "views",
        ])
        .current_dir(d)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("view_005.png"), "{}", text(&o));
    assert_nothing_left(left_behind(&d.join("views")));

    // A full file system, when this machine lets a test mount one.
    let mount = d.join("small-disk");
    std::fs::create_dir(&mount).unwrap();
    let mounted = Command::new("mount").args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"]).arg(&mount).output();
    if !mounted.as_ref().is_ok_and(|o| o.status.success()) {
        eprintln!("note: mount -t tmpfs is not permitted here; the full-disk variant was skipped");
        return;
    }
    let o = holo(&["export-views", "noisy.holo", "-o", "small-disk/views"], d);
    let left = left_behind(&mount.join("views"));
    assert!(Command::new("umount").arg(&mount).status().unwrap().success());
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("No space left"), "{}", text(&o));
    assert_nothing_left(left);
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn a_write_that_fails_names_the_file_asked_for_and_leaves_nothing() {
    // A file-size limit (4 KiB) every output here exceeds, as a full disk
    // would stop it: the error names the file asked for, not the hidden
    // temporary it was being written to, and the folder keeps only the input.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spot = super::spot();
    let spot = spot.as_str();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "ramp.holo"], d));
    ok(holo(&["export-quilt", "ramp.holo", "-o", "ramp_qs8x4a1.png"], d));
    let commands: [&[&str]; 4] = [
        &["pattern", "--layout", "mark1", "--kind", "view-ramp", "--compression", "none", "-o", "big.holo"],
        &["convert", "mesh", spot, "--layout", "mark1", "-o", "big.holo"],
        // (Its rows go to a scratch file first.)
        &["convert", "cameras", "ramp_qs8x4a1.png", "--layout", "mark1", "-o", "big.holo"],
        &["holoflick", "encode", spot, "-o", "big.hflk"],
    ];
    let before: Vec<String> =
        std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    for args in commands {
        let o = Command::new("sh")
            .args(["-c", "trap '' XFSZ; ulimit -f 4; exec \"$@\"", "sh", HOLO])
            .args(args)
            .current_dir(d)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        let output = args[args.len() - 1];
        assert!(text(&o).contains(&format!("{output}: File too large")), "{args:?}: {}", text(&o));
        assert!(!text(&o).contains(".partial") && !text(&o).contains(".spool"), "{args:?}: {}", text(&o));
        let after: Vec<String> =
            std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
        assert_eq!(after, before, "{args:?} left files behind");
    }
}

#[test]
fn an_output_never_replaces_its_input() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "same.holo"], d));
    let before = std::fs::read(d.join("same.holo")).unwrap();
    std::fs::hard_link(d.join("same.holo"), d.join("linked.holo")).unwrap();
    std::os::unix::fs::symlink("same.holo", d.join("alias.holo")).unwrap();
    for output in ["same.holo", "./same.holo", "linked.holo", "alias.holo"] {
        let o = holo(&["export-quilt", "same.holo", "-o", output, "--force"], d);
        assert_eq!(o.status.code(), Some(1), "{output}: {}", text(&o));
        assert!(text(&o).contains("is the input"), "{}", text(&o));
        assert_eq!(std::fs::read(d.join("same.holo")).unwrap(), before, "{output}");
    }
    // A layout profile is an input too.
    std::fs::write(d.join("profile.toml"), ok(holo(&["layout", "mark1"], d)).stdout).unwrap();
    let profile = std::fs::read(d.join("profile.toml")).unwrap();
    let o =
        holo(&["pattern", "--layout", "profile.toml", "--kind", "checkerboard", "-o", "profile.toml", "--force"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("is the input"), "{}", text(&o));
    assert_eq!(std::fs::read(d.join("profile.toml")).unwrap(), profile);
    // A .holo file given as the layout is refused as a layout, before the output is looked at.
    let o = holo(&["pattern", "--layout", "same.holo", "--kind", "checkerboard", "-o", "linked.holo", "--force"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("same.holo: not a layout profile"), "{}", text(&o));
    assert_eq!(std::fs::read(d.join("same.holo")).unwrap(), before);
    for args in [
        &["view", "same.holo", "--layout", "mark1", "-o", "same.holo", "--force"],
        &["import-views", ".", "--geometry", "mark1", "-o", "same.holo", "--force"],
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("is the input"), "{args:?}: {}", text(&o));
        assert_eq!(std::fs::read(d.join("same.holo")).unwrap(), before, "{args:?}");
    }
}

#[test]
fn a_closed_stdout_ends_a_listing_quietly() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "a.holo"], d));
    // Far more than a pipe holds, so the writer meets the closed pipe.
    let mut args = vec!["info", "--headers-only"];
    args.extend(std::iter::repeat("a.holo").take(600));
    let mut child =
        Command::new(HOLO).args(&args).current_dir(d).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut first).unwrap();
    assert!(first.contains("a.holo"), "{first}");
    // The reader is gone (as `head -1` goes).
    let out = child.wait_with_output().unwrap();
    let messages = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{messages}");
    assert!(messages.is_empty(), "{messages}");
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn refusals_come_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark3", "--kind", "colour-bars", "-o", "m3.holo"], d));
    std::fs::write(d.join("taken.png"), b"mine").unwrap();
    for (output, needle) in [("taken.png", "already exists"), ("no/such/folder/v.png", "does not exist")] {
        let started = Instant::now();
        let o = holo(&["view", "m3.holo", "-o", output], d);
        let seconds = started.elapsed().as_secs_f64();
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(text(&o).contains(needle) && text(&o).contains(output), "{}", text(&o));
        assert!(seconds < 0.5, "view took {seconds:.2} s to refuse {output}");
    }
    assert_eq!(std::fs::read(d.join("taken.png")).unwrap(), b"mine");
    for args in [
        &["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "no/such/folder/p.holo"][..],
        &["convert", "mesh", "m3.holo", "-o", "taken.png"],
        &["export-quilt", "m3.holo", "-o", "taken.png"],
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("already exists") || text(&o).contains("does not exist"), "{}", text(&o));
    }

    // assemble makes its folder only for an input it can read and assemble.
    let mut cut = std::fs::read(d.join("m3.holo")).unwrap();
    cut.truncate(cut.len() - 200);
    std::fs::write(d.join("cut.holo"), cut).unwrap();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "m1.holo"], d));
    for input in ["missing.holo", "cut.holo", "m1.holo"] {
        let o = holo(&["assemble", input, "-o", "made"], d);
        assert_eq!(o.status.code(), Some(1), "{input}: {}", text(&o));
        assert!(!d.join("made").exists(), "assemble {input} left a folder");
        let o = holo(&["export-views", input, "-o", "views/of/it"], d);
        if input != "m1.holo" {
            assert_eq!(o.status.code(), Some(1), "{input}: {}", text(&o));
            assert!(!d.join("views").exists(), "export-views {input} left a folder");
        }
    }
}

/// Whether `path` is a FIFO (as `mkfifo` made it), not a regular file.
fn is_fifo(path: &Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_fifo())
}

fn mkfifo(path: &Path) {
    assert!(Command::new("mkfifo").arg(path).status().unwrap().success(), "mkfifo {}", path.display());
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn an_output_that_is_not_a_regular_file_is_refused_even_with_force() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "ramp.holo"], d));
    ok(holo(&["export-quilt", "ramp.holo", "-o", "ramp_qs8x4a1.png"], d));
    ok(holo(&["export-views", "ramp.holo", "-o", "views"], d));
    mkfifo(&d.join("n"));
    let spot = super::spot();
    let spot = spot.as_str();
    let commands: [&[&str]; 11] = [
        &["pattern", "--layout", "mark1", "--kind", "checkerboard", "-o", "n", "--force"],
        &["convert", "holoflick", "n.hflk", "--layout", "mark1", "-o", "n", "--force"],
        &["convert", "mesh", spot, "--layout", "mark1", "-o", "n", "--force"],
        &["convert", "cameras", "ramp_qs8x4a1.png", "--layout", "mark1", "-o", "n", "--force"],
        &[
            "convert",
            "cameras",
            "ramp_qs8x4a1.png",
            "--layout",
            "mark1",
            "-o",
            "c.holo",
            "--unseen-mask",
            "n",
            "--force",
        ],
        &["export-quilt", "ramp.holo", "-o", "n", "--force"],
        &["view", "ramp.holo", "--layout", "mark1", "-o", "n", "--force"],
        &["import-views", "views", "-o", "n", "--force"],
        &["holoflick", "encode", spot, "-o", "n", "--force"],
        &["holoflick", "pack", spot, "-o", "n", "--force"],
        &["holoflick", "unpack", "n.hflk", "-o", "n", "--force"],
    ];
    ok(holo(&["holoflick", "pack", spot, "-o", "n.hflk"], d));
    for args in commands {
        let o = super::holo_bounded(args, d, 120, 4096);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("n: is a FIFO, not a regular file"), "{args:?}: {}", text(&o));
        assert!(is_fifo(&d.join("n")), "{args:?} replaced the FIFO");
    }
    assert!(!d.join("c.holo").exists(), "the refusal came after the conversion");
    // A set whose folder holds a FIFO where one of its files goes.
    std::fs::remove_file(d.join("views/view_002.png")).unwrap();
    mkfifo(&d.join("views/view_002.png"));
    std::fs::create_dir(d.join("fringes")).unwrap();
    mkfifo(&d.join("fringes/frame0000-green.png"));
    for (args, fifo) in [
        (&["export-views", "ramp.holo", "-o", "views", "--force"][..], "views/view_002.png"),
        (&["assemble", "ramp.holo", "--layout", "mark1", "-o", "fringes", "--force"], "fringes/frame0000-green.png"),
    ] {
        let o = super::holo_bounded(args, d, 120, 4096);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("is a FIFO, not a regular file"), "{args:?}: {}", text(&o));
        assert!(is_fifo(&d.join(fifo)), "{args:?} replaced the FIFO");
    }
    // The set's own folder a FIFO.
    mkfifo(&d.join("m"));
    let o = super::holo_bounded(&["assemble", "ramp.holo", "--layout", "mark1", "-o", "m", "--force"], d, 120, 4096);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("m: is a FIFO, not a folder"), "{}", text(&o));
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn any_name_the_file_system_takes_is_written_and_a_longer_one_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 245 and 255 characters: legal names, whose hidden temporaries cannot
    // be the name with a suffix.
    for length in [245, 255] {
        let name = format!("{}.holo", "p".repeat(length - 5));
        ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", &name], d));
        assert!(d.join(&name).is_file());
        let picture = format!("{}.png", "v".repeat(length - 4));
        ok(holo(&["view", &name, "--layout", "mark1", "-o", &picture], d));
        let views = "w".repeat(length);
        ok(holo(&["export-views", &name, "-o", &views], d));
        ok(holo(&["import-views", &views, "-o", "back.holo", "--force"], d));
        std::fs::remove_file(d.join(&name)).unwrap();
    }
    assert_eq!(hidden(d), Vec::<String>::new());
    // 256: refused before any work, naming the name's length, not the folder.
    ok(holo(&["pattern", "--layout", "mark3", "--kind", "view-ramp", "-o", "m3.holo"], d));
    let long = format!("{}.png", "v".repeat(252));
    let started = Instant::now();
    let o = holo(&["view", "m3.holo", "-o", &long], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(started.elapsed() < Duration::from_millis(500), "refused after {:?}", started.elapsed());
    assert!(text(&o).contains("name is 256 bytes long") && text(&o).contains("255"), "{}", text(&o));
    let o = holo(&["export-views", "m3.holo", "-o", &"w".repeat(256)], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("name is 256 bytes long"), "{}", text(&o));
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn a_second_writer_of_an_output_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = small_profile(d, 2);
    let p = profile.to_str().unwrap();
    ok(holo(&["pattern", "--layout", p, "--kind", "colour-bars", "-o", "a.holo"], d));
    let frames = 12;
    noise_movie(&profile, &d.join("b.holo"), frames);
    // A set: the second run into the folder, with or without --force, is
    // refused at once naming the first, which finishes with a whole set.
    // The first is held still (SIGSTOP) from the moment its temporary is
    // there until the second has been refused, so it is mid-write however
    // fast it runs, and the test waits for no more work than it needs.
    let fringes = d.join("fringes");
    let mut first = spawn(&["assemble", "b.holo", "--layout", p, "-o", "fringes"], d);
    let pid = first.id().to_string();
    wait_for_hidden(&mut first, &fringes, ".partial");
    signal_child(&first, "STOP");
    for force in [false, true] {
        let mut args = vec!["assemble", "a.holo", "--layout", p, "-o", "fringes"];
        if force {
            args.push("--force");
        }
        let started = Instant::now();
        let o = holo(&args, d);
        assert_eq!(o.status.code(), Some(1), "{}", text(&o));
        assert!(started.elapsed() < Duration::from_secs(2), "refused after {:?}", started.elapsed());
        assert!(text(&o).contains("being written by another process") && text(&o).contains(&pid), "{}", text(&o));
    }
    signal_child(&first, "CONT");
    let out = first.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    let last = (frames - 1).to_string();
    ok(holo(&["check", "b.holo", "--fringes", "fringes", "--frame", &last], d));
    assert_eq!(hidden(&fringes), Vec::<String>::new());
    assert_eq!(hidden(d), Vec::<String>::new(), "the lock is gone with its writer");
    // A file: a second conversion into the same name is refused while the
    // first writes it.
    let glb = fixture("mesh/AnimatedMorphCube.glb");
    let glb = glb.to_str().unwrap();
    let mut first = spawn(&["convert", "mesh", glb, "--frames", "0..1", "-o", "out.holo"], d);
    let pid = first.id().to_string();
    wait_for_hidden(&mut first, d, ".partial");
    signal_child(&first, "STOP");
    let o = holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "out.holo", "--force"], d);
    signal_child(&first, "CONT");
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("being written by another process") && text(&o).contains(&pid), "{}", text(&o));
    let out = first.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(holo::HoloFile::open(d.join("out.holo")).unwrap().info().frames.len(), 1);
    assert_eq!(hidden(d), Vec::<String>::new());
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn temporaries_a_killed_run_left_are_removed_by_the_next_run_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let glb = fixture("mesh/AnimatedMorphCube.glb");
    let glb = glb.to_str().unwrap();
    ok(holo(&["pattern", "--layout", "mark3", "--kind", "view-ramp", "-o", "ramp.holo"], d));
    ok(holo(&["export-quilt", "ramp.holo", "-o", "ramp_qs8x6a0.75.png"], d));
    let mesh: &[&str] =
        &["convert", "mesh", glb, "--frames", "0..4", "--f32", "--compression", "none", "-o", "out.holo", "--force"];
    let cameras: &[&str] = &["convert", "cameras", "ramp_qs8x6a0.75.png", "-o", "out.holo", "--force"];
    for (args, mid_write) in [(mesh, ".partial"), (cameras, ".spool")] {
        let mut child = spawn(args, d);
        wait_for_hidden(&mut child, d, mid_write);
        let (status, _) = interrupt(child, "KILL");
        assert_eq!(status, None, "killed");
        // (Its lock stays too, but a lock no process holds is no obstacle.)
        let left: Vec<String> = hidden(d).into_iter().filter(|n| !n.ends_with(".lock")).collect();
        assert!(!left.is_empty(), "SIGKILL leaves its temporaries");
        // The next run to the same output removes them, and says which.
        let o = ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "out.holo", "--force"], d));
        for name in &left {
            assert!(text(&o).contains(name.as_str()) && text(&o).contains("removed"), "{name}: {}", text(&o));
        }
        assert_eq!(hidden(d), Vec::<String>::new());
    }
    // In a set's folder too.
    let profile = small_profile(d, 2);
    let p = profile.to_str().unwrap();
    noise_movie(&profile, &d.join("noise.holo"), 12);
    ok(holo(&["assemble", "noise.holo", "--layout", p, "-o", "fringes"], d));
    let mut child = spawn(&["assemble", "noise.holo", "--layout", p, "-o", "fringes", "--force", "--format", "raw"], d);
    wait_for_hidden(&mut child, &d.join("fringes"), ".partial");
    interrupt(child, "KILL");
    let left: Vec<String> = hidden(&d.join("fringes")).into_iter().filter(|n| !n.ends_with(".lock")).collect();
    assert!(!left.is_empty(), "SIGKILL leaves its temporaries");
    let o = ok(holo(&["assemble", "noise.holo", "--layout", p, "-o", "fringes", "--force"], d));
    assert!(text(&o).contains(left[0].as_str()) && text(&o).contains("removed"), "{}", text(&o));
    assert_eq!(hidden(&d.join("fringes")), Vec::<String>::new());
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn every_reader_of_a_set_says_its_replacement_was_interrupted_and_how_to_repair_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "ramp.holo"], d));
    ok(holo(&["assemble", "ramp.holo", "--layout", "mark1", "-o", "fringes"], d));
    ok(holo(&["export-views", "ramp.holo", "-o", "views"], d));
    // As a replacement interrupted between taking the old set apart and
    // putting the new manifest in place leaves them.
    for (folder, manifest) in [("fringes", "holo-fringes.json"), ("views", "holo-views.json")] {
        std::fs::write(d.join(folder).join(format!(".{manifest}.incomplete")), b"interrupted").unwrap();
        std::fs::remove_file(d.join(folder).join(manifest)).unwrap();
    }
    for args in [
        &["view", "fringes", "-o", "v.png"][..],
        &["check", "ramp.holo", "--fringes", "fringes"],
        &["import-views", "views", "-o", "back.holo"],
        &["import-views", "views", "--geometry", "mark1", "-o", "back.holo"],
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(
            text(&o).contains("replacement was interrupted") && text(&o).contains("with --force"),
            "{args:?}: {}",
            text(&o)
        );
    }
    // Repaired as it says.
    ok(holo(&["assemble", "ramp.holo", "--layout", "mark1", "-o", "fringes", "--force"], d));
    ok(holo(&["view", "fringes", "-o", "v.png"], d));
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn an_interrupted_demo_into_an_earlier_demos_folder_leaves_it_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // An earlier demo's folder (its marker, its files), with a file of yours.
    let folder = d.join("earlier");
    std::fs::create_dir_all(folder.join("spot")).unwrap();
    std::fs::create_dir_all(folder.join("movie")).unwrap();
    std::fs::write(folder.join(".holo-demo"), "Made by `holo demo`.\n").unwrap();
    for name in ["demo.holo", "demo_qs8x6a0.75.png", "fringe.png", "eyes.png", "eyes-moving.png", "movie/cube.holo"] {
        std::fs::write(folder.join(name), format!("the earlier demo's {name}")).unwrap();
    }
    std::fs::write(folder.join("notes.txt"), "my notes").unwrap();
    let before = snapshot(&folder);
    let mut child = spawn(&["demo", "-o", "earlier"], d);
    // Once the new demo.holo is complete (its temporary gone again), before the rest.
    let partial = |dir: &Path| -> bool {
        fn walk(dir: &Path, found: &mut bool) {
            for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                *found |= name.starts_with(".demo.holo.") && name.ends_with(".partial");
                if e.file_type().is_ok_and(|t| t.is_dir()) {
                    walk(&e.path(), found);
                }
            }
        }
        let mut found = false;
        walk(dir, &mut found);
        found
    };
    let started = Instant::now();
    while !partial(&folder) {
        assert!(child.try_wait().unwrap().is_none(), "the demo ended before writing demo.holo");
        assert!(started.elapsed() < Duration::from_secs(300));
        std::thread::sleep(Duration::from_millis(1));
    }
    while partial(&folder) {
        assert!(child.try_wait().unwrap().is_none(), "the demo ended while writing demo.holo");
        std::thread::sleep(Duration::from_millis(1));
    }
    let (status, messages) = interrupt(child, "INT");
    assert_eq!(status, Some(130), "{messages}");
    assert!(snapshot(&folder) == before, "the interrupted demo left a mix: {:?}", snapshot(&folder).keys());
    let mut all_hidden = hidden(&folder);
    all_hidden.retain(|n| n != ".holo-demo");
    assert_eq!(all_hidden, Vec::<String>::new());
}
