//! `holo::output`: atomic files, sets with manifests, the checks before any
//! work, and the interrupt cleanup, in the library. Tests that need a
//! process of their own (a file-size limit, a signal, the registry marked
//! interrupted) run this binary again as a child, with `HOLO_OUTPUT_CHILD`
//! naming their folder.

use std::borrow::Cow;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

use holo::assemble::output::{assemble_file, read_sidecar, AssembleOptions, FringeFormat, FRINGE_SIDECAR};
use holo::geometry::{mono_channel, Geometry, Views};
use holo::output::{
    check_output, check_set_complete, check_set_output, verify_set, AtomicFile, FileSet, SetFile, Spool,
};
use holo::{Error, Modulation, OutputProblem, SetProblem};

/// Names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    n.sort();
    n
}

/// The folder a child run works in, when this process is one.
fn child_folder() -> Option<PathBuf> {
    std::env::var_os("HOLO_OUTPUT_CHILD").map(PathBuf::from)
}

/// The full name of test `name` of this module as the test harness knows it
/// (`output::NAME`: the path below the test binary's root), so that `--exact`
/// runs it, and only it, in the child.
fn test_path(name: &str) -> String {
    let module = module_path!().split_once("::").map_or("", |(_, below_root)| below_root);
    format!("{module}::{name}")
}

/// This binary running test `name` alone in a child, after the shell lines `prelude`.
fn child(name: &str, folder: &Path, prelude: &str) -> Command {
    let mut c = Command::new("sh");
    c.args(["-c", &format!("{prelude} exec \"$@\""), "sh"])
        .arg(std::env::current_exe().unwrap())
        .args([&test_path(name), "--exact", "--nocapture", "--test-threads=1"])
        .env("HOLO_OUTPUT_CHILD", folder);
    c
}

fn is_output(e: &Error, expected: &OutputProblem) -> bool {
    matches!(e, Error::Output { problem, .. } if problem == expected)
}

#[test]
fn an_atomic_file_is_whole_at_its_destination_or_absent() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("a.bin");
    // Dropped without a commit: nothing is left.
    let mut file = AtomicFile::create(&path).unwrap();
    file.write_all(b"half").unwrap();
    let temp = file.temporary_path().file_name().unwrap().to_string_lossy().into_owned();
    assert!(temp.starts_with(".a.bin.") && temp.ends_with(".partial"), "{temp}");
    // Beside it, while it is written, the lock that keeps other writers out.
    assert_eq!(names(dir.path()), vec![temp, ".a.bin.lock".to_string()]);
    drop(file);
    assert!(names(dir.path()).is_empty());

    let mut file = AtomicFile::create(&path).unwrap();
    file.write_all(b"first").unwrap();
    assert_eq!(file.commit(false).unwrap(), 5);
    assert_eq!(std::fs::read(&path).unwrap(), b"first");
    // Not replaced unless asked; the temporary goes either way.
    let mut file = AtomicFile::create(&path).unwrap();
    file.write_all(b"second").unwrap();
    let e = file.commit(false).unwrap_err();
    assert!(is_output(&e, &OutputProblem::Exists) && e.to_string().contains("a.bin"), "{e}");
    assert_eq!(std::fs::read(&path).unwrap(), b"first");
    assert_eq!(names(dir.path()), vec!["a.bin"]);
    let mut file = AtomicFile::create(&path).unwrap();
    file.write_all(b"second").unwrap();
    file.commit(true).unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"second");
    holo::format::write_bytes_beside(&dir.path().join("b.bin"), b"whole", false).unwrap();
    assert!(holo::format::write_bytes_beside(&dir.path().join("b.bin"), b"other", false).is_err());
    assert_eq!(std::fs::read(dir.path().join("b.bin")).unwrap(), b"whole");

    let spool = Spool::create(&path).unwrap();
    let name = spool.path().file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with(".a.bin.") && name.ends_with(".spool"), "{name}");
    drop(spool);
    assert_eq!(names(dir.path()), vec!["a.bin", "b.bin"]);
}

