//! Helpers shared by the integration tests.

// Each test binary uses its own subset of these helpers.
#![allow(dead_code)]

use std::path::PathBuf;

/// The shared test data folder (`$HOLO_SHARED_DATA`, else `../shared/data`),
/// or `None` when it is not there: tests then say plainly what did not run.
///
/// With `HOLO_REQUIRE_DATA=1` (CI sets it) a missing folder is a failure, not
/// a skip, so a run without the data cannot pass silently.
pub fn shared_data() -> Option<PathBuf> {
    let d = std::env::var("HOLO_SHARED_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data")));
    if d.is_dir() {
        return Some(d);
    }
    assert!(
        std::env::var("HOLO_REQUIRE_DATA").as_deref() != Ok("1"),
        "HOLO_REQUIRE_DATA=1 but the shared test data folder {} is not there",
        d.display()
    );
    None
}

/// A file of the shared data that is not there: said plainly, and a failure
/// when `HOLO_REQUIRE_DATA=1`.
pub fn missing(what: &str) {
    assert!(std::env::var("HOLO_REQUIRE_DATA").as_deref() != Ok("1"), "{what} is missing and HOLO_REQUIRE_DATA=1");
    println!("SKIPPED: {what} not present");
}
