//! Any bytes opened as a HoloFlick give a result or an error, never a panic,
//! an abort or an unbounded allocation; a file that opens has every frame
//! read (references resolved) and, when a frame reads, its stored form agrees.
#![no_main]

use holo::holoflick::container::HoloFlickReader;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("input.hflk");
    std::fs::write(&path, data).expect("write input");
    if let Ok(mut reader) = HoloFlickReader::open(&path) {
        let count = reader.frame_count();
        assert!(count as u64 * 16 <= data.len() as u64, "more frames than the index has bytes for");
        for n in (0..count).chain([count]) {
            if let Ok(resolved) = reader.read_frame(n) {
                assert!(n < count);
                assert_eq!(resolved.objects.len(), resolved.frame.objects.len());
                let stored = reader.read_stored_frame(n).expect("a frame that resolved reads as stored");
                assert_eq!(stored, resolved.frame);
            }
        }
    }
});
