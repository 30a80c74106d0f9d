//! The pictures holo writes, as a user looks at them.

use std::path::Path;

use holo::picture::decode::{self, Decoded};

use super::{holo, ok, small_profile, text};

/// A picture read back as 8-bit RGB.
struct Rgb8 {
    width: usize,
    height: usize,
    samples: Vec<u8>,
}

impl Rgb8 {
    fn open(path: &Path) -> Rgb8 {
        let picture = decode::open(path).unwrap();
        Rgb8 { width: picture.width, height: picture.height, samples: picture.rgb8() }
    }

    fn get(&self, x: usize, y: usize) -> [u8; 3] {
        let at = 3 * (y * self.width + x);
        [self.samples[at], self.samples[at + 1], self.samples[at + 2]]
    }
}

/// Tile `i`'s centre pixel of a quilt (view 0 bottom left, row by row up).
fn tile_centre(quilt: &Rgb8, columns: usize, rows: usize, i: usize) -> [u8; 3] {
    let (w, h) = (quilt.width / columns, quilt.height / rows);
    let (col, row) = (i % columns, rows - 1 - i / columns);
    quilt.get(col * w + w / 2, row * h + h / 2)
}

/// By default a quilt spans the file's own views: every tile shows one, and
/// only the outer tiles' view of the display's far side, beyond the views, is
/// said; a cone wider or narrower than the views is said, with the cone that
/// fits.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn a_quilt_fits_the_file_s_views_by_default() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = small_profile(d, 40);
    // Every view of the middle emitters lit (views span ±11.9° in Mark III).
    ok(holo(
        &["pattern", "--layout", profile.to_str().unwrap(), "--kind", "checkerboard", "--cell", "400", "-o", "c.holo"],
        d,
    ));
    let o = ok(holo(&["export-quilt", "c.holo", "-o", "fit.png"], d));
    assert!(!text(&o).contains("look from beyond the file's views"), "{}", text(&o));
    // What is said: the outer tiles see the display's far side beyond the views.
    assert!(text(&o).contains("16 of 48 tiles see part of the display from beyond"), "{}", text(&o));
    assert!(text(&o).contains("a 23.8° view cone"), "{}", text(&o));
    let fit = Rgb8::open(&d.join("fit.png"));
    for i in 0..48 {
        assert!(tile_centre(&fit, 8, 6, i) != [0, 0, 0], "tile {i} is black");
    }
    let o = ok(holo(&["export-quilt", "c.holo", "-o", "wide.png", "--view-cone", "35"], d));
    assert!(
        text(&o).contains("16 of 48 tiles look from beyond the file's views") && text(&o).contains("23.8°"),
        "{}",
        text(&o)
    );
    let wide = Rgb8::open(&d.join("wide.png"));
    assert_eq!((0..48).filter(|&i| tile_centre(&wide, 8, 6, i) == [0, 0, 0]).count(), 16);
    let o = ok(holo(&["export-quilt", "c.holo", "-o", "narrow.png", "--view-cone", "10"], d));
    assert!(text(&o).contains("56 of the file's 96 views lie outside the quilt's 10.0°"), "{}", text(&o));
}

/// The bounding box (columns, rows) of the pixels brighter than half of the
/// brightest in `rect` (x0, y0, width, height) of a picture.
fn lit_box(img: &Decoded, rect: (usize, usize, usize, usize)) -> (f64, f64) {
    let grey = img.grey8();
    let at = |x: usize, y: usize| grey[y * img.width + x];
    let (x0, y0, w, h) = rect;
    let peak = (y0..y0 + h).flat_map(|y| (x0..x0 + w).map(move |x| (x, y))).map(|(x, y)| at(x, y)).max();
    let half = peak.unwrap() / 2;
    let lit: Vec<(usize, usize)> =
        (y0..y0 + h).flat_map(|y| (x0..x0 + w).map(move |x| (x, y))).filter(|&(x, y)| at(x, y) > half).collect();
    let (xs, ys): (Vec<usize>, Vec<usize>) = lit.into_iter().unzip();
    let span = |v: &[usize]| (v.iter().max().unwrap() - v.iter().min().unwrap() + 1) as f64;
    (span(&xs), span(&ys))
}

