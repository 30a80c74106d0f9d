//! `holoflick pack | unpack | info` as library calls: key frames store a
//! static object once (same frames, smaller file by the blocks not
//! repeated), unpacked meshes read back, `.cg` output and bad requests.

use std::path::PathBuf;

use holo::holoflick::container::HoloFlickReader;
use holo::holoflick::tools::{frame_objects, info, pack, unpack, PackOptions};

fn spot() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/mesh/spot/spot.obj"))
}

#[test]
fn key_frames_store_a_static_object_once() {
    let dir = tempfile::tempdir().unwrap();
    let inputs = vec![spot(), spot(), spot()];
    let once = dir.path().join("once.hflk");
    let every = dir.path().join("every.hflk");
    let a = pack(&inputs, &once, &PackOptions::default(), &holo::progress::Silent).unwrap();
    let b = pack(&inputs, &every, &PackOptions { key_interval: 1, ..PackOptions::default() }, &holo::progress::Silent)
        .unwrap();
    assert_eq!((a.frames, a.stored, a.references), (3, 1, 2));
    assert_eq!((b.frames, b.stored, b.references), (3, 3, 0));
    // The same frames either way.
    for f in 0..3 {
        let (x, y) = (frame_objects(&once, f).unwrap(), frame_objects(&every, f).unwrap());
        assert_eq!(x.len(), 1);
        assert!(x[0].positions == y[0].positions && x[0].colours == y[0].colours && x[0].triangles == y[0].triangles);
    }
    // Smaller by two stored objects, less the two references: a GEOM chunk
    // is 8 (chunk header) + 144 (fields) + the block (8 + stream), a KREF
    // chunk 8 + its payload (id, key frame, transform: 8 + 128).
    let block = {
        let mut r = HoloFlickReader::open(&once).unwrap();
        r.read_frame(0).unwrap().objects[0].block.cg_record().len() as u64
    };
    let geom = 8 + 144 + block;
    let kref = 8 + 8 + 128;
    assert_eq!(b.file_bytes - a.file_bytes, 2 * (geom - kref), "{} vs {}", b.file_bytes, a.file_bytes);
    let text = info(&once).unwrap();
    assert!(text.contains("3 frames") && text.contains("(1 from key frames)"), "{text}");
}

#[test]
fn unpacked_frames_read_back_and_cg_files_pack() {
    let dir = tempfile::tempdir().unwrap();
    let hflk = dir.path().join("spot.hflk");
    pack(&[spot()], &hflk, &PackOptions::default(), &holo::progress::Silent).unwrap();
    for ext in ["glb", "ply"] {
        let out = dir.path().join(format!("spot.{ext}"));
        assert_eq!(unpack(&hflk, 0, &out, false).unwrap(), 500);
        let scene = holo::mesh::load::SceneSource::open(&out).unwrap().scene_at(0.0).unwrap();
        assert_eq!(scene.triangle_count(), 500);
    }
    let cg = dir.path().join("spot.cg");
    let r = pack(&[spot()], &cg, &PackOptions::default(), &holo::progress::Silent).unwrap();
    assert_eq!(r.cg_transforms.len(), 1);
    let objects = frame_objects(&cg, 0).unwrap();
    assert_eq!(objects[0].triangles.len(), 500);
    // In the normalised frame: every coordinate in [−1, 1).
    assert!(objects[0].positions.iter().flatten().all(|x| (-1.0..1.0).contains(x)));
    // Bad requests: several frames into a .cg, a missing frame, an existing output.
    let e = pack(&[spot(), spot()], &dir.path().join("two.cg"), &PackOptions::default(), &holo::progress::Silent)
        .unwrap_err();
    assert!(e.to_string().contains("one frame"), "{e}");
    let e = unpack(&hflk, 3, &dir.path().join("x.glb"), false).unwrap_err();
    assert!(e.to_string().contains("no frame 3"), "{e}");
    let e = pack(&[spot()], &hflk, &PackOptions::default(), &holo::progress::Silent).unwrap_err();
    assert!(e.to_string().contains("already exists"), "{e}");
}
