//! `assemble_file` end to end on a small custom profile (Mark III with four
//! hololines, loaded from TOML as a user's would be): every output format
//! reads back to the signals the assembler computed, frames are chosen,
//! nothing is overwritten, bytes are reproducible, mismatches are named.

use std::borrow::Cow;
use std::path::Path;

use holo::assemble::output::{assemble_file, read_frame_images, read_sidecar, AssembleOptions, FringeFormat};
use holo::format::{write_frames, WriteOptions};
use holo::layout::Layout;
use holo::Modulation;
use rand::{Rng, SeedableRng};

fn small_layout(dir: &Path) -> Layout {
    let mut l = holo::layout::mark3();
    l.name = "mark3-4".into();
    l.geometry.hololines = 4;
    l.fringe.as_mut().unwrap().frame_buffer.height = 30;
    let path = dir.join("mark3-4.toml");
    std::fs::write(&path, l.to_toml()).unwrap();
    Layout::load(path.to_str().unwrap()).unwrap()
}

fn random(layout: &Layout, seed: u64) -> Modulation {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    Modulation::from_fn(layout.geometry.clone(), |_, _, _, _| rng.gen_range(0.0..1.0)).unwrap()
}

fn write_two_frames(layout: &Layout, path: &Path) -> [Modulation; 2] {
    let frames = [random(layout, 1), random(layout, 2)];
    write_frames(path, &layout.geometry, 2, &WriteOptions::default(), |i| Ok(Cow::Borrowed(&frames[i]))).unwrap();
    frames
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn every_format_reads_back_to_the_assembled_signal() {
    let dir = tempfile::tempdir().unwrap();
    let layout = small_layout(dir.path());
    let input = dir.path().join("in.holo");
    write_two_frames(&layout, &input);
    // The f16-rounded frame, as the assembler sees it.
    let stored = holo::HoloFile::open(&input).unwrap().read_frame(1).unwrap();
    let assembler = holo::assemble::Assembler::new(&layout).unwrap();
    let mut direct = assembler.signals_reference(&stored, 0, 0..4).unwrap();
    // What is sent: the blanking gains on the samples beside each blanked run.
    for (j, hololine) in direct.iter_mut().enumerate() {
        assembler.blanking_gains_reference(&stored, j, 0, hololine);
    }
    for (format, tolerance) in
        [(FringeFormat::Exr, 2e-6), (FringeFormat::Png, 0.5 / 127.0 + 2e-6), (FringeFormat::Raw, 0.5 / 127.0 + 2e-6)]
    {
        let out = dir.path().join(format.extension());
        let options = AssembleOptions { frames: Some(1..2), format, overwrite: false, resample: false };
        let calls = std::sync::Mutex::new(Vec::new());
        let progress = holo::progress::Counting::new(|d, t| calls.lock().unwrap().push((d, t)));
        let report = assemble_file(&input, &layout, &out, &options, &progress).unwrap();
        assert_eq!(calls.into_inner().unwrap(), vec![(1, 1)]);
        assert_eq!(report.files.len(), 3, "two heads and the sidecar");
        let sidecar = read_sidecar(&out).unwrap();
        assert_eq!(sidecar.layout, layout);
        assert_eq!(sidecar.frames[0].index, 1);
        let images = read_frame_images(&out, &sidecar, 0).unwrap();
        let signals = images.unpack(&assembler, 4).unwrap().remove(0);
        let mut worst = 0f64;
        for (j, want) in direct.iter().enumerate() {
            for (s, want) in want.iter().enumerate() {
                for (n, (got, want)) in signals.row(s, j).iter().zip(want).enumerate() {
                    let want = if n % 4096 >= 4080 { 0.0 } else { *want };
                    worst = worst.max((f64::from(*got) - want).abs());
                }
            }
        }
        assert!(worst <= tolerance, "{format:?}: worst {worst}");
        // Asking again is refused and leaves the files alone.
        let before = std::fs::read(&report.files[0]).unwrap();
        let err = assemble_file(&input, &layout, &out, &options, &holo::progress::Silent).unwrap_err().to_string();
        assert!(err.contains("already exists"), "{err}");
        assert_eq!(std::fs::read(&report.files[0]).unwrap(), before);
    }
}

#[test]
fn bytes_are_reproducible_and_mismatches_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let layout = small_layout(dir.path());
    let input = dir.path().join("in.holo");
    write_two_frames(&layout, &input);
    let options = AssembleOptions { frames: None, format: FringeFormat::Raw, overwrite: false, resample: false };
    let a = assemble_file(&input, &layout, &dir.path().join("a"), &options, &holo::progress::Silent).unwrap();
    let b = assemble_file(&input, &layout, &dir.path().join("b"), &options, &holo::progress::Silent).unwrap();
    assert_eq!(a.frames.len(), 2);
    for (x, y) in a.files.iter().zip(&b.files).take(4) {
        assert_eq!(std::fs::read(x).unwrap(), std::fs::read(y).unwrap(), "{}", x.display());
    }
    // Frames out of range.
    let bad = AssembleOptions { frames: Some(1..3), ..options.clone() };
    let err =
        assemble_file(&input, &layout, &dir.path().join("c"), &bad, &holo::progress::Silent).unwrap_err().to_string();
    assert!(err.contains("in.holo") && err.contains("frames 1..3"), "{err}");
    // A file for another display.
    let other = dir.path().join("mark1.holo");
    holo::write(&other, &Modulation::zeros(holo::layout::mark1().geometry).unwrap(), &WriteOptions::default()).unwrap();
    let err = assemble_file(&other, &layout, &dir.path().join("d"), &options, &holo::progress::Silent)
        .unwrap_err()
        .to_string();
    assert!(err.contains("mark1.holo") && err.contains("64 hololines (the layout has 4)"), "{err}");
    assert!(err.contains("resampling"), "{err}");
    // Asked for explicitly, the frames are resampled onto the layout by rays.
    let resampling = AssembleOptions { resample: true, ..options.clone() };
    let r = assemble_file(&other, &layout, &dir.path().join("e"), &resampling, &holo::progress::Silent).unwrap();
    let stats = r.resampled.unwrap();
    assert!(stats.total == 4 * 336 * 96 && stats.outside > 0, "{stats:?}");
}

