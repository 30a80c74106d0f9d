//! Any bytes given to the reader give a result or an error, never a panic,
//! an abort or an unbounded allocation.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // libfuzzer-sys's panic hook aborts before any unwinding, which would
    // also abort on a panic the reader catches and turns into an error (it
    // contains the exr crate's decoder panics). A quiet hook instead: a panic
    // that escapes the reader still aborts (libfuzzer-sys aborts when the
    // run unwinds out), one it handles does not.
    static QUIET: std::sync::Once = std::sync::Once::new();
    QUIET.call_once(|| std::panic::set_hook(Box::new(|_| {})));
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("input.holo");
    std::fs::write(&path, data).expect("write input");
    let _ = holo::validate(&path);
    if let Ok(file) = holo::HoloFile::open(&path) {
        let g = file.geometry().clone();
        let _ = file.read_frame(0);
        let region = holo::format::Region {
            hololines: 0..1,
            emitters: 0..g.emitters.min(2),
            views: 0..1,
            vertical_views: 0..g.vertical_view_count().min(2),
        };
        let _ = file.read_region(0, &region);
    }
});
