//! The HoloFlick container (spec/holoflick.md): round trips, key frames and
//! references, random access, the frozen test vectors (1.0 read, 1.1 read and
//! written), checksums (every single-bit flip found), and bad input (every
//! truncation, corrupted counts and offsets, bad references, unknown versions
//! and chunks, random byte flips) giving clear errors and never a panic.
//! Regenerate the 1.1 vector only on a deliberate format change:
//! `HOLO_BLESS=1 cargo test --test holoflick container` (then update spec §12).
//!
//! The structural checks are tested on patched files whose checksums
//! [`reseal`] recomputes, as a careless or hostile writer would leave them:
//! without it the checksums would report every patch as damage first.

use std::path::{Path, PathBuf};

use holo::holoflick::container::{
    write_cg_file, Binding, ContainerError, Descriptor, Frame, GeometryBlock, GeometryObject, HoloFlickReader,
    HoloFlickWriteOptions, HoloFlickWriter, KeyFrameReference, Matrix4, ObjectRecord, Primitive, SpecularLight,
    SpecularMaterial, SpecularModel, ViewerCouch, IDENTITY,
};
use rand::{Rng, SeedableRng};

/// Bits written most significant first, as Deering streams are.
#[derive(Default)]
struct Bits {
    bytes: Vec<u8>,
    count: usize,
}

impl Bits {
    fn put(&mut self, value: u64, n: usize) {
        for i in (0..n).rev() {
            if self.count % 8 == 0 {
                self.bytes.push(0);
            }
            let bit = ((value >> i) & 1) as u8;
            *self.bytes.last_mut().unwrap() |= bit << (7 - self.count % 8);
            self.count += 1;
        }
    }
}

/// A Deering command stream of `words` 32-bit words (at least 6) holding
/// one triangle, positions only: (−0.5, −0.5, 0), (0.5, −0.5, 0), (0, 0.5, 0).
/// Java 3D 1.5.2 decodes it to exactly that (spec §12). Commands, each 8-bit
/// header sent before the previous command's body (header forwarding):
/// setState (no bundling); setTable for positions: one entry for every tag
/// (tag length 0), 16-bit data shifted right by 8 (8 bits sent), absolute;
/// three vertices (replace codes restart, then replace-oldest twice); a
/// variable-length no-op whose 29 ignored bits carry `marker`; then
/// end-of-stream headers that use the words up exactly, since Java's decoder
/// reads the next header before each body and stops only at the end.
fn triangle_stream(marker: u32, words: usize) -> Vec<u8> {
    assert!(words >= 6 && marker < 1 << 29);
    let mut commands: Vec<(u64, (u64, usize))> = vec![(0x18, (0, 3)), (0x10, ((1 << 9) | (1 << 4) | 8, 15))];
    for (x, y, z, replace) in [(-64i64, -64i64, 0i64, 1u64), (64, -64, 0, 3), (0, 64, 0, 3)] {
        let p = ((x as u64 & 0xFF) << 16) | ((y as u64 & 0xFF) << 8) | (z as u64 & 0xFF);
        // Header: the first 6 bits of x y z; body: replace code, no push, the other 18 bits.
        commands.push((0x40 | p >> 18, ((replace << 19) | (p & 0x3FFFF), 21)));
    }
    commands.push((0x01, ((29 << 29) | marker as u64, 34)));
    let mut bits = Bits::default();
    let mut pending = (0, 5); // the body of the implicit first no-op: count 0
    for (header, body) in commands {
        bits.put(header, 8);
        bits.put(pending.0, pending.1);
        pending = body;
    }
    bits.put(0x00, 8);
    bits.put(pending.0, pending.1);
    let end = words * 32;
    assert!(bits.count <= end && (end - bits.count) % 8 == 0);
    while bits.count < end {
        bits.put(0, 8);
    }
    bits.bytes
}

/// Triangles without normals or colours: what [`triangle_stream`] holds.
const TRIANGLES: Descriptor =
    Descriptor { primitive: Primitive::Triangle, normals: false, colours: false, alpha: false };

fn block(marker: u32, words: usize) -> GeometryBlock {
    GeometryBlock::new(TRIANGLES, &triangle_stream(marker, words)).unwrap()
}

fn translate(x: f64, y: f64, z: f64, scale: f64) -> Matrix4 {
    [[scale, 0.0, 0.0, x], [0.0, scale, 0.0, y], [0.0, 0.0, scale, z], [0.0, 0.0, 0.0, 1.0]]
}

fn couch() -> ViewerCouch {
    ViewerCouch { min_m: [-0.3, -0.1, 0.4], max_m: [0.3, 0.1, 0.7] }
}

fn lights() -> Vec<SpecularLight> {
    vec![
        SpecularLight::Directional { direction: [0.0, -0.6, -0.8], irradiance: [3.0, 3.0, 2.5] },
        SpecularLight::Point { position_m: [0.2, 0.5, 0.3], intensity: [0.25, 0.2, 0.2] },
    ]
}

