//! Frozen test vectors (spec §12): files written by format versions 1.0 to
//! 1.3 must always read back to the same samples, and today's writer must
//! produce the same bytes for each (the older ones when asked for them).
//! Regenerate the newest version's vectors only on a deliberate format change:
//! `HOLO_BLESS=1 cargo test --test format vectors` (then update spec §12);
//! the vectors of older versions are never rewritten. The newest is 1.2 for
//! horizontal parallax (1.3 changed nothing for it) and 1.3 for full
//! parallax (spec §8), whose vectors are in `fixtures/v1.3/`.

use std::borrow::Cow;
use std::path::PathBuf;

use holo::format::{read, write, write_frames, Compression, FormatVersion, HoloFile, SampleType, WriteOptions};
use holo::geometry::{mono_channel, rgb_channels, ColourChannel, Geometry, ViewSpacing, Views};
use holo::Modulation;

/// Every version written, with its folder of vectors.
const VERSIONS: [(FormatVersion, &str); 3] =
    [(FormatVersion::V1_0, "v1.0"), (FormatVersion::V1_1, "v1.1"), (FormatVersion::V1_2, "v1.2")];

/// The version whose horizontal-parallax vectors `HOLO_BLESS=1` may write.
const NEWEST: FormatVersion = FormatVersion::V1_2;

/// The version whose full-parallax vectors `HOLO_BLESS=1` may write.
const NEWEST_FULL: FormatVersion = FormatVersion::V1_3;

fn fixture_of(version: FormatVersion, name: &str) -> PathBuf {
    let folder = match version {
        FormatVersion::V1_3 => "v1.3",
        _ => VERSIONS.iter().find(|v| v.0 == version).map(|v| v.1).unwrap(),
    };
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures").join(folder).join(name)
}

fn fixture(name: &str) -> PathBuf {
    fixture_of(NEWEST, name)
}

/// 2 hololines × 3 emitters × 2 views, one channel: the spec's worked example.
fn tiny() -> Modulation {
    let g = Geometry::centred(
        2,
        3,
        Views::tan_spaced(2, -0.1, 0.1),
        1e-3,
        2e-3,
        0.01,
        0.5,
        vec![ColourChannel::new("Y", 633e-9)],
    );
    // Sample value = 1 + hololine + emitter/4 + view/8: every sample distinct and exact in f16.
    Modulation::from_fn(g, |_, j, e, v| 1.0 + j as f32 + e as f32 / 4.0 + v as f32 / 8.0).unwrap()
}

/// 4 × 5 × 3 RGB, 2 frames, f32, ZIP.
fn small_frames() -> Vec<Modulation> {
    let g = Geometry::centred(4, 5, Views::tan_spaced(3, -0.2, 0.2), 1e-4, 2e-4, 0.02, 0.6, rgb_channels());
    (0..2)
        .map(|f| {
            Modulation::from_fn(g.clone(), |c, j, e, v| (f * 1000 + c * 100 + j * 20 + e * 3 + v) as f32 / 7.0).unwrap()
        })
        .collect()
}

fn check(version: FormatVersion, name: &str, written: &std::path::Path) {
    let path = fixture_of(version, name);
    let bytes = std::fs::read(written).unwrap();
    if std::env::var_os("HOLO_BLESS").is_some() && (version == NEWEST || version == NEWEST_FULL) {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, &bytes).unwrap();
    }
    let frozen = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    if frozen == bytes {
        return;
    }
    // A ZIP block's zlib stream is the deflate's choice (spec §6): the same
    // headers and the same blocks decoded are the same file.
    let zip = |p: &std::path::Path| {
        let meta = exr::meta::MetaData::read_from_file(p, true).unwrap();
        meta.headers.iter().all(|h| {
            matches!(h.compression, exr::compression::Compression::ZIP1 | exr::compression::Compression::ZIP16)
        })
    };
    assert!(
        zip(&path) && zip(written) && blocks(&path) == blocks(written),
        "{name} ({version:?}): the writer's bytes changed; a format change needs a spec change and HOLO_BLESS=1"
    );
}

