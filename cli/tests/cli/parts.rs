//! The command line's parts one by one, through `holo_cli::parts`: value
//! parsers, and the demo's drawing (canvas, labels, animations, the fringe
//! picture's legend, the font) and viewing zone.

use std::ffi::OsStr;

use clap::builder::TypedValueParser;
use clap::{Arg, Command};
use holo::picture::White;
use holo::reconstruct::picture::Picture;
use holo::Modulation;
use holo_cli::parts::*;

fn parse<T: Clone + Send + Sync + 'static>(p: Checked<T>, s: &str) -> Result<T, String> {
    let arg = Arg::new("fps").long("fps");
    p.parse_ref(&Command::new("t"), Some(&arg), OsStr::new(s)).map_err(|e| e.to_string())
}

#[test]
fn values_are_converted_and_refused_with_their_meaning() {
    assert_eq!(parse(positive(), "30").unwrap(), 30.0);
    let e = parse(positive(), "-30").unwrap_err();
    assert!(e.contains("--fps must be positive, not -30"), "{e}");
    assert_eq!(parse(frame_rate(), "24000/1001").unwrap(), 24000.0 / 1001.0);
    assert_eq!(parse(frame_rate(), "12.5").unwrap(), 12.5);
    let e = parse(frame_rate(), "30/0").unwrap_err();
    assert!(e.contains("--fps must be a positive number or a fraction"), "{e}");
    assert_eq!(parse(positive_millimetres(), "4").unwrap(), 4e-3);
    assert_eq!(parse(millimetre_triple(), "-1,0,2").unwrap(), [-1e-3, 0.0, 2e-3]);
    assert!(parse(millimetre_triple(), "1,2").is_err());
    assert!(parse(millimetre_triple(), "1,2,3,4").is_err());
    assert!(parse(millimetre_triple(), "1,x,3").is_err());
    assert_eq!(parse(eye_millimetres(), "-40").unwrap(), (-0.04, 0.0));
    assert_eq!(parse(eye_millimetres(), "-20,5").unwrap(), (-0.02, 0.005));
    assert_eq!(parse(range(), "2..=4").unwrap(), 2..5);
    assert!(parse(range(), "3..1").is_err());
    assert_eq!(parse(by(64, true), "3").unwrap(), (3, 3));
    assert!(parse(by(64, false), "3").is_err());
    assert_eq!(parse(white(), "auto").unwrap(), White::Auto);
    assert_eq!(parse(white(), "max").unwrap(), White::Max);
    assert_eq!(parse(white(), "0.5").unwrap(), White::Value(0.5));
    assert!(parse(white(), "-1").unwrap_err().contains("must be auto, max or a finite positive number"));
    assert_eq!(parse(white_number(), "0.5").unwrap(), 0.5);
    assert!(parse(white_number(), "auto").unwrap_err().contains("exported with"));
    assert!(parse(whole(1, 16), "17").unwrap_err().contains("must be 1 to 16"));
    let m = parse(matrix(), "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16").unwrap();
    assert_eq!((m[0][3], m[3][0]), (4.0, 13.0));
}

#[test]
fn a_layout_file_that_is_not_there_is_named() {
    let Err(Failure(e)) = load_layout("nowhere/x.toml") else { panic!("loaded") };
    assert!(e.starts_with("nowhere/x.toml: no such file"), "{e}");
    let Err(Failure(e)) = load_layout("mark9") else { panic!("loaded") };
    assert!(e.contains("unknown layout"), "{e}");
    assert!(load_layout("mark1-hogel").is_ok());
}

