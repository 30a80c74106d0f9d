//! Any bytes given to the reader give a result or an error, never a panic,
//! an abort or an unbounded allocation.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("input.holo");
    std::fs::write(&path, data).expect("write input");
    let _ = holo::format::validate(&path);
    if let Ok(file) = holo::HoloFile::open(&path) {
        let g = file.geometry().clone();
        let _ = file.read_frame(0);
        let region = holo::format::Region { hololines: 0..1, emitters: 0..g.emitters.min(2), views: 0..1 };
        let _ = file.read_region(0, &region);
    }
});