#[test]
fn outputs_are_checked_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let input = d.join("in.holo");
    std::fs::write(&input, b"input").unwrap();
    std::fs::hard_link(&input, d.join("hard.holo")).unwrap();
    std::os::unix::fs::symlink(&input, d.join("soft.holo")).unwrap();
    let inputs = [input.as_path()];
    drop(check_output(&d.join("new.holo"), &inputs, false).unwrap());
    for same in ["in.holo", "hard.holo", "soft.holo"] {
        for overwrite in [false, true] {
            let e = check_output(&d.join(same), &inputs, overwrite).unwrap_err();
            assert!(is_output(&e, &OutputProblem::IsAnInput(input.clone())), "{same}: {e}");
        }
    }
    let relative = d.join(".").join("in.holo");
    assert!(check_output(&relative, &inputs, true).is_err());
    std::fs::write(d.join("taken.png"), b"mine").unwrap();
    let e = check_output(&d.join("taken.png"), &inputs, false).unwrap_err();
    assert!(is_output(&e, &OutputProblem::Exists), "{e}");
    drop(check_output(&d.join("taken.png"), &inputs, true).unwrap());
    let e = check_output(&d.join("no/folder/x.holo"), &inputs, true).unwrap_err();
    assert!(is_output(&e, &OutputProblem::FolderMissing(d.join("no/folder"))), "{e}");
    assert!(e.to_string().contains("does not exist"), "{e}");
    assert!(check_output(d, &inputs, true).is_err(), "a folder is no output file");

    // Sets: a folder holding a manifest is a set; a file of the set may not be an input.
    let set_names = vec!["v0.png".to_string(), "v1.png".to_string()];
    drop(check_set_output(&d.join("views"), "m.json", &set_names, &inputs, false).unwrap());
    std::fs::create_dir(d.join("views")).unwrap();
    std::fs::write(d.join("views/m.json"), b"{}").unwrap();
    let e = check_set_output(&d.join("views"), "m.json", &set_names, &inputs, false).unwrap_err();
    assert!(is_output(&e, &OutputProblem::SetExists("m.json".into())), "{e}");
    drop(check_set_output(&d.join("views"), "m.json", &set_names, &inputs, true).unwrap());
    let e = check_set_output(d, "m.json", &["in.holo".to_string()], &inputs, true).unwrap_err();
    assert!(is_output(&e, &OutputProblem::IsAnInput(input.clone())), "{e}");
    assert!(check_set_output(&input, "m.json", &set_names, &[], true).is_err(), "a file is no folder");
}

/// A set of `files` (name, bytes) committed into `folder` with a manifest
/// that is just the list.
fn commit_set(folder: &Path, files: &[(&str, &[u8])], overwrite: bool) -> holo::Result<Vec<SetFile>> {
    let mut set = FileSet::create(folder, "set.json")?;
    for (name, bytes) in files {
        set.add_bytes(name, bytes)?;
    }
    let listed = set.files();
    set.commit(overwrite, |files| Ok(serde_json::to_vec(&serde_json::json!({ "files": files })).unwrap()))?;
    Ok(listed)
}

fn listed(folder: &Path) -> Vec<SetFile> {
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(folder.join("set.json")).unwrap()).unwrap();
    serde_json::from_value(v["files"].clone()).unwrap()
}

