//! The header digest of spec §7.2: each part's header, as stored, sealed by a
//! SHA-256 in its own `holo.headerDigest` attribute, so that a bit flipped in
//! any attribute (a view direction, a pitch, a frame number, the sample
//! digest itself) is found by every reader before a sample is believed.
//!
//! The digest is of bytes, not of parsed values: the file's first 8 bytes
//! (magic number and version field) and the part's attribute list as stored,
//! from its first attribute's name to the NUL that ends the list, with the 64
//! hex digits of `holo.headerDigest`'s own value read as `0`. Any EXR reader
//! plus a SHA-256 reproduces it (`tests/peer/openexr_peer.py` does).
//!
//! This module also holds the one scanner of stored headers, which the writer
//! uses to put the attributes in name order and fill in the digests.

use std::io::Read;
use std::ops::Range;
use std::path::Path;

use sha2::{Digest, Sha256};

use super::attributes::name;
use super::digest::DIGEST_PREFIX;
use crate::error::{Error, Result};

/// The largest run of header bytes a reader scans: far above any header the
/// format's limits allow in practice (a 288-channel part is about 7 KiB, so a
/// thousand-frame file's headers are 7 MiB).
const MAX_HEADER_BYTES: u64 = 256 << 20;

/// Bytes of the magic number and version field that start every EXR file.
const PREAMBLE: usize = 8;

/// One attribute as stored: `name NUL type NUL size value`.
#[derive(Clone, Debug)]
pub(crate) struct StoredAttribute {
    /// Its name's bytes.
    pub name: Range<usize>,
    /// Its type name's bytes.
    pub type_name: Range<usize>,
    /// Its value's bytes.
    pub value: Range<usize>,
    /// The whole record, name to the end of the value.
    pub whole: Range<usize>,
}

/// One part's header as stored.
#[derive(Clone, Debug)]
pub(crate) struct StoredHeader {
    /// Its attributes, in file order.
    pub attributes: Vec<StoredAttribute>,
    /// From the first attribute's name to the NUL that ends the list, inclusive.
    pub bytes: Range<usize>,
}

/// Every part's header of a file, and the bytes they were read from.
pub(crate) struct StoredHeaders {
    /// The file's first bytes, through the end of the last header.
    pub bytes: Vec<u8>,
    /// Each part's header, in part order.
    pub parts: Vec<StoredHeader>,
}

/// Why a run of bytes is not (yet) a whole set of headers.
#[derive(Debug, PartialEq, Eq)]
pub(crate) enum ScanProblem {
    /// The bytes end inside a header: read more.
    Incomplete,
    /// The bytes cannot be EXR headers.
    Malformed(String),
}

/// Find the headers in `head`, the first bytes of an EXR file.
pub(crate) fn scan(head: &[u8]) -> std::result::Result<Vec<StoredHeader>, ScanProblem> {
    if head.len() < PREAMBLE {
        return Err(ScanProblem::Incomplete);
    }
    if head[..4] != crate::signature::OPENEXR {
        return Err(ScanProblem::Malformed("it does not start with OpenEXR's magic number".into()));
    }
    // Version field flags (OpenEXR's file layout): bit 12 multi-part, bit 10 long names.
    let multipart = head[5] & 0x10 != 0;
    let max_name = if head[5] & 0x04 != 0 { 255 } else { 31 };
    let mut at = PREAMBLE;
    let mut parts = Vec::new();
    loop {
        let start = at;
        let mut attributes = Vec::new();
        loop {
            let name_end = nul_within(head, at, max_name + 1)?;
            if name_end == at {
                at += 1;
                break;
            }
            let type_end = nul_within(head, name_end + 1, max_name + 1)?;
            let size_at = type_end + 1;
            let size = head.get(size_at..size_at + 4).ok_or(ScanProblem::Incomplete)?;
            let size = i32::from_le_bytes([size[0], size[1], size[2], size[3]]);
            let size = usize::try_from(size)
                .map_err(|_| ScanProblem::Malformed(format!("an attribute declares {size} bytes")))?;
            let end = size_at + 4 + size;
            if end > head.len() {
                return Err(ScanProblem::Incomplete);
            }
            attributes.push(StoredAttribute {
                name: at..name_end,
                type_name: name_end + 1..type_end,
                value: size_at + 4..end,
                whole: at..end,
            });
            at = end;
        }
        parts.push(StoredHeader { attributes, bytes: start..at });
        if !multipart {
            return Ok(parts);
        }
        match head.get(at) {
            None => return Err(ScanProblem::Incomplete),
            Some(0) => return Ok(parts),
            Some(_) => {}
        }
    }
}