fn materials() -> Vec<SpecularMaterial> {
    vec![
        SpecularMaterial { specular: [0.04; 3], exponent: 40.0, model: SpecularModel::Blinn },
        SpecularMaterial { specular: [0.9, 0.8, 0.5], exponent: 200.0, model: SpecularModel::Phong },
    ]
}

fn stored(id: u32, marker: u32, words: usize, world_from_object: Matrix4) -> ObjectRecord {
    ObjectRecord::Stored(GeometryObject { id, world_from_object, radiance_scale: 1.5, block: block(marker, words) })
}

fn reference(id: u32, key_frame: u32, world_from_object: Matrix4) -> ObjectRecord {
    ObjectRecord::Reference(KeyFrameReference { id, key_frame, world_from_object })
}

/// Four frames: a set (object 1, static) and an actor (object 2, moving,
/// re-diced each frame) and a prop (object 3, rigid, moving): frame 0 is a
/// key frame storing all three; frames 1–3 refer to the set and the prop and
/// store the actor; frame 2 is a second key frame storing a new prop (id 4).
fn movie() -> Vec<Frame> {
    let background = translate(0.0, 0.0, -0.2, 0.5);
    let bindings = |ids: &[u32]| {
        ids.iter().map(|&id| Binding { object_id: id, material: (id % 2), lights: vec![0, 1] }).collect::<Vec<_>>()
    };
    vec![
        Frame {
            key_frame: true,
            couch: couch(),
            lights: lights(),
            materials: materials(),
            bindings: bindings(&[1, 2]),
            objects: vec![
                stored(1, 0x111, 8, background),
                stored(2, 0x200, 6, translate(0.0, 0.0, 0.0, 0.1)),
                stored(3, 0x333, 7, translate(0.1, 0.0, 0.0, 0.05)),
            ],
        },
        Frame {
            key_frame: false,
            couch: couch(),
            lights: lights()[..1].to_vec(),
            materials: materials(),
            bindings: vec![Binding { object_id: 2, material: 1, lights: vec![0] }],
            objects: vec![
                reference(1, 0, background),
                stored(2, 0x201, 6, translate(0.01, 0.0, 0.0, 0.1)),
                reference(3, 0, translate(0.12, 0.0, 0.0, 0.05)),
            ],
        },
        Frame {
            key_frame: true,
            couch: ViewerCouch { min_m: [-0.2, -0.1, 0.4], max_m: [0.2, 0.1, 0.6] },
            lights: Vec::new(),
            materials: Vec::new(),
            bindings: Vec::new(),
            objects: vec![stored(2, 0x202, 6, translate(0.02, 0.0, 0.0, 0.1)), stored(4, 0x444, 6, IDENTITY)],
        },
        Frame {
            key_frame: false,
            couch: couch(),
            lights: lights(),
            materials: materials(),
            bindings: bindings(&[1, 4]),
            objects: vec![
                reference(1, 0, background),
                reference(4, 2, translate(0.0, 0.01, 0.0, 1.0)),
                stored(2, 0x203, 6, translate(0.03, 0.0, 0.0, 0.1)),
                reference(3, 0, translate(0.14, 0.0, 0.0, 0.05)),
            ],
        },
    ]
}

fn options() -> HoloFlickWriteOptions {
    HoloFlickWriteOptions {
        frames_per_second: (24000, 1001),
        text: vec![
            ("title".into(), "container test vector".into()),
            ("software".into(), "holo tests/holoflick_container.rs".into()),
        ],
        overwrite: false,
    }
}

fn write(path: &Path, frames: &[Frame]) -> u64 {
    let mut w = HoloFlickWriter::create(path, &options()).unwrap();
    for f in frames {
        w.add_frame(f).unwrap();
    }
    w.finish().unwrap().file_bytes
}

fn written_movie() -> (tempfile::TempDir, PathBuf, Vec<u8>) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("movie.hflk");
    write(&path, &movie());
    let bytes = std::fs::read(&path).unwrap();
    (dir, path, bytes)
}

/// Open and read every frame; the first error, if any.
fn read_all(path: &Path) -> Result<usize, ContainerError> {
    let mut r = HoloFlickReader::open(path)?;
    for n in 0..r.frame_count() {
        r.read_frame(n)?;
    }
    Ok(r.frame_count() as usize)
}

fn with_bytes(bytes: &[u8], f: impl FnOnce(&Path)) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("damaged.hflk");
    std::fs::write(&path, bytes).unwrap();
    f(&path);
}

/// CRC-32 (ISO-HDLC, as PNG and zlib; the library's unit tests check the
/// crate against the bit-by-bit definition).
fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

fn le32(bytes: &[u8], at: usize) -> Option<u32> {
    bytes.get(at..at + 4).map(|b| u32::from_le_bytes(b.try_into().unwrap()))
}

