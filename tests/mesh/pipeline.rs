//! The one conversion path (`holo::pipeline`) as mesh conversion uses it:
//! warnings said once with a count, frame ranges checked against the
//! animation, cancellation leaving nothing behind.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use holo::geometry::{mono_channel, Geometry, Views};
use holo::mesh::convert::{convert_mesh, ConvertOptions, SceneFramesOptions};
use holo::progress::{Progress, Silent};

fn small_display() -> Geometry {
    Geometry::centred(24, 32, Views::tan_spaced(8, -0.2, 0.2), 1.0e-3, 1.0e-3, 0.0, 0.6, mono_channel())
}

/// A glTF whose one mesh ("tile": a triangle and a degenerate one) is used
/// by `instances` unnamed nodes side by side.
fn instanced_tile(dir: &Path, instances: usize) -> std::path::PathBuf {
    let positions: [[f32; 3]; 6] =
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let bytes: Vec<u8> = positions.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
    std::fs::write(dir.join("tiles.bin"), &bytes).unwrap();
    let nodes: Vec<String> =
        (0..instances).map(|k| format!(r#"{{"mesh": 0, "translation": [{}, 0, 0]}}"#, 1.5 * k as f64)).collect();
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [{}]}}],
  "nodes": [{}],
  "meshes": [{{"name": "tile", "primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                  "min": [0, 0, 0], "max": [2, 1, 0]}}],
  "bufferViews": [{{"buffer": 0, "byteLength": {len}}}],
  "buffers": [{{"byteLength": {len}, "uri": "tiles.bin"}}]
}}"#,
        (0..instances).map(|k| k.to_string()).collect::<Vec<_>>().join(", "),
        nodes.join(", "),
        len = bytes.len(),
    );
    let path = dir.join("tiles.gltf");
    std::fs::write(&path, json).unwrap();
    path
}

#[test]
fn the_same_warning_for_forty_instances_is_one_line_with_a_count() {
    let dir = tempfile::tempdir().unwrap();
    let scene = instanced_tile(dir.path(), 40);
    let out = dir.path().join("tiles.holo");
    let report = convert_mesh(&scene, &small_display(), &out, &ConvertOptions::default(), &Silent).unwrap();
    let zero_area: Vec<&String> = report.warnings.iter().filter(|w| w.contains("zero area")).collect();
    assert_eq!(zero_area.len(), 1, "{:#?}", report.warnings);
    assert!(zero_area[0].ends_with("(40 times)"), "{}", zero_area[0]);
    assert!(zero_area[0].contains("object \"tile\": 1 of 2 triangles have zero area"), "{}", zero_area[0]);
}

#[test]
fn a_still_scene_has_one_frame_and_a_range_beyond_it_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let scene = instanced_tile(dir.path(), 2);
    let out = dir.path().join("tiles.holo");
    let options = ConvertOptions {
        scene: SceneFramesOptions { frames: Some(0..3), ..Default::default() },
        ..ConvertOptions::default()
    };
    let e = convert_mesh(&scene, &small_display(), &out, &options, &Silent).unwrap_err();
    assert!(e.to_string().ends_with("tiles.gltf: frames 0..3 asked for; it has frames 0..1"), "{e}");
    assert!(!out.exists());
}

#[test]
fn a_cancelled_conversion_leaves_nothing_behind() {
    /// Cancels once the first hololines are rendered.
    struct CancelMidFrame(AtomicBool);
    impl Progress for CancelMidFrame {
        fn phase(&self, _: &str, _: u64) {}
        fn advance(&self, done: u64) {
            if done >= 2 {
                self.0.store(true, Ordering::Relaxed);
            }
        }
        fn cancelled(&self) -> bool {
            self.0.load(Ordering::Relaxed)
        }
    }
    let dir = tempfile::tempdir().unwrap();
    let scene = instanced_tile(dir.path(), 2);
    let out = dir.path().join("tiles.holo");
    let progress = CancelMidFrame(AtomicBool::new(false));
    let e = convert_mesh(&scene, &small_display(), &out, &ConvertOptions::default(), &progress).unwrap_err();
    assert!(matches!(e, holo::Error::Cancelled), "{e}");
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert!(!out.exists());
    assert_eq!(left.len(), 2, "only the input is left: {left:?}");
}

/// The placement a conversion chose is in the file exactly (`holo.placement`,
/// OpenEXR's `m44d`), so the conversion can be made again from the file: the
/// same matrix given back places the scene the same way, and the samples
/// are the same.
#[test]
fn the_placement_is_recorded_exactly_and_remakes_the_conversion() {
    let dir = tempfile::tempdir().unwrap();
    let scene = instanced_tile(dir.path(), 2);
    let out = dir.path().join("tiles.holo");
    let report = convert_mesh(&scene, &small_display(), &out, &ConvertOptions::default(), &Silent).unwrap();
    let file = holo::HoloFile::open(&out).unwrap();
    let stored = file.info().placement.expect("holo.placement");
    assert_eq!(stored, report.placed.matrix, "bit for bit");
    assert!(holo::validate(&out).unwrap().is_valid());
    // Again, placed by the stored matrix alone.
    let mut again = ConvertOptions::default();
    again.scene.placement.matrix = Some(stored);
    let out2 = dir.path().join("again.holo");
    convert_mesh(&scene, &small_display(), &out2, &again, &Silent).unwrap();
    let (a, b) = (holo::HoloFile::open(&out2).unwrap(), file);
    assert_eq!(a.info().placement, Some(stored));
    assert_eq!(a.info().frames[0].digest, b.info().frames[0].digest, "the same samples");
}