#[test]
fn a_set_is_replaced_whole_and_refused_when_it_disagrees() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("set");
    let first = commit_set(&folder, &[("a.bin", b"aaaa"), ("b.bin", b"bb")], false).unwrap();
    assert_eq!(names(&folder), vec!["a.bin", "b.bin", "set.json"]);
    assert_eq!(listed(&folder), first);
    assert_eq!(first[0].bytes, 4);
    // SHA-256 of "aaaa".
    assert_eq!(first[0].sha256, "61be55a8e2f6b4e172338bddf184d6dbee29c98853e0a0485ecee7f27b9af0b4");
    verify_set(&folder, "set.json", &first, "write it again").unwrap();

    // Not replaced unless asked.
    std::fs::write(folder.join("notes.txt"), b"the user's").unwrap();
    let e = commit_set(&folder, &[("c.bin", b"c")], false).unwrap_err();
    assert!(is_output(&e, &OutputProblem::SetExists("set.json".into())), "{e}");
    assert_eq!(names(&folder), vec!["a.bin", "b.bin", "notes.txt", "set.json"]);
    // Replaced whole: a.bin (of the old set only) goes, the user's file stays.
    let second = commit_set(&folder, &[("b.bin", b"BB"), ("c.bin", b"c")], true).unwrap();
    assert_eq!(names(&folder), vec!["b.bin", "c.bin", "notes.txt", "set.json"]);
    assert_eq!(listed(&folder), second);
    assert_eq!(std::fs::read(folder.join("b.bin")).unwrap(), b"BB");

    // Disagreements are named.
    let refused = |problem: fn(&SetProblem) -> bool, file: &str| {
        let e = verify_set(&folder, "set.json", &second, "write it again").unwrap_err();
        assert!(matches!(&e, Error::Set { path, problem: p } if problem(p) && path.ends_with(file)), "{e}");
    };
    std::fs::write(folder.join("c.bin"), b"C").unwrap();
    refused(|p| matches!(p, SetProblem::Digest(_)), "c.bin");
    std::fs::write(folder.join("c.bin"), b"cc").unwrap();
    refused(|p| matches!(p, SetProblem::Size { listed: 1, found: 2, .. }), "c.bin");
    std::fs::remove_file(folder.join("c.bin")).unwrap();
    refused(|p| matches!(p, SetProblem::Missing(_)), "c.bin");
    let e = verify_set(&folder, "set.json", &[], "write it again").unwrap_err();
    assert!(e.to_string().contains("write it again"), "{e}");
    let bad = [SetFile { name: "../x".into(), bytes: 0, sha256: String::new() }];
    assert!(matches!(
        verify_set(&folder, "set.json", &bad, "again"),
        Err(Error::Set { problem: SetProblem::BadName(_), .. })
    ));

    // A set that fails while being written leaves nothing, not even the
    // folder it made, nor the parents it made for it.
    let fresh = dir.path().join("made/for/fresh");
    let mut set = FileSet::create(&fresh, "set.json").unwrap();
    set.add_bytes("x.bin", b"x").unwrap();
    let e = set.add("y.bin", |out| {
        out.write_all(b"half of y").unwrap();
        Err(Error::Io { path: out.destination().to_path_buf(), source: std::io::Error::other("the disk is full") })
    });
    assert!(e.is_err());
    assert!(fresh.exists());
    drop(set);
    assert!(!dir.path().join("made").exists());
    assert!(dir.path().is_dir());
}

#[test]
fn a_set_may_hold_more_files_than_a_process_may_keep_open() {
    // A folder of hogels is tens of thousands of files; the set keeps none
    // of them open while it waits to put them in place.
    let count = 300;
    let contents = |i: usize| format!("file {i}").into_bytes();
    if let Some(folder) = child_folder() {
        // Under a limit of 64 open files.
        let bytes: Vec<(String, Vec<u8>)> = (0..count).map(|i| (format!("f{i:03}.bin"), contents(i))).collect();
        let files: Vec<(&str, &[u8])> = bytes.iter().map(|(n, b)| (n.as_str(), b.as_slice())).collect();
        commit_set(&folder.join("set"), &files, false).unwrap();
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out =
        child("a_set_may_hold_more_files_than_a_process_may_keep_open", dir.path(), "ulimit -n 64;").output().unwrap();
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && said.contains("1 passed"), "the child must pass: {said}");
    let folder = dir.path().join("set");
    let files = listed(&folder);
    assert_eq!(files.len(), count);
    verify_set(&folder, "set.json", &files, "write it again").unwrap();
    assert_eq!(std::fs::read(folder.join("f299.bin")).unwrap(), contents(299));
}

