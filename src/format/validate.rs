//! `holo validate`'s part in the format: every rule of the spec but what
//! the conversion record's values mean (the crate's `validate` adds those, from
//! the converters), every problem listed.

use std::path::Path;

use serde::Serialize;

use super::header::{parse, read_meta, FileInfo};
use super::header_digest::read_stored;
use super::read::HoloFile;
use crate::error::{Error, Result};

/// The outcome of validating a file.
#[derive(Clone, Debug, Serialize)]
pub struct Validation {
    /// What the headers say, when they could be read.
    pub info: Option<FileInfo>,
    /// Rules broken; empty means the file is valid.
    pub violations: Vec<String>,
    /// Things worth knowing that break no rule.
    pub warnings: Vec<String>,
}

impl Validation {
    /// Whether no rule is broken.
    pub fn is_valid(&self) -> bool {
        self.violations.is_empty()
    }
}

/// Check every header rule, then decode every frame: samples finite and
/// non-negative, digests matching. Returns `Err` only when the file cannot be
/// read as OpenEXR at all (or is of a newer major version). The conversion
/// record is checked only as attributes; the crate's `validate` checks the
/// values too.
pub fn validate_format(path: impl AsRef<Path>) -> Result<Validation> {
    let path = path.as_ref();
    let (meta, file_bytes) = read_meta(path)?;
    let stored = read_stored(path)?;
    let parsed = parse(path, &meta, file_bytes, Some(&stored))?;
    let mut violations = parsed.problems;
    let warnings = parsed.warnings;
    if violations.is_empty() {
        if let Some(info) = &parsed.info {
            let file = HoloFile::open(path)?;
            for (i, _) in info.frames.iter().enumerate() {
                // A full-parallax frame may be larger than memory: band by band (spec §10).
                let read = match info.geometry.vertical_views {
                    None => file.read_frame(i).map(drop),
                    Some(_) => file.read_frame_in_bands(i, BAND_ROWS, |_, _| Ok(())),
                };
                match read {
                    Ok(_) => {}
                    Err(Error::Invalid { problem, .. }) => violations.push(format!("frame {i}: {problem}")),
                    Err(Error::Exr { message, .. }) => violations.push(format!("frame {i}: pixel data: {message}")),
                    Err(e @ (Error::BadSample { .. } | Error::DigestMismatch { .. })) => {
                        let text = e.to_string();
                        let text = text.split_once(": ").map(|(_, rest)| rest.to_string()).unwrap_or(text);
                        violations.push(text)
                    }
                    Err(e) => return Err(e),
                }
            }
        }
    }
    Ok(Validation { info: parsed.info, violations, warnings })
}

/// Emitter rows a full-parallax frame is validated in at a time.
const BAND_ROWS: usize = 32;