/// A pHYs chunk's pixels per metre, x and y.
fn pixels_per_metre(png: &[u8]) -> (f64, f64) {
    let at = png.windows(4).position(|w| w == b"pHYs").expect("a pHYs chunk");
    let word = |k: usize| f64::from(u32::from_be_bytes(png[at + 4 + k..at + 8 + k].try_into().unwrap()));
    assert_eq!(png[at + 12], 1, "pHYs in metres");
    (word(0), word(4))
}

/// A 20 mm square, lit in every view, on Mark III's grid (emitters 0.238 mm
/// apart, hololines 0.136 mm): every picture shows it square, within 2%.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn pictures_show_a_square_square() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let profile = small_profile(d, 160);
    let g = holo::layout::Layout::load(profile.to_str().unwrap()).unwrap().geometry;
    // Centred on the hololines the profile keeps (its top stays Mark III's).
    let y_mid = 0.5 * (g.hololine_y_m(0) + g.hololine_y_m(g.hololines - 1));
    let m = holo::Modulation::from_fn(g.clone(), |_, j, e, _| {
        f32::from(g.emitter_x_m(e).abs() < 0.010 && (g.hololine_y_m(j) - y_mid).abs() < 0.010)
    })
    .unwrap();
    holo::format::write(d.join("square.holo"), &m, &holo::WriteOptions::default()).unwrap();
    let square_within = |what: &str, (w, h): (f64, f64)| {
        assert!((w / h - 1.0).abs() < 0.02, "{what}: the square is {w:.1} × {h:.1}, {:.3} wide for its height", w / h);
    };

    // The .holo file itself: one pixel per emitter and hololine, shown at its
    // pixelAspectRatio (a pixel's width over its height) by EXR viewers.
    let file = holo::HoloFile::open(d.join("square.holo")).unwrap();
    let aspect = file.info().pixel_aspect;
    let frame = file.read_frame(0).unwrap();
    let (mut columns, mut rows) = (std::collections::BTreeSet::new(), std::collections::BTreeSet::new());
    for j in 0..g.hololines {
        for e in 0..g.emitters {
            if frame.get(0, j, e, g.views.count / 2) > 0.5 {
                columns.insert(e);
                rows.insert(j);
            }
        }
    }
    square_within(".holo (pixelAspectRatio)", (columns.len() as f64 * f64::from(aspect), rows.len() as f64));
    let o = ok(holo(&["validate", "square.holo"], d));
    assert!(!text(&o).contains("pixel aspect"), "{}", text(&o));

    // export-views: one pixel per emitter and hololine, the physical size in pHYs.
    ok(holo(&["export-views", "square.holo", "-o", "views"], d));
    let png = std::fs::read(d.join("views/view_048.png")).unwrap();
    assert!(png.windows(4).any(|w| w == b"sRGB"), "export-views: no sRGB chunk");
    let (xppm, yppm) = pixels_per_metre(&png);
    let img = decode::decode(std::io::Cursor::new(&png)).unwrap();
    let (w, h) = lit_box(&img, (0, 0, img.width, img.height));
    square_within("export-views (pHYs)", (w / xppm, h / yppm));

    // view: square pixels.
    ok(holo(&["view", "square.holo", "--layout", profile.to_str().unwrap(), "-o", "eye.png"], d));
    let img = decode::open(&d.join("eye.png")).unwrap();
    square_within("view", lit_box(&img, (0, 0, img.width, img.height)));
    // view --coherent: the same shape, another picture (neighbours interfere).
    ok(holo(
        &["view", "square.holo", "--layout", profile.to_str().unwrap(), "--coherent", "-o", "eye-coherent.png"],
        d,
    ));
    let coherent = decode::open(&d.join("eye-coherent.png")).unwrap();
    square_within("view --coherent", lit_box(&coherent, (0, 0, coherent.width, coherent.height)));
    assert_ne!(coherent.rgb8(), img.rgb8(), "--coherent changed nothing");

    // export-quilt: the middle tile, shown at the preset's aspect (square pixels).
    ok(holo(&["export-quilt", "square.holo", "-o", "q.png"], d));
    let img = decode::open(&d.join("q.png")).unwrap();
    let (tw, th) = (img.width / 8, img.height / 6);
    square_within("export-quilt", lit_box(&img, (4 * tw, 3 * th, tw, th)));
}
