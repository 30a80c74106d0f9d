//! What a new user meets first, from the README and `--help` alone: lights
//! that say what they replace and which way they shine, a scene placed in
//! the unit `--scale` takes and said when it leaves the display, `holoflick
//! encode` placed as `convert mesh` is, quilts that say which tiles are cut,
//! `check` with a verdict, every argument checked before the output, and
//! messages that name flags, never the library's types.

use std::path::Path;

use super::{fixture, holo, ok, spot, text};

/// The line of `out` that starts with `start`.
fn line<'a>(out: &'a str, start: &str) -> &'a str {
    out.lines().find(|l| l.starts_with(start)).unwrap_or_else(|| panic!("no line {start:?} in:\n{out}"))
}

#[test]
fn a_light_given_says_it_replaces_the_default_lights_and_dir_says_where_light_goes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let help = text(&ok(holo(&["convert", "mesh", "--help"], d)));
    for words in ["replace the two default lights", "dir:1,-1,-1", "travelling along DX,DY,DZ, the way its light goes"]
    {
        assert!(help.contains(words), "{words}: {help}");
    }
    let spot = &spot();
    let o = text(&ok(holo(&["convert", "mesh", spot, "--layout", "mark1", "-o", "a.holo", "--supersample", "1"], d)));
    assert!(!o.contains("note:"), "{o}");
    let args = ["convert", "mesh", spot, "--layout", "mark1", "-o", "b.holo", "--supersample", "1"];
    let o = text(&ok(holo(&[&args[..], &["--light", "dir:0,0,-1"]].concat(), d)));
    assert!(
        o.contains(
            "holo: note: the lights given replace the default ones (--light dir:1,-1,-1 --light ambient:0.08,0.08,0.08)"
        ),
        "{o}"
    );
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn placement_is_said_in_millimetres_and_a_scene_beyond_the_display_is_warned() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spot = &spot();
    let base = ["convert", "mesh", spot, "--layout", "mark1", "--supersample", "1"];
    let fitted = text(&ok(holo(&[&base[..], &["-o", "fit.holo"]].concat(), d)));
    assert!(line(&fitted, "placed at ").contains(" display mm per scene unit"), "{fitted}");
    assert!(!fitted.contains("leaves the display"), "{fitted}");
    // Mark I's 5 views resolve little depth, and its hololines span 19 mm: 20 mm a
    // unit puts the cow's head and feet beyond them.
    let large = text(&ok(holo(&[&base[..], &["-o", "large.holo", "--scale", "20"]].concat(), d)));
    assert!(line(&large, "placed at ").starts_with("placed at 20 display mm per scene unit"), "{large}");
    assert!(large.contains("spot.obj: placed, the scene leaves the display's volume: y from"), "{large}");
    assert!(large.contains("y up to +17.0 mm, beyond the display's edge at +9.6 mm (cut off)"), "{large}");
    assert!(large.contains("the views resolve (blurred)"), "{large}");
    // The same warning from holoflick encode, which places alike.
    let o = text(&ok(holo(&["holoflick", "encode", spot, "--layout", "mark1", "-o", "l.hflk", "--scale", "20"], d)));
    assert!(o.contains("leaves the display's volume: y from"), "{o}");
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn holoflick_encode_places_the_scene_as_convert_mesh_does() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spot = &spot();
    let matrix = "0.01,0,0,0.002,0,0.01,0,0,0,0,0.01,0,0,0,0,1";
    for (k, placement) in [
        &["--scale", "10"][..],
        &["--rotate", "0,-60,0"],
        &["--rotate", "0,90,0", "--translate", "0,5,-2"],
        &["--matrix", matrix],
    ]
    .into_iter()
    .enumerate()
    {
        let holo_out = format!("m{k}.holo");
        let mesh = ["convert", "mesh", spot, "--layout", "mark1", "--supersample", "1", "-o", &holo_out];
        let mesh = text(&ok(holo(&[&mesh[..], placement].concat(), d)));
        let hflk = format!("e{k}.hflk");
        let encode = text(&ok(holo(
            &[&["holoflick", "encode", spot, "--layout", "mark1", "-o", &hflk][..], placement].concat(),
            d,
        )));
        assert_eq!(line(&encode, "placed at "), line(&mesh, "placed at "), "{placement:?}");
        // The file records the placement chosen.
        let info = text(&ok(holo(&["holoflick", "info", &hflk], d)));
        assert!(info.contains(line(&mesh, "placed at ")), "{placement:?}: {info}");
    }
    // Fitted, nothing chosen: the provenance is as it was.
    ok(holo(&["holoflick", "encode", spot, "--layout", "mark1", "-o", "fit.hflk"], d));
    let info = text(&ok(holo(&["holoflick", "info", "fit.hflk"], d)));
    assert!(!info.contains("placed at"), "{info}");
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn export_quilt_says_which_tiles_see_the_display_from_beyond_its_views() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark3", "--kind", "view-ramp", "-o", "ramp.holo"], d));
    let o = text(&ok(holo(&["export-quilt", "ramp.holo", "-o", "q.png"], d)));
    assert!(o.contains("of 48 tiles see part of the display from beyond the file's views"), "{o}");
    assert!(o.contains("views 0–") && o.contains("–47 are black there, with a hard edge"), "{o}");
    let cone = o.split("a view cone of ").nth(1).and_then(|t| t.split('°').next()).expect("a cone said");
    // The cone said shows every tile whole (and leaves the outer views out, as is said).
    let o = text(&ok(holo(&["export-quilt", "ramp.holo", "-o", "whole.png", "--view-cone", cone], d)));
    assert!(!o.contains("beyond") && o.contains("views lie outside the quilt's"), "{o}");
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn check_judges_the_figures_by_the_spec_s_bounds() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "--level", "0.8", "-o", "ramp.holo"], d));
    let o = text(&ok(holo(&["check", "ramp.holo", "--layout", "mark1"], d)));
    assert_eq!(o.matches("    pass: ").count(), 2, "{o}");
    assert!(o.contains("is below the bound 1.2%") && o.contains("is below the bound 6.0%"), "{o}");
    assert!(o.contains("verdict: pass (the bounds of spec/layouts.md §9.1 for mark1, 8-bit fringes)"), "{o}");
    let o = ok(holo(&["check", "ramp.holo", "--layout", "mark1", "--json"], d));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["verdict"]["pass"], true);
    assert_eq!(json["verdict"]["bounds"]["signal"], 0.012);
    // Far brighter than the 8-bit quantization holds: clipped, and failed.
    ok(holo(&["pattern", "--layout", "mark1", "--kind", "view-ramp", "--level", "40", "-o", "hot.holo"], d));
    let o = holo(&["check", "hot.holo", "--layout", "mark1"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(
        text(&o).contains("FAIL") && text(&o).contains("outside the bounds of spec/layouts.md §9.1"),
        "{}",
        text(&o)
    );
    let o = ok(holo(&["check", "hot.holo", "--layout", "mark1", "--report-only", "--json"], d));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(json["verdict"]["pass"], false);
    // A layout the spec states no bound for: figures only, exit 0.
    ok(holo(&["pattern", "--layout", "mark1-hogel", "--kind", "view-ramp", "-o", "hogel.holo"], d));
    let o = text(&ok(holo(&["check", "hogel.holo", "--layout", "mark1-hogel", "--hololines", "0..2"], d)));
    assert!(o.contains("verdict: none (spec/layouts.md §9.1 states bounds for mark3 and mark1"), "{o}");
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn check_takes_the_frames_of_a_movie() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cube = fixture("mesh/AnimatedMorphCube.glb");
    let cube = cube.to_str().unwrap();
    let convert =
        ["convert", "mesh", cube, "--layout", "mark1", "--fps", "0.5", "--supersample", "1", "-o", "cube.holo"];
    ok(holo(&convert, d));
    let o = text(&ok(holo(&["check", "cube.holo", "--layout", "mark1", "--frames", "0..3"], d)));
    assert_eq!(o.matches("verdict: pass").count(), 3, "{o}");
    assert!(o.contains("cube.holo frame 2 on layout mark1") && o.contains("verdict over frames 0..3: pass"), "{o}");
    let o = ok(holo(&["check", "cube.holo", "--layout", "mark1", "--frames", "1..=2", "--json"], d));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!((json["frames"].as_array().unwrap().len(), &json["pass"]), (2, &serde_json::Value::Bool(true)));
    assert_eq!(json["frames"][1]["frame"], 2);
    let o = holo(&["check", "cube.holo", "--layout", "mark1", "--frames", "2..5"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("cube.holo") && text(&o).contains("2..5"), "{}", text(&o));
    let o = holo(&["check", "cube.holo", "--frame", "1", "--frames", "0..2"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

/// Pictures for a capture folder.
fn pictures(d: &Path, names: &[&str]) {
    std::fs::create_dir_all(d).unwrap();
    for name in names {
        let mut png = Vec::new();
        let mut encoder = png::Encoder::new(&mut png, 8, 6);
        encoder.set_color(png::ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        writer.write_image_data(&[90, 120, 60].repeat(8 * 6)).unwrap();
        writer.finish().unwrap();
        std::fs::write(d.join(name), png).unwrap();
    }
}

#[test]
fn messages_name_flags_never_the_library_s_types() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    pictures(&d.join("rail"), &["a.png", "b.png"]);
    pictures(&d.join("stanford"), &["out_00_00_-10.0_-10.0_.png", "out_00_01_-10.0_10.0_.png"]);
    let convert = |capture: &str, more: &[&str]| {
        let args = [&["convert", "cameras", capture, "--layout", "mark1", "-o", "c.holo"][..], more].concat();
        let o = holo(&args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        text(&o)
    };
    let cases = [
        (convert("rail", &[]), "--baseline"),
        (convert("rail", &["--baseline", "1"]), "--focal-px or --fov"),
        (convert("stanford", &[]), "--focal-px or --fov"),
        (convert("stanford", &["--focal-px", "10"]), "--focus"),
    ];
    for (message, flag) in &cases {
        assert!(message.contains(flag), "{flag}: {message}");
        assert_eq!(message.lines().count(), 1, "{message}");
        for library in ["Options", "CameraHints", "focal_length_px", "horizontal_fov_deg", "focus_distance", "::"] {
            assert!(!message.contains(library), "{library}: {message}");
        }
    }
    let o = holo(&["convert", "cameras", "rail", "-o", "c.holo", "--focal-px", "10", "--fov", "40"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}

#[test]
fn every_argument_is_checked_before_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in ["exists.holo", "exists.hflk", "exists.png"] {
        std::fs::write(d.join(name), b"a file of the user's").unwrap();
    }
    pictures(&d.join("rail"), &["a.png", "b.png"]);
    let spot = &spot();
    let unknown = "unknown layout \"mark9\"";
    for (args, said) in [
        (&["convert", "mesh", spot, "--layout", "mark9", "-o", "exists.holo"][..], unknown),
        (&["convert", "cameras", "rail", "--layout", "mark9", "-o", "exists.holo"], unknown),
        (&["convert", "holoflick", "x.hflk", "--layout", "mark9", "-o", "exists.holo"], unknown),
        (&["holoflick", "encode", spot, "--layout", "mark9", "-o", "exists.hflk"], unknown),
        (&["pattern", "--layout", "mark9", "--kind", "view-ramp", "-o", "exists.holo"], unknown),
        (&["convert", "mesh", "missing.obj", "--layout", "mark1", "-o", "exists.holo"], "missing.obj"),
        (&["convert", "mesh", spot, "--light", "dir:0,0,0", "-o", "exists.holo"], "zero direction"),
        (&["convert", "holoflick", "missing.hflk", "-o", "exists.holo"], "missing.hflk"),
        (&["holoflick", "encode", "missing.obj", "-o", "exists.hflk"], "missing.obj"),
        (&["holoflick", "pack", "missing.obj", "-o", "exists.hflk"], "missing.obj"),
        (&["export-quilt", "missing.holo", "-o", "exists.png", "--view-cone", "20"], "missing.holo"),
        (&["view", "missing.holo", "-o", "exists.png"], "missing.holo"),
        (&["import-views", "no-views", "--geometry", "mark1", "-o", "exists.holo"], "no-views"),
    ] {
        let o = holo(args, d);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {}", text(&o));
        assert!(text(&o).contains(said) && !text(&o).contains("already exists"), "{args:?}: {}", text(&o));
    }
    for name in ["exists.holo", "exists.hflk", "exists.png"] {
        assert_eq!(std::fs::read(d.join(name)).unwrap(), b"a file of the user's");
    }
}

/// A 2-D capture made full parallax: an HCI folder without its
/// parameters.cfg asks for the numbers it lacks by their flags, then
/// converts with `--vertical-views` into a file that says it is full
/// parallax (and the command line that makes it again) and is valid, which
/// `convert like` makes again with the same content; `--vertical-cone`
/// alone is a usage error.
#[test]
fn a_grid_of_pictures_converts_to_full_parallax() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let names: Vec<String> = (0..9).map(|n| format!("input_Cam{n:03}.png")).collect();
    pictures(&d.join("grid"), &names.iter().map(String::as_str).collect::<Vec<_>>());
    let o = holo(&["convert", "cameras", "grid", "--layout", "mark1", "--vertical-views", "3", "-o", "fp.holo"], d);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("parameters.cfg") && text(&o).contains("--baseline"), "{}", text(&o));
    let o = holo(&["convert", "cameras", "grid", "--layout", "mark1", "--vertical-cone", "20", "-o", "fp.holo"], d);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    let args =
        ["--baseline", "0.1", "--focal-px", "10", "--focus", "2", "--vertical-views", "3", "--vertical-cone", "20"];
    let convert = [&["convert", "cameras", "grid", "--layout", "mark1", "-o", "fp.holo"][..], &args].concat();
    ok(holo(&convert, d));
    let info = text(&ok(holo(&["info", "fp.holo"], d)));
    assert!(info.contains("full parallax") && info.contains("× 3 views"), "{info}");
    assert!(info.contains("-10.000° … 10.000°"), "the vertical cone asked for: {info}");
    assert!(info.contains("--layout mark1 -o OUT.holo --vertical-views 3 --vertical-cone 20"), "{info}");
    assert!(holo::validate(d.join("fp.holo")).unwrap().is_valid());
    // Made again from what the file records: the same views, digest by digest.
    let again = text(&ok(holo(&["convert", "like", "fp.holo", "-o", "again.holo"], d)));
    assert!(again.contains("same content as fp.holo: yes"), "{again}");
}
