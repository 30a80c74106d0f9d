//! The container's problems found in bytes, before the reader or writer
//! names the file and frame ([`ContainerError`], with the library's errors).

use super::{At, ContainerError};

/// A problem found in bytes, before the reader or writer adds the file and
/// frame to it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Problem {
    Truncated(String),
    Invalid(String),
    TooLarge { what: &'static str, value: u64, limit: u64 },
    UnknownChunk([u8; 4]),
    Damaged(String),
}

impl Problem {
    /// `Ok` when `value` is within `limit`, else the limit broken.
    pub(crate) fn at_most(what: &'static str, value: u64, limit: u64) -> Result<(), Problem> {
        if value > limit {
            Err(Problem::TooLarge { what, value, limit })
        } else {
            Ok(())
        }
    }

    pub(crate) fn at(self, path: &std::path::Path, frame: Option<u32>) -> ContainerError {
        let path = path.to_path_buf();
        let at = At(frame);
        match self {
            Problem::Truncated(what) => ContainerError::Truncated { path, at, what },
            Problem::Invalid(problem) => ContainerError::Invalid { path, at, problem },
            Problem::TooLarge { what, value, limit } => ContainerError::TooLarge { path, at, what, value, limit },
            Problem::UnknownChunk(tag) => ContainerError::UnknownChunk { path, at, tag: tag_text(tag) },
            Problem::Damaged(what) => ContainerError::Damaged { path, at, what },
        }
    }
}

/// A chunk tag for messages: ASCII as is, other bytes escaped.
pub(crate) fn tag_text(tag: [u8; 4]) -> String {
    tag.iter().flat_map(|b| std::ascii::escape_default(*b)).map(char::from).collect()
}

pub(crate) fn invalid(s: impl Into<String>) -> Problem {
    Problem::Invalid(s.into())
}