/// The position of the NUL ending a string that starts at `at`, at most
/// `longest` bytes on.
fn nul_within(head: &[u8], at: usize, longest: usize) -> std::result::Result<usize, ScanProblem> {
    let window = head.get(at..).ok_or(ScanProblem::Incomplete)?;
    match window.iter().take(longest + 1).position(|b| *b == 0) {
        Some(n) => Ok(at + n),
        None if window.len() <= longest => Err(ScanProblem::Incomplete),
        None => Err(ScanProblem::Malformed("a name in the header is longer than OpenEXR allows".into())),
    }
}

/// Read a file's headers as stored, reading only as far as they go.
pub(crate) fn read_stored(path: &Path) -> Result<StoredHeaders> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = std::io::BufReader::new(file);
    let mut bytes = Vec::new();
    let mut want: u64 = 64 * 1024;
    loop {
        let have = bytes.len() as u64;
        let got =
            Read::by_ref(&mut reader).take(want - have).read_to_end(&mut bytes).map_err(|e| Error::io(path, e))?;
        match scan(&bytes) {
            Ok(parts) => {
                let end = parts.last().map_or(PREAMBLE, |p| p.bytes.end) + usize::from(bytes[5] & 0x10 != 0);
                bytes.truncate(end);
                return Ok(StoredHeaders { bytes, parts });
            }
            Err(ScanProblem::Malformed(why)) => return Err(Error::invalid(path, format!("the header: {why}"))),
            Err(ScanProblem::Incomplete) if got == 0 || (bytes.len() as u64) < want => {
                return Err(Error::invalid(path, "the file ends inside its header: it is truncated"))
            }
            Err(ScanProblem::Incomplete) if want >= MAX_HEADER_BYTES => {
                return Err(Error::TooLarge {
                    path: path.into(),
                    what: "header bytes",
                    value: want,
                    limit: MAX_HEADER_BYTES,
                })
            }
            Err(ScanProblem::Incomplete) => want = (want * 4).min(MAX_HEADER_BYTES),
        }
    }
}

/// The placeholder a writer stores before the digest is known, and the text a
/// digest's own value is read as while hashing.
pub(crate) fn placeholder() -> String {
    format!("{DIGEST_PREFIX}{}", "0".repeat(64))
}

/// What a part's `holo.headerDigest` says, and what its header hashes to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Seal {
    /// No `holo.headerDigest` (files of version 1.0 and 1.1).
    Absent,
    /// Present, and not a `string` of `sha256:` and 64 hex digits.
    Malformed(String),
    /// Stored and computed digests.
    Stored { stored: String, computed: String },
}

impl Seal {
    /// Whether the header is sealed and matches.
    #[cfg(test)]
    pub(crate) fn matches(&self) -> bool {
        matches!(self, Seal::Stored { stored, computed } if stored == computed)
    }
}

/// The seal of `part` in `headers`.
pub(crate) fn seal(headers: &StoredHeaders, part: usize) -> Seal {
    let Some(header) = headers.parts.get(part) else { return Seal::Absent };
    let bytes = &headers.bytes;
    let Some(attribute) = header.attributes.iter().find(|a| &bytes[a.name.clone()] == name::HEADER_DIGEST.as_bytes())
    else {
        return Seal::Absent;
    };
    let type_name = String::from_utf8_lossy(&bytes[attribute.type_name.clone()]);
    let stored = String::from_utf8_lossy(&bytes[attribute.value.clone()]).into_owned();
    if type_name != "string" {
        return Seal::Malformed(format!("has type {type_name}, not string"));
    }
    if !super::digest::is_well_formed(&stored) {
        return Seal::Malformed(format!("{stored:?} is not `sha256:` and 64 hex digits"));
    }
    Seal::Stored { stored, computed: digest_of(bytes, header, Some(attribute.value.clone())) }
}

