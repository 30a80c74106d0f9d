//! `holo farm` against a real Slurm cluster (`.ci/slurm.sh start`, then
//! `SLURM_CONF` from `.ci/slurm.sh env`): these tests are ignored by a plain
//! `cargo test` and run by CI with `--ignored` (`.ci/slurm.sh test`), where a
//! missing cluster fails them. The refusals before submission run
//! everywhere, against an `sbatch` that only records being called.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use super::{fixture, holo, ok, text};

/// A Mark III with 16 hololines, and the animated tube lying across it.
fn scene(d: &Path) {
    let o = ok(holo(&["layout", "mark3"], d));
    let profile = String::from_utf8(o.stdout).unwrap().replace("hololines = 440", "hololines = 16");
    std::fs::write(d.join("small.toml"), profile).unwrap();
    std::fs::copy(fixture("mesh/skinned_tube.glb"), d.join("tube.glb")).unwrap();
}

/// The conversion: 24 frames of the animation, heavy enough per frame
/// (4×4 sub-rays) that a task can be cancelled between its frames.
fn convert(output: &str) -> Vec<String> {
    "convert mesh tube.glb --layout small.toml --fps 24 --frames 0..24 --rotate 0,0,90 --supersample 4 -o"
        .split(' ')
        .map(String::from)
        .chain([output.to_string()])
        .collect()
}

/// The cluster, which these tests need: its commands on PATH and `sinfo` answering.
fn require_slurm() {
    let sinfo = Command::new("sinfo").arg("--noheader").output();
    assert!(
        sinfo.as_ref().is_ok_and(|o| o.status.success()),
        "no Slurm cluster answers (start one with .ci/slurm.sh start and export SLURM_CONF from .ci/slurm.sh env): {sinfo:?}"
    );
}

fn run(words: &[String], d: &Path) -> std::process::Output {
    let words: Vec<&str> = words.iter().map(String::as_str).collect();
    holo(&words, d)
}

/// Submit `command` in `d`; the job id (the last line printed).
fn submit(d: &Path, chunk: usize, command: &[String]) -> String {
    let mut words: Vec<String> =
        ["farm", "submit", "--chunk", &chunk.to_string(), "--sbatch", "--mem=300M --time=10"].map(String::from).into();
    words.push("--".into());
    words.extend(command.iter().cloned());
    let o = ok(run(&words, d));
    let out = String::from_utf8(o.stdout).unwrap();
    out.lines().last().unwrap().trim().to_string()
}

