//! Numbered sequences (`shot.0007.holo`): read as one movie by number, each
//! member checked to be the frame its name says, of the sequence's geometry;
//! joined into one multi-part file with every frame's digest kept.

use holo::farm::{check_sequence, join_sequence};
use holo::format::sequence::member_path;
use holo::format::{write, Frames, HoloFile, WriteOptions};
use holo::geometry::{mono_channel, Geometry, Views};
use holo::Modulation;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn geometry(emitters: usize) -> Geometry {
    Geometry::centred(3, emitters, Views::tan_spaced(4, -0.2, 0.2), 1.3e-4, 2.4e-4, 0.027, 0.6, mono_channel())
}

fn random(g: Geometry, seed: u64) -> Modulation {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    Modulation::from_fn(g, |_, _, _, _| rng.gen_range(0.01..2.0)).unwrap()
}

/// Frame `n` of a sequence as a farm writes it: `holo.frame` = `n`.
fn member(name: &std::path::Path, n: usize, m: &Modulation) {
    let options = WriteOptions { first_frame_number: n as i32, ..WriteOptions::default() };
    write(member_path(name, n), m, &options).unwrap();
}

#[test]
fn a_sequence_reads_by_number_and_joins_into_one_file_with_the_same_digests() {
    let dir = tempfile::tempdir().unwrap();
    let name = dir.path().join("shot.holo");
    let frames: Vec<Modulation> = (0..4).map(|i| random(geometry(5), 10 + i)).collect();
    for (i, m) in frames.iter().enumerate() {
        member(&name, 3 + i, m);
    }
    // Not members: another sequence, an unpadded number.
    std::fs::copy(member_path(&name, 3), dir.path().join("shots.0001.holo")).unwrap();
    std::fs::copy(member_path(&name, 3), dir.path().join("shot.12.holo")).unwrap();

    let seq = Frames::open(&name).unwrap();
    assert_eq!(seq.numbers(), [3, 4, 5, 6]);
    assert_eq!(seq.all(), 3..7);
    for (i, m) in frames.iter().enumerate() {
        let read = seq.read_frame(3 + i).unwrap();
        let written = holo::format::read(member_path(&name, 3 + i)).unwrap();
        assert_eq!(read.samples(), written.samples());
        assert!(read.samples().iter().zip(m.samples()).all(|(a, b)| (a - b).abs() <= 2e-3 * b.abs()));
    }
    assert!(matches!(seq.read_frame(7), Err(holo::Error::Io { .. })));
    assert!(seq.check_range(&(2..5)).unwrap_err().to_string().contains("shot.0002.holo"));

    let digests = check_sequence(&name, 3..7).unwrap();
    let joined = dir.path().join("joined.holo");
    join_sequence(&name, 3..7, &joined, false).unwrap();
    let file = HoloFile::open(&joined).unwrap();
    let info = file.info();
    let stored: Vec<Option<String>> = info.frames.iter().map(|f| f.digest.clone()).collect();
    assert_eq!(stored, digests);
    assert_eq!(info.frames.iter().map(|f| f.number).collect::<Vec<_>>(), [3, 4, 5, 6]);
    for i in 0..4 {
        assert_eq!(file.read_frame(i).unwrap().samples(), seq.read_frame(3 + i).unwrap().samples());
    }
    // A file that exists is a file, even beside a sequence of its name.
    assert!(matches!(Frames::open(&joined).unwrap(), Frames::File(_)));
    // An existing output is kept.
    assert!(join_sequence(&name, 3..7, &joined, false).is_err());
}

