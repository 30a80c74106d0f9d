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