#[test]
fn labels_land_where_they_are_drawn() {
    let mut c = Canvas::new(20, 12, true);
    c.text(2, 1, 1, "-", WHITE);
    // The minus sign is the glyph's fourth row, five pixels wide.
    let lit: Vec<(usize, usize)> =
        (0..12).flat_map(|y| (0..20).map(move |x| (x, y))).filter(|&(x, y)| c.rgb[y * 20 + x][0] > 0.0).collect();
    assert_eq!(lit, (2..7).map(|x| (x, 4)).collect::<Vec<_>>());
    c.text(0, 0, 2, "1", [1.0, 0.0, 0.0]);
    assert!(!c.grey, "a red label makes the canvas colour");
    assert_eq!(c.rgb[4], [1.0, 0.0, 0.0], "the 1's top, scaled by two");
}

#[test]
fn pictures_shrink_keeping_their_proportions() {
    // 4 emitters twice as wide as the 3 hololines are tall: 8 × 3 square pixels.
    let picture = Picture {
        emitters: 4,
        hololines: 3,
        channels: vec!["Y".into()],
        column_aspect: 2.0,
        data: (0..12).map(|i| i as f32 / 12.0).collect(),
    };
    let full = Canvas::from_picture(&picture, 1);
    assert_eq!((full.width, full.height, full.grey), (8, 3, true));
    assert_eq!(full.rgb[8 + 3], [5.0 / 12.0; 3], "row 1, emitter 1");
    let half = Canvas::from_picture(&picture, 2);
    assert_eq!((half.width, half.height), (4, 1));
    assert!(half.rgb[0].iter().all(|v| (v - 8.0 / 48.0).abs() < 1e-6), "{:?}", half.rgb[0]);
}

#[test]
fn an_animation_holds_its_frames() {
    let frames: Vec<Canvas> = (0..3)
        .map(|k| {
            let mut c = Canvas::new(6, 9, true);
            c.text(0, 1, 1, &k.to_string(), WHITE);
            c
        })
        .collect();
    let bytes = apng(&frames, 0.1, 0).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes)).read_info().unwrap();
    assert_eq!(reader.info().animation_control.map(|a| a.num_frames), Some(3));
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let mut seen = Vec::new();
    while reader.next_frame(&mut buf).is_ok() {
        seen.push(buf.clone());
    }
    assert_eq!(seen.len(), 3);
    assert!(seen[0] != seen[1] && seen[1] != seen[2]);
    let err = apng(&[Canvas::new(2, 2, true), Canvas::new(3, 2, true)], 0.1, 0).unwrap_err().to_string();
    assert!(err.contains("2×2 and 3×2"), "{err}");
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn the_legend_says_what_the_colours_zones_and_lobes_are() {
    let layout = holo::layout::mark3();
    let a = holo::assemble::Assembler::new(&layout).unwrap();
    // Two stretches of lit emitters on every hololine, every view.
    let lit = |e: usize| (40..100).contains(&e) || (150..230).contains(&e);
    let m =
        Modulation::from_fn(layout.geometry.clone(), |_, _, e, v| if lit(e) { 0.2 + 0.005 * v as f32 } else { 0.0 })
            .unwrap();
    let (images, _) = a.assemble::<u8>(&m).unwrap();
    let picture = fringe_picture(&a, &images).unwrap();
    let legend = picture.legend.join("\n");
    // Spec/layouts.md §7.1: head 1 R, G = zone 1 sine, cosine; B = zone 2 sine.
    assert!(legend.contains("head1: yellow = zone1 (red sin, green cos), blue = zone2 (blue sin)"), "{legend}");
    assert!(legend.contains("head2: yellow = zone3 (red sin, green cos), blue = zone2 (blue cos)"), "{legend}");
    // Zone 1 carries the views toward +θ, zone 3 those toward −θ.
    assert!(legend.contains("zone1: views +4.") && legend.contains("to +11.9 deg"), "{legend}");
    assert!(legend.contains("zone3: views -11.9 to -4."), "{legend}");
    assert_eq!(picture.lobes.len(), 2, "{legend}");
    for (lobe, want) in picture.lobes.iter().zip([40..100, 150..230]) {
        assert!(lobe.start.abs_diff(want.start) <= 3 && lobe.end.abs_diff(want.end) <= 3, "{lobe:?}: {legend}");
    }
    assert!(legend.contains("lobes: the bright stretches") && legend.contains("emitters 4"), "{legend}");
    let chars = line_chars(picture.canvas.width);
    for line in &picture.legend {
        assert!(font::covers(line) && line.chars().count() <= chars, "{line:?}");
    }
    // Drawn: the rows under the thumbnails are no longer black.
    let th = images.height / THUMBNAIL_SHRINK;
    let below = (MARGIN + label_height() + th + MARGIN) * picture.canvas.width;
    let lit_pixels =
        picture.canvas.rgb[below..below + label_height() * picture.canvas.width].iter().filter(|p| p[0] > 0.5).count();
    assert!(lit_pixels > 100, "{lit_pixels}");
}

