//! Checksums of a HoloFlick (spec §3.3, from version 1.1): the CRC-32 of
//! every frame, kept in an ancillary `sums` chunk at the start of the frame
//! together with one CRC-32 per sub-chunk (so damage is named down to the
//! object), and two in the file header (the file-level chunks, the index).
//!
//! CRC-32 is the one of PNG, zlib and gzip (ISO 3309 / ITU-T V.42; reflected
//! polynomial 0xEDB88320, initial value and final XOR 0xFFFFFFFF). It
//! detects every single-bit error and every burst of up to 32 bits in a
//! frame of any size, and misses other damage with probability 2⁻³²; it is
//! a guard against storage and transfer faults, not against tampering
//! (anyone can recompute it).

use super::chunk::{padding, put_chunk, CHUNK_HEADER};
use super::error::Problem;

/// Tag of the checksum chunk.
pub(crate) const SUMS: [u8; 4] = *b"sums";

/// Bytes of the `sums` payload before the per-sub-chunk values: the count
/// and the frame's checksum.
const SUMS_HEAD: usize = 8;

/// Where the frame's checksum lies in a `FRAM` payload: after the frame
/// number and flags, the `sums` chunk's header and its count.
const FRAME_SUM: std::ops::Range<usize> = 20..24;

/// CRC-32 of `bytes`.
pub(crate) fn crc32(bytes: &[u8]) -> u32 {
    crc32fast::hash(bytes)
}

/// The payload of a `FRAM` chunk with its `sums` chunk: `head` (frame number
/// and flags, 8 bytes) and `body` (the sub-chunks, padded), where `chunks`
/// gives each sub-chunk's byte range in `body`, padding excluded. The
/// frame's checksum covers the whole payload, its own four bytes taken as
/// zero.
pub(crate) fn seal_frame(head: &[u8], body: &[u8], chunks: &[std::ops::Range<usize>]) -> Vec<u8> {
    let mut sums = Vec::with_capacity(SUMS_HEAD + 4 * chunks.len());
    sums.extend_from_slice(&(chunks.len() as u32).to_le_bytes());
    sums.extend_from_slice(&[0; 4]); // the frame's checksum, below
    for r in chunks {
        sums.extend_from_slice(&crc32(&body[r.clone()]).to_le_bytes());
    }
    let mut payload = Vec::with_capacity(head.len() + CHUNK_HEADER + sums.len() + 8 + body.len());
    payload.extend_from_slice(head);
    put_chunk(&mut payload, SUMS, &sums);
    payload.extend_from_slice(body);
    let frame_sum = crc32(&payload);
    payload[FRAME_SUM].copy_from_slice(&frame_sum.to_le_bytes());
    payload
}