/// A patched 1.1 file with its checksums recomputed from spec §3.3 where
/// its structure still lets them be found: the index's and the file-level
/// chunks' in the file header, each frame's in its `sums` chunk.
fn reseal(mut b: Vec<u8>) -> Vec<u8> {
    let Some(index) = b.get(16..24).map(|x| u64::from_le_bytes(x.try_into().unwrap()) as usize) else { return b };
    if index > b.len() {
        return b;
    }
    let Some(frames) = le32(&b, index + 8) else { return b };
    let mut entries = Vec::new();
    for n in 0..frames as usize {
        let at = index + 16 + 16 * n;
        match (b.get(at..at + 8), le32(&b, at + 8)) {
            (Some(o), Some(len)) => entries.push((u64::from_le_bytes(o.try_into().unwrap()) as usize, len as usize)),
            _ => break,
        }
    }
    if let Some(index_bytes) = b.get(index..) {
        let sum = crc32(index_bytes);
        b[12..16].copy_from_slice(&sum.to_le_bytes());
    }
    let first_frame = entries.first().map_or(index, |e| e.0);
    if let Some(file_chunks) = b.get(32..first_frame) {
        let sum = crc32(file_chunks);
        b[28..32].copy_from_slice(&sum.to_le_bytes());
    }
    for (offset, len) in entries {
        let Some(chunk) = b.get(offset..offset + len) else { continue };
        let payload = &chunk[8.min(chunk.len())..];
        if payload.get(8..12) != Some(b"sums") {
            continue;
        }
        if payload.len() < 24 {
            continue;
        }
        let sum = crc32(&[&payload[..20], &[0; 4], &payload[24..]].concat());
        b[offset + 8 + 20..offset + 8 + 24].copy_from_slice(&sum.to_le_bytes());
    }
    b
}

fn find(bytes: &[u8], needle: &[u8], nth: usize) -> usize {
    bytes.windows(needle.len()).enumerate().filter(|(_, w)| *w == needle).nth(nth).map(|(i, _)| i).unwrap()
}

#[test]
fn round_trip_and_resolution() {
    let (_dir, path, _) = written_movie();
    let frames = movie();
    let mut r = HoloFlickReader::open(&path).unwrap();
    assert_eq!(r.frame_count(), 4);
    assert_eq!(r.info().version, (1, 1));
    assert_eq!(r.info().frames_per_second, (24000, 1001));
    assert_eq!(r.info().geometry_version, [1, 0, 2]);
    assert_eq!(r.info().text, options().text);
    assert_eq!((0..4).map(|n| r.is_key_frame(n)).collect::<Vec<_>>(), [true, false, true, false]);
    for (n, f) in frames.iter().enumerate() {
        assert_eq!(&r.read_stored_frame(n as u32).unwrap(), f, "frame {n}");
    }
    let last = r.read_frame(3).unwrap();
    assert_eq!(last.frame, frames[3]);
    let by_id = |id: u32| last.objects.iter().find(|o| o.id == id).unwrap();
    let key0 = match &frames[0].objects[0] {
        ObjectRecord::Stored(o) => o.clone(),
        _ => unreachable!(),
    };
    assert_eq!(by_id(1).block, key0.block);
    assert_eq!(by_id(1).radiance_scale, key0.radiance_scale);
    assert_eq!(by_id(1).stored_in_frame, 0);
    assert_eq!(by_id(3).stored_in_frame, 0);
    assert_eq!(by_id(3).world_from_object, translate(0.14, 0.0, 0.0, 0.05), "a reference carries its own transform");
    assert_eq!(by_id(4).stored_in_frame, 2);
    assert_eq!(by_id(2).stored_in_frame, 3);
    assert_eq!(last.objects.iter().map(|o| o.id).collect::<Vec<_>>(), [1, 4, 2, 3], "drawing order kept");
}

#[test]
fn random_access_in_any_order() {
    let (_dir, path, _) = written_movie();
    let mut r = HoloFlickReader::open(&path).unwrap();
    let in_order: Vec<_> = (0..4).map(|n| r.read_frame(n).unwrap()).collect();
    let mut fresh = HoloFlickReader::open(&path).unwrap();
    for n in [3, 1, 0, 2, 3, 1] {
        assert_eq!(fresh.read_frame(n).unwrap(), in_order[n as usize], "frame {n}");
    }
    let e = fresh.read_frame(4).unwrap_err();
    assert!(matches!(e, ContainerError::NoFrame { frame: 4, frames: 4, .. }), "{e}");
    assert!(e.to_string().contains("frame 4 asked for; the file has 4 frames"), "{e}");
}

#[test]
fn a_static_object_is_stored_once() {
    let (_dir, _path, bytes) = written_movie();
    // Object 1's stream (8 words, marker 0x111) appears once; the actor's in every frame.
    let count = |stream: Vec<u8>| bytes.windows(stream.len()).filter(|w| *w == &stream[..]).count();
    assert_eq!(count(triangle_stream(0x111, 8)), 1);
    for m in 0x200..0x204 {
        assert_eq!(count(triangle_stream(m, 6)), 1);
    }
}

