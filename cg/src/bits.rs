//! Bit I/O for compressed geometry: the stream is one MSB-first bit string,
//! which Java 3D's `GeometryDecompressor.getBits` reads by refilling a 32-bit
//! buffer with 4 bytes at a time, big-endian. A stream is therefore a whole
//! number of 4-byte words (the decoders check that up front), and reading
//! past its last bit is an error ("the stream ends inside a command").

use crate::error::StreamProblem;

/// Where a stream read went wrong: the bit offset (from the start of the
/// stream) of the command being decoded, and what is wrong. Small and
/// `Copy` for the decoders' hot loops; [`crate::Error::Stream`] outside.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct StreamError {
    /// Bit offset of the start of the command (its header) in the stream.
    pub bit: u64,
    /// What is wrong.
    pub problem: StreamProblem,
}

impl From<StreamError> for crate::Error {
    fn from(e: StreamError) -> Self {
        crate::Error::Stream { bit: e.bit, problem: e.problem }
    }
}

/// Reading ran past the end of the stream (the caller adds the command's offset).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct PastEnd;

impl From<PastEnd> for StreamProblem {
    fn from(_: PastEnd) -> Self {
        StreamProblem::EndsInsideCommand
    }
}

impl StreamProblem {
    /// This problem in the command whose header is at `bit`.
    pub(crate) fn at(self, bit: u64) -> StreamError {
        StreamError { bit, problem: self }
    }
}

/// Fast reader: a 64-bit left-aligned buffer refilled with as many whole
/// bytes as fit.
pub(crate) struct WordReader<'a> {
    bytes: &'a [u8],
    /// Next byte to load into `buf`.
    next: usize,
    /// Unread bits, left-aligned.
    buf: u64,
    /// Number of valid bits in `buf`.
    count: u32,
}

impl<'a> WordReader<'a> {
    /// A reader over `bytes`, whose length must be a multiple of 4 (checked by the caller).
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        WordReader { bytes, next: 0, buf: 0, count: 0 }
    }

    /// Top the buffer up to 56..=63 bits, or to the end of the stream.
    /// Away from the end one big-endian 8-byte load fills every whole byte
    /// that fits ([`Self::refill_fast`]); the last few bytes go one at a
    /// time. (Java refills a 4-byte word at a time; the bits are the same
    /// either way.)
    #[inline(always)]
    fn refill(&mut self) {
        if self.far_from_end(8) {
            self.refill_fast();
            return;
        }
        while self.count <= 55 {
            let Some(&byte) = self.bytes.get(self.next) else { return };
            self.buf |= u64::from(byte) << (56 - self.count);
            self.count += 8;
            self.next += 1;
        }
    }

    /// Top the buffer up to 56..=63 bits without looking for the end: the
    /// caller has made sure that 8 bytes remain to be loaded
    /// ([`Self::far_from_end`]). Branch-free: the bits of the byte only
    /// partly taken stay in the buffer below `count` and are loaded again
    /// at the same place, which OR-ing leaves as they are (the bits below
    /// `count` are always 0 or the stream's own). "Without looking for the
    /// end" means no branch on the stream's length: the slice below is still
    /// bounds-checked, so were the margin of `decode::run` ever wrong this
    /// would panic, never read outside the stream (the crate has no `unsafe`).
    #[inline(always)]
    fn refill_fast(&mut self) {
        let mut word = [0u8; 8];
        word.copy_from_slice(&self.bytes[self.next..self.next + 8]);
        // count <= 63 always (every refill leaves 56..=63), so the shift is in range.
        self.buf |= u64::from_be_bytes(word) >> self.count;
        self.next += ((63 - self.count) >> 3) as usize;
        self.count |= 56;
    }

    /// At least `bytes` bytes remain to be loaded (the decoder's test for
    /// `FAST` reads; `decode::run` works out the margin they need).
    #[inline(always)]
    pub(crate) fn far_from_end(&self, bytes: usize) -> bool {
        self.bytes.len() - self.next >= bytes
    }

    /// The next `n` bits (`n <= 32`) as an unsigned number. `FAST`: no
    /// end-of-stream check, for callers that checked [`Self::far_from_end`].
    #[inline(always)]
    pub(crate) fn read<const FAST: bool>(&mut self, n: u32) -> Result<u32, PastEnd> {
        if !self.ensure::<FAST>(n) {
            return Err(PastEnd);
        }
        Ok(self.take(n) as u32)
    }

    /// Make the next `n` bits (`n <= 56`) available to [`Self::take`]:
    /// false when the stream ends first. After a refill at least 56 bits are
    /// buffered unless the stream ends, so one check covers a whole body.
    /// `FAST`: as [`Self::read`].
    #[inline(always)]
    pub(crate) fn ensure<const FAST: bool>(&mut self, n: u32) -> bool {
        if FAST {
            // Unconditionally: a refill costs a few instructions, while a
            // branch on the bit count goes whichever way the data says and
            // was mispredicted most of the time.
            debug_assert!(n <= 56);
            self.refill_fast();
            return true;
        }
        if self.count < n {
            self.refill();
        }
        self.count >= n
    }

    /// The next `n` bits (`n <= 56`), which [`Self::ensure`] has made available.
    #[inline(always)]
    pub(crate) fn take(&mut self, n: u32) -> u64 {
        debug_assert!(n <= self.count && n <= 56);
        // Two shifts so that n = 0 gives 0 without a branch.
        let v = (self.buf >> 1) >> (63 - n);
        self.buf <<= n;
        self.count -= n;
        v
    }

    /// Every bit has been read.
    #[inline(always)]
    pub(crate) fn at_end(&self) -> bool {
        self.count == 0 && self.next >= self.bytes.len()
    }

    /// Bits read so far.
    #[inline(always)]
    pub(crate) fn position(&self) -> u64 {
        self.next as u64 * 8 - u64::from(self.count)
    }
}

