//! Helpers shared by the integration tests.

use std::path::PathBuf;

/// The shared test data folder (`$HOLO_SHARED_DATA`, else `../shared/data`),
/// or `None` when it is not there: tests then say plainly what did not run.
pub fn shared_data() -> Option<PathBuf> {
    let d = std::env::var("HOLO_SHARED_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/data")));
    d.is_dir().then_some(d)
}