/// The SHA-256 of the preamble and `header`'s bytes, with the hex digits of
/// the value at `own` (the digest's own, when it has one) read as `0`.
pub(crate) fn digest_of(bytes: &[u8], header: &StoredHeader, own: Option<Range<usize>>) -> String {
    let mut sha = Sha256::new();
    sha.update(&bytes[..PREAMBLE]);
    match own {
        Some(value) => {
            let digits = value.start + DIGEST_PREFIX.len()..value.end;
            sha.update(&bytes[header.bytes.start..digits.start]);
            sha.update(vec![b'0'; digits.len()]);
            sha.update(&bytes[digits.end..header.bytes.end]);
        }
        None => sha.update(&bytes[header.bytes.clone()]),
    }
    let mut out = String::with_capacity(DIGEST_PREFIX.len() + 64);
    out.push_str(DIGEST_PREFIX);
    for b in sha.finalize() {
        out.push_str(&format!("{b:02x}"));
    }
    out
}

/// What the seals of a file's parts say, as problems (damage first): `sealed`
/// when the file's version requires every part to carry one (1.2 on).
pub(crate) fn problems(headers: &StoredHeaders, sealed: bool) -> Vec<String> {
    let many = headers.parts.len() > 1;
    let mut out = Vec::new();
    for part in 0..headers.parts.len() {
        let prefix = if many { format!("part {part}: ") } else { String::new() };
        match seal(headers, part) {
            Seal::Absent if sealed => out.push(format!(
                "{prefix}required attribute {} is missing: the header cannot be checked (damaged, or rewritten by a program that dropped it)",
                name::HEADER_DIGEST
            )),
            Seal::Absent => {}
            Seal::Malformed(why) => out.push(format!("{prefix}{} {why}", name::HEADER_DIGEST)),
            Seal::Stored { stored, computed } if stored != computed => out.push(format!(
                "{prefix}the header does not match its digest ({} {stored}, computed {computed}): the header is damaged, or was changed after it was written",
                name::HEADER_DIGEST
            )),
            Seal::Stored { .. } => {}
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A two-part header by hand: magic, version 2 with the multi-part flag,
    /// then each part's attributes and NUL, then the NUL that ends them.
    fn two_parts() -> Vec<u8> {
        let mut b = vec![0x76, 0x2f, 0x31, 0x01, 2, 0x10, 0, 0];
        let attribute = |b: &mut Vec<u8>, n: &str, t: &str, v: &[u8]| {
            b.extend_from_slice(n.as_bytes());
            b.push(0);
            b.extend_from_slice(t.as_bytes());
            b.push(0);
            b.extend_from_slice(&(v.len() as i32).to_le_bytes());
            b.extend_from_slice(v);
        };
        for part in 0..2i32 {
            attribute(&mut b, "holo.frame", "int", &part.to_le_bytes());
            attribute(&mut b, name::HEADER_DIGEST, "string", placeholder().as_bytes());
            b.push(0);
        }
        b.push(0);
        b
    }

    #[test]
    fn scan_finds_every_attribute_and_asks_for_more_when_cut_short() {
        let b = two_parts();
        let parts = scan(&b).unwrap();
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[1].attributes.len(), 2);
        assert_eq!(&b[parts[1].attributes[0].value.clone()], &1i32.to_le_bytes());
        assert_eq!(parts[1].bytes.end, b.len() - 1);
        for cut in 0..b.len() {
            assert_eq!(scan(&b[..cut]).unwrap_err(), ScanProblem::Incomplete, "cut at {cut}");
        }
    }

    #[test]
    fn the_digest_ignores_only_its_own_digits() {
        let mut b = two_parts();
        let parts = scan(&b).unwrap();
        let own = parts[0].attributes[1].value.clone();
        let sealed = digest_of(&b, &parts[0], Some(own.clone()));
        // Writing the digest into its own value leaves the digest unchanged.
        b[own.clone()].copy_from_slice(sealed.as_bytes());
        let headers = StoredHeaders { bytes: b.clone(), parts: parts.clone() };
        assert!(seal(&headers, 0).matches());
        // Part 1 still holds the placeholder: a mismatch.
        assert!(!seal(&headers, 1).matches());
        // Every byte of part 0's header (its digest's own digits as well: they
        // no longer match, or are no longer hex), and of the preamble, counts.
        for at in (0..8).chain(parts[0].bytes.clone()) {
            let mut flipped = b.clone();
            flipped[at] ^= 0x20;
            let headers = StoredHeaders { bytes: flipped, parts: parts.clone() };
            assert!(!seal(&headers, 0).matches(), "byte {at}");
        }
    }
}
