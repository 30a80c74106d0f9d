//! The pictures holo writes, as a user looks at them.

use super::{holo, ok, small_profile, text};

/// Tile `i`'s centre pixel of a quilt (view 0 bottom left, row by row up).
fn tile_centre(quilt: &image::RgbImage, columns: u32, rows: u32, i: u32) -> [u8; 3] {
    let (w, h) = (quilt.width() / columns, quilt.height() / rows);
    let (col, row) = (i % columns, rows - 1 - i / columns);
    quilt.get_pixel(col * w + w / 2, row * h + h / 2).0
}

/// By default a quilt spans the file's own views: every tile shows one, and
/// nothing is said; a cone wider or narrower than the views is said, with
/// the cone that fits.
#[test]
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
    assert!(!text(&o).contains("warning"), "{}", text(&o));
    assert!(text(&o).contains("a 23.8° view cone"), "{}", text(&o));
    let fit = image::open(d.join("fit.png")).unwrap().to_rgb8();
    for i in 0..48 {
        assert!(tile_centre(&fit, 8, 6, i) != [0, 0, 0], "tile {i} is black");
    }
    let o = ok(holo(&["export-quilt", "c.holo", "-o", "wide.png", "--view-cone", "35"], d));
    assert!(
        text(&o).contains("16 of 48 tiles look from beyond the file's views") && text(&o).contains("23.8°"),
        "{}",
        text(&o)
    );
    let wide = image::open(d.join("wide.png")).unwrap().to_rgb8();
    assert_eq!((0..48).filter(|&i| tile_centre(&wide, 8, 6, i) == [0, 0, 0]).count(), 16);
    let o = ok(holo(&["export-quilt", "c.holo", "-o", "narrow.png", "--view-cone", "10"], d));
    assert!(text(&o).contains("56 of the file's 96 views lie outside the quilt's 10.0°"), "{}", text(&o));
}