#[test]
fn a_renamed_or_foreign_member_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let name = dir.path().join("shot.holo");
    member(&name, 0, &random(geometry(5), 1));
    member(&name, 1, &random(geometry(5), 2));
    // Frame 1's file renamed to 2: its holo.frame says 1.
    std::fs::rename(member_path(&name, 1), member_path(&name, 2)).unwrap();
    let e = Frames::open(&name).unwrap_err().to_string();
    assert!(e.contains("shot.0002.holo") && e.contains("frame 1"), "{e}");
    // Another geometry.
    std::fs::remove_file(member_path(&name, 2)).unwrap();
    member(&name, 1, &random(geometry(6), 3));
    let e = Frames::open(&name).unwrap_err().to_string();
    assert!(e.contains("shot.0001.holo") && e.contains("another geometry"), "{e}");
    // Nothing of the name at all: the file's own error, with the form looked for.
    let e = Frames::open(dir.path().join("none.holo")).unwrap_err().to_string();
    assert!(e.contains("none.holo"), "{e}");
}

/// A farm's frame, once read whole and found good, is not read again while
/// its size and time stay; damage that changes its time is found at once,
/// damage that does not only when every frame is read (`verify`).
#[test]
fn a_frame_found_good_is_trusted_until_it_changes() {
    use holo::farm::{checked_frame_state, FarmOutput, FrameState};
    let dir = tempfile::tempdir().unwrap();
    let name = dir.path().join("shot.holo");
    member(&name, 4, &random(geometry(5), 7));
    let output = FarmOutput::Sequence(name.clone());
    let path = member_path(&name, 4);
    assert!(checked_frame_state(&output, 4, false).is_done());
    assert!(output.state_folder().join("verified/0004.json").exists());
    assert_eq!(checked_frame_state(&output, 3, false), FrameState::Missing);

    // Flip a sample byte near the end, and put the time back as it was.
    let when = std::fs::metadata(&path).unwrap().modified().unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let at = bytes.len() - 9;
    bytes[at] ^= 0x40;
    std::fs::write(&path, &bytes).unwrap();
    let file = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
    file.set_modified(when).unwrap();
    drop(file);
    assert!(checked_frame_state(&output, 4, false).is_done(), "unchanged size and time: trusted");
    assert!(matches!(checked_frame_state(&output, 4, true), FrameState::Damaged { .. }), "read whole: found");
    assert!(matches!(checked_frame_state(&output, 4, false), FrameState::Damaged { .. }), "and remembered");

    // Its time moves on (any write does): read again, found.
    let file = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
    file.set_modified(when + std::time::Duration::from_secs(1)).unwrap();
    drop(file);
    assert!(matches!(checked_frame_state(&output, 4, false), FrameState::Damaged { .. }));
}

/// A farm splits a full-parallax movie by frame as a horizontal-parallax one:
/// its members read by number and join into one file, every view's digest kept.
#[test]
fn a_full_parallax_sequence_joins_with_every_views_digest() {
    let dir = tempfile::tempdir().unwrap();
    let name = dir.path().join("shot.holo");
    let g = geometry(5).with_vertical_views(Views::tan_spaced(3, -0.1, 0.1));
    let frames: Vec<Modulation> = (0..3).map(|i| random(g.clone(), 20 + i)).collect();
    for (i, m) in frames.iter().enumerate() {
        member(&name, i, m);
    }
    check_sequence(&name, 0..3).unwrap();
    let joined = dir.path().join("joined.holo");
    join_sequence(&name, 0..3, &joined, false).unwrap();
    let file = HoloFile::open(&joined).unwrap();
    assert_eq!(file.geometry(), &g);
    for i in 0..3 {
        let alone = HoloFile::open(member_path(&name, i)).unwrap();
        let views = |f: &HoloFile, n: usize| -> Vec<Option<String>> {
            f.info().frames[n].views.iter().map(|v| v.digest.clone()).collect()
        };
        assert_eq!(views(&file, i), views(&alone, 0), "frame {i}");
        assert!(views(&file, i).iter().all(Option::is_some));
        assert_eq!(file.read_frame(i).unwrap().samples(), alone.read_frame(0).unwrap().samples());
    }
    assert!(holo::validate(&joined).unwrap().is_valid());
}