/// Check a frame's bytes against its `sums` chunk (`payload`: the `FRAM`
/// payload). `Ok(true)` when the frame carries checksums and they hold,
/// `Ok(false)` when it carries none and `required` is false (a 1.0 file).
/// A mismatch names the sub-chunk (and for objects, the id as stored)
/// whose own checksum fails, when one does.
pub(crate) fn verify_frame(payload: &[u8], required: bool) -> Result<bool, Problem> {
    let damaged = |what: String| Problem::Damaged(what);
    let u32_at = |at: usize| payload.get(at..at + 4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
    if payload.get(8..12) != Some(&SUMS[..]) {
        return if required {
            Err(damaged("the frame's checksum chunk (sums, first in every frame of a 1.1 file) is missing".into()))
        } else {
            Ok(false)
        };
    }
    let cut_short = || damaged("the frame's checksum chunk is cut short".into());
    let sums_len = u32_at(12).ok_or_else(cut_short)? as usize;
    let body_start = 16usize.checked_add(sums_len).map(|e| e + padding(sums_len as u64) as usize);
    let body_start = body_start.filter(|&e| e <= payload.len() && sums_len >= SUMS_HEAD).ok_or_else(cut_short)?;
    let count = u32_at(16).ok_or_else(cut_short)? as usize;
    if count.checked_mul(4).and_then(|b| b.checked_add(SUMS_HEAD)) != Some(sums_len) {
        return Err(damaged(format!(
            "the frame's checksum chunk has {sums_len} bytes for {count} sub-chunks, not {}",
            SUMS_HEAD as u64 + 4 * count as u64
        )));
    }
    let stored = u32_at(FRAME_SUM.start).ok_or_else(cut_short)?;
    // The whole payload, this field read as zero: every byte of the frame
    // but its tag and length (which the index checks) is covered.
    let mut whole = crc32fast::Hasher::new();
    whole.update(&payload[..FRAME_SUM.start]);
    whole.update(&[0; 4]);
    whole.update(&payload[FRAME_SUM.end..]);
    if whole.finalize() == stored {
        return Ok(true);
    }
    // Locate the damage for the message: the first sub-chunk whose own
    // checksum fails, walking as far as the lengths allow.
    let body = &payload[body_start..];
    let mut at = 0usize;
    for i in 0..count {
        let header = body.get(at..at + CHUNK_HEADER);
        let Some(header) = header else { break };
        let tag = [header[0], header[1], header[2], header[3]];
        let len = u32::from_le_bytes([header[4], header[5], header[6], header[7]]) as usize;
        let Some(chunk) = body.get(at..at + CHUNK_HEADER + len) else {
            return Err(damaged(format!(
                "the frame does not match its checksum, and sub-chunk {} says {len} bytes, more than the frame holds",
                i + 1
            )));
        };
        if u32_at(24 + 4 * i) != Some(crc32(chunk)) {
            let name = super::error::tag_text(tag);
            let what = match &tag {
                b"GEOM" | b"KREF" => match chunk.get(8..12) {
                    Some(id) => format!(
                        "object {} (its {name} chunk, sub-chunk {} of the frame)",
                        u32::from_le_bytes([id[0], id[1], id[2], id[3]]),
                        i + 1
                    ),
                    None => format!("the {name} chunk (sub-chunk {} of the frame)", i + 1),
                },
                _ => format!("the {name} chunk (sub-chunk {} of the frame)", i + 1),
            };
            return Err(damaged(format!("{what} does not match its checksum")));
        }
        at += CHUNK_HEADER + len + padding(len as u64) as usize;
    }
    Err(damaged(
        "the frame does not match its checksum (the damage is in its header, padding or checksum chunk)".into(),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// CRC-32 bit by bit, straight from the definition: the slow reference.
    fn crc32_reference(bytes: &[u8]) -> u32 {
        let mut crc = 0xFFFF_FFFFu32;
        for &b in bytes {
            crc ^= b as u32;
            for _ in 0..8 {
                crc = if crc & 1 != 0 { (crc >> 1) ^ 0xEDB8_8320 } else { crc >> 1 };
            }
        }
        !crc
    }

    #[test]
    fn crc32_is_the_png_one() {
        // The check value of CRC-32/ISO-HDLC.
        assert_eq!(crc32(b"123456789"), 0xCBF4_3926);
        let mut state = 0x1234_5678_9abc_def0u64;
        for len in [0, 1, 7, 64, 1000, 4099] {
            let bytes: Vec<u8> = (0..len)
                .map(|_| {
                    state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                    (state >> 56) as u8
                })
                .collect();
            assert_eq!(crc32(&bytes), crc32_reference(&bytes), "{len} bytes");
        }
    }

    #[test]
    fn every_single_bit_flip_is_found_and_located() {
        let head = [3, 0, 0, 0, 1, 0, 0, 0];
        let mut body = Vec::new();
        let mut ranges = Vec::new();
        for (tag, payload) in [(*b"COUC", &[7u8; 48][..]), (*b"GEOM", &[9, 0, 0, 0, 1, 2, 3][..])] {
            let start = body.len();
            put_chunk(&mut body, tag, payload);
            ranges.push(start..start + CHUNK_HEADER + payload.len());
        }
        let sealed = seal_frame(&head, &body, &ranges);
        assert_eq!(verify_frame(&sealed, true), Ok(true));
        assert_eq!(verify_frame(&[head.to_vec(), body.clone()].concat(), false), Ok(false));
        assert!(verify_frame(&[head.to_vec(), body.clone()].concat(), true).is_err());
        let body_start = sealed.len() - body.len();
        for bit in 0..sealed.len() * 8 {
            let mut b = sealed.clone();
            b[bit / 8] ^= 1 << (bit % 8);
            let Err(Problem::Damaged(what)) = verify_frame(&b, true) else { panic!("bit {bit} not found") };
            let at = bit / 8;
            if at >= body_start + ranges[1].start + 12 && at < body_start + ranges[1].end {
                assert!(what.contains("object 9 (its GEOM chunk, sub-chunk 2"), "bit {bit}: {what}");
            }
        }
    }
}
