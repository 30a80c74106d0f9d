//! OpenEXR's ZIP compression (`ZIP_COMPRESSION`, 16 scan lines a block, and
//! `ZIPS_COMPRESSION`, one), written here with libdeflate rather than the
//! `exr` crate's deflate, which is about half as fast at the same size
//! (`cargo bench --bench format_io` prints both on real content).
//!
//! The encoding (OpenEXR's *OpenEXR File Layout*, "ZIP compression", and its
//! reference `ImfZip.cpp`): the block's bytes in the file's little-endian
//! layout are reordered, every even-indexed byte first and every odd-indexed
//! one after them (so the high and low bytes of half floats gather); then,
//! from the second byte on, each byte is replaced by its difference from the
//! byte before it plus 128, modulo 256; the result is compressed as one zlib
//! stream (RFC 1950). A block whose stream would not be smaller than its
//! bytes is stored as the bytes themselves, which readers recognise by its
//! size. Any zlib stream that inflates to the predicted bytes is a valid
//! block: the bytes depend on the deflate implementation and its level
//! (spec holo-format §8), the samples do not.

use std::cell::RefCell;

/// libdeflate's level used. Chosen with the table `cargo bench --bench
/// format_io` prints (one thread, Mark III frames): level 4 is as small as the
/// `exr` crate's deflate on the Spot (16.3 % against 16.2 %) and smaller on
/// noisy RGB (48.3 % against 49.6 %), at 1.9× and 2.2× its speed; level 6
/// gains 0.4–0.6 % of size for a fifth of the speed.
pub const LEVEL: i32 = 4;

/// The reordered, differenced bytes the zlib stream holds.
pub fn predict(le: &[u8]) -> Vec<u8> {
    let half = le.len().div_ceil(2);
    let mut out = vec![0u8; le.len()];
    let (evens, odds) = out.split_at_mut(half);
    for (i, pair) in le.chunks(2).enumerate() {
        evens[i] = pair[0];
        if let Some(&b) = pair.get(1) {
            odds[i] = b;
        }
    }
    let mut previous = match out.first() {
        Some(&b) => b,
        None => return out,
    };
    for b in &mut out[1..] {
        let value = *b;
        *b = value.wrapping_sub(previous).wrapping_add(128);
        previous = value;
    }
    out
}

thread_local! {
    /// One compressor per thread: libdeflate's state is large to set up.
    static COMPRESSOR: RefCell<Option<libdeflater::Compressor>> = const { RefCell::new(None) };
}

/// One block's payload: the zlib stream of [`predict`]`(le)`, or `le`
/// itself when the stream is not smaller.
pub fn compress(le: &[u8], level: i32) -> Vec<u8> {
    let predicted = predict(le);
    COMPRESSOR.with(|cell| {
        let mut slot = cell.borrow_mut();
        let lvl = libdeflater::CompressionLvl::new(level).unwrap_or_default();
        let compressor = slot.get_or_insert_with(|| libdeflater::Compressor::new(lvl));
        let mut out = vec![0u8; compressor.zlib_compress_bound(predicted.len())];
        match compressor.zlib_compress(&predicted, &mut out) {
            Ok(n) if n < le.len() => {
                out.truncate(n);
                out
            }
            _ => le.to_vec(),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OpenEXR's two loops as `ImfZip.cpp` writes them, byte by byte.
    fn reference(raw: &[u8]) -> Vec<u8> {
        let n = raw.len();
        let mut tmp = vec![0u8; n];
        let (mut t1, mut t2) = (0, n.div_ceil(2));
        let mut r = 0;
        loop {
            if r < n {
                tmp[t1] = raw[r];
                t1 += 1;
                r += 1;
            } else {
                break;
            }
            if r < n {
                tmp[t2] = raw[r];
                t2 += 1;
                r += 1;
            } else {
                break;
            }
        }
        let mut p = i32::from(tmp.first().copied().unwrap_or(0));
        for t in tmp.iter_mut().skip(1) {
            let d = i32::from(*t) - p + (128 + 256);
            p = i32::from(*t);
            *t = d as u8;
        }
        tmp
    }

    fn bytes(n: usize, seed: u64) -> Vec<u8> {
        let mut x = seed;
        (0..n)
            .map(|_| {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (x >> 56) as u8
            })
            .collect()
    }

    #[test]
    fn the_prediction_is_openexr_s_for_every_length() {
        for n in [0, 1, 2, 3, 7, 64, 1001] {
            let raw = bytes(n, n as u64 + 1);
            assert_eq!(predict(&raw), reference(&raw), "{n} bytes");
        }
    }

    #[test]
    fn a_block_inflates_to_its_prediction_or_is_stored_raw() {
        // Smooth 16-bit ramps compress; noise does not, and is stored as it is.
        let smooth: Vec<u8> = (0..4096u32).flat_map(|i| ((i / 7) as u16 ^ 0x3c00).to_le_bytes()).collect();
        let packed = compress(&smooth, LEVEL);
        assert!(packed.len() < smooth.len() / 4);
        let mut inflated = vec![0u8; smooth.len()];
        let n = libdeflater::Decompressor::new().zlib_decompress(&packed, &mut inflated).unwrap();
        assert_eq!(&inflated[..n], &predict(&smooth)[..]);
        let noise = bytes(4096, 9);
        assert_eq!(compress(&noise, LEVEL), noise);
    }
}
