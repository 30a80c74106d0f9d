//! Each command as a user meets it: exit codes (0 ok, 1 error, 2 usage),
//! one-sentence errors naming the file, `--help` everywhere, nothing overwritten.

use std::path::Path;

use holo::picture::{decode, Bits};

use super::{holo, ok, small_profile, spot, text};

/// A Mark I view ramp written as `name` in `d`.
fn mark1_ramp(d: &Path, name: &str) {
    let o = holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", name], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}

#[test]
fn help_on_every_command_and_usage_errors_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for cmd in [
        &["--help"][..],
        &["info", "--help"],
        &["validate", "--help"],
        &["pattern", "--help"],
        &["export-views", "--help"],
        &["import-views", "--help"],
        &["export-hogels", "--help"],
        &["import-hogels", "--help"],
        &["export-hci", "--help"],
        &["demo", "--help"],
        &["assemble", "--help"],
        &["layout", "--help"],
        &["check", "--help"],
        &["view", "--help"],
        &["export-quilt", "--help"],
        &["holoflick", "pack", "--help"],
        &["holoflick", "encode", "--help"],
        &["convert", "holoflick", "--help"],
        &["convert", "mesh", "--help"],
        &["convert", "cameras", "--help"],
        &["holoflick", "unpack", "--help"],
        &["holoflick", "info", "--help"],
    ] {
        let o = holo(cmd, dir.path());
        assert_eq!(o.status.code(), Some(0), "{cmd:?}: {}", text(&o));
        assert!(text(&o).contains("Usage"), "{cmd:?}");
    }
    for cmd in [
        &["frobnicate"][..],
        &["info"],
        &["pattern", "--kind", "nonsense", "-o", "x.holo"],
        &["pattern", "--kind", "view-ramp"],
        &["export-views", "a.holo", "--out", "d", "--bits", "12"],
        &["assemble", "a.holo", "-o", "d", "--format", "jpeg"],
        &["assemble", "a.holo", "-o", "d", "--frames", "3..1"],
        &["view", "a.holo", "-o", "v.png", "--eye", "left"],
        &["check", "a.holo", "--hololines", "5..2"],
        &["export-quilt", "a.holo", "--preset", "hologram"],
        &["export-quilt", "a.holo", "--tile", "64"],
        &["export-quilt", "a.holo", "-o", "q.png", "--output-dir", "d"],
        &["export-quilt", "a.holo", "--columns", "0"],
        &["export-quilt", "a.holo", "--aspect=-1"],
        &["convert", "mesh", "a.obj", "-o", "a.holo", "--supersample", "0x2"],
        &["convert", "cameras", "a", "-o", "a.holo", "--blend", "cubic"],
    ] {
        let o = holo(cmd, dir.path());
        assert_eq!(o.status.code(), Some(2), "{cmd:?}: {}", text(&o));
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn every_pattern_for_both_layouts_is_valid_and_described() {
    let dir = tempfile::tempdir().unwrap();
    for layout in ["mark3", "mark1"] {
        for kind in ["single-emitter", "single-view", "every-nth-emitter", "view-ramp", "colour-bars", "checkerboard"] {
            let file = format!("{layout}-{kind}.holo");
            let o = holo(&["pattern", "--layout", layout, "--kind", kind, "-o", &file], dir.path());
            assert_eq!(o.status.code(), Some(0), "{}", text(&o));
            let o = holo(&["validate", &file], dir.path());
            assert_eq!(o.status.code(), Some(0), "{}", text(&o));
            let o = holo(&["info", "--json", &file], dir.path());
            let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
            let g = &json["files"][0]["geometry"];
            let expected = holo::layout::builtin(layout).unwrap().geometry;
            assert_eq!(g["hololines"], expected.hololines);
            assert_eq!(g["emitters"], expected.emitters);
            assert_eq!(g["views"]["count"], expected.views.count);
            assert!(json["files"][0]["source"].as_str().unwrap().contains(kind));
        }
    }
}

#[test]
fn errors_name_the_file_exit_1_and_overwrite_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let o = holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "-o", "a.holo"], dir.path());
    assert_eq!(o.status.code(), Some(0));
    let before = std::fs::read(dir.path().join("a.holo")).unwrap();
    let o = holo(&["pattern", "--layout", "mark1", "--kind", "checkerboard", "-o", "a.holo"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("a.holo") && text(&o).contains("already exists"), "{}", text(&o));
    assert_eq!(std::fs::read(dir.path().join("a.holo")).unwrap(), before);
    // --force replaces.
    let o = holo(&["pattern", "--layout", "mark1", "--kind", "checkerboard", "-o", "a.holo", "--force"], dir.path());
    assert_eq!(o.status.code(), Some(0));

    for (args, needle) in [
        (&["info", "missing.holo"][..], "missing.holo"),
        (&["pattern", "--layout", "mark9", "--kind", "view-ramp", "-o", "b.holo"], "unknown layout"),
        (&["pattern", "--layout", "mark3", "--kind", "single-view", "--view", "96", "-o", "b.holo"], "view 96"),
    ] {
        let o = holo(args, dir.path());
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        let t = text(&o);
        assert!(t.contains(needle), "{args:?}: {t}");
        assert_eq!(t.lines().count(), 1, "one sentence: {t}");
        assert!(!t.contains("panicked") && !t.contains("RUST_BACKTRACE"));
    }
    // A damaged file: validate lists the problem and exits 1.
    let mut bytes = std::fs::read(dir.path().join("a.holo")).unwrap();
    let n = bytes.len();
    bytes.truncate(n - 100);
    std::fs::write(dir.path().join("cut.holo"), &bytes).unwrap();
    let o = holo(&["validate", "cut.holo"], dir.path());
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("cut.holo"));
    let o = holo(&["info", "cut.holo"], dir.path());
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    // A file of another kind: said once what it is, the file named once.
    let flick = super::fixture("holoflick/v1.1/movie.hflk");
    std::fs::copy(flick, dir.path().join("movie.hflk")).unwrap();
    let o = holo(&["validate", "movie.hflk"], dir.path());
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("violation: is a HoloFlick"), "{}", text(&o));
    assert_eq!(text(&o).matches("movie.hflk").count(), 1, "{}", text(&o));
}

