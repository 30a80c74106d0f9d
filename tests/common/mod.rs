//! Helpers shared by the integration tests.

// Each test binary uses its own subset of these helpers.
#![allow(dead_code)]

use std::path::PathBuf;

/// The shared test data folder (`$HOLO_SHARED_DATA`, else `../shared/data`),
/// or `None` when it is not there: tests then say plainly what did not run.
///
/// With `HOLO_REQUIRE_DATA=1` (CI sets it) a missing folder is a failure, not
/// a skip, so a run without the data cannot pass silently.
pub fn shared_data() -> Option<PathBuf> {
    let d = std::env::var("HOLO_SHARED_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data")));
    if d.is_dir() {
        return Some(d);
    }
    assert!(
        std::env::var("HOLO_REQUIRE_DATA").as_deref() != Ok("1"),
        "HOLO_REQUIRE_DATA=1 but the shared test data folder {} is not there",
        d.display()
    );
    None
}

/// A file of the shared data that is not there: said plainly, and a failure
/// when `HOLO_REQUIRE_DATA=1`.
pub fn missing(what: &str) {
    assert!(std::env::var("HOLO_REQUIRE_DATA").as_deref() != Ok("1"), "{what} is missing and HOLO_REQUIRE_DATA=1");
    println!("SKIPPED: {what} not present");
}

/// The samples of `pixel(x, y)` for every pixel of a `width × height`
/// picture, row by row from the top: what [`png8`] and [`png16`] take.
pub fn pixels<T, const N: usize>(width: u32, height: u32, pixel: impl Fn(u32, u32) -> [T; N]) -> Vec<T> {
    (0..height).flat_map(|y| (0..width).map(move |x| (x, y))).flat_map(|(x, y)| pixel(x, y)).collect()
}

/// A PNG of `width × height` pixels of `channels` 8-bit samples each (1
/// grey, 2 grey and alpha, 3 RGB, 4 RGBA), row by row from the top.
pub fn png8(width: u32, height: u32, channels: usize, samples: &[u8]) -> Vec<u8> {
    png_of(width, height, channels, png::BitDepth::Eight, samples)
}

/// A PNG of 16-bit samples, as [`png8`].
pub fn png16(width: u32, height: u32, channels: usize, samples: &[u16]) -> Vec<u8> {
    // PNG stores 16-bit samples most significant byte first.
    let bytes: Vec<u8> = samples.iter().flat_map(|s| s.to_be_bytes()).collect();
    png_of(width, height, channels, png::BitDepth::Sixteen, &bytes)
}

fn png_of(width: u32, height: u32, channels: usize, depth: png::BitDepth, bytes: &[u8]) -> Vec<u8> {
    let colour = match channels {
        1 => png::ColorType::Grayscale,
        2 => png::ColorType::GrayscaleAlpha,
        3 => png::ColorType::Rgb,
        4 => png::ColorType::Rgba,
        _ => panic!("a PNG pixel has 1 to 4 samples, not {channels}"),
    };
    let mut png = Vec::new();
    let mut encoder = png::Encoder::new(&mut png, width, height);
    encoder.set_color(colour);
    encoder.set_depth(depth);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(bytes).unwrap();
    writer.finish().unwrap();
    png
}