#[test]
fn a_set_whose_replacement_stops_midway_is_refused_by_every_reader() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("views");
    let manifest = holo::views::SIDECAR;
    let old = [("view_000.png", &b"old 0"[..]), ("view_001.png", b"old 1"), ("view_002.png", b"old 2")];
    let mut set = FileSet::create(&folder, manifest).unwrap();
    for (name, bytes) in old {
        set.add_bytes(name, bytes).unwrap();
    }
    set.commit(false, |files| Ok(serde_json::to_vec(&serde_json::json!({ "files": files })).unwrap())).unwrap();
    check_set_complete(&folder, manifest, "again").unwrap();

    // The replacement stops after view 0 is renamed: view 2 cannot be (a
    // folder now stands at its name), as if the power had gone.
    let mut set = FileSet::create(&folder, manifest).unwrap();
    for name in ["view_000.png", "view_001.png", "view_002.png"] {
        set.add_bytes(name, b"new").unwrap();
    }
    std::fs::remove_file(folder.join("view_002.png")).unwrap();
    std::fs::create_dir(folder.join("view_002.png")).unwrap();
    set.commit(true, |files| Ok(serde_json::to_vec(&serde_json::json!({ "files": files })).unwrap())).unwrap_err();
    assert_eq!(std::fs::read(folder.join("view_000.png")).unwrap(), b"new");
    assert!(!folder.join(manifest).exists(), "the old manifest went first");

    // Files of two sets and no manifest: every reader refuses, even one
    // told the geometry and reading pictures without a sidecar.
    let interrupted = |e: Error| matches!(e, Error::Set { problem: SetProblem::Interrupted { .. }, .. });
    assert!(interrupted(check_set_complete(&folder, manifest, "again").unwrap_err()));
    let new_view_0 = SetFile { name: "view_000.png".into(), bytes: 3, sha256: String::new() };
    assert!(interrupted(verify_set(&folder, manifest, &[new_view_0], "again").unwrap_err()));
    let g = Geometry::centred(2, 2, Views::tan_spaced(3, -0.2, 0.2), 1.3e-4, 2.4e-4, 0.027, 0.6, mono_channel());
    let e = holo::views::import_views(&folder, &g, &Default::default()).unwrap_err();
    assert!(e.to_string().contains("interrupted") && e.to_string().contains("export the views again"), "{e}");

    // A complete replacement clears it.
    std::fs::remove_dir(folder.join("view_002.png")).unwrap();
    let mut set = FileSet::create(&folder, manifest).unwrap();
    set.add_bytes("view_000.png", b"newer").unwrap();
    set.commit(true, |files| Ok(serde_json::to_vec(&serde_json::json!({ "files": files })).unwrap())).unwrap();
    check_set_complete(&folder, manifest, "again").unwrap();
    let mut expected = vec!["view_000.png", "view_001.png", manifest];
    expected.sort();
    assert_eq!(names(&folder), expected);
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fringe_readers_refuse_a_mixed_or_unlisted_set() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut layout = holo::layout::mark3();
    layout.geometry.hololines = 2;
    let write = |name: &str, level: f32| {
        let m = Modulation::from_fn(layout.geometry.clone(), |_, j, e, v| level * ((j + e + v) % 3) as f32).unwrap();
        holo::write(d.join(name), &m, &holo::WriteOptions::default()).unwrap();
    };
    write("a.holo", 0.3);
    write("b.holo", 0.6);
    let options = AssembleOptions { frames: None, format: FringeFormat::Png, overwrite: false, resample: false };
    for (input, out) in [("a.holo", "fa"), ("b.holo", "fb")] {
        let report = assemble_file(&d.join(input), &layout, &d.join(out), &options, &holo::progress::Silent).unwrap();
        assert!(report.files.last().unwrap().ends_with(FRINGE_SIDECAR));
    }
    let sidecar = read_sidecar(&d.join("fa")).unwrap();
    assert_eq!(sidecar.files.len(), 2);
    assert!(sidecar.files.iter().all(|f| f.sha256.len() == 64 && f.bytes > 0));

    // One image from the other file's set.
    let image = "frame0000-head2.png";
    std::fs::copy(d.join("fb").join(image), d.join("fa").join(image)).unwrap();
    let e = read_sidecar(&d.join("fa")).unwrap_err();
    assert!(matches!(&e, Error::Set { path, .. } if path.ends_with(image)), "{e}");
    // A sidecar of an older holo lists no digests: refused, saying what to do.
    let mut old: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("fb").join(FRINGE_SIDECAR)).unwrap()).unwrap();
    old.as_object_mut().unwrap().remove("files");
    std::fs::write(d.join("fb").join(FRINGE_SIDECAR), serde_json::to_vec(&old).unwrap()).unwrap();
    let e = read_sidecar(&d.join("fb")).unwrap_err();
    assert!(e.to_string().contains("assemble the fringes again"), "{e}");
    // Re-assembling with overwrite replaces it, old names and all.
    let again = AssembleOptions { overwrite: true, ..options.clone() };
    assemble_file(&d.join("b.holo"), &layout, &d.join("fb"), &again, &holo::progress::Silent).unwrap();
    read_sidecar(&d.join("fb")).unwrap();
    // An unreadable input leaves no folder.
    std::fs::write(d.join("bad.holo"), b"not a file").unwrap();
    assert!(assemble_file(&d.join("bad.holo"), &layout, &d.join("fc"), &options, &holo::progress::Silent).is_err());
    assert!(!d.join("fc").exists());
}