/// `holo.scale` says what absolute radiance a sample stands for; fringes are
/// normalised to the quantizer's range, so two files that differ only in it
/// assemble to the same bytes (spec/layouts.md §4.1).
#[test]
fn holo_scale_does_not_change_the_fringes() {
    let dir = tempfile::tempdir().unwrap();
    let layout = small_layout(dir.path());
    let m = random(&layout, 3);
    let options = AssembleOptions { frames: None, format: FringeFormat::Raw, overwrite: false, resample: false };
    let mut files = Vec::new();
    for (name, scale) in [("one", 1.0), ("bright", 2.5e3)] {
        let input = dir.path().join(format!("{name}.holo"));
        let mut write = WriteOptions::default();
        write.radiometry.scale = scale;
        holo::format::write(&input, &m, &write).unwrap();
        assert_eq!(holo::HoloFile::open(&input).unwrap().info().radiometry.scale, scale);
        files.push(assemble_file(&input, &layout, &dir.path().join(name), &options, &holo::progress::Silent).unwrap());
    }
    let mut compared = 0;
    for (a, b) in files[0].files.iter().zip(&files[1].files) {
        if a.extension().is_some_and(|x| x == "json") {
            continue;
        }
        assert_eq!(std::fs::read(a).unwrap(), std::fs::read(b).unwrap(), "{}", a.display());
        compared += 1;
    }
    assert!(compared > 0, "{:?}", files[0].files);
}

/// The (y, x) of each tile of the EXR file at `path`, in the order they
/// are stored.
fn exr_tiles(path: &Path) -> Vec<(usize, usize)> {
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let reader = exr::block::read(file, true).unwrap();
    assert_eq!(reader.meta_data().headers[0].line_order, exr::meta::attribute::LineOrder::Increasing);
    reader
        .all_chunks(true)
        .unwrap()
        .map(|chunk| match chunk.unwrap().compressed_block {
            exr::block::chunk::CompressedBlock::Tile(block) => {
                let at = block.coordinates.tile_index;
                (at.y(), at.x())
            }
            _ => panic!("{}: not a tile", path.display()),
        })
        .collect()
}

/// The same input gives the same bytes in every format whatever the number
/// of threads (what `holo farm gather`'s byte-for-byte check relies on), and
/// an EXR's chunks are stored in increasing y, as its header says.
#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn fringes_are_the_same_bytes_at_any_thread_count_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    // Mark III's whole frame buffer (64 × 53 tiles of 64 × 64 in an EXR)
    // for a few hololines.
    let mut layout = holo::layout::mark3();
    layout.geometry.hololines = 4;
    let input = dir.path().join("in.holo");
    holo::write(&input, &random(&layout, 3), &WriteOptions::default()).unwrap();
    for format in [FringeFormat::Exr, FringeFormat::Png, FringeFormat::Raw] {
        let mut first: Option<Vec<Vec<u8>>> = None;
        for threads in [1, 5] {
            let out = dir.path().join(format!("{}-{threads}", format.extension()));
            let options = AssembleOptions { frames: None, format, overwrite: false, resample: false };
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let report =
                pool.install(|| assemble_file(&input, &layout, &out, &options, &holo::progress::Silent)).unwrap();
            let images: Vec<Vec<u8>> = report
                .files
                .iter()
                .filter(|f| !f.ends_with("holo-fringes.json"))
                .map(|f| std::fs::read(f).unwrap())
                .collect();
            assert_eq!(images.len(), 2);
            if format == FringeFormat::Exr {
                for f in report.files.iter().filter(|f| f.extension().is_some_and(|e| e == "exr")) {
                    let tiles = exr_tiles(f);
                    assert_eq!(tiles.len(), 4080usize.div_ceil(64) * 3386usize.div_ceil(64), "{}", f.display());
                    assert!(tiles.windows(2).all(|w| w[0] < w[1]), "{}: tiles stored as {tiles:?}", f.display());
                }
            }
            match &first {
                None => first = Some(images),
                Some(expected) => assert!(images == *expected, "{format:?}: {threads} threads gave other bytes"),
            }
        }
    }
}
