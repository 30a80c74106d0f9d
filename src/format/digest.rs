//! The frame digest of spec §7: SHA-256 over the samples of the whole display
//! window, row by row; within a row channel by channel in channel-list order
//! (ASCII order of the names); within a channel emitter by emitter; each sample
//! as the little-endian bytes of its stored type, +0.0 outside the data window.
//! This is exactly the byte order of an uncompressed EXR scan line, so any
//! EXR reader plus a SHA-256 reproduces it (see `tests/peer/openexr_peer.py`).

use sha2::{Digest, Sha256};

use super::channels::ChannelOrder;
use super::SampleType;
use crate::Modulation;

/// Prefix of the stored digest text.
pub const DIGEST_PREFIX: &str = "sha256:";

/// The digest of one frame as stored (`sha256:` and 64 lower-case hex digits).
pub fn frame_digest(m: &Modulation, sample_type: SampleType) -> String {
    let g = m.geometry();
    let order = ChannelOrder::new(g);
    let (emitters, views, colours) = (g.emitters, g.views.count, g.channels.len());
    let bytes_per_sample = sample_type.bytes();
    let mut row = vec![0u8; order.len() * emitters * bytes_per_sample];
    let mut hasher = Sha256::new();
    for j in 0..g.hololines {
        for c in 0..colours {
            let line = m.hololine(c, j);
            for e in 0..emitters {
                for v in 0..views {
                    let slot = order.slot_of(v, c) * emitters + e;
                    let x = line[e * views + v];
                    let at = slot * bytes_per_sample;
                    match sample_type {
                        SampleType::F16 => row[at..at + 2].copy_from_slice(&half::f16::from_f32(x).to_le_bytes()),
                        SampleType::F32 => row[at..at + 4].copy_from_slice(&x.to_le_bytes()),
                    }
                }
            }
        }
        hasher.update(&row);
    }
    let mut out = String::with_capacity(DIGEST_PREFIX.len() + 64);
    out.push_str(DIGEST_PREFIX);
    for b in hasher.finalize() {
        out.push_str(&format!("{b:02x}"));
    }
    out
}

/// Whether a stored digest text is well formed.
pub fn is_well_formed(digest: &str) -> bool {
    digest
        .strip_prefix(DIGEST_PREFIX)
        .is_some_and(|hex| hex.len() == 64 && hex.bytes().all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b)))
}