#[test]
fn geometry_blocks_are_cg_records() {
    let b = block(0x111, 8);
    let record = b.cg_record();
    assert_eq!(&record[..4], &32u32.to_be_bytes(), "stream size, big-endian");
    assert_eq!(&record[4..8], &0x03u32.to_be_bytes(), "triangles");
    assert_eq!(b.stream(), &triangle_stream(0x111, 8)[..]);
    assert_eq!(
        &b.stream()[..24],
        &[
            0x18, 0x00, 0x80, 0x70, 0x04, 0x30, 0xa0, 0x8c, 0x00, 0x04, 0x0c, 0x60, 0x00, 0x00, 0xe1, 0x00, 0x00, 0x03,
            0xa0, 0x00, 0x01, 0x11, 0x00, 0x00
        ],
        "the stream Java 3D decodes (spec §12)"
    );
    assert_eq!(GeometryBlock::from_cg_record(record).unwrap(), b);
    assert_eq!(Descriptor::from_bits(0x13).unwrap().primitive, Primitive::Triangle);
    assert!(Descriptor::from_bits(0).is_none() && Descriptor::from_bits(0x23).is_none());
    assert!(GeometryBlock::new(Descriptor::LIT_TRIANGLES, &[0; 6]).is_err(), "not whole words");
    assert!(GeometryBlock::from_cg_record(&record[..20]).is_err(), "size disagrees");

    // Lifted out into a Java 3D .cg file unchanged.
    let dir = tempfile::tempdir().unwrap();
    let cg = dir.path().join("objects.cg");
    let blocks = [block(1, 6), block(2, 7)];
    let n = write_cg_file(&cg, &blocks, false).unwrap();
    let bytes = std::fs::read(&cg).unwrap();
    assert_eq!(bytes.len() as u64, n);
    assert_eq!(&bytes[..4], &[0xBA, 0xDD, 0xFA, 0xB4]);
    assert_eq!(&bytes[4..16], &[0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 2]);
    assert_eq!(&bytes[16..20], &2u32.to_be_bytes());
    assert_eq!(&bytes[32..64], blocks[0].cg_record());
    assert_eq!(&bytes[64..100], blocks[1].cg_record());
    let directory = u64::from_be_bytes(bytes[24..32].try_into().unwrap()) as usize;
    assert_eq!(directory, 104, "records padded to 8 bytes before the directory");
    assert_eq!(&bytes[directory..], &[32u64.to_be_bytes(), 64u64.to_be_bytes()].concat()[..]);
    assert!(write_cg_file(&cg, &blocks, false).is_err(), "never overwrites unless asked");
}

