//! The conversion record (`holo.convert.*`) of a HoloFlick: the options read
//! back from the file alone, exactly, and the conversion made again with
//! them gives the same frames.

use std::path::Path;

use holo::format::{FileInfo, HoloFile};
use holo::geometry::{rgb_channels, Geometry, Views};
use holo::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
use holo::mesh::render::{RenderOptions, Supersample};
use holo::progress::Silent;
use holo::provenance::ConverterOptions;

fn convert(input: &Path, g: &Geometry, out: &Path, options: &HoloFlickConvertOptions) -> FileInfo {
    convert_holoflick(input, g, out, options, &Silent).unwrap();
    HoloFile::open(out).unwrap().info().clone()
}

#[test]
fn a_holoflick_converted_again_from_its_record_gives_the_same_frames() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/holoflick/v1.1/movie.hflk");
    let g = Geometry::centred(12, 20, Views::tan_spaced(8, -0.2, 0.2), 0.5e-3, 0.5e-3, 0.0, 0.5, rgb_channels());
    let dir = tempfile::tempdir().unwrap();
    let options = HoloFlickConvertOptions {
        frames: Some(1..3),
        render: RenderOptions { supersample: Supersample { emitter: 2, view: 3, hololine: 2 }, ..Default::default() },
        fit: true,
        ..Default::default()
    };
    let first = convert(&input, &g, &dir.path().join("a.holo"), &options);
    let c = first.conversion().unwrap().expect("a conversion record");
    assert_eq!(c.input, "movie.hflk");
    assert!(c.input_sha256.as_ref().is_some_and(|d| d.starts_with("sha256:") && d.len() == 71), "{c:?}");
    let ConverterOptions::HoloFlick(back) = &c.options else { panic!("{c:?}") };
    assert_eq!(back, &options);
    let again = convert(&input, &g, &dir.path().join("b.holo"), back);
    let digests = |i: &FileInfo| i.frames.iter().map(|f| f.digest.clone()).collect::<Vec<_>>();
    assert_eq!(digests(&again), digests(&first));
    assert_eq!(again.placement, first.placement, "fitted the same way");
    assert_eq!(first.frames.len(), 2);
}

/// What a farm does with a movie that is fitted: the placement decided on
/// the movie's first frame, given to a chunk that starts later, draws that
/// chunk's frames exactly as the whole run drew them (a chunk fitted on its
/// own first frame would not).
#[test]
fn a_chunk_given_the_movie_s_placement_draws_as_the_whole_run() {
    let input = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/holoflick/v1.1/movie.hflk");
    let g = Geometry::centred(12, 20, Views::tan_spaced(8, -0.2, 0.2), 0.5e-3, 0.5e-3, 0.0, 0.5, rgb_channels());
    let dir = tempfile::tempdir().unwrap();
    let whole = HoloFlickConvertOptions { fit: true, ..Default::default() };
    let all = convert(&input, &g, &dir.path().join("all.holo"), &whole);
    let frames = all.frames.len();
    assert!(frames >= 2, "the movie has {frames} frames");
    let last = frames - 1;
    let alone = |options: &HoloFlickConvertOptions, name: &str| {
        let options = HoloFlickConvertOptions { frames: Some(last..last + 1), ..options.clone() };
        convert(&input, &g, &dir.path().join(name), &options)
    };
    let given = alone(&HoloFlickConvertOptions { matrix: all.placement, ..whole.clone() }, "given.holo");
    assert_eq!(given.frames[0].digest, all.frames[last].digest);
    assert_eq!(given.placement, all.placement);
    // The record keeps the matrix, so the chunk can be made again from it.
    let c = given.conversion().unwrap().expect("a record");
    let ConverterOptions::HoloFlick(back) = &c.options else { panic!("{c:?}") };
    assert_eq!(back.matrix, all.placement);
    // Fitted on its own first frame instead, the chunk is placed otherwise.
    let own = alone(&whole, "own.holo");
    assert_ne!(own.placement, all.placement, "the fixture's frames do not move: this test would prove nothing");
    assert_ne!(own.frames[0].digest, all.frames[last].digest);
}
