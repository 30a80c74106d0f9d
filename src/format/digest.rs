//! The frame digest of spec §7.1: SHA-256 over the samples of the whole display
//! window, row by row; within a row channel by channel in channel-list order
//! (ASCII order of the names); within a channel emitter by emitter; each sample
//! as the little-endian bytes of its stored type, +0.0 outside the data window.
//! This is exactly the byte order of an uncompressed EXR scan line, so any
//! EXR reader plus a SHA-256 reproduces it (see `tests/peer/openexr_peer.py`).

use sha2::{Digest, Sha256};

use super::channels::ChannelOrder;
use super::SampleType;
use crate::geometry::Geometry;
use crate::modulation::Modulation;

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

/// The frame digest (spec §7.1) from a frame's blocks (decoded by a reader,
/// built by a writer), which may come in any order: each block's rows are the stored scan lines of the data window, so
/// they are hashed as they are (widened with +0.0 samples to the display
/// window), row after row, zero rows above and below the data window. A
/// block that comes early waits for the ones before it. The hashing runs on
/// a thread of its own, beside the decoding and placing (a SHA-256 of a
/// frame costs about as much as placing it): blocks go to it through a short
/// queue.
pub(crate) struct BlockDigest {
    queue: Option<std::sync::mpsc::SyncSender<(usize, usize, Vec<u8>)>>,
    hasher: Option<std::thread::JoinHandle<String>>,
}

impl BlockDigest {
    pub(crate) fn new(g: &Geometry, sample_type: SampleType, window: super::Window) -> BlockDigest {
        let mut rows = OrderedRows {
            digest: RowDigest::default(),
            next: 0,
            rows: g.hololines,
            window,
            channels: g.views.count * g.channels.len(),
            emitters: g.emitters,
            bytes: sample_type.bytes(),
            waiting: Default::default(),
            row: vec![0; row_bytes(g, sample_type)],
        };
        let (queue, blocks) = std::sync::mpsc::sync_channel::<(usize, usize, Vec<u8>)>(8);
        let hasher = std::thread::Builder::new()
            .name("holo-digest".into())
            .spawn(move || {
                for (top, count, data) in blocks {
                    rows.push(top, count, data.into());
                }
                rows.finish()
            })
            .ok();
        BlockDigest { queue: hasher.as_ref().map(|_| queue), hasher }
    }

    /// Block bytes for display rows `top .. top + rows`.
    pub(crate) fn push(&mut self, top: usize, rows: usize, data: Vec<u8>) {
        if let Some(queue) = &self.queue {
            // A hasher that has gone (it cannot, but if it did) shows as a
            // digest that does not match.
            let _ = queue.send((top, rows, data));
        }
    }

    /// The stored text, once every block has come (`None` when no hashing
    /// thread could be started; the caller hashes the samples instead).
    pub(crate) fn finish(mut self) -> Option<String> {
        drop(self.queue.take());
        self.hasher.take().and_then(|h| h.join().ok())
    }
}

/// One decoded block of a part: (part, first display row, rows, its bytes).
pub(crate) type PartBlock<'a> = (usize, usize, usize, &'a [u8]);

/// The digests of a full-parallax frame's view parts (spec §8, §7.1) from
/// their decoded blocks, as [`BlockDigest`] takes a frame's: each part's rows
/// hashed in order as its blocks come (one that comes early waits), the
/// parts of a batch side by side on every core. Hashing the blocks' own
/// bytes spares gathering each view's samples back out of the frame, a
/// cache line per sample.
pub(crate) struct PartDigests {
    parts: Vec<std::sync::Mutex<OrderedRows>>,
}

impl PartDigests {
    /// One digest per part, each part's data window in `windows`; its rows
    /// are the colours of `g`'s emitters.
    pub(crate) fn new(g: &Geometry, sample_type: SampleType, windows: impl Iterator<Item = super::Window>) -> Self {
        let colours = super::channels::colour_slots(g).len();
        let parts = windows
            .map(|window| {
                std::sync::Mutex::new(OrderedRows {
                    digest: RowDigest::default(),
                    next: 0,
                    rows: g.hololines,
                    window,
                    channels: colours,
                    emitters: g.emitters,
                    bytes: sample_type.bytes(),
                    waiting: Default::default(),
                    row: vec![0; colours * g.emitters * sample_type.bytes()],
                })
            })
            .collect();
        PartDigests { parts }
    }

    /// A batch of decoded blocks, in any order.
    pub(crate) fn push_batch(&self, blocks: &mut [PartBlock<'_>]) {
        use rayon::prelude::*;
        blocks.sort_unstable_by_key(|&(part, top, _, _)| (part, top));
        let groups: Vec<&[PartBlock<'_>]> = blocks.chunk_by(|a, b| a.0 == b.0).collect();
        groups.par_iter().for_each(|group| {
            let Some(rows) = self.parts.get(group[0].0) else { return };
            // A poisoned lock (a panic elsewhere) leaves a digest that does not match.
            let Ok(mut rows) = rows.lock() else { return };
            for &(_, top, count, data) in group.iter() {
                rows.push(top, count, data.into());
            }
        });
    }

    /// Each part's digest text, in part order.
    pub(crate) fn finish(self) -> Vec<String> {
        self.parts.into_iter().map(|rows| rows.into_inner().map(OrderedRows::finish).unwrap_or_default()).collect()
    }
}

/// The rows of a frame hashed in order (see [`BlockDigest`]).
struct OrderedRows {
    digest: RowDigest,
    /// The next display row to hash.
    next: usize,
    /// Display rows.
    rows: usize,
    /// The data window.
    window: super::Window,
    /// Channels, emitters of the display window, bytes per sample.
    channels: usize,
    emitters: usize,
    bytes: usize,
    /// Blocks that came early, by first display row: (rows, bytes).
    waiting: std::collections::BTreeMap<usize, (usize, Vec<u8>)>,
    /// One widened or zero row, reused.
    row: Vec<u8>,
}

impl OrderedRows {
    fn push(&mut self, top: usize, rows: usize, data: std::borrow::Cow<'_, [u8]>) {
        self.zero_rows_until(self.window.y.min(self.rows));
        if top == self.next {
            self.hash_block(rows, &data);
        } else {
            self.waiting.insert(top, (rows, data.into_owned()));
        }
        while let Some((rows, data)) = self.waiting.remove(&self.next) {
            self.hash_block(rows, &data);
        }
    }

    fn zero_rows_until(&mut self, end: usize) {
        if self.next >= end {
            return;
        }
        self.row.fill(0);
        while self.next < end {
            self.digest.update(&self.row);
            self.next += 1;
        }
    }

    fn hash_block(&mut self, rows: usize, data: &[u8]) {
        let w = self.window.width;
        let line = self.channels * w * self.bytes;
        let full = self.window.x == 0 && w == self.emitters;
        for r in 0..rows {
            let Some(stored) = data.get(r * line..(r + 1) * line) else { return };
            if full {
                self.digest.update(stored);
            } else {
                self.row.fill(0);
                let (left, width) = (self.window.x * self.bytes, w * self.bytes);
                for (slot, run) in stored.chunks_exact(width).enumerate() {
                    let at = slot * self.emitters * self.bytes + left;
                    self.row[at..at + width].copy_from_slice(run);
                }
                self.digest.update(&self.row);
            }
            self.next += 1;
        }
    }

    fn finish(mut self) -> String {
        self.zero_rows_until(self.rows);
        self.digest.finish()
    }
}