#[test]
fn frozen_test_vectors() {
    let fixtures = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures/holoflick");
    let fixture = fixtures.join("v1.1/movie.hflk");
    let (_dir, _path, bytes) = written_movie();
    if std::env::var_os("HOLO_BLESS").is_some() {
        std::fs::create_dir_all(fixture.parent().unwrap()).unwrap();
        std::fs::write(&fixture, &bytes).unwrap();
    }
    let frozen = std::fs::read(&fixture).unwrap_or_else(|e| panic!("{}: {e}", fixture.display()));
    assert!(frozen == bytes, "the writer's bytes changed; a format change needs a spec change and HOLO_BLESS=1");
    // The checksums cover what spec §3.3 says and lie where it says:
    // recomputing them here changes nothing.
    assert!(reseal(frozen.clone()) == frozen, "checksums differ from the spec's CRC-32");
    // Every version ever written reads to the same frames; 1.0 files carry
    // no checksums and need none.
    for version in ["v1.0", "v1.1"] {
        let path = fixtures.join(version).join("movie.hflk");
        let mut r = HoloFlickReader::open(&path).unwrap();
        assert_eq!(r.info().version.1, if version == "v1.0" { 0 } else { 1 });
        for (n, f) in movie().iter().enumerate() {
            assert_eq!(&r.read_stored_frame(n as u32).unwrap(), f, "{version} frame {n}");
            r.read_frame(n as u32).unwrap();
        }
    }
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn every_single_bit_flip_is_found() {
    let (_dir, _path, bytes) = written_movie();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flipped.hflk");
    let frames = movie();
    let geom = find(&bytes, b"GEOM", 0);
    for bit in 0..bytes.len() * 8 {
        let mut b = bytes.clone();
        b[bit / 8] ^= 1 << (bit % 8);
        std::fs::write(&path, &b).unwrap();
        let at = bit / 8;
        match read_all(&path) {
            // The minor version may change: the file then reads as another
            // 1.x, and still to the same frames.
            Ok(_) if (10..12).contains(&at) => {
                let mut r = HoloFlickReader::open(&path).unwrap();
                for (n, f) in frames.iter().enumerate() {
                    assert_eq!(&r.read_stored_frame(n as u32).unwrap(), f);
                }
            }
            Ok(_) => panic!("a flip of bit {} of byte {at:#x} was not found", bit % 8),
            Err(e) => {
                let text = e.to_string();
                assert!(text.starts_with(&path.display().to_string()), "{text}");
                // Inside the first object's geometry: the frame and object are named.
                if at >= geom + 12 && at < geom + 8 + 184 {
                    assert!(matches!(e, ContainerError::Damaged { .. }), "byte {at:#x}: {text}");
                    assert!(text.contains("frame 0: damaged: object 1 (its GEOM chunk"), "{text}");
                }
            }
        }
    }
}

#[test]
fn writer_refuses_what_a_reader_would() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("refused.hflk");
    let frames = movie();
    let mut w = HoloFlickWriter::create(&path, &options()).unwrap();
    let try_frame = |w: &mut HoloFlickWriter, f: &Frame| w.add_frame(f).unwrap_err().to_string();

    let mut f = frames[0].clone();
    f.objects.push(reference(9, 0, IDENTITY));
    assert!(try_frame(&mut w, &f).contains("a key frame holds no references"));
    f.key_frame = false;
    assert!(try_frame(&mut w, &f).contains("refers to frame 0, which is not earlier"));
    f.objects.pop();
    w.add_frame(&frames[0]).unwrap();
    w.add_frame(&frames[1]).unwrap();

    let mut f = frames[1].clone();
    f.objects[0] = reference(1, 1, IDENTITY);
    assert!(try_frame(&mut w, &f).contains("not a key frame"));
    f.objects[0] = reference(1, 5, IDENTITY);
    assert!(try_frame(&mut w, &f).contains("not earlier"));
    f.objects[0] = reference(7, 0, IDENTITY);
    assert!(try_frame(&mut w, &f).contains("holds no such object"));
    let mut f = frames[2].clone();
    f.objects.push(reference(1, 0, IDENTITY));
    assert!(try_frame(&mut w, &f).contains("a key frame holds no references"));
    let mut f = frames[1].clone();
    f.objects.push(stored(2, 5, 6, IDENTITY));
    assert!(try_frame(&mut w, &f).contains("object id 2 appears twice"));
    let mut f = frames[1].clone();
    f.bindings[0].lights = vec![3];
    assert!(try_frame(&mut w, &f).contains("light 3"));
    f.bindings[0] = Binding { object_id: 8, material: 0, lights: vec![] };
    assert!(try_frame(&mut w, &f).contains("does not hold"));
    let mut f = frames[1].clone();
    f.couch.min_m[2] = 0.9;
    assert!(try_frame(&mut w, &f).contains("couch"));
    let mut f = frames[1].clone();
    f.lights[0] = SpecularLight::Directional { direction: [0.0, 0.0, 2.0], irradiance: [1.0; 3] };
    assert!(try_frame(&mut w, &f).contains("unit length"));
    let mut f = frames[1].clone();
    f.objects[1] =
        stored(2, 1, 6, [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]]);
    assert!(try_frame(&mut w, &f).contains("not invertible"));
    let mut f = frames[1].clone();
    f.materials[0].exponent = f64::NAN;
    assert!(try_frame(&mut w, &f).contains("material 0"));

    // Refused frames left the writer as it was.
    assert_eq!(w.frame_count(), 2);
    let report = w.finish().unwrap();
    assert_eq!(report.frames, 2);
    assert_eq!(read_all(&path).unwrap(), 2);

    // Never overwrite unless asked; dropping an unfinished writer leaves nothing.
    let e = HoloFlickWriter::create(&path, &options()).unwrap_err();
    assert!(e.to_string().contains("already exists"), "{e}");
    let other = dir.path().join("unfinished.hflk");
    let mut w = HoloFlickWriter::create(&other, &options()).unwrap();
    w.add_frame(&frames[0]).unwrap();
    drop(w);
    assert!(!other.exists());
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "no temporary file left behind");
    let mut again = options();
    again.overwrite = true;
    let mut w = HoloFlickWriter::create(&path, &again).unwrap();
    w.add_frame(&frames[0]).unwrap();
    w.finish().unwrap();
    assert_eq!(read_all(&path).unwrap(), 1);
}

#[test]
fn every_truncation_is_an_error() {
    let (_dir, _path, bytes) = written_movie();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("short.hflk");
    for len in 0..bytes.len() {
        std::fs::write(&path, &bytes[..len]).unwrap();
        let e = read_all(&path).expect_err(&format!("a file cut to {len} bytes was accepted"));
        let text = e.to_string();
        assert!(text.starts_with(&path.display().to_string()), "{len}: {text}");
        assert!(matches!(e, ContainerError::Truncated { .. } | ContainerError::Invalid { .. }), "{len}: {text}");
    }
}