/// A file's headers and every block decoded, in file order.
fn blocks(path: &std::path::Path) -> (Vec<exr::meta::header::Header>, Vec<(usize, Vec<u8>)>) {
    use exr::block::chunk::Chunk;
    use exr::block::UncompressedBlock;
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let reader = exr::block::read(file, true).unwrap();
    let meta = reader.meta_data().clone();
    let decoded = reader
        .all_chunks(true)
        .unwrap()
        .map(|chunk: exr::error::Result<Chunk>| {
            let block = UncompressedBlock::decompress_chunk(chunk.unwrap(), &meta, true).unwrap();
            (block.index.layer, block.data)
        })
        .collect();
    (meta.headers.to_vec(), decoded)
}

/// Write `m` as one frame with `compression` and `source`, f16, in every
/// version, and check the bytes against the frozen vectors `name`.
fn write_and_check(name: &str, m: &Modulation, compression: Compression, source: &str) {
    let dir = tempfile::tempdir().unwrap();
    for (version, folder) in VERSIONS {
        let out = dir.path().join(folder).join(name);
        std::fs::create_dir_all(out.parent().unwrap()).unwrap();
        let options = WriteOptions { compression, source: source.into(), version, ..WriteOptions::default() };
        write(&out, m, &options).unwrap();
        check(version, name, &out);
    }
}

#[test]
fn tiny_vector_is_stable() {
    write_and_check("tiny-y-f16-none.holo", &tiny(), Compression::None, "spec worked example");
    for (version, _) in VERSIONS {
        let path = fixture_of(version, "tiny-y-f16-none.holo");
        assert_eq!(read(&path).unwrap(), tiny());
        let file = HoloFile::open(&path).unwrap();
        assert_eq!(file.info().version, version.number());
        assert!(holo::validate(&path).unwrap().is_valid());
    }
}

#[test]
fn a_zip_file_is_the_same_bytes_whatever_the_threads() {
    let frames = small_frames();
    let dir = tempfile::tempdir().unwrap();
    let options = WriteOptions { sample_type: SampleType::F32, ..WriteOptions::default() };
    let write_with = |threads: usize, name: &str| {
        let out = dir.path().join(name);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            write_frames(&out, frames[0].geometry(), 2, &options, |i| Ok(Cow::Borrowed(&frames[i]))).unwrap()
        });
        std::fs::read(out).unwrap()
    };
    let one = write_with(1, "one.holo");
    assert_eq!(one, write_with(3, "three.holo"));
    assert_eq!(one, write_with(1, "again.holo"));
}

#[test]
fn multi_frame_vector_is_stable() {
    let dir = tempfile::tempdir().unwrap();
    let frames = small_frames();
    for (version, folder) in VERSIONS {
        let out = dir.path().join(format!("{folder}-frames.holo"));
        let options = WriteOptions {
            sample_type: SampleType::F32,
            frames_per_second: Some((30, 1)),
            version,
            ..WriteOptions::default()
        };
        write_frames(&out, frames[0].geometry(), 2, &options, |i| Ok(Cow::Borrowed(&frames[i]))).unwrap();
        check(version, "frames-rgb-f32-zip.holo", &out);
        let file = HoloFile::open(fixture_of(version, "frames-rgb-f32-zip.holo")).unwrap();
        for (i, f) in frames.iter().enumerate() {
            assert_eq!(&file.read_frame(i).unwrap(), f);
        }
    }
}

/// 8 hololines × 8 emitters × 1 view, HALF, B44: a ramp rising from black,
/// sample `(j, e) = 0.37 · max(0, j + e − 6)`. B44 returns small negative
/// values where it meets the black; the vector freezes a file whose decoded
/// samples hold some (spec §3.4, §12).
fn undershoot() -> Modulation {
    let g = Geometry::centred(
        8,
        8,
        Views::tan_spaced(1, 0.0, 0.0),
        1e-3,
        1e-3,
        0.01,
        0.5,
        vec![ColourChannel::new("Y", 633e-9)],
    );
    Modulation::from_fn(g, |_, j, e, _| 0.37 * ((j + e) as f32 - 6.0).max(0.0)).unwrap()
}

#[test]
fn lossy_undershoot_vector_reads_as_zero() {
    write_and_check("undershoot-y-f16-b44.holo", &undershoot(), Compression::B44, "spec undershoot example");
    let file = HoloFile::open(fixture("undershoot-y-f16-b44.holo")).unwrap();
    let decoded = file.read_decoded(0, &holo::format::Region::all(&file.info().geometry)).unwrap();
    let negative: Vec<(usize, f32)> = decoded.samples().iter().copied().enumerate().filter(|&(_, x)| x < 0.0).collect();
    assert!(!negative.is_empty(), "B44 no longer undershoots this content: the vector tests nothing");
    let read_back = file.read_frame(0).unwrap();
    for (i, (&d, &r)) in decoded.samples().iter().zip(read_back.samples()).enumerate() {
        assert_eq!(r, d.max(0.0), "sample {i}");
    }
    assert!(holo::validate(fixture("undershoot-y-f16-b44.holo")).unwrap().is_valid());
    eprintln!("decoded below zero (index, value): {negative:?}");
}