#[test]
fn views_export_and_import_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let o = holo(
        &["pattern", "--layout", "mark1", "--kind", "colour-bars", "--level", "0.7", "-o", "bars.holo", "--f32"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = holo(&["export-views", "bars.holo", "--out", "views"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(dir.path().join("views/view_000.png").exists() && dir.path().join("views/view_004.png").exists());
    // Exporting again refuses to overwrite.
    let o = holo(&["export-views", "bars.holo", "--out", "views"], dir.path());
    assert_eq!(o.status.code(), Some(1));
    let o = holo(&["import-views", "views", "-o", "back.holo", "--f32"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let a = holo::read(dir.path().join("bars.holo")).unwrap();
    let b = holo::read(dir.path().join("back.holo")).unwrap();
    assert_eq!(a.geometry(), b.geometry());
    // 16-bit sRGB steps are at most ~1e-4 of white near white.
    let worst = a.samples().iter().zip(b.samples()).map(|(x, y)| (x - y).abs()).fold(0f32, f32::max);
    assert!(worst < 1e-4, "worst {worst}");
    assert!(b.samples().iter().any(|x| *x > 0.69));
}

#[test]
fn white_is_auto_max_or_a_positive_number_with_one_meaning_everywhere() {
    use holo::picture::White;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A view ramp with two specular glints.
    let g = holo::layout::builtin("mark1").unwrap().geometry;
    let m = holo::Modulation::from_fn(
        g,
        |c, j, e, v| {
            if (c, j, e) == (0, 30, 100) && v < 2 {
                25.0
            } else {
                0.1 + 0.15 * v as f32
            }
        },
    )
    .unwrap();
    holo::write(d.join("glints.holo"), &m, &holo::WriteOptions::default()).unwrap();
    let m = holo::read(d.join("glints.holo")).unwrap();
    let auto = White::Auto.level(m.samples().iter().copied());
    // The brightest view (0.7, as f16 stores it), not the glints.
    assert!((auto - 0.7).abs() < 1e-3, "{auto}");
    assert_eq!(White::Max.level(m.samples().iter().copied()), 25.0);
    // export-views: the level chosen is printed and recorded in the sidecar.
    for (word, want) in [("auto", auto), ("max", 25.0), ("0.5", 0.5)] {
        let o = holo(&["export-views", "glints.holo", "--out", word, "--white", word, "--bits", "8"], d);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
        assert!(text(&o).contains(&format!("white = {want}")), "{word}: {}", text(&o));
        let sidecar = holo::views::read_sidecar(&d.join(word).join(holo::views::SIDECAR)).unwrap();
        assert_eq!(sidecar.tone.white, want, "{word}");
    }
    // export-quilt: auto is the same percentile, of the quilt's pixels.
    let o = holo(&["export-quilt", "glints.holo", "-o", "q.png", "--tile", "40x30"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let spec = holo::cameras::quilt::QuiltSpec {
        tile_width: 40,
        tile_height: 30,
        ..holo::cameras::quilt::QuiltSpec::portrait()
    };
    let quilt = holo::cameras::quilt::quilt_from_modulation(&m, &spec).unwrap();
    let want = quilt.white_level(White::Auto);
    assert!(text(&o).contains(&format!("white = {want}")), "{want}: {}", text(&o));
    // Anything else is a usage error naming what is accepted.
    for args in [
        &["export-views", "glints.holo", "--out", "x", "--white", "0"][..],
        &["export-views", "glints.holo", "--out", "x", "--white", "-1"],
        &["export-quilt", "glints.holo", "-o", "x.png", "--white", "bright"],
        &["export-quilt", "glints.holo", "-o", "x.png", "--white", "nan"],
        &["view", "glints.holo", "--layout", "mark1", "-o", "x.png", "--white", "inf"],
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(text(&o).contains("auto, max or a finite positive number"), "{args:?}: {}", text(&o));
    }
    let o = holo(&["import-views", "auto", "-o", "back.holo", "--white", "auto"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("exported with"), "{}", text(&o));
    assert!(!d.join("x").exists() && !d.join("x.png").exists() && !d.join("back.holo").exists());
}

#[test]
fn info_tells_whether_two_files_hold_the_same_content() {
    let dir = tempfile::tempdir().unwrap();
    for (file, compression, kind) in
        [("zip.holo", "zip", "view-ramp"), ("piz.holo", "piz", "view-ramp"), ("other.holo", "zip", "checkerboard")]
    {
        let o = holo(
            &["pattern", "--layout", "mark1", "--kind", kind, "--compression", compression, "-o", file],
            dir.path(),
        );
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    }
    let o = holo(&["info", "zip.holo", "piz.holo"], dir.path());
    assert!(text(&o).contains("same content: yes"), "{}", text(&o));
    let o = holo(&["info", "zip.holo", "other.holo"], dir.path());
    assert!(text(&o).contains("same content: no"), "{}", text(&o));
}

/// The frames of a PNG or APNG, decoded to RGB(A) bytes, with their width and height.
fn png_frames(path: &Path) -> (usize, usize, Vec<Vec<u8>>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let count = reader.info().animation_control.map_or(1, |a| a.num_frames as usize);
    let mut frames = Vec::new();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    for k in 0..count {
        let info = reader.next_frame(&mut buf).unwrap_or_else(|e| panic!("{} frame {k}: {e}", path.display()));
        frames.push(buf[..info.buffer_size()].to_vec());
    }
    let (w, h) = reader.info().size();
    (w as usize, h as usize, frames)
}

/// The pixel `(x, y)` of an RGB frame `w` wide.
fn rgb(frame: &[u8], w: usize, x: usize, y: usize) -> [u8; 3] {
    frame[(y * w + x) * 3..][..3].try_into().unwrap()
}

/// The outlines of the display drawn in a picture (blue, no scene's colour):
/// each as the box inside it, (left, top, width, height), found by scanning
/// rows for an outline's top edge.
fn display_outlines(frame: &[u8], w: usize, h: usize) -> Vec<(usize, usize, usize, usize)> {
    let edge = |x: usize, y: usize| {
        let [r, g, b] = rgb(frame, w, x, y);
        b > 60 && r < 10 && g < 40
    };
    let mut boxes: Vec<(usize, usize, usize, usize)> = Vec::new();
    for y in 0..h {
        let mut x = 0;
        while x < w {
            let inside =
                |b: &&(usize, usize, usize, usize)| x + 1 >= b.0 && x <= b.0 + b.2 && y + 1 >= b.1 && y <= b.1 + b.3;
            if edge(x, y) && !boxes.iter().any(|b| inside(&b)) {
                let right = (x..w).take_while(|&xx| edge(xx, y)).last().unwrap();
                let bottom = (y..h).take_while(|&yy| edge(x, yy)).last().unwrap();
                boxes.push((x + 1, y + 1, right - x - 1, bottom - y - 1));
                x = right;
            }
            x += 1;
        }
    }
    boxes
}

/// The demo, run once: every file its text names is there and is what it
/// says; eyes across the viewing zone see different pictures; every picture
/// of the display is at its physical proportions; counts and rates are true.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn demo_runs_and_says_where_its_files_are() {
    let dir = tempfile::tempdir().unwrap();
    // The folder already holds what an earlier run left, from before the
    // demo marked its folders (only its names, the bundled scene in spot/):
    // the demo replaces its own files, and marks the folder.
    let d = dir.path().join("holo-demo");
    std::fs::create_dir_all(d.join("spot")).unwrap();
    for name in ["spot.obj", "spot.mtl", "spot_texture.png"] {
        std::fs::copy(super::fixture("mesh/spot").join(name), d.join("spot").join(name)).unwrap();
    }
    ok(holo(&["pattern", "--layout", "mark3", "--kind", "view-ramp", "-o", "demo.holo"], &d));
    let earlier = std::fs::read(d.join("demo.holo")).unwrap();
    let o = holo(&["demo", "-o", "holo-demo"], dir.path());
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let said = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(std::fs::read(d.join("demo.holo")).unwrap() != earlier);
    assert!(d.join(".holo-demo").is_file(), "the folder is marked as the demo's");
    assert!(holo::validate(d.join("demo.holo")).unwrap().is_valid());
    let full = holo::HoloFile::open(d.join("demo-full-parallax.holo")).unwrap();
    assert_eq!(full.geometry().vertical_view_count(), 9);
    assert!(holo::validate(d.join("demo-full-parallax.holo")).unwrap().is_valid());
    let movie = holo::HoloFile::open(d.join("movie/cube.holo")).unwrap();
    assert_eq!(movie.info().frames.len(), 3);

    // One line a file, each file there; the pictures valid PNGs.
    let named: Vec<&str> = said
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("holo-demo/"))
        .map(|l| l.split(':').next().unwrap())
        .collect();
    for f in [
        "demo.holo",
        "demo_qs8x6a0.75.png",
        "fringe.png",
        "eyes.png",
        "eyes-moving.png",
        "demo-full-parallax.holo",
        "eyes-full-parallax.png",
        "movie/cube.hflk",
        "movie/frames.png",
    ] {
        assert!(named.contains(&f), "{f} not named in:\n{said}");
    }
    for f in &named {
        assert!(d.join(f).is_file(), "{f} is named but not there:\n{said}");
        if f.ends_with(".png") {
            let (_, _, frames) = png_frames(&d.join(f));
            assert!(!frames.is_empty(), "{f}");
        }
    }

    // The eye moving: an animation, there and back, each frame labelled and different.
    let (w, h, moving) = png_frames(&d.join("eyes-moving.png"));
    assert!(said.contains(&format!("an animated PNG of {} frames", moving.len())), "{said}");
    assert!(moving.len() > 10, "{} frames", moving.len());
    // Parallax: the first and last tiles of the contact sheet differ, and
    // so do the ends of the sweep, by more than a few pixels' worth.
    let differ = |a: &[u8], b: &[u8]| a.iter().zip(b).filter(|(x, y)| x.abs_diff(**y) > 16).count();
    let ends = differ(&moving[0], &moving[moving.len() / 2]);
    assert!(ends > w * h / 50, "the ends of the sweep differ in {ends} of {} values", w * h * 3);

    // Every picture of the display at its physical proportions: the outline
    // of the display (its emitter plane, 80 × 60 mm on Mark III) within 2%.
    let g = holo::layout::mark3().geometry;
    let physical = (g.emitters as f64 * g.emitter_pitch_m) / (g.hololines as f64 * g.hololine_pitch_m);
    let (sw, sh, sheet) = png_frames(&d.join("eyes.png"));
    let (mw, mh, movie_frames) = png_frames(&d.join("movie/frames.png"));
    let (fw, fh, full) = png_frames(&d.join("eyes-full-parallax.png"));
    for (what, frame, w, h, count) in [
        ("eyes.png", &sheet[0], sw, sh, 9),
        ("eyes-full-parallax.png", &full[0], fw, fh, 3),
        ("eyes-moving.png", &moving[0], w, h, 1),
        ("movie/frames.png", &movie_frames[0], mw, mh, 3),
    ] {
        let outlines = display_outlines(frame, w, h);
        assert_eq!(outlines.len(), count, "{what}: {outlines:?}");
        for (x, y, bw, bh) in &outlines {
            let aspect = *bw as f64 / *bh as f64;
            assert!(
                (aspect / physical - 1.0).abs() < 0.02,
                "{what}: the display at ({x}, {y}) is {bw} × {bh} pixels, {aspect:.3} wide for its height, not {physical:.3}"
            );
        }
        if what == "eyes.png" || what == "eyes-full-parallax.png" {
            // The contact sheet's first and last tiles see the cow differently
            // (full parallax: from above and from below).
            let (a, b) = (outlines[0], outlines[count - 1]);
            let tile = |(x, y, _, _): (usize, usize, usize, usize)| -> Vec<u8> {
                (0..a.3).flat_map(|yy| (0..a.2).flat_map(move |xx| rgb(frame, w, x + xx, y + yy))).collect()
            };
            let n = differ(&tile(a), &tile(b));
            assert!(n > a.2 * a.3 / 50, "{what}: the first and last eyes' tiles differ in {n} values");
        }
    }

    // True counts and rates with units.
    assert!(said.contains("(2 fringe images)") && said.contains("(6 fringe images)"), "{said}");
    assert!(said.contains("3 frames taken at 0.5 frames/s"), "{said}");
    assert!(!said.contains("/1000") && !said.contains("per second"), "{said}");
    let o = ok(holo(&["info", "holo-demo/movie/cube.holo"], dir.path()));
    assert!(text(&o).contains("frame rate    0.5 frames/s"), "{}", text(&o));
    // The command the text gives for the fringes names the layout and a folder beside the file.
    let assemble = said.lines().find_map(|l| l.trim_start().strip_prefix("holo assemble holo-demo/demo.holo")).unwrap();
    let args: Vec<&str> = assemble.split("    ").next().unwrap().split_whitespace().collect();
    assert_eq!(args, ["--layout", "mark3", "-o", "holo-demo/fringes"], "{said}");
}

#[test]
fn assemble_writes_head_images_and_refuses_to_overwrite() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A custom profile: Mark III with 2 hololines, as a user would edit it.
    small_profile(d, 2);
    let o = holo(&["pattern", "--layout", "small.toml", "--kind", "single-emitter", "-o", "s.holo"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = holo(&["assemble", "s.holo", "--layout", "small.toml", "-o", "fringes"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("assembled 1 frame(s)"), "{}", text(&o));
    for f in ["frame0000-head1.png", "frame0000-head2.png", "holo-fringes.json"] {
        assert!(d.join("fringes").join(f).exists(), "{f}");
    }
    let o = holo(&["assemble", "s.holo", "--layout", "small.toml", "-o", "fringes"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("already exists"), "{}", text(&o));
    // The built-in layout wants 440 hololines: said plainly.
    let o = holo(&["assemble", "s.holo", "-o", "other"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("s.holo") && text(&o).contains("2 hololines (the layout has 440)"), "{}", text(&o));
}

#[test]
fn a_profile_whose_basis_does_not_fit_is_refused_with_its_reasons_everywhere() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = std::fs::read_to_string(small_profile(d, 2)).unwrap();
    let o = holo(&["pattern", "--layout", "small.toml", "--kind", "single-emitter", "-o", "s.holo"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    // Two emitters more than Mark III's chirps reach: the layout's data is
    // consistent, its fringe side cannot be assembled.
    let wide = profile.replace("emitters = 336", "emitters = 338");
    std::fs::write(d.join("wide.toml"), wide).unwrap();
    for cmd in [
        &["layout", "wide.toml"][..],
        &["assemble", "s.holo", "--layout", "wide.toml", "-o", "fringes"],
        &["check", "s.holo", "--layout", "wide.toml"],
        &["view", "s.holo", "--layout", "wide.toml", "-o", "v.png"],
    ] {
        let o = holo(cmd, d);
        assert_eq!(o.status.code(), Some(1), "{cmd:?}: {}", text(&o));
        assert!(
            text(&o).contains("wide.toml: inconsistent layout: ") && text(&o).contains("338 emitters do not fit"),
            "{cmd:?}: {}",
            text(&o)
        );
    }
    assert!(!d.join("fringes").exists() && !d.join("v.png").exists());
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn check_and_view_recover_what_was_assembled() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Mark III with 2 hololines, as a user would edit the profile.
    small_profile(d, 2);
    let o = holo(&["pattern", "--layout", "small.toml", "--kind", "colour-bars", "-o", "s.holo"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));

    // Assembled in memory.
    let o = holo(&["check", "s.holo", "--layout", "small.toml", "--json"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let report: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(report["signal"]["relative_l2"].as_f64().unwrap() < 0.03, "{report}");
    assert!(report["optical"]["relative_l2"].as_f64().unwrap() < 0.15, "{report}");
    assert_eq!(report["fringes"], "assembled in memory (8-bit)");

    // Fringes written first, then checked and viewed from the directory.
    let o = holo(&["assemble", "s.holo", "--layout", "small.toml", "-o", "fringes"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = holo(&["check", "s.holo", "--fringes", "fringes"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("signal recovery") && text(&o).contains("optical recovery"), "{}", text(&o));
    let o = holo(&["view", "fringes", "--eye", "-20,5", "-o", "left.png"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("x = -20 mm"), "{}", text(&o));
    let png = decode::open(&d.join("left.png")).unwrap();
    assert!(png.width > 336 && png.height == 2, "{} × {}", png.width, png.height);
    // An eye no view reaches: a black picture, and a warning that says why;
    // none from an eye inside the viewing zone.
    for (eye, warned) in [("5000", true), ("0", false)] {
        let o = holo(&["view", "s.holo", "--layout", "small.toml", "--eye", eye, "-o", &format!("{eye}.png")], d);
        assert_eq!(o.status.code(), Some(0), "{}", text(&o));
        assert_eq!(text(&o).contains("outside the viewing zone and sees nothing"), warned, "{}", text(&o));
    }
    // Not overwritten without --force.
    let o = holo(&["view", "fringes", "-o", "left.png"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("already exists"), "{}", text(&o));

    // Errors name the file and the problem.
    std::fs::create_dir(d.join("empty")).unwrap();
    let o = holo(&["view", "empty", "-o", "e.png"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("empty") && text(&o).contains("holo-fringes.json"), "{}", text(&o));
    let o = holo(&["check", "s.holo", "--fringes", "fringes", "--frame", "3"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("fringes") && text(&o).contains("frame 3"), "{}", text(&o));
    let o = holo(&["check", "s.holo", "--layout", "mark1"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("s.holo") && text(&o).contains("the layout has"), "{}", text(&o));
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn export_quilt_names_its_file_and_overwrites_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mark1_ramp(d, "ramp.holo");
    // The portrait preset, named as Looking Glass software expects, next to the input.
    let o = holo(&["export-quilt", "ramp.holo"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let quilt = d.join("ramp_qs8x6a0.75.png");
    let img = decode::open(&quilt).unwrap();
    assert_eq!((img.width, img.height, img.channels, img.bits()), (3360, 3360, 3, Bits::Eight));
    let before = std::fs::read(&quilt).unwrap();
    let o = holo(&["export-quilt", "ramp.holo", "--white", "0.5"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("ramp_qs8x6a0.75.png") && text(&o).contains("already exists"), "{}", text(&o));
    assert_eq!(std::fs::read(&quilt).unwrap(), before);
    let o = holo(&["export-quilt", "ramp.holo", "--white", "0.5", "--force", "--tile", "40x30"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert_eq!(decode::open(&quilt).unwrap().width, 320);
    // Another preset into a directory; explicit grid and aspect.
    let o = holo(&["export-quilt", "ramp.holo", "--preset", "go", "--tile", "12x22", "--output-dir", "out"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(d.join("out/ramp_qs11x6a0.5625.png").exists());
    let o = holo(
        &[
            "export-quilt",
            "ramp.holo",
            "--columns",
            "5",
            "--rows",
            "2",
            "--tile",
            "16x10",
            "--aspect",
            "1.6",
            "-o",
            "x.png",
        ],
        d,
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert_eq!(decode::open(&d.join("x.png")).unwrap().width, 80);
    for (args, needle) in [
        (&["export-quilt", "missing.holo"][..], "missing.holo"),
        (&["export-quilt", "ramp.holo", "--frame", "4", "-o", "y.png"], "no frame 4"),
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        let t = text(&o);
        assert!(t.contains(needle), "{args:?}: {t}");
        assert_eq!(t.lines().count(), 1, "one sentence: {t}");
    }
    assert!(!d.join("y.png").exists());
}

#[test]
fn convert_cameras_reads_a_quilt_and_names_what_is_wrong() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mark1_ramp(d, "ramp.holo");
    let o =
        holo(&["export-quilt", "ramp.holo", "--tile", "64x32", "--columns", "4", "--rows", "2", "--aspect", "2"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let quilt = "ramp_qs4x2a2.png";
    assert!(d.join(quilt).exists());
    let o =
        holo(&["convert", "cameras", quilt, "--layout", "mark1", "-o", "back.holo", "--unseen-mask", "unseen.png"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("rail, 8 cameras") && text(&o).contains("placement:"), "{}", text(&o));
    assert!(d.join("back.holo").exists() && d.join("unseen.png").exists());
    let before = std::fs::read(d.join("back.holo")).unwrap();
    let o = holo(&["convert", "cameras", quilt, "--layout", "mark1", "-o", "back.holo"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("back.holo") && text(&o).contains("already exists"), "{}", text(&o));
    assert_eq!(std::fs::read(d.join("back.holo")).unwrap(), before);
    // A rig file whose camera's picture is missing: the camera and file are named.
    std::fs::write(
        d.join("rig.toml"),
        "units = \"mm\"\nfocus_distance = 500\nimage_size = [64, 32]\nfocal_length_px = 100\n[[cameras]]\nimage = \"a.png\"\nposition = [0, 0, 500]\nlook_at = [0, 0, 0]\n",
    )
    .unwrap();
    let o = holo(&["convert", "cameras", "rig.toml", "--layout", "mark1", "-o", "rig.holo"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("a.png"), "{}", text(&o));
    assert!(!d.join("rig.holo").exists());
    let o = holo(&["convert", "cameras", "nothing-here", "--layout", "mark1", "-o", "x.holo"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("nothing-here"), "{}", text(&o));
}

#[test]
fn holoflick_pack_info_unpack() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spot = &spot();
    let o = holo(&["holoflick", "pack", spot, spot, "-o", "cow.hflk", "--position-bits", "12"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("2 frames, 1 objects stored, 1 from key frames"), "{}", text(&o));
    let o = holo(&["holoflick", "info", "cow.hflk"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("frame 1: 1 objects (1 from key frames), 500 triangles"), "{}", text(&o));
    // The frame rate as a number with its unit.
    assert!(text(&o).contains("2 frames at 30 frames/s"), "{}", text(&o));
    let o = holo(&["convert", "holoflick", "cow.hflk", "--layout", "mark1", "-o", "cow.holo", "--supersample", "1"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("reused from key frames 1"), "{}", text(&o));
    let o = holo(&["holoflick", "unpack", "cow.hflk", "--frame", "1", "-o", "cow.glb"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(d.join("cow.glb").exists());
    let o = holo(&["holoflick", "pack", spot, "-o", "cow.cg"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("model = normalised"), "{}", text(&o));
    let o = holo(&["holoflick", "info", "cow.cg"], d);
    assert!(text(&o).contains("Java 3D compressed geometry 1.0.2, 1 objects"), "{}", text(&o));
    // Errors name the file and exit 1; the couch must be six numbers (usage: 2).
    let o = holo(&["holoflick", "unpack", "cow.hflk", "--frame", "5", "-o", "x.ply"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("cow.hflk") && text(&o).contains("no frame 5"), "{}", text(&o));
    let o = holo(&["holoflick", "pack", spot, "-o", "y.hflk", "--couch", "1,2,3"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

#[test]
fn help_lists_every_choice() {
    let dir = tempfile::tempdir().unwrap();
    let help = |args: &[&str]| {
        let o = holo(args, dir.path());
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", text(&o));
        text(&o)
    };
    // The built-in layouts, from the library's own list, wherever a layout is asked for.
    for cmd in [
        &["pattern"][..],
        &["assemble"],
        &["check"],
        &["view"],
        &["layout"],
        &["convert", "mesh"],
        &["convert", "cameras"],
        &["convert", "holoflick"],
        &["holoflick", "encode"],
    ] {
        let t = help(&[cmd, &["--help"]].concat());
        for name in holo::layout::BUILTIN {
            assert!(t.contains(name), "{cmd:?} --help lacks {name}: {t}");
        }
        assert!(t.contains(".toml/.json profile"), "{cmd:?}: {t}");
    }
    let t = help(&["pattern", "--help"]);
    for (_, kind) in holo::pattern::PatternKind::ALL {
        assert!(t.contains(kind), "pattern --help lacks {kind}");
    }
    for c in holo::format::Compression::ALL {
        assert!(t.contains(c.name()), "pattern --help lacks {}", c.name());
    }
    assert!(t.contains("rgb") && t.contains("lossy"), "{t}");
    let t = help(&["assemble", "--help"]);
    assert!(["png", "raw", "exr"].iter().all(|f| t.contains(f)), "{t}");
    let t = help(&["export-quilt", "--help"]);
    assert!(holo::cameras::quilt::PRESETS.iter().all(|p| t.contains(p)), "{t}");
    let t = help(&["export-views", "--help"]);
    assert!(t.contains("8-bit") && t.contains("16-bit"), "{t}");
    let t = help(&["convert", "mesh", "--help"]);
    assert!(t.contains("blinn") && t.contains("phong"), "{t}");
    let t = help(&["convert", "cameras", "--help"]);
    assert!(["nearest", "linear", "natural"].iter().all(|b| t.contains(b)), "{t}");
}

/// Negative numbers reach the argument checks: where they make sense they
/// are taken, elsewhere refused with what the value means. A value the
/// command line itself gets wrong is a usage error, exit 2, as clap's own
/// refusals are: it is found before any file is read.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn negative_values_are_taken_or_refused_with_their_meaning() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spot = &spot();
    for (args, needle) in [
        (&["convert", "mesh", spot, "-o", "x.holo", "--fps", "-30"][..], "--fps must be positive, not -30"),
        (&["holoflick", "pack", spot, "-o", "x.hflk", "--fps", "-30"], "--fps must be positive"),
        (&["holoflick", "encode", spot, "-o", "x.hflk", "--fps=-30"], "--fps must be positive"),
        (&["view", "x.holo", "-o", "x.png", "--pupil", "-4"], "--pupil must be positive (millimetres), not -4"),
        (&["pattern", "--kind", "single-view", "--view", "-3", "-o", "x.holo"], "--view must be a whole number"),
        (
            &["export-views", "x.holo", "-o", "v", "--white", "-1"],
            "--white must be auto, max or a finite positive number",
        ),
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", text(&o));
        assert!(text(&o).contains(needle), "{args:?}: {}", text(&o));
        assert!(!text(&o).contains("-- -"), "no clap tip: {}", text(&o));
    }
    let o = holo(
        &["convert", "mesh", spot, "--layout", "mark1", "--supersample", "1", "-o", "moved.holo"]
            .iter()
            .chain(&["--translate", "-1,0,0", "--rotate", "-90,0,0", "--scale", "2"])
            .copied()
            .collect::<Vec<_>>(),
        d,
    );
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    let o = holo(&["view", "moved.holo", "--layout", "mark1", "--eye", "-40", "-o", "left.png"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
    assert!(text(&o).contains("x = -40 mm"), "{}", text(&o));
    let o = holo(&["holoflick", "pack", spot, "-o", "c.hflk", "--couch", "-1,-1,0,1,1,2"], d);
    assert_eq!(o.status.code(), Some(0), "{}", text(&o));
}

#[test]
fn a_layout_file_that_is_not_there_is_named() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["pattern", "--layout", "x.toml", "--kind", "view-ramp", "-o", "a.holo"][..],
        &["assemble", "a.holo", "--layout", "x.toml", "-o", "f"],
        &["layout", "x.toml"],
    ] {
        let o = holo(args, dir.path());
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        let t = text(&o);
        assert!(t.contains("x.toml: no such file") && !t.contains("unknown layout"), "{args:?}: {t}");
        assert_eq!(t.lines().count(), 1, "one sentence: {t}");
    }
}

/// `-o/--output` is the thing written, a file or the folder of a
/// multi-file output; `--out` stays as a hidden alias for old scripts.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn output_is_o_everywhere_and_out_still_works() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    mark1_ramp(d, "r.holo");
    for (flag, folder) in [("-o", "a"), ("--output", "b"), ("--out", "c")] {
        let o = holo(&["export-views", "r.holo", flag, &format!("views-{folder}")], d);
        assert_eq!(o.status.code(), Some(0), "{flag}: {}", text(&o));
        assert!(d.join(format!("views-{folder}/view_000.png")).exists());
        let o = holo(&["assemble", "r.holo", "--layout", "mark1", flag, &format!("fringes-{folder}")], d);
        assert_eq!(o.status.code(), Some(0), "{flag}: {}", text(&o));
        assert!(d.join(format!("fringes-{folder}/holo-fringes.json")).exists());
    }
    for flag in ["-o", "--out"] {
        let o = holo(&["export-views", "--help"], d);
        assert!(!text(&o).contains("--out "), "--out is hidden: {}", text(&o));
        // A folder that cannot be made: the demo fails at once, naming it.
        let o = holo(&["demo", flag, "r.holo"], d);
        assert_eq!(o.status.code(), Some(1), "{flag}: {}", text(&o));
        assert!(text(&o).contains("r.holo"), "{flag}: {}", text(&o));
    }
}

/// Files are written as format 1.2 (pixels at the emitter grid's proportions,
/// each header sealed by its digest) unless version 1.1 (unsealed) or 1.0
/// (square pixels, for 1.0 readers) is asked for; all validate and hold the
/// same samples.
#[test]
fn format_versions_differ_only_in_the_pixel_aspect_ratio_and_the_seal() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = super::small_profile(d, 4);
    let layout = profile.to_str().unwrap();
    ok(holo(&["pattern", "--layout", layout, "--kind", "view-ramp", "-o", "new.holo"], d));
    ok(holo(&["pattern", "--layout", layout, "--kind", "view-ramp", "-o", "mid.holo", "--format-version", "1.1"], d));
    ok(holo(&["pattern", "--layout", layout, "--kind", "view-ramp", "-o", "old.holo", "--format-version", "1.0"], d));
    let new = text(&ok(holo(&["info", "new.holo"], d)));
    let mid = text(&ok(holo(&["info", "mid.holo"], d)));
    let old = text(&ok(holo(&["info", "old.holo"], d)));
    assert!(new.contains(".holo 1.2 (OpenEXR), 1 frame(s), pixel aspect ratio 1.7460"), "{new}");
    assert!(mid.contains(".holo 1.1 (OpenEXR), 1 frame(s), pixel aspect ratio 1.7460"), "{mid}");
    assert!(old.contains(".holo 1.0 (OpenEXR), 1 frame(s), pixel aspect ratio 1.0000\n"), "{old}");
    let sealed = |name: &str| {
        let bytes = std::fs::read(d.join(name)).unwrap();
        bytes.windows(b"holo.headerDigest".len()).any(|w| w == b"holo.headerDigest")
    };
    assert!(sealed("new.holo") && !sealed("mid.holo") && !sealed("old.holo"));
    ok(holo(&["validate", "new.holo", "mid.holo", "old.holo"], d));
    let all = text(&ok(holo(&["info", "new.holo", "mid.holo", "old.holo"], d)));
    assert!(all.to_lowercase().contains("same content"), "{all}");
}

/// `holo info` prints the placement a conversion recorded in the form
/// `--matrix` takes, and converting again with it gives the same content.
#[test]
fn the_recorded_placement_remakes_the_conversion_from_the_command_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = super::small_profile(d, 4);
    let layout = profile.to_str().unwrap();
    let spot = super::spot();
    ok(holo(&["convert", "mesh", &spot, "--layout", layout, "-o", "a.holo", "--supersample", "1"], d));
    let info = text(&ok(holo(&["info", "a.holo"], d)));
    let line = info.lines().find(|l| l.contains("placement")).unwrap_or_else(|| panic!("{info}"));
    let matrix = line.rsplit(' ').next().unwrap();
    assert_eq!(matrix.split(',').count(), 16, "{line}");
    let matrix_arg = format!("--matrix={matrix}");
    ok(holo(&["convert", "mesh", &spot, "--layout", layout, "-o", "b.holo", "--supersample", "1", &matrix_arg], d));
    let both = text(&ok(holo(&["info", "a.holo", "b.holo"], d)));
    assert!(both.to_lowercase().contains("same content"), "{both}");
}

/// `holo info` prints the conversion a file records as the command line
/// that makes it (the scene named as recorded, the layout a stand-in when
/// it is not built in), and that command line makes the same content.
#[test]
fn info_prints_the_command_line_that_makes_the_conversion_again() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = super::small_profile(d, 4);
    let layout = profile.to_str().unwrap();
    for f in ["spot.obj", "spot.mtl", "spot_texture.png"] {
        std::fs::copy(super::fixture("mesh/spot").join(f), d.join(f)).unwrap();
    }
    let asked = [
        "--supersample=2x3",
        "--hololine-supersample=2",
        "--specular=phong",
        "--light=point:10,20,300:1,2,3",
        "--light=ambient:0.1,0.2,0.3",
        "--rotate=10,20,30",
        "--translate=0.1,-0.3,0.2",
        "--scale=0.7",
        "--no-scene-lights",
    ];
    ok(holo(&[&["convert", "mesh", "spot.obj", "--layout", layout, "-o", "a.holo"][..], &asked].concat(), d));
    let info = text(&ok(holo(&["info", "a.holo"], d)));
    let line = info.lines().find_map(|l| l.strip_prefix("  conversion    holo ")).unwrap_or_else(|| panic!("{info}"));
    assert!(line.starts_with("convert mesh spot.obj --layout LAYOUT -o OUT.holo"), "{line}");
    for flag in asked {
        let (name, value) = flag.split_once('=').unwrap_or((flag, ""));
        assert!(line.contains(&format!("{name} {value}").trim().to_string()), "{flag} not in {line}");
    }
    assert!(info.contains("input         spot.obj, sha256:"), "{info}");
    assert!(info.contains("holo convert like a.holo -o OUT.holo"), "{info}");
    let args: Vec<&str> = line
        .split(' ')
        .map(|a| {
            if a == "LAYOUT" {
                layout
            } else if a == "OUT.holo" {
                "b.holo"
            } else {
                a
            }
        })
        .collect();
    ok(holo(&args, d));
    let both = text(&ok(holo(&["info", "a.holo", "b.holo"], d)));
    assert!(both.to_lowercase().contains("same content: yes"), "{both}");
}

/// `holo convert like` makes the conversion a file records again, for its
/// display, and says whether the content is the same; a file that records
/// none is refused, naming it.
#[test]
fn convert_like_makes_the_recorded_conversion_again() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let movie = super::fixture("holoflick/v1.1/movie.hflk");
    let movie = movie.to_str().unwrap();
    let convert = ["convert", "holoflick", movie, "--layout", "mark1", "-o", "a.holo", "--frames", "1..3", "--fit"];
    ok(holo(&[&convert[..], &["--supersample", "1x2", "--hololine-supersample", "2"]].concat(), d));
    let again = text(&ok(holo(&["convert", "like", "a.holo", "--input", movie, "-o", "b.holo"], d)));
    assert!(again.contains("same content as a.holo: yes"), "{again}");
    let both = text(&ok(holo(&["info", "--headers-only", "a.holo", "b.holo"], d)));
    assert!(both.contains("same content: yes"), "{both}");
    // The input where the record says, by default: here it is not.
    let o = holo(&["convert", "like", "a.holo", "-o", "c.holo"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("movie.hflk"), "{}", text(&o));
    mark1_ramp(d, "ramp.holo");
    let o = holo(&["convert", "like", "ramp.holo", "-o", "c.holo"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("ramp.holo: the file does not record the conversion"), "{}", text(&o));
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn timings_say_where_the_time_went_stage_by_stage() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_profile(d, 4);
    let cube = super::fixture("mesh/AnimatedMorphCube.glb");
    let o = ok(holo(
        &[
            "convert",
            "mesh",
            cube.to_str().unwrap(),
            "--layout",
            "small.toml",
            "--frames",
            "0..3",
            "-o",
            "c.holo",
            "--timings",
        ],
        d,
    ));
    let said = text(&o);
    let line = said.lines().find(|l| l.starts_with("timings: ")).unwrap_or_else(|| panic!("{said}"));
    for stage in ["open ", "place ", "decode ", "render ", "write ", "per frame (3)"] {
        assert!(line.contains(stage), "{stage}: {line}");
    }
    let o = ok(holo(&["assemble", "c.holo", "--layout", "small.toml", "-o", "fringes", "--timings"], d));
    let said = text(&o);
    let line = said.lines().find(|l| l.starts_with("timings: ")).unwrap_or_else(|| panic!("{said}"));
    for stage in ["read ", "assemble ", "encode "] {
        assert!(line.contains(stage), "{stage}: {line}");
    }
    // Not asked for, not said.
    let o = ok(holo(&["assemble", "c.holo", "--layout", "small.toml", "-o", "f2"], d));
    assert!(!text(&o).contains("timings"));
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn raw_blanking_drops_the_layouts_blanking_gains() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    small_profile(d, 2);
    let printed = |raw: bool| {
        let args: &[&str] = if raw { &["layout", "mark3", "--raw-blanking"] } else { &["layout", "mark3"] };
        String::from_utf8(ok(holo(args, d)).stdout).unwrap()
    };
    assert!(printed(false).contains("[fringe.blanking_gains]"));
    assert!(!printed(true).contains("blanking_gains"));
    ok(holo(&["pattern", "--layout", "small.toml", "--kind", "single-emitter", "-o", "s.holo"], d));
    for (out, raw) in [("with", false), ("raw", true)] {
        let mut args = vec!["assemble", "s.holo", "--layout", "small.toml", "-o", out];
        if raw {
            args.push("--raw-blanking");
        }
        ok(holo(&args, d));
        // The fringe set records the layout it was made with.
        let sidecar = std::fs::read_to_string(d.join(out).join("holo-fringes.json")).unwrap();
        assert_eq!(sidecar.contains("blanking_gains"), !raw, "{out}");
    }
    let image = |out: &str| std::fs::read(d.join(out).join("frame0000-head1.png")).unwrap();
    assert_ne!(image("with"), image("raw"), "the gains change the samples beside the blanking");
    // Gains with emitter phases other than zero: kept, with a warning that
    // they do not fit; none once they are dropped, none for the profile as built.
    let profile = std::fs::read_to_string(d.join("small.toml")).unwrap();
    assert!(!profile.contains("emitter_phases"));
    let phased = profile.replacen("[fringe]\n", "[fringe]\nemitter_phases = \"viewer\"\n", 1);
    std::fs::write(d.join("phased.toml"), phased).unwrap();
    for (layout, raw, warned) in
        [("phased.toml", false, true), ("phased.toml", true, false), ("small.toml", false, false)]
    {
        let out = format!("v-{layout}-{raw}.png");
        let mut args = vec!["view", "s.holo", "--layout", layout, "-o", &out];
        if raw {
            args.push("--raw-blanking");
        }
        let o = ok(holo(&args, d));
        assert_eq!(
            text(&o).contains("were found for every emitter at phase 0"),
            warned,
            "{layout} {raw}: {}",
            text(&o)
        );
    }
}

#[test]
fn a_full_parallax_file_is_described_validated_quilted_and_its_views_exported_as_pictures_hogels_and_hci() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let file = crate::fixture("v1.3/full-frames-rgb-f32-zip.holo");
    let file = file.to_str().unwrap();
    let info = text(&ok(holo(&["info", file], d)));
    assert!(
        info.contains("3 emitter rows × 4 emitters × 2 × 2 views (horizontal × vertical), full parallax"),
        "{info}"
    );
    assert!(info.contains("vertical      -2.865° … 2.865°, uniform in sin (positive up)"), "{info}");
    assert!(info.contains("a digest for each of 4 views"), "{info}");
    assert!(text(&ok(holo(&["validate", file], d))).contains("valid"));
    // Every view a picture named by both indices, and every hogel (3 rows ×
    // 4 emitters) a 2 × 2 picture of its views, for a printer; and back,
    // sample for sample at 16 bits.
    let views = ["view_000_000.png", "view_001_000.png", "view_000_001.png", "view_001_001.png"];
    let hogels = ["hogel_000_000.png", "hogel_000_003.png", "hogel_002_003.png"];
    for (export, import, folder, said, names) in [
        ("export-views", "import-views", "views", "wrote 4 view PNGs", &views[..]),
        ("export-hogels", "import-hogels", "hogels", "wrote 12 hogel PNGs and holo-hogels.json", &hogels[..]),
    ] {
        let o = ok(holo(&[export, file, "--frame", "1", "--white", "200", "-o", folder], d));
        assert!(text(&o).contains(said), "{}", text(&o));
        for name in names {
            assert!(d.join(folder).join(name).exists(), "{name}");
        }
        let back = format!("{folder}.holo");
        ok(holo(&[import, folder, "-o", &back, "--f32"], d));
        let back = holo::format::read(d.join(&back)).unwrap();
        let original = holo::HoloFile::open(file).unwrap().read_frame(1).unwrap();
        assert_eq!(back.geometry(), original.geometry());
        for (a, b) in back.samples().iter().zip(original.samples()) {
            assert!((a - b).abs() <= 200.0 / 65535.0 * 2.0, "{export}: {a} {b}");
        }
    }
    // What holo cannot do with it yet is refused, saying why.
    let o = holo(&["assemble", file, "-o", "fringes"], d);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("is full parallax (2 × 2 views)") && !d.join("fringes").exists(), "{}", text(&o));
    // A quilt shows each row's views toward the viewer line.
    let o = ok(holo(&["export-quilt", file, "-o", "q.png", "--tile", "40x30"], d));
    assert!(text(&o).contains("a 320×180 quilt of 48 views"), "{}", text(&o));

    let full = file;
    let o = holo(&["export-hogels", full, "-o", "hogels"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("hogels"), "{}", text(&o));
    // Horizontal parallax: each hogel a strip one pixel tall.
    let flat = crate::fixture("v1.2/frames-rgb-f32-zip.holo");
    ok(holo(&["export-hogels", flat.to_str().unwrap(), "--white", "max", "-o", "strips"], d));
    let png = std::fs::read(d.join("strips/hogel_003_004.png")).unwrap();
    let picture = decode::decode(std::io::Cursor::new(png)).unwrap();
    assert_eq!((picture.width, picture.height), (3, 1));
    ok(holo(&["import-hogels", "strips", "-o", "strips.holo"], d));
    // A frame the file does not have: one sentence naming it, no folder.
    let o = holo(&["export-hogels", full, "--frame", "7", "-o", "h7"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("full-frames-rgb-f32-zip.holo") && !d.join("h7").exists(), "{}", text(&o));
    let o = holo(&["import-hogels", "h7", "-o", "x.holo"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    std::fs::create_dir(d.join("empty")).unwrap();
    let o = holo(&["import-hogels", "empty", "-o", "x.holo"], d);
    assert!(text(&o).contains("no holo-hogels.json here") && !d.join("x.holo").exists(), "{}", text(&o));

    // As an HCI benchmark folder.
    let o = ok(holo(&["export-hci", full, "--frame", "1", "--white", "auto", "-o", "hci"], d));
    // 2 × 2 views 0.2 rad apart, 490 mm from the viewer: cameras 98.33 mm apart.
    assert!(
        text(&o)
            .contains("wrote 4 cameras (2 × 2, 98.33 mm apart, focused 490 mm away), parameters.cfg and holo-hci.json"),
        "{}",
        text(&o)
    );
    // What the benchmark's cameras cannot hold is said.
    assert!(text(&o).contains("warning: the horizontal views are 98.33 mm apart"), "{}", text(&o));
    for name in ["input_Cam000.png", "input_Cam003.png", "parameters.cfg", "holo-hci.json"] {
        assert!(d.join("hci").join(name).exists(), "{name}");
    }
    let cfg = std::fs::read_to_string(d.join("hci/parameters.cfg")).unwrap();
    assert!(cfg.contains("num_cams_x = 2\n") && cfg.contains("focus_distance_m = 0.49\n"), "{cfg}");
    let o = holo(&["export-hci", full, "-o", "hci"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    ok(holo(&["export-hci", full, "-o", "hci", "--force"], d));
    let o = holo(&["export-hci", flat.to_str().unwrap(), "-o", "flat"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("is horizontal parallax (3 views in a row)") && !d.join("flat").exists(), "{}", text(&o));
}

#[test]
fn layout_list_names_every_builtin_with_its_parallax_and_full_parallax_layouts_go_where_they_are_taken() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = ok(holo(&["layout", "--list"], d));
    let listing = text(&o);
    for name in holo::layout::BUILTIN {
        let line = listing.lines().find(|l| l.split_whitespace().next() == Some(name));
        let line = line.unwrap_or_else(|| panic!("{name} not listed:\n{listing}"));
        let full = holo::layout::builtin(name).unwrap().geometry.vertical_views.is_some();
        assert!(line.contains(if full { " full " } else { " horizontal " }), "{line}");
    }
    assert!(listing.contains("120 × 67") && listing.contains("16 × 16"), "{listing}");
    let o = ok(holo(&["layout", "--list", "--json"], d));
    let listed: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let listed = listed.as_array().unwrap();
    assert_eq!(listed.len(), holo::layout::BUILTIN.len());
    let chimera = listed.iter().find(|l| l["name"] == "chimera").unwrap();
    assert_eq!((chimera["parallax"].as_str(), chimera["vertical_views"].as_u64()), (Some("full"), Some(32)));
    assert!(chimera["basis"].is_null());
    let mark3 = listed.iter().find(|l| l["name"] == "mark3").unwrap();
    assert_eq!((mark3["parallax"].as_str(), mark3["basis"].as_str()), (Some("horizontal"), Some("chirp")));
    assert!(mark3.get("vertical_views").is_none());
    // A name and --list together is a usage error.
    assert_eq!(holo(&["layout", "mark3", "--list"], d).status.code(), Some(2));

    // A full-parallax profile prints, reads back, and is taken by the converter that makes full parallax ...
    let profile = ok(holo(&["layout", "pluto2-hogels"], d)).stdout;
    let text_profile = String::from_utf8(profile.clone()).unwrap();
    assert!(text_profile.contains("[geometry.vertical_views]") && !text_profile.contains("[fringe"), "{text_profile}");
    std::fs::write(d.join("hogels.toml"), &profile).unwrap();
    assert_eq!(ok(holo(&["layout", "hogels.toml"], d)).stdout, profile);
    // A HoloFlick made for a full-parallax display: its couch a rectangle of eyes, drawn with vertical views.
    ok(holo(&["holoflick", "encode", &spot(), "--layout", "mark1", "--vertical-views", "3", "-o", "e.hflk"], d));
    let args = ["convert", "holoflick", "e.hflk", "--layout", "mark1", "--vertical-views", "3", "-o", "h.holo"];
    let o = ok(holo(&args, d));
    assert!(!text(&o).contains("couch does not hold"), "made for the display: {}", text(&o));
    let h = holo::HoloFile::open(d.join("h.holo")).unwrap();
    assert_eq!((h.geometry().views.count, h.geometry().vertical_view_count()), (5, 3));
    // A pattern in both axes: the vertical view ramp rises from the lowest vertical view to the highest.
    ok(holo(&["pattern", "--layout", "hogels.toml", "--kind", "vertical-view-ramp", "-o", "ramp.holo"], d));
    let m = holo::read(d.join("ramp.holo")).unwrap();
    let g = m.geometry().clone();
    assert_eq!((m.get(0, 3, 5, g.view_index(7, 0)), m.get(0, 3, 5, g.view_index(7, 15))), (0.0, 1.0));
    let o = holo(&["pattern", "--layout", "mark1", "--kind", "vertical-view-ramp", "-o", "q.holo"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("needs a full-parallax layout") && !d.join("q.holo").exists(), "{}", text(&o));
    for cmd in ["mesh", "cameras"] {
        let input = if cmd == "mesh" { spot() } else { "x".to_string() };
        let o = holo(&["convert", cmd, &input, "--layout", "chimera", "--vertical-views", "4", "-o", "c.holo"], d);
        assert_eq!(o.status.code(), Some(1), "{cmd}: {}", text(&o));
        assert!(text(&o).contains("full parallax already"), "{cmd}: {}", text(&o));
    }
    // A fringe side on a full-parallax geometry is refused wherever a layout is loaded.
    let with_fringe = ok(holo(&["layout", "mark3"], d)).stdout;
    let vertical =
        "\n[geometry.vertical_views]\ncount = 4\nfirst_theta_rad = -0.1\nlast_theta_rad = 0.1\nspacing = \"tan\"\n";
    let mut full = String::from_utf8(with_fringe).unwrap().replace("parallax = \"horizontal\"", "parallax = \"full\"");
    let at = full.find("\n[geometry.views]").unwrap();
    full.insert_str(at, vertical);
    std::fs::write(d.join("full3.toml"), full).unwrap();
    let o = holo(&["layout", "full3.toml"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("has no fringe side yet"), "{}", text(&o));
    assert!(!["m.holo", "p.holo", "c.holo"].iter().any(|f| d.join(f).exists()));
}