#[test]
fn corrupted_counts_and_offsets() {
    let (_dir, _path, bytes) = written_movie();
    let index = u64::from_le_bytes(bytes[16..24].try_into().unwrap()) as usize;
    let patch = |at: usize, new: &[u8]| {
        let mut b = bytes.clone();
        b[at..at + new.len()].copy_from_slice(new);
        b
    };
    let expect = |b: Vec<u8>, needle: &str| {
        with_bytes(&reseal(b), |p| {
            let e = read_all(p).unwrap_err().to_string();
            assert!(e.contains(needle), "expected {needle:?} in: {e}");
        })
    };
    // File header.
    expect(patch(0, b"\x89HFLX"), "not a HoloFlick");
    expect(patch(16, &0u64.to_le_bytes()), "unfinished");
    expect(patch(16, &(bytes.len() as u64 + 64).to_le_bytes()), "truncated");
    expect(patch(16, &u64::MAX.to_le_bytes()), "index");
    expect(patch(24, &5u32.to_le_bytes()), "index");
    expect(patch(24, &u32::MAX.to_le_bytes()), "the number of frames is 4294967295, more than the limit");
    // Index: frame count, an entry pointing outside the file or into another frame, lengths.
    expect(patch(index + 8, &7u32.to_le_bytes()), "the index lists 7");
    expect(patch(index + 16, &(bytes.len() as u64 * 2).to_le_bytes()), "frame 0: the index places the frame");
    expect(patch(index + 16 + 16, &(index as u64 - 8).to_le_bytes()), "frame 0: the index places the frame at offset");
    expect(patch(index + 16 + 8, &u32::MAX.to_le_bytes()), "a frame's bytes is 4294967295");
    // Flags disagree with the frame.
    expect(patch(index + 16 + 12, &0u32.to_le_bytes()), "frame 0: the index says key frame: false");
    // Counts inside a frame.
    let lght = find(&bytes, b"LGHT", 0);
    expect(patch(lght + 8, &u32::MAX.to_le_bytes()), "frame 0: the number of lights is 4294967295");
    expect(patch(lght + 8, &3u32.to_le_bytes()), "frame 0: truncated: LGHT declares 3 records");
    let matl = find(&bytes, b"MATL", 0);
    expect(patch(matl + 12, &8u32.to_le_bytes()), "MATL records of 8 bytes");
    let bind = find(&bytes, b"BIND", 0);
    expect(patch(bind + 8, &60000u32.to_le_bytes()), "BIND declares 60000 bindings");
    expect(patch(bind + 16 + 8, &u32::MAX.to_le_bytes()), "the lights of a binding is 4294967295");
    expect(patch(bind + 16 + 4, &9u32.to_le_bytes()), "names material 9 of 2");
    let geom = find(&bytes, b"GEOM", 0);
    expect(patch(geom + 4, &u32::MAX.to_le_bytes()), "frame 0: truncated: chunk \"GEOM\"");
    expect(patch(geom + 8 + 144, &9u32.to_be_bytes()), "geometry block header says 9 stream bytes");
    expect(patch(geom + 8 + 144 + 4, &0x40u32.to_be_bytes()), "geometry descriptor 0x00000040");
    expect(patch(geom + 8 + 4, &8u32.to_le_bytes()), "geometry block offset 8");
    expect(patch(geom + 8 + 8, &(-1.0f64).to_le_bytes()), "radiance scale -1");
    expect(patch(geom + 8 + 16 + 12 * 8, &1.0f64.to_le_bytes()), "last row");
    let frame0 = find(&bytes, b"FRAM", 0);
    expect(patch(frame0 + 8, &2u32.to_le_bytes()), "frame 0: the frame's chunk says it is frame 2");
    expect(patch(frame0 + 4, &8u32.to_le_bytes()), "frame 0: the FRAM chunk says 8 payload bytes");
    // File-level chunks.
    let head = find(&bytes, b"HEAD", 0);
    expect(patch(head + 8, &0u32.to_le_bytes()), "frame rate 0/1001");
    expect(patch(head + 4, &100000u32.to_le_bytes()), "runs into the frames");
    expect(patch(head, b"HEAP"), "the first chunk is \"HEAP\"");
    let text = find(&bytes, b"text", 0);
    expect(patch(text + 8, b"ti le"), "printable ASCII");
    expect(patch(text, b"HEAD"), "two HEAD chunks");
    expect(patch(text, b"te t"), "not four ASCII letters");
}

#[test]
fn references_to_non_key_or_later_frames() {
    let (_dir, _path, bytes) = written_movie();
    // Frame 3's first chunk object is KREF(1 → 0); its key-frame field follows the id.
    let kref = find(&bytes, b"KREF", 2);
    let patch = |k: u32| {
        let mut b = bytes.clone();
        b[kref + 12..kref + 16].copy_from_slice(&k.to_le_bytes());
        reseal(b)
    };
    with_bytes(&patch(1), |p| {
        let mut r = HoloFlickReader::open(p).unwrap();
        let e = r.read_frame(3).unwrap_err();
        assert!(matches!(e, ContainerError::BadReference { frame: 3, object: 1, key_frame: 1, .. }), "{e}");
        assert!(e.to_string().ends_with("frame 3: object 1 refers to frame 1: not a key frame"), "{e}");
    });
    for k in [3, 4, 99] {
        with_bytes(&patch(k), |p| {
            let e = HoloFlickReader::open(p).unwrap().read_frame(3).unwrap_err().to_string();
            assert!(e.contains(&format!("frame 3: object 1 refers to frame {k}, which is not earlier")), "{e}");
        });
    }
    // An id the key frame does not store (frame 3's KREF of object 3, which has no binding).
    let mut b = bytes.clone();
    let kref3 = find(&bytes, b"KREF", 4);
    b[kref3 + 8..kref3 + 12].copy_from_slice(&77u32.to_le_bytes());
    with_bytes(&reseal(b), |p| {
        let e = HoloFlickReader::open(p).unwrap().read_frame(3).unwrap_err().to_string();
        assert!(e.contains("frame 3: object 77 refers to frame 0: the key frame holds no such object"), "{e}");
    });
    // Key frames themselves still read.
    with_bytes(&patch(1), |p| {
        let mut r = HoloFlickReader::open(p).unwrap();
        r.read_frame(0).unwrap();
        r.read_frame(2).unwrap();
    });
}