/// A file of 16 views whose view 5 is noise (its PNG some kilobytes) and
/// whose others are flat (a few hundred bytes each).
fn one_noisy_view() -> Modulation {
    let g = Geometry::centred(32, 64, Views::tan_spaced(16, -0.2, 0.2), 1.3e-4, 2.4e-4, 0.027, 0.6, mono_channel());
    Modulation::from_fn(g, |_, j, e, v| {
        if v == 5 {
            let k = ((j * 64 + e) as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            ((k >> 40) % 1000) as f32 / 1000.0
        } else {
            0.5
        }
    })
    .unwrap()
}

#[test]
fn export_views_whose_writes_fail_midway_leave_no_file() {
    let tone = holo::views::ToneMapping { white: 1.0, bits: 16 };
    if let Some(folder) = child_folder() {
        // Under a 2 KiB file-size limit: view 5 cannot be written.
        let e = holo::views::export_views(&one_noisy_view(), &folder.join("views"), &tone, true).unwrap_err();
        assert!(e.to_string().contains("view_005.png"), "{e}");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let previous = dir.path().join("views");
    std::fs::create_dir(&previous).unwrap();
    std::fs::write(previous.join("view_000.png"), b"the user's").unwrap();
    let out = child("export_views_whose_writes_fail_midway_leave_no_file", dir.path(), "trap '' XFSZ; ulimit -f 4;")
        .output()
        .unwrap();
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && said.contains("1 passed"), "the child must run the test: {said}");
    assert_eq!(names(&previous), vec!["view_000.png"], "{said}");
    assert_eq!(std::fs::read(previous.join("view_000.png")).unwrap(), b"the user's");

    // Without the limit the same export is one whole set.
    let written = holo::views::export_views(&one_noisy_view(), &previous, &tone, true).unwrap();
    assert_eq!(written.len(), 17);
    let sidecar = holo::views::read_sidecar(&previous.join(holo::views::SIDECAR)).unwrap();
    verify_set(&previous, holo::views::SIDECAR, &sidecar.files, "export again").unwrap();
    let g = one_noisy_view().geometry().clone();
    holo::views::import_views(&previous, &g, &tone).unwrap();
    std::fs::copy(previous.join("view_005.png"), previous.join("view_002.png")).unwrap();
    let Err(e) = holo::views::import_views(&previous, &g, &tone) else { panic!("a mixed set was imported") };
    assert!(e.to_string().contains("view_002.png"), "{e}");
}

#[test]
fn removing_the_temporaries_stops_every_rename() {
    if let Some(folder) = child_folder() {
        let path = folder.join("out.bin");
        let mut file = AtomicFile::create(&path).unwrap();
        file.write_all(b"never in place").unwrap();
        let spool = Spool::create(&path).unwrap();
        assert_eq!(holo::output::remove_temporaries(), 2);
        assert!(!file.temporary_path().exists() && !spool.path().exists());
        let e = file.commit(true).unwrap_err();
        assert!(is_output(&e, &OutputProblem::Interrupted), "{e}");
        assert!(AtomicFile::create(&path).is_err());
        assert!(!path.exists());
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let out = child("removing_the_temporaries_stops_every_rename", dir.path(), "").output().unwrap();
    let said = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success() && said.contains("1 passed"), "the child must run the test: {said}");
    assert!(names(dir.path()).is_empty());
}

#[test]
fn a_signal_during_commits_leaves_only_whole_files() {
    const BYTES: usize = 1 << 16;
    if let Some(folder) = child_folder() {
        holo::output::install_interrupt_cleanup().unwrap();
        std::fs::write(folder.join("started"), b"").unwrap();
        // Commit whole files as fast as possible until the signal ends the process.
        for i in 0.. {
            let mut file = AtomicFile::create(folder.join(format!("f{i:06}.bin"))).unwrap();
            for _ in 0..BYTES / 8 {
                file.write_all(&(i as u64).to_le_bytes()).unwrap();
            }
            file.commit(false).unwrap();
        }
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    for (signal, code) in [("TERM", 143), ("INT", 130), ("HUP", 129)] {
        let folder = dir.path().join(signal);
        std::fs::create_dir(&folder).unwrap();
        let mut running = child("a_signal_during_commits_leaves_only_whole_files", &folder, "").spawn().unwrap();
        while !folder.join("started").exists() || names(&folder).len() < 20 {
            assert!(running.try_wait().unwrap().is_none(), "the child ended early");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        let pid = running.id().to_string();
        assert!(Command::new("kill").args([&format!("-{signal}"), &pid]).status().unwrap().success());
        assert_eq!(running.wait().unwrap().code(), Some(code));
        for name in names(&folder).iter().filter(|n| *n != "started") {
            assert!(!name.starts_with('.'), "{name} left behind");
            assert_eq!(std::fs::metadata(folder.join(name)).unwrap().len() as usize, BYTES, "{name} not whole");
        }
    }
}

#[test]
fn a_banded_write_leaves_no_spool_and_keeps_an_existing_file() {
    let dir = tempfile::tempdir().unwrap();
    let g = Geometry::centred(20, 6, Views::tan_spaced(3, -0.2, 0.2), 1.3e-4, 2.4e-4, 0.027, 0.6, mono_channel());
    let path = dir.path().join("kept.holo");
    std::fs::write(&path, b"mine").unwrap();
    let e = holo::format::write_frame_in_bands(&path, &g, 4, &holo::WriteOptions::default(), |_| Ok(())).unwrap_err();
    assert!(is_output(&e, &OutputProblem::Exists), "{e}");
    let options = holo::WriteOptions { overwrite: true, ..Default::default() };
    let failed = holo::format::write_frame_in_bands(&path, &g, 4, &options, |band| {
        if band.hololines().start >= 8 {
            return Err(Error::Argument { what: "source", problem: "the source failed".into() });
        }
        Ok(())
    });
    assert!(failed.is_err());
    assert_eq!(std::fs::read(&path).unwrap(), b"mine");
    assert_eq!(names(dir.path()), vec!["kept.holo"]);
    let frames = [Modulation::zeros(g.clone()).unwrap()];
    holo::format::write_frames(&path, &g, 1, &options, |i| Ok(Cow::Borrowed(&frames[i]))).unwrap();
    assert_eq!(names(dir.path()), vec!["kept.holo"]);
}

/// What is not a regular file (a FIFO here; a device the same) is never
/// replaced, whether the check before the work or only the final rename
/// meets it; a name the file system takes is written whatever its length
/// (its temporary's own name kept within the limit), and one it cannot
/// take is refused before any work, saying so.
#[test]
fn outputs_that_are_not_regular_files_or_too_long_a_name_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let fifo = d.join("n");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let is_fifo = || {
        use std::os::unix::fs::FileTypeExt;
        std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo()
    };
    for overwrite in [false, true] {
        let e = check_output(&fifo, &[], overwrite).unwrap_err();
        assert!(e.to_string().ends_with("n: is a FIFO, not a regular file"), "{e}");
        let mut file = AtomicFile::create(&fifo).unwrap();
        file.write_all(b"bytes").unwrap();
        let e = file.commit(overwrite).unwrap_err();
        assert!(e.to_string().contains("is a FIFO, not a regular file") || !overwrite, "{e}");
        let e = holo::format::write_bytes_beside(&fifo, b"bytes", overwrite).unwrap_err();
        assert!(e.to_string().contains("n: ") && is_fifo(), "{e}");
    }
    assert_eq!(names(d), vec!["n"]);
    let e = check_set_output(d, "m.json", &["n".to_string()], &[], true).unwrap_err();
    assert!(e.to_string().contains("is a FIFO, not a regular file"), "{e}");

    for length in [200, 245, 255] {
        let path = d.join("a".repeat(length));
        drop(check_output(&path, &[], false).unwrap());
        let mut file = AtomicFile::create(&path).unwrap();
        let temp = file.temporary_path().file_name().unwrap().len();
        assert!(temp <= 255, "a temporary's name of {temp} bytes");
        let spool = Spool::create(&path).unwrap();
        assert!(spool.path().file_name().unwrap().len() <= 255);
        file.write_all(b"whole").unwrap();
        file.commit(false).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"whole");
    }
    let e = check_output(&d.join("a".repeat(256)), &[], false).unwrap_err();
    assert!(e.to_string().contains("name is 256 bytes long; the file system takes at most 255"), "{e}");
}