/// `rows × columns` emitters, 2 × 2 views (horizontal `tan`, vertical `sin`
/// spaced), 1 mm × 2 mm pitches: the full-parallax vectors' geometry.
fn full_geometry(rows: usize, columns: usize, channels: Vec<ColourChannel>) -> Geometry {
    Geometry::centred(rows, columns, Views::tan_spaced(2, -0.1, 0.1), 1e-3, 2e-3, 0.01, 0.5, channels)
        .with_vertical_views(Views {
            count: 2,
            first_theta_rad: -0.05,
            last_theta_rad: 0.05,
            spacing: ViewSpacing::Sin,
        })
}

/// The full-parallax worked example (spec §12): 2 rows × 3 columns × 2 × 2
/// views of one 633 nm channel, sample `(j, e, h, k) = 1 + j + e/4 + h/8 +
/// k/16`, every one distinct and exact in f16.
fn full_tiny() -> Modulation {
    let g = full_geometry(2, 3, mono_channel());
    Modulation::from_fn(g.clone(), |_, j, e, v| {
        let (h, k) = g.view_of_index(v);
        1.0 + j as f32 + e as f32 / 4.0 + h as f32 / 8.0 + k as f32 / 16.0
    })
    .unwrap()
}

/// Two frames of 3 rows × 4 columns × 2 × 2 views, RGB.
fn full_frames() -> Vec<Modulation> {
    let g = full_geometry(3, 4, rgb_channels());
    (0..2)
        .map(|f| {
            Modulation::from_fn(g.clone(), |c, j, e, v| (f * 1000 + c * 100 + j * 20 + e * 3 + v) as f32 / 7.0).unwrap()
        })
        .collect()
}

/// A ramp rising from black over 8 × 8 emitters, each view brighter, for B44.
fn full_ramp() -> Modulation {
    let g = full_geometry(8, 8, mono_channel());
    Modulation::from_fn(g, |_, j, e, v| 0.37 * ((j + e + v) as f32 - 6.0).max(0.0)).unwrap()
}

#[test]
fn full_parallax_vectors_are_stable() {
    let dir = tempfile::tempdir().unwrap();
    let f16 = |compression| WriteOptions { compression, ..WriteOptions::default() };
    let cases: [(&str, Vec<Modulation>, WriteOptions); 3] = [
        (
            "full-tiny-y-f16-none.holo",
            vec![full_tiny()],
            WriteOptions { source: "spec full-parallax example".into(), ..f16(Compression::None) },
        ),
        (
            "full-frames-rgb-f32-zip.holo",
            full_frames(),
            WriteOptions { sample_type: SampleType::F32, frames_per_second: Some((30, 1)), ..WriteOptions::default() },
        ),
        ("full-ramp-y-f16-b44.holo", vec![full_ramp()], f16(Compression::B44)),
    ];
    for (name, frames, options) in cases {
        let out = dir.path().join(name);
        write_frames(&out, frames[0].geometry(), frames.len(), &options, |i| Ok(Cow::Borrowed(&frames[i]))).unwrap();
        check(NEWEST_FULL, name, &out);
        let path = fixture_of(NEWEST_FULL, name);
        let file = HoloFile::open(&path).unwrap();
        assert_eq!(file.info().version, (1, 3));
        for (i, f) in frames.iter().enumerate() {
            let back = file.read_frame(i).unwrap();
            if options.compression == Compression::B44 {
                // B44 keeps a 4 × 4 block's steps from its largest in 6 bits:
                // errors are a few per cent of the block's range.
                let worst = back.samples().iter().zip(f.samples()).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
                let peak = f.samples().iter().copied().fold(0f32, f32::max);
                assert!(worst > 0.0 && worst < 0.1 * peak, "{name}: {worst} of {peak}");
            } else {
                assert_eq!(&back, f, "{name} frame {i}");
            }
        }
        assert!(holo::validate(&path).unwrap().is_valid(), "{name}");
    }
}