#[test]
fn versions_and_unknown_chunks() {
    let (_dir, _path, bytes) = written_movie();
    let patch = |at: usize, new: &[u8]| {
        let mut b = bytes.clone();
        b[at..at + new.len()].copy_from_slice(new);
        reseal(b)
    };
    with_bytes(&patch(8, &2u16.to_le_bytes()), |p| {
        let e = HoloFlickReader::open(p).unwrap_err();
        assert!(matches!(e, ContainerError::UnsupportedVersion { .. }));
        assert!(e.to_string().contains("HoloFlick version 2.1; this reader reads 1.x"), "{e}");
    });
    // A newer minor version reads.
    with_bytes(&patch(10, &7u16.to_le_bytes()), |p| {
        assert_eq!(read_all(p).unwrap(), 4);
        assert_eq!(HoloFlickReader::open(p).unwrap().info().version, (1, 7));
    });
    let head = find(&bytes, b"HEAD", 0);
    with_bytes(&patch(head + 16, &2u32.to_le_bytes()), |p| {
        let e = HoloFlickReader::open(p).unwrap_err().to_string();
        assert!(e.contains("compressed geometry version 2.0.2"), "{e}");
    });
    // Unknown chunks: an ancillary one is skipped, a critical one refused.
    let text = find(&bytes, b"text", 0);
    with_bytes(&patch(text, b"tExT"), |p| {
        assert_eq!(read_all(p).unwrap(), 4);
        assert_eq!(HoloFlickReader::open(p).unwrap().info().text.len(), 1);
    });
    with_bytes(&patch(text, b"TEXT"), |p| {
        let e = HoloFlickReader::open(p).unwrap_err();
        assert!(matches!(e, ContainerError::UnknownChunk { .. }), "{e}");
    });
    // Frame 2 stores objects 2 and 4; object 4 has no binding there. Hiding
    // object 2 (the first GEOM of frame 2) leaves a readable frame.
    let geom = find(&bytes, b"GEOM", 4);
    with_bytes(&patch(geom, b"gEOM"), |p| {
        let mut r = HoloFlickReader::open(p).unwrap();
        assert_eq!(r.read_frame(2).unwrap().objects.len(), 1);
    });
    with_bytes(&patch(geom, b"GEOX"), |p| {
        let e = HoloFlickReader::open(p).unwrap().read_frame(2).unwrap_err();
        assert!(matches!(e, ContainerError::UnknownChunk { at: holo::holoflick::container::At(Some(2)), .. }), "{e}");
        assert!(e.to_string().contains("frame 2: critical chunk \"GEOX\""), "{e}");
    });
    // Sub-chunks out of order.
    let lght = find(&bytes, b"LGHT", 0);
    with_bytes(&patch(lght, b"MATL"), |p| {
        let e = HoloFlickReader::open(p).unwrap().read_frame(0).unwrap_err().to_string();
        assert!(e.contains("chunk MATL found where LGHT was expected"), "{e}");
    });
}

#[test]
fn random_byte_flips_never_panic() {
    let (_dir, _path, bytes) = written_movie();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("flipped.hflk");
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(6);
    let mut accepted = 0;
    for _ in 0..3000 {
        let mut b = bytes.clone();
        for _ in 0..rng.gen_range(1..4) {
            let i = rng.gen_range(0..b.len());
            match rng.gen_range(0..3) {
                0 => b[i] ^= 1 << rng.gen_range(0..8),
                1 => b[i] = rng.gen(),
                _ => b[i] = 0xFF,
            }
        }
        std::fs::write(&path, &b).unwrap();
        if read_all(&path).is_ok() {
            accepted += 1;
        }
    }
    // Flips in floats, padding and ignored fields may still read; most must not.
    assert!(accepted < 3000, "{accepted}");
}

#[test]
fn an_empty_movie_reads() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("empty.hflk");
    let bytes = write(&path, &[]);
    assert_eq!(bytes % 8, 0);
    let mut r = HoloFlickReader::open(&path).unwrap();
    assert_eq!(r.frame_count(), 0);
    assert!(matches!(r.read_frame(0).unwrap_err(), ContainerError::NoFrame { frame: 0, frames: 0, .. }));
    // Converted to the crate's error, the message keeps the file and the problem.
    let e: holo::Error = r.read_frame(0).unwrap_err().into();
    assert!(e.to_string().contains("empty.hflk: frame 0 asked for"), "{e}");
    assert!(matches!(e, holo::Error::HoloFlick(ContainerError::NoFrame { .. })), "{e:?}");
}

