//! The conversion record (`holo.convert.*`) of a camera capture: how it was
//! read and resampled, read back from the file alone exactly, and the
//! conversion made again with it gives the same frame.

use std::path::Path;

use holo::cameras::convert::{convert_camera_files, CameraConvertOptions};
use holo::cameras::read::{CameraHints, OpenOptions};
use holo::cameras::resample::{Blend, CameraOptions, Framing, Parallax, PlacementRequest};
use holo::format::{FileInfo, HoloFile};
use holo::geometry::{rgb_channels, Geometry, Views};
use holo::progress::Silent;
use holo::provenance::ConverterOptions;

use crate::common;

/// A plain folder of three pictures on a rail: a pattern that shifts from
/// picture to picture, as a scene behind the focus would.
fn capture(folder: &Path) {
    std::fs::create_dir_all(folder).unwrap();
    for i in 0..3u32 {
        let picture = common::pixels(32, 24, |x, y| [(x * 7 + i * 5) as u8, (y * 9) as u8, 40]);
        std::fs::write(folder.join(format!("view{i}.png")), common::png8(32, 24, 3, &picture)).unwrap();
    }
}

fn convert(input: &Path, g: &Geometry, out: &Path, options: &CameraConvertOptions) -> FileInfo {
    convert_camera_files(input, g, out, options, &Silent).unwrap();
    HoloFile::open(out).unwrap().info().clone()
}

#[test]
fn a_capture_converted_again_from_its_record_gives_the_same_frame() {
    let dir = tempfile::tempdir().unwrap();
    let folder = dir.path().join("rail");
    capture(&folder);
    let g = Geometry::centred(12, 20, Views::tan_spaced(8, -0.2, 0.2), 1.0e-3, 1.0e-3, 0.0, 0.5, rgb_channels());
    // What `holo convert cameras rail --baseline 0.1 --fov 60 --focus 1.2
    // --framing fill --parallax true --blend natural --taps 2` asks for.
    let hints = CameraHints { focal_length_px: None, horizontal_fov_deg: Some(60.0), focus_distance: Some(1.2) };
    let mut open = OpenOptions::default();
    open.folder.baseline = Some(0.1);
    open.folder.camera = hints.clone();
    open.stanford.camera = hints;
    let options = CameraConvertOptions {
        resample: CameraOptions {
            blend: Blend::NaturalNeighbour,
            placement: PlacementRequest {
                scale: None,
                centre: Some([0.001, -0.002, 1.0 / 3.0]),
                focus: Some(1.2),
                framing: Framing::Fill,
                parallax: Parallax::True,
            },
            use_depth: false,
            emitter_taps: Some(2),
            ..CameraOptions::default()
        },
        open,
        ..CameraConvertOptions::default()
    };
    let first = convert(&folder, &g, &dir.path().join("a.holo"), &options);
    let c = first.conversion().unwrap().expect("a conversion record");
    // A folder is named, not hashed.
    assert_eq!((c.input.as_str(), c.input_sha256.as_ref()), ("rail", None));
    let ConverterOptions::Cameras(back) = &c.options else { panic!("{c:?}") };
    assert_eq!(back, &options);
    let again = convert(&folder, &g, &dir.path().join("b.holo"), back);
    assert_eq!(again.frames[0].digest, first.frames[0].digest);
    assert_eq!(again.placement, first.placement);
    let (_, brightest) = holo::read(dir.path().join("a.holo")).unwrap().value_range();
    assert!(brightest > 0.0, "the cameras see the display");
}
