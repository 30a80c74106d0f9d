//! The frame digest of spec §7: SHA-256 over the samples of the whole display
//! window, row by row; within a row channel by channel in channel-list order
//! (ASCII order of the names); within a channel emitter by emitter; each sample
//! as the little-endian bytes of its stored type, +0.0 outside the data window.
//! This is exactly the byte order of an uncompressed EXR scan line, so any
//! EXR reader plus a SHA-256 reproduces it (see `tests/peer/openexr_peer.py`).

use sha2::{Digest, Sha256};

use super::channels::ChannelOrder;
use super::SampleType;
use crate::geometry::Geometry;
use crate::Modulation;

/// Prefix of the stored digest text.
pub const DIGEST_PREFIX: &str = "sha256:";

/// The digest of one frame as stored (`sha256:` and 64 lower-case hex digits).
pub fn frame_digest(m: &Modulation, sample_type: SampleType) -> String {
    let g = m.geometry();
    let order = ChannelOrder::new(g);
    let mut row = vec![0u8; row_bytes(g, sample_type)];
    let mut digest = RowDigest::default();
    for j in 0..g.hololines {
        stored_row(g, &order, sample_type, |c| m.hololine(c, j), &mut row);
        digest.update(&row);
    }
    digest.finish()
}

/// Bytes of one stored row of the display window (every channel, every emitter).
pub(crate) fn row_bytes(g: &Geometry, sample_type: SampleType) -> usize {
    g.views.count * g.channels.len() * g.emitters * sample_type.bytes()
}

/// One hololine as the digest hashes it (and as an uncompressed EXR scan line
/// of the display window holds it): channel by channel in list order, emitter
/// by emitter, little-endian samples of the stored type. `line(c)` gives
/// colour `c`'s (emitter, view) samples; `out` is [`row_bytes`] long.
pub(crate) fn stored_row<'a>(
    g: &Geometry,
    order: &ChannelOrder,
    sample_type: SampleType,
    line: impl Fn(usize) -> &'a [f32],
    out: &mut [u8],
) {
    let (emitters, views) = (g.emitters, g.views.count);
    let bytes_per_sample = sample_type.bytes();
    for c in 0..g.channels.len() {
        let line = line(c);
        for e in 0..emitters {
            for v in 0..views {
                let at = (order.slot_of(v, c) * emitters + e) * bytes_per_sample;
                let x = line[e * views + v];
                match sample_type {
                    SampleType::F16 => out[at..at + 2].copy_from_slice(&half::f16::from_f32(x).to_le_bytes()),
                    SampleType::F32 => out[at..at + 4].copy_from_slice(&x.to_le_bytes()),
                }
            }
        }
    }
}

/// The digest fed row by row, so a frame need not be whole in memory.
#[derive(Default)]
pub(crate) struct RowDigest(Sha256);

impl RowDigest {
    /// Hash the next row (rows in increasing hololine order).
    pub(crate) fn update(&mut self, row: &[u8]) {
        self.0.update(row);
    }
    /// The stored text.
    pub(crate) fn finish(self) -> String {
        let mut out = String::with_capacity(DIGEST_PREFIX.len() + 64);
        out.push_str(DIGEST_PREFIX);
        for b in self.0.finalize() {
            out.push_str(&format!("{b:02x}"));
        }
        out
    }
}

/// Whether a stored digest text is well formed.
pub fn is_well_formed(digest: &str) -> bool {
    digest
        .strip_prefix(DIGEST_PREFIX)
        .is_some_and(|hex| hex.len() == 64 && hex.bytes().all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b)))
}
