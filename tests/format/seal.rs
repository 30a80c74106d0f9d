//! The header digest of spec §7.2, written here from the spec alone (not
//! from the library), for tests that edit a header on purpose: an edit of a
//! sealed header is damage, so a test of another rule reseals what it edits,
//! as a writer that wrote those values would have.

use sha2::{Digest, Sha256};

const NAME: &[u8] = b"holo.headerDigest";

/// Recompute every part's `holo.headerDigest` in an EXR file's bytes: the
/// SHA-256 of the first 8 bytes and the part's attribute list (first name
/// through the terminating NUL) with the digest's own 64 hex digits read as
/// `0`. Parts without the attribute are left as they are.
pub fn reseal(bytes: &mut [u8]) {
    let multipart = bytes[5] & 0x10 != 0;
    let mut at = 8;
    loop {
        let start = at;
        let mut own = None;
        loop {
            let name_end = at + bytes[at..].iter().position(|b| *b == 0).unwrap();
            if name_end == at {
                at += 1;
                break;
            }
            let type_end = name_end + 1 + bytes[name_end + 1..].iter().position(|b| *b == 0).unwrap();
            let size = i32::from_le_bytes(bytes[type_end + 1..type_end + 5].try_into().unwrap()) as usize;
            let value = type_end + 5..type_end + 5 + size;
            if &bytes[at..name_end] == NAME {
                own = Some(value.clone());
            }
            at = value.end;
        }
        if let Some(own) = own {
            let digits = own.start + "sha256:".len()..own.end;
            let mut sha = Sha256::new();
            sha.update(&bytes[..8]);
            sha.update(&bytes[start..digits.start]);
            sha.update(vec![b'0'; digits.len()]);
            sha.update(&bytes[digits.end..at]);
            let hex: String = sha.finalize().iter().map(|b| format!("{b:02x}")).collect();
            bytes[digits].copy_from_slice(hex.as_bytes());
        }
        if !multipart || bytes[at] == 0 {
            return;
        }
    }
}