#[test]
fn the_eyes_span_where_the_whole_scene_is_seen() {
    let layout = holo::layout::mark3();
    let g = &layout.geometry;
    let d = g.viewer_distance_m - g.emitter_z_m;
    let half_tan = g.views.last_theta_rad.tan();
    // Emitters lit from −10 to +10 mm: seen in the views from eyes within
    // ±(d·tan θ_last − 10 mm).
    let m = Modulation::from_fn(g.clone(), |_, _, e, _| f32::from(g.emitter_x_m(e).abs() <= 0.010)).unwrap();
    let eyes = viewing_zone_eyes_x_m(&m, 5);
    let x_lit = (0..g.emitters).map(|e| g.emitter_x_m(e)).filter(|x| x.abs() <= 0.010);
    let (lo, hi) = x_lit.fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
    assert!((eyes[0] - (hi - d * half_tan)).abs() < 1e-9, "{eyes:?}");
    assert!((eyes[4] - (lo + d * half_tan)).abs() < 1e-9, "{eyes:?}");
    assert!((eyes[2] - 0.5 * (eyes[0] + eyes[4])).abs() < 1e-12);
    // Nothing lit: the zone of the middle of the display.
    let dark = Modulation::zeros(g.clone()).unwrap();
    let eyes = viewing_zone_eyes_x_m(&dark, 2);
    let middle = 0.5 * (g.emitter_x_m(0) + g.emitter_x_m(g.emitters - 1));
    assert!((eyes[1] - (middle + d * half_tan)).abs() < 1e-9, "{eyes:?}");
}

/// A text drawn as rows of `#` and `.`.
fn drawn(text: &str) -> Vec<String> {
    let mut rows = vec![vec!['.'; font::width(text)]; font::GLYPH_SIZE.1];
    for (x, y) in font::lit(text) {
        rows[y][x] = '#';
    }
    rows.into_iter().map(|r| r.into_iter().collect()).collect()
}

#[test]
fn digits_and_signs_are_drawn_as_their_shapes() {
    assert_eq!(
        drawn("-1x"),
        [
            "........#........",
            ".......##........",
            "........#...#...#",
            "#####...#....#.#.",
            "........#.....#..",
            "........#....#.#.",
            ".......###..#...#",
            ".................",
        ]
    );
    assert_eq!(font::width("x = -120 mm"), 11 * 6 - 1);
}

#[test]
fn every_glyph_is_distinct_and_within_five_columns() {
    for (k, (c, rows)) in font::GLYPHS.iter().enumerate() {
        assert!(rows.iter().all(|r| r >> font::GLYPH_SIZE.0 == 0), "{c:?} is wider than 5");
        for (d, other) in &font::GLYPHS[k + 1..] {
            assert!(rows != other, "{c:?} and {d:?} look the same");
        }
    }
}

#[test]
fn a_missing_character_is_a_box_and_is_told() {
    assert!(font::covers("eye x = +12 mm, frame 2 (head1): 0.5"));
    assert!(!font::covers("θ"));
    assert_eq!(font::lit("θ").count(), 40);
}