/// Slow reader for the reference decoder: one bit at a time, no buffer.
pub(crate) struct BitByBit<'a> {
    bytes: &'a [u8],
    /// Next bit to read.
    bit: u64,
}

impl<'a> BitByBit<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        BitByBit { bytes, bit: 0 }
    }

    /// The next `n` bits, most significant first.
    pub(crate) fn read(&mut self, n: u32) -> Result<u64, PastEnd> {
        let mut v = 0u64;
        for _ in 0..n {
            let byte = usize::try_from(self.bit / 8).map_err(|_| PastEnd)?;
            let b = self.bytes.get(byte).ok_or(PastEnd)?;
            v = (v << 1) | u64::from((b >> (7 - self.bit % 8)) & 1);
            self.bit += 1;
        }
        Ok(v)
    }

    pub(crate) fn at_end(&self) -> bool {
        self.bit >= self.bytes.len() as u64 * 8
    }

    pub(crate) fn position(&self) -> u64 {
        self.bit
    }
}

/// MSB-first bit writer.
#[derive(Default)]
pub(crate) struct BitWriter {
    bytes: Vec<u8>,
    /// Bits written so far.
    len: u64,
}

impl BitWriter {
    /// Append the low `n` bits of `value` (`n <= 64`), most significant first.
    pub(crate) fn write(&mut self, value: u64, n: u32) {
        for i in (0..n).rev() {
            let bit = ((value >> i) & 1) as u8;
            let used = (self.len % 8) as u32;
            if used == 0 {
                self.bytes.push(0);
            }
            if bit != 0 {
                if let Some(last) = self.bytes.last_mut() {
                    *last |= 0x80 >> used;
                }
            }
            self.len += 1;
        }
    }

    /// Bits written so far.
    pub(crate) fn bit_len(&self) -> u64 {
        self.len
    }

    pub(crate) fn into_bytes(self) -> Vec<u8> {
        self.bytes
    }
}

/// The low `n` bits set (`n <= 64`).
#[inline(always)]
pub(crate) fn mask(n: u32) -> u64 {
    if n >= 64 {
        u64::MAX
    } else {
        (1u64 << n) - 1
    }
}

/// `v`'s low `n` bits as a two's-complement number (0 when `n == 0`).
#[inline(always)]
pub(crate) fn sign_extend(v: u64, n: u32) -> i32 {
    if n == 0 {
        return 0;
    }
    let shift = 64 - n;
    (((v << shift) as i64) >> shift) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn readers_agree_with_writer() {
        let mut w = BitWriter::default();
        let fields: Vec<(u64, u32)> =
            (0..200u64).map(|i| ((i * 2654435761) & mask((i % 33) as u32), (i % 33) as u32)).collect();
        for &(v, n) in &fields {
            w.write(v, n);
        }
        while w.bit_len() % 32 != 0 {
            w.write(0, 1);
        }
        let bytes = w.into_bytes();
        let mut fast = WordReader::new(&bytes);
        let mut slow = BitByBit::new(&bytes);
        for &(v, n) in &fields {
            assert_eq!(u64::from(fast.read::<false>(n).unwrap()), v);
            assert_eq!(slow.read(n).unwrap(), v);
            assert_eq!(fast.position(), slow.position());
        }
    }

    /// Random bytes read in random widths (0..=56 bits, by `read` and by
    /// `ensure`/`take`, checked and, 8 bytes or more from the end, `FAST`):
    /// the word reader, whose refill takes 8 bytes at a time away from the
    /// end, gives the bit-by-bit reader's values, positions and end.
    #[test]
    fn random_reads_agree() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for len in [4usize, 8, 12, 36, 400] {
            let bytes: Vec<u8> = (0..len).map(|_| next() as u8).collect();
            let mut fast = WordReader::new(&bytes);
            let mut slow = BitByBit::new(&bytes);
            loop {
                let n = (next() % 57) as u32;
                let fast_ok = fast.far_from_end(8) && next() % 2 == 0;
                let want = slow.read(n);
                let got = if fast_ok && n <= 32 {
                    fast.read::<true>(n).map(u64::from)
                } else if fast_ok && fast.ensure::<true>(n) {
                    Ok(fast.take(n))
                } else if next() % 2 == 0 && n <= 32 {
                    fast.read::<false>(n).map(u64::from)
                } else if fast.ensure::<false>(n) {
                    Ok(fast.take(n))
                } else {
                    Err(PastEnd)
                };
                if want.is_err() {
                    assert!(got.is_err(), "{len} bytes: {n} bits past the end");
                    break;
                }
                assert_eq!(got, want, "{len} bytes, {n} bits at {}", slow.position() - u64::from(n));
                assert_eq!(fast.position(), slow.position());
                assert_eq!(fast.at_end(), slow.at_end());
            }
        }
    }

    #[test]
    fn past_end_is_an_error() {
        let bytes = [0xAB, 0xCD, 0xEF, 0x01];
        let mut r = WordReader::new(&bytes);
        assert_eq!(r.read::<false>(16).unwrap(), 0xABCD);
        assert_eq!(r.read::<false>(17), Err(PastEnd));
        let mut s = BitByBit::new(&bytes);
        assert_eq!(s.read(16).unwrap(), 0xABCD);
        assert_eq!(s.read(17), Err(PastEnd));
    }

    #[test]
    fn sign_extension() {
        assert_eq!(sign_extend(0b111, 3), -1);
        assert_eq!(sign_extend(0b011, 3), 3);
        assert_eq!(sign_extend(0x8000, 16), -32768);
        assert_eq!(sign_extend(5, 0), 0);
    }
}