/// A random valid movie: key frames at random, references to objects that
/// earlier key frames store, random lights, materials and bindings.
fn random_movie(seed: u64, frames: usize) -> Vec<Frame> {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut stored_in_key: Vec<(u32, u32)> = Vec::new(); // (key frame, object id)
    let mut out = Vec::new();
    for n in 0..frames as u32 {
        let key_frame = n == 0 || rng.gen_bool(0.3);
        let mut ids: Vec<u32> = (0..12).filter(|_| rng.gen_bool(0.4)).collect();
        ids.truncate(6);
        let mut objects = Vec::new();
        for &id in &ids {
            let m = translate(rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), rng.gen(), rng.gen_range(0.01..2.0));
            let candidates: Vec<u32> = stored_in_key.iter().filter(|(_, i)| *i == id).map(|(k, _)| *k).collect();
            if !key_frame && !candidates.is_empty() && rng.gen_bool(0.6) {
                objects.push(reference(id, candidates[rng.gen_range(0..candidates.len())], m));
            } else {
                let descriptor = Descriptor::from_bits(rng.gen_range(1..32)).unwrap_or(Descriptor::LIT_TRIANGLES);
                let stream: Vec<u8> = (0..4 * rng.gen_range(0..40)).map(|_| rng.gen()).collect();
                let block = GeometryBlock::new(descriptor, &stream).unwrap();
                let radiance_scale = rng.gen_range(0.001..100.0);
                objects.push(ObjectRecord::Stored(GeometryObject { id, world_from_object: m, radiance_scale, block }));
            }
        }
        if key_frame {
            stored_in_key.extend(ids.iter().map(|&id| (n, id)));
        }
        let lights: Vec<SpecularLight> = (0..rng.gen_range(0..4))
            .map(|_| {
                if rng.gen_bool(0.5) {
                    let d: [f64; 3] = [rng.gen_range(-1.0..1.0), rng.gen_range(-1.0..1.0), 1.0];
                    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    SpecularLight::Directional {
                        direction: d.map(|x| x / len),
                        irradiance: [rng.gen(), rng.gen(), 0.0],
                    }
                } else {
                    SpecularLight::Point { position_m: [rng.gen(), -rng.gen::<f64>(), 3.0], intensity: [rng.gen(); 3] }
                }
            })
            .collect();
        let materials: Vec<SpecularMaterial> = (0..rng.gen_range(0..3))
            .map(|_| SpecularMaterial {
                specular: [rng.gen(), rng.gen(), rng.gen()],
                exponent: rng.gen_range(0.0..500.0),
                model: if rng.gen_bool(0.5) { SpecularModel::Phong } else { SpecularModel::Blinn },
            })
            .collect();
        let mut bindings = Vec::new();
        for &object_id in &ids {
            if !materials.is_empty() && rng.gen_bool(0.5) {
                let material = rng.gen_range(0..materials.len() as u32);
                let lights = (0..lights.len() as u32).filter(|_| rng.gen_bool(0.5)).collect();
                bindings.push(Binding { object_id, material, lights });
            }
        }
        let lo: [f64; 3] = [rng.gen_range(-2.0..0.0), rng.gen_range(-2.0..0.0), rng.gen_range(0.0..1.0)];
        let couch = ViewerCouch { min_m: lo, max_m: [lo[0] + rng.gen::<f64>(), lo[1] + 1.0, lo[2] + 0.5] };
        out.push(Frame { key_frame, couch, lights, materials, bindings, objects });
    }
    out
}

/// 32 random movies (seeded, so a failure names the case that reproduces it):
/// every frame read back, in reverse order, resolves to what was written.
#[test]
fn random_movies_round_trip() {
    let mut cases = rand_chacha::ChaCha8Rng::seed_from_u64(0x00f1_1c45);
    for case in 0..32 {
        let (seed, frames) = (cases.gen::<u64>(), cases.gen_range(1usize..8));
        let context = format!("case {case}: random_movie({seed}, {frames})");
        let movie = random_movie(seed, frames);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("random.hflk");
        write(&path, &movie);
        let mut r = HoloFlickReader::open(&path).unwrap();
        assert_eq!(r.frame_count() as usize, movie.len(), "{context}");
        for (n, f) in movie.iter().enumerate().rev() {
            let resolved = r.read_frame(n as u32).unwrap();
            assert_eq!(&resolved.frame, f, "{context}, frame {n}");
            for (object, record) in resolved.objects.iter().zip(&f.objects) {
                assert_eq!(object.id, record.id(), "{context}, frame {n}");
                assert_eq!(&object.world_from_object, record.world_from_object(), "{context}, frame {n}");
                let stored_in = match record {
                    ObjectRecord::Stored(_) => n as u32,
                    ObjectRecord::Reference(k) => k.key_frame,
                };
                let original = movie[stored_in as usize]
                    .objects
                    .iter()
                    .find_map(|o| match o {
                        ObjectRecord::Stored(s) if s.id == object.id => Some(s),
                        _ => None,
                    })
                    .unwrap();
                assert_eq!(object.stored_in_frame, stored_in, "{context}, frame {n}");
                assert_eq!(&object.block, &original.block, "{context}, frame {n}");
                assert_eq!(object.radiance_scale, original.radiance_scale, "{context}, frame {n}");
            }
        }
    }
}
