//! The conversion record (`holo.convert.*`): a scene converted, its options
//! read back from the file alone, and the conversion made again with them
//! gives the same frames; options off their defaults come back exactly.

use std::path::{Path, PathBuf};

use sha2::Digest;

use holo::format::{Compression, FileInfo, HoloFile, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, Geometry, Views};
use holo::mesh::convert::{convert_mesh, ConvertOptions, SceneFramesOptions};
use holo::mesh::place::Placement;
use holo::mesh::render::{Engine, RenderOptions, Supersample};
use holo::mesh::shade::{Lighting, SpecularModel};
use holo::mesh::Light;
use holo::progress::Silent;
use holo::provenance::{Conversion, ConverterOptions};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh").join(name)
}

fn small_display() -> Geometry {
    Geometry::centred(24, 32, Views::tan_spaced(8, -0.2, 0.2), 1.0e-3, 1.0e-3, 0.0, 0.6, rgb_channels())
}

fn digests(info: &FileInfo) -> Vec<Option<String>> {
    info.frames.iter().map(|f| f.digest.clone()).collect()
}

/// Convert `scene` with `options` into `name` in `dir`; the file's headers.
fn convert(dir: &Path, name: &str, scene: &Path, g: &Geometry, options: &ConvertOptions) -> FileInfo {
    let out = dir.join(name);
    convert_mesh(scene, g, &out, options, &Silent).unwrap();
    HoloFile::open(&out).unwrap().info().clone()
}

/// The mesh options a file records.
fn recorded(info: &FileInfo) -> (Conversion, ConvertOptions) {
    let c = info.conversion().unwrap().expect("a conversion record").clone();
    match &c.options {
        ConverterOptions::Mesh(o) => {
            let o = o.clone();
            (c, o)
        }
        other => panic!("not a mesh conversion: {other:?}"),
    }
}

#[test]
fn a_scene_converted_again_from_its_record_gives_the_same_frames() {
    let dir = tempfile::tempdir().unwrap();
    let (d, g) = (dir.path(), small_display());
    let spot = fixture("spot/spot.obj");
    let first = convert(d, "a.holo", &spot, &g, &ConvertOptions::default());
    let (c, options) = recorded(&first);
    assert_eq!(c.input, "spot.obj");
    // The digest of the input's bytes, as any SHA-256 tool gives it.
    let sha = format!("sha256:{:x}", sha2::Sha256::digest(std::fs::read(&spot).unwrap()));
    assert_eq!(c.input_sha256.as_deref(), Some(sha.as_str()));
    assert_eq!(options, ConvertOptions::default(), "the defaults come back as they were");
    let again = convert(d, "b.holo", &spot, &g, &options);
    assert_eq!(digests(&again), digests(&first));
    assert_eq!(again.placement, first.placement);
    // Placed by the recorded placement instead: the same frames, and the
    // given matrix is recorded as such.
    let mut by_matrix = options.clone();
    by_matrix.scene.placement.matrix = first.placement;
    let third = convert(d, "c.holo", &spot, &g, &by_matrix);
    assert_eq!(digests(&third), digests(&first));
    assert_eq!(recorded(&third).1, by_matrix);
}

#[test]
fn an_animation_converted_again_from_its_record_gives_the_same_frames() {
    let dir = tempfile::tempdir().unwrap();
    let (d, g) = (dir.path(), small_display());
    let cube = fixture("AnimatedMorphCube.glb");
    let options = ConvertOptions {
        scene: SceneFramesOptions { frames: Some(1..4), frames_per_second: 12.5, ..SceneFramesOptions::default() },
        render: RenderOptions { supersample: Supersample::new(1, 1), ..RenderOptions::default() },
        ..ConvertOptions::default()
    };
    let first = convert(d, "a.holo", &cube, &g, &options);
    assert_eq!(first.frames.len(), 3);
    let (c, back) = recorded(&first);
    assert_eq!((c.input.as_str(), &back), ("AnimatedMorphCube.glb", &options));
    let again = convert(d, "b.holo", &cube, &g, &back);
    assert_eq!(digests(&again), digests(&first));
    assert_eq!(again.frames[0].number, 1);
}

#[test]
fn scene_options_off_their_defaults_come_back_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let g = Geometry::centred(16, 24, Views::tan_spaced(6, -0.2, 0.2), 1.0e-3, 1.0e-3, 0.0, 0.6, mono_channel());
    let lights = vec![
        Light::Point { position: [0.01, 0.02, 0.3], intensity: [0.1, 0.2, 0.3], name: "a point".into() },
        Light::Directional {
            direction: [0.0, -std::f64::consts::FRAC_1_SQRT_2, -std::f64::consts::FRAC_1_SQRT_2],
            irradiance: [3.0, 2.5, 1.0 / 3.0],
            name: "key".into(),
        },
        Light::Ambient { radiance: [0.05, 0.06, 0.07] },
    ];
    let options = ConvertOptions {
        scene: SceneFramesOptions {
            placement: Placement {
                rotate_deg: [10.0, -20.5, 1.0 / 3.0],
                scale: Some(0.7e-3),
                translate_m: [1e-4, -3e-4, 0.1 / 3.0 * 1e-3],
                matrix: None,
            },
            frames: Some(0..1),
            frames_per_second: 24.0,
            smooth_normals_deg: Some(30.0),
        },
        render: RenderOptions {
            supersample: Supersample { emitter: 2, view: 3, hololine: 2 },
            lighting: Lighting { lights, model: SpecularModel::Phong },
            scene_lights: false,
            default_lights: false,
            engine: Engine::Reference,
        },
        write: WriteOptions { sample_type: SampleType::F32, compression: Compression::Piz, ..WriteOptions::default() },
    };
    let first = convert(dir.path(), "a.holo", &fixture("spot/spot.obj"), &g, &options);
    let (_, back) = recorded(&first);
    assert_eq!(back, options);
    let again = convert(dir.path(), "b.holo", &fixture("spot/spot.obj"), &g, &back);
    assert_eq!(digests(&again), digests(&first));
}
