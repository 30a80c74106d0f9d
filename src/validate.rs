//! `holo validate`: every rule of the spec, every problem listed. The
//! format checks its own rules ([`crate::format::validate_format`]); the
//! conversion record's values (spec §4.4) mean what the converters say, so
//! they are read here, as [`crate::format::FileInfo::conversion`] reads them.

use std::path::Path;

use crate::error::Result;
use crate::format::{validate_format, Validation};

/// Check every header rule, then decode every frame: samples finite and
/// non-negative, digests matching; a conversion record that cannot be read
/// as its converter's options is a warning (the samples are still good, and
/// a newer minor version's values never make a file invalid here). Returns
/// `Err` only when the file cannot be read as OpenEXR at all (or is of a
/// newer major version).
pub fn validate(path: impl AsRef<Path>) -> Result<Validation> {
    let mut validation = validate_format(path)?;
    if let Some(info) = &validation.info {
        if let Err(crate::error::Error::Invalid { problem, .. }) = info.conversion() {
            validation.warnings.push(format!("{problem}: the conversion record (holo.convert.*) is ignored"));
        }
    }
    Ok(validation)
}