/// `holo farm status --json` of `output`.
fn status(d: &Path, output: &str) -> serde_json::Value {
    let o = ok(holo(&["farm", "status", output, "--json"], d));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// Wait until no task of the farm is queued or running.
fn settle(d: &Path, output: &str) -> serde_json::Value {
    let start = Instant::now();
    loop {
        let s = status(d, output);
        let active = s["frames"]
            .as_array()
            .unwrap()
            .iter()
            .any(|f| matches!(f["slurm"].as_str(), Some("PENDING" | "RUNNING" | "CONFIGURING" | "COMPLETING")));
        if !active {
            return s;
        }
        assert!(start.elapsed() < Duration::from_secs(300), "the farm did not finish in 5 minutes: {s}");
        std::thread::sleep(Duration::from_millis(200));
    }
}

/// Per frame: its state and digest.
fn states(s: &serde_json::Value) -> Vec<(String, Option<String>)> {
    s["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["state"].as_str().unwrap().to_string(), f["digest"].as_str().map(String::from)))
        .collect()
}

/// The frames' digests as `holo info --json` reads them.
fn digests(d: &Path, file: &str) -> Vec<String> {
    let o = ok(holo(&["info", file, "--json"], d));
    let info: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    info["files"][0]["frames"].as_array().unwrap().iter().map(|f| f["digest"].as_str().unwrap().to_string()).collect()
}

/// The frames of the newest submission in the farm's manifest.
fn last_submission(d: &Path, farm: &str) -> Vec<usize> {
    let text = std::fs::read_to_string(d.join(farm).join("manifest.json")).unwrap();
    let m: serde_json::Value = serde_json::from_str(&text).unwrap();
    let last = m["submissions"].as_array().unwrap().last().unwrap().clone();
    last["frames"].as_array().unwrap().iter().map(|v| v.as_u64().unwrap() as usize).collect()
}

fn modified(path: &Path) -> std::time::SystemTime {
    std::fs::metadata(path).unwrap().modified().unwrap()
}

#[test]
#[ignore = "needs a Slurm cluster: .ci/slurm.sh test"]
fn a_movie_split_across_the_cluster_is_the_movie_made_on_one_machine() {
    require_slurm();
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d);
    std::fs::create_dir(d.join("out")).unwrap();
    ok(run(&convert("one.holo"), d));
    let one = digests(d, "one.holo");
    assert_eq!(one.len(), 24);

    // Four tasks of six frames; task 1 cancelled once it has made a frame.
    let job = submit(d, 6, &convert("out/shot.holo"));
    let start = Instant::now();
    while !d.join("out/shot.0006.holo").exists() {
        assert!(start.elapsed() < Duration::from_secs(120), "task 1 never wrote its first frame");
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = Command::new("scancel").arg(format!("{job}_1")).output().unwrap();
    assert!(o.status.success(), "scancel: {o:?}");
    let s = settle(d, "out/shot.holo");
    let frames = s["frames"].as_array().unwrap();
    assert_eq!(frames[7]["slurm"], "CANCELLED", "{s}");
    let lost: Vec<usize> = (0..24).filter(|&n| frames[n]["state"] != "done").collect();
    assert!(!lost.is_empty() && lost.iter().all(|n| (6..12).contains(n)), "only task 1's frames are lost: {lost:?}");
    // Nothing half-written is left where a frame goes.
    for n in &lost {
        assert_eq!(frames[*n]["state"], "missing", "frame {n}: {s}");
    }

    // The same command again: only the lost frames run; the others are untouched.
    let kept: Vec<(usize, std::time::SystemTime)> = (0..24)
        .filter(|n| !lost.contains(n))
        .map(|n| (n, modified(&d.join(format!("out/shot.{n:04}.holo")))))
        .collect();
    submit(d, 6, &convert("out/shot.holo"));
    assert_eq!(last_submission(d, "out/shot.farm"), lost);
    let s = settle(d, "out/shot.holo");
    for (n, when) in &kept {
        assert_eq!(modified(&d.join(format!("out/shot.{n:04}.holo"))), *when, "frame {n} was made again");
    }
    let farm: Vec<(String, Option<String>)> = states(&s);
    let expected: Vec<(String, Option<String>)> = one.iter().map(|g| ("done".to_string(), Some(g.clone()))).collect();
    assert_eq!(farm, expected, "the farm's frames are the one machine's");

    // A frame damaged after the run is found and made again, alone.
    let three = d.join("out/shot.0003.holo");
    let mut bytes = std::fs::read(&three).unwrap();
    let at = bytes.len() - 40;
    bytes[at] ^= 0x55;
    std::fs::write(&three, bytes).unwrap();
    let s = status(d, "out/shot.holo");
    assert_eq!(s["frames"][3]["state"], "damaged", "{s}");
    assert_eq!(s["damaged"], 1, "{s}");
    let said = text(&ok(holo(&["farm", "status", "out/shot.holo"], d)));
    assert!(said.contains("frame 3: damaged"), "{said}");
    let o = holo(&["farm", "gather", "out/shot.holo"], d);
    assert_eq!(o.status.code(), Some(1), "gather refuses a damaged sequence: {}", text(&o));
    submit(d, 6, &convert("out/shot.holo"));
    assert_eq!(last_submission(d, "out/shot.farm"), [3]);
    let s = settle(d, "out/shot.holo");
    assert_eq!(states(&s), expected);

    // Nothing to do: nothing is submitted.
    let o = ok(run(&[&["farm".to_string(), "submit".into(), "--".into()][..], &convert("out/shot.holo")].concat(), d));
    assert!(text(&o).contains("nothing submitted"), "{}", text(&o));

    // Gathered and joined: one file with the one machine's digests.
    ok(holo(&["farm", "gather", "out/shot.holo", "--join", "joined.holo"], d));
    assert_eq!(digests(d, "joined.holo"), one);

    // The sequence assembled across the cluster: the one machine's fringes, byte for byte.
    ok(holo(&["assemble", "out/shot.holo", "--layout", "small.toml", "-o", "single"], d));
    let assemble: Vec<String> =
        "assemble out/shot.holo --layout small.toml -o fringes".split(' ').map(String::from).collect();
    submit(d, 8, &assemble);
    let s = settle(d, "fringes");
    assert_eq!(s["done"], 24, "{s}");
    ok(holo(&["farm", "gather", "fringes", "--join", "joined-fringes"], d));
    let listing = |folder: &str| -> Vec<(String, Vec<u8>)> {
        let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(d.join(folder))
            .unwrap()
            .map(|e| e.unwrap().path())
            .map(|p: PathBuf| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
            .collect();
        files.sort();
        files
    };
    let single = listing("single");
    assert_eq!(single.len(), 24 * 2 + 1, "two heads a frame and the sidecar");
    assert!(single == listing("joined-fringes"), "the cluster's fringes differ from one machine's");
    let per_frame = listing("fringes/0013");
    assert!(per_frame.iter().filter(|(n, _)| n.starts_with("frame0013")).all(|f| single.contains(f)));
}

/// A folder holding an `sbatch` that records being called, and the record.
fn recording_sbatch(d: &Path) -> (PathBuf, PathBuf) {
    let bin = d.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let record = d.join("sbatch-was-called");
    let script = bin.join("sbatch");
    std::fs::write(&script, format!("#!/bin/sh\ntouch '{}'\necho 1\n", record.display())).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    (bin, record)
}

#[test]
fn a_bad_submission_fails_in_one_sentence_before_anything_is_submitted() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    scene(d);
    let (bin, record) = recording_sbatch(d);
    let empty = d.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let with_path = |words: &[&str], path: &Path| {
        Command::new(env!("CARGO_BIN_EXE_holo")).args(words).current_dir(d).env("PATH", path).output().unwrap()
    };
    let base = ["farm", "submit", "--", "convert", "mesh", "tube.glb", "--fps", "24"];
    let cases: [(&[&str], &Path, &str); 6] = [
        (&["--layout", "mark9", "-o", "shot.holo"], &bin, "unknown layout"),
        (&["--layout", "small.toml", "--frames", "5..5", "-o", "shot.holo"], &bin, "--frames must be"),
        (&["--layout", "small.toml", "--frames", "20..40", "-o", "shot.holo"], &bin, "frames 20..40"),
        (&["--layout", "small.toml", "-o", "shot.holo"], &empty, "sbatch is not on PATH"),
        (&["--layout", "small.toml", "-o", "nowhere/shot.holo"], &bin, "does not exist"),
        (&["--layout", "small.toml", "-o", "shot.holo", "--supersample", "0"], &bin, "--supersample"),
    ];
    for (tail, path, expected) in cases {
        let words: Vec<&str> = base.iter().chain(tail).copied().collect();
        let o = with_path(&words, path);
        let said = String::from_utf8_lossy(&o.stderr).into_owned();
        assert_eq!(o.status.code(), Some(1), "{words:?}: {said}");
        assert!(said.contains(expected), "{words:?}: {said}");
        assert_eq!(said.trim().lines().count(), 1, "one sentence: {said}");
        assert!(!record.exists(), "{words:?} reached sbatch");
        assert!(!d.join("shot.farm").exists() && !d.join("nowhere").exists(), "{words:?} left a farm behind");
    }
    // Not a command that makes frames.
    let o = with_path(&["farm", "submit", "--", "info", "x.holo"], &bin);
    assert!(text(&o).contains("holo farm splits"), "{}", text(&o));
    // An sbatch that refuses: the farm it was to start is not left behind.
    std::fs::write(
        bin.join("sbatch"),
        "#!/bin/sh\necho 'sbatch: error: invalid partition specified: nope' >&2\nexit 1\n",
    )
    .unwrap();
    let words: Vec<&str> =
        base.iter().chain(&["--layout", "small.toml", "--frames", "0..2", "-o", "shot.holo"]).copied().collect();
    let o = with_path(&words, &bin);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("sbatch refused the job: invalid partition specified: nope"), "{}", text(&o));
    assert!(!d.join("shot.farm").exists(), "the refused farm's state was left behind");
    // A damaged manifest is said as it is, and left as it is.
    std::fs::create_dir(d.join("shot.farm")).unwrap();
    std::fs::write(d.join("shot.farm/manifest.json"), "{").unwrap();
    let o = with_path(&words, &bin);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("manifest.json: not a holo farm manifest"), "{}", text(&o));
    assert_eq!(std::fs::read_to_string(d.join("shot.farm/manifest.json")).unwrap(), "{");
}
