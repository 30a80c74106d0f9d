//! Packing signals into the frame buffer: the sample types a frame buffer
//! holds ([`FringeSample`]: 8-bit codes or floats), the kernel's sink that
//! encodes blocks as they are made, and the interleaving of channels into
//! pixels. These run on every sample of every frame, so they are written to
//! vectorise.

use std::any::Any;

use super::plan::{BlockSink, Blocks, LaneSink, PaddedWeights, Plan};
use crate::layout::Quantization;
use crate::simd::Simd;
#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::{
    __m128i, __m256, __m256i, _mm256_castsi256_si128, _mm256_cvtps_epi32, _mm256_fmadd_ps, _mm256_max_epu32,
    _mm256_packs_epi32, _mm256_packus_epi16, _mm256_permutevar8x32_epi32, _mm256_set1_epi32, _mm256_set1_ps,
    _mm256_setr_epi32, _mm256_setr_epi8, _mm256_setzero_si256, _mm256_shuffle_epi8, _mm256_storeu_ps,
    _mm256_storeu_si256, _mm256_testz_si256, _mm_storel_epi64, _mm_storeu_si128,
};

/// A frame-buffer sample type: 8-bit codes, or the float signal itself.
pub trait FringeSample: Copy + Send + Sync + 'static {
    /// Encode a piece of a hololine signal in the order it is sent
    /// (`reversed`: last sample first) into `out`; returns the number of
    /// clipped samples.
    fn encode_line(signal: &[f32], reversed: bool, out: &mut [Self], q: &Quantization) -> u64;
    /// How many samples of `signal` [`FringeSample::encode_line`] would
    /// count clipped.
    fn count_clipped(signal: &[f32], q: &Quantization) -> u64;
    /// The signal a stored value stands for.
    fn decode(self, q: &Quantization) -> f32;
    /// The value of pixels no signal reaches.
    fn blank(q: &Quantization) -> Self;
    /// `row[3x + k] = [a, b, c][k][x]`: three components into pixels (with
    /// vector instructions where the type has them and `simd` allows).
    fn interleave3(row: &mut [Self], a: &[Self], b: &[Self], c: &[Self], _simd: Simd) {
        for (((px, a), b), c) in row.chunks_exact_mut(3).zip(a).zip(b).zip(c) {
            px.copy_from_slice(&[*a, *b, *c]);
        }
    }
}

impl FringeSample for u8 {
    /// `round(clamp(offset + gain · x, 0, 255))`, ties to even. Inlined
    /// into the kernel's block store, so it is compiled with the kernel's
    /// vector instructions.
    #[inline(always)]
    fn encode_line(signal: &[f32], reversed: bool, out: &mut [u8], q: &Quantization) -> u64 {
        encode_bytes(signal, reversed, out, q.offset as f32, q.gain as f32)
    }
    fn count_clipped(signal: &[f32], q: &Quantization) -> u64 {
        let (offset, gain) = (q.offset as f32, q.gain as f32);
        signal.iter().filter(|x| clips(offset + gain * **x)).count() as u64
    }
    fn decode(self, q: &Quantization) -> f32 {
        ((f64::from(self) - q.offset) / q.gain) as f32
    }
    fn blank(q: &Quantization) -> u8 {
        q.offset.round().clamp(0.0, 255.0) as u8
    }
    fn interleave3(row: &mut [u8], a: &[u8], b: &[u8], c: &[u8], simd: Simd) {
        assert!(row.len() == 3 * a.len() && a.len() == b.len() && a.len() == c.len());
        #[cfg(target_arch = "x86_64")]
        if simd.ssse3() {
            // SAFETY: the feature is present; the lengths are checked above.
            unsafe { interleave3_ssse3(row, a, b, c) };
            return;
        }
        for (((px, a), b), c) in row.chunks_exact_mut(3).zip(a).zip(b).zip(c) {
            px.copy_from_slice(&[*a, *b, *c]);
        }
    }
}

/// Three byte planes into RGB pixels, 16 pixels per step: each 16-byte
/// output vector gathers its bytes from the three inputs with a shuffle.
/// Callers guarantee `row.len() == 3 · a.len()` and equal input lengths.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "ssse3")]
unsafe fn interleave3_ssse3(row: &mut [u8], a: &[u8], b: &[u8], c: &[u8]) {
    // SAFETY: SSSE3 is present (the caller checked it for this target_feature
    // function). Loads read 16 bytes at x <= pixels - 16 of each input; stores
    // write 16 bytes at 3x + 16o <= 3 pixels - 16 of `row`, whose length the
    // caller checked to be 3 pixels.
    unsafe {
        use std::arch::x86_64::{_mm_loadu_si128, _mm_or_si128, _mm_sfence, _mm_shuffle_epi8, _mm_stream_si128};
        // MASKS[o][s][j]: output vector o, byte j takes source s's byte
        // (16o + j) / 3 when (16o + j) mod 3 = s, else zero (0x80).
        const MASKS: [[[u8; 16]; 3]; 3] = {
            let mut masks = [[[0x80u8; 16]; 3]; 3];
            let mut i = 0;
            while i < 48 {
                masks[i / 16][i % 3][i % 16] = (i / 3) as u8;
                i += 1;
            }
            masks
        };
        let m = MASKS.map(|per_output| per_output.map(|mask| _mm_loadu_si128(mask.as_ptr().cast::<__m128i>())));
        // The frame buffer is written once and not read back here: aligned rows
        // are streamed past the caches (no read of the lines first).
        let stream = row.as_ptr() as usize % 16 == 0;
        let pixels = a.len();
        let mut x = 0;
        while x + 16 <= pixels {
            let src = [a, b, c].map(|s| _mm_loadu_si128(s.as_ptr().add(x).cast::<__m128i>()));
            for (o, m) in m.iter().enumerate() {
                let v = _mm_or_si128(
                    _mm_or_si128(_mm_shuffle_epi8(src[0], m[0]), _mm_shuffle_epi8(src[1], m[1])),
                    _mm_shuffle_epi8(src[2], m[2]),
                );
                let to = row.as_mut_ptr().add(3 * x + 16 * o).cast::<__m128i>();
                if stream {
                    _mm_stream_si128(to, v);
                } else {
                    _mm_storeu_si128(to, v);
                }
            }
            x += 16;
        }
        if stream {
            // Streamed stores are ordered before anything after this function.
            _mm_sfence();
        }
        for x in x..pixels {
            row[3 * x..3 * x + 3].copy_from_slice(&[a[x], b[x], c[x]]);
        }
    }
}

impl FringeSample for f32 {
    fn encode_line(signal: &[f32], reversed: bool, out: &mut [f32], _: &Quantization) -> u64 {
        if reversed {
            signal.iter().rev().zip(out.iter_mut()).for_each(|(x, o)| *o = *x);
        } else {
            out.copy_from_slice(signal);
        }
        0
    }
    fn count_clipped(_: &[f32], _: &Quantization) -> u64 {
        0
    }
    fn decode(self, _: &Quantization) -> f32 {
        self
    }
    fn blank(_: &Quantization) -> f32 {
        0.0
    }
}

/// The 8-bit codes of a signal and the number clipped. Branch-free so that
/// it vectorises: this runs on every sample of every frame.
#[inline(always)]
fn encode_bytes(signal: &[f32], reversed: bool, out: &mut [u8], offset: f32, gain: f32) -> u64 {
    encode_with(signal, reversed, out, |x| offset + gain * x)
}

/// Whether an unrounded 8-bit code needs clamping (spec/layouts.md §5.3):
/// the one rule every count of clipped samples uses.
/// (Two comparisons, not a range test: a NaN is not counted, and the test
/// stays branch-free in the vectorised loops.)
#[inline(always)]
#[allow(clippy::manual_range_contains)]
fn clips(code: f32) -> bool {
    (code < -0.5) | (code > 255.5)
}

/// [`encode_bytes`] with the unrounded code of each value given by `code`.
#[inline(always)]
fn encode_with(signal: &[f32], reversed: bool, out: &mut [u8], code: impl Fn(f32) -> f32) -> u64 {
    let encode = |x: &f32, o: &mut u8| -> u32 {
        let code = code(*x);
        let clamped = code.clamp(0.0, 255.0);
        // Adding 2²³ leaves the integer nearest (ties to even) in the low
        // mantissa bits: a rounding that vectorises, unlike `as`.
        *o = (clamped + 8_388_608.0).to_bits() as u8;
        u32::from(clips(code))
    };
    let clipped: u32 = if reversed {
        signal.iter().rev().zip(out.iter_mut()).map(|(x, o)| encode(x, o)).sum()
    } else {
        signal.iter().zip(out.iter_mut()).map(|(x, o)| encode(x, o)).sum()
    };
    u64::from(clipped)
}

/// What is done to a zone's samples of one hololine once the kernel has
/// encoded them: the blanking gains (spec/layouts.md §5.5) make the samples
/// beside each blanked run again, with their gains, and encode them over the
/// kernel's.
pub(super) trait AfterKernel: Copy {
    /// Send zone `zone`'s samples again through `sink`, made from `weights`.
    fn after<T: FringeSample>(self, plan: &Plan, weights: &PaddedWeights, zone: usize, sink: &mut Encoder<'_, T>);
}

/// The kernel's sink in frame assembly: each lane's blocks encoded straight
/// into the codes of the channel that carries it, in the order they are sent.
pub(super) struct Encoder<'a, T> {
    /// The channel that carries lane 0 and lane 1, if any.
    pub lane_channel: [Option<usize>; 2],
    /// The codes of every channel of the line, in the order sent.
    pub codes: &'a mut Vec<Vec<T>>,
    /// Samples per hololine.
    pub samples: usize,
    /// Whether this line is sent backwards.
    pub reversed: bool,
    /// The quantization.
    pub q: &'a Quantization,
    /// Samples clipped so far.
    pub clipped: u64,
}

impl<T: FringeSample> Encoder<'_, T> {
    /// Zone `zone` of one hololine from its weights
    /// ([`Plan::padded_weights_into`]), encoded; returns the samples clipped.
    /// 8-bit codes are made in the kernel's registers (the downcast picks
    /// that sink for `u8`), other sample types from blocks of floats.
    /// With `after` (the layout's blanking gains for this hololine), some
    /// samples are then sent again over what the kernel wrote.
    pub fn encode<A: AfterKernel>(self, plan: &Plan, weights: &PaddedWeights, zone: usize, after: Option<A>) -> u64 {
        let Encoder { lane_channel, codes, samples, reversed, q, clipped } = self;
        match (codes as &mut dyn Any).downcast_mut::<Vec<Vec<u8>>>() {
            Some(codes) => {
                let mut sink = Encoder { lane_channel, codes, samples, reversed, q, clipped };
                plan.zone_padded(weights, zone, &mut sink);
                if let Some(a) = after {
                    a.after(plan, weights, zone, &mut sink);
                }
                sink.clipped
            }
            None => {
                let mut sink = Encoder { lane_channel, codes, samples, reversed, q, clipped };
                plan.zone_padded(weights, zone, &mut Blocks::<_, true>(&mut sink));
                if let Some(a) = after {
                    a.after(plan, weights, zone, &mut sink);
                }
                sink.clipped
            }
        }
    }
}

impl<T: FringeSample> BlockSink for Encoder<'_, T> {
    #[inline(always)]
    fn put(&mut self, lane: usize, first: usize, values: &[f32]) {
        if let Some(ch) = self.lane_channel[lane] {
            let len = values.len();
            let at = if self.reversed { self.samples - first - len } else { first };
            self.clipped += T::encode_line(values, self.reversed, &mut self.codes[ch][at..at + len], self.q);
        }
    }
}

/// 8-bit codes made in the vector kernel's registers, `offset + gain · norm
/// · sum` with one multiply-add. A block whose codes all round into
/// 0 ..= 255 has none clipped and needs no clamping: its rounded codes are
/// packed and stored as they are; any other block (rare) is clamped and
/// counted by [`encode_with`].
impl LaneSink for Encoder<'_, u8> {
    const ANY_ORDER: bool = true;

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn put_vectors<const V: usize>(&mut self, lane: usize, first: usize, acc: &[__m256; V], norm: f32) {
        // SAFETY: only the AVX2 + FMA kernel calls this (features checked by
        // `Simd::avx2_fma`); each store writes `run` <= `len` bytes inside `out`, a
        // slice of `len` codes.
        unsafe {
            let Some(ch) = self.lane_channel[lane] else { return };
            let (offset, scale) = (_mm256_set1_ps(self.q.offset as f32), _mm256_set1_ps(norm * self.q.gain as f32));
            let codes: [__m256; V] = std::array::from_fn(|v| _mm256_fmadd_ps(acc[v], scale, offset));
            // Rounded to the nearest, ties to even (the default rounding mode).
            let rounded: [__m256i; V] = std::array::from_fn(|v| _mm256_cvtps_epi32(codes[v]));
            // Out of 0 ..= 255 (or beyond i32, or NaN) as unsigned: above 255.
            let largest = rounded.iter().fold(_mm256_setzero_si256(), |m, c| _mm256_max_epu32(m, *c));
            let len = 8 * V;
            let at = if self.reversed { self.samples - first - len } else { first };
            let out = &mut self.codes[ch][at..at + len];
            if _mm256_testz_si256(largest, _mm256_set1_epi32(!255)) == 0 {
                let mut floats = [[0f32; 8]; V];
                for (floats, codes) in floats.iter_mut().zip(&codes) {
                    _mm256_storeu_ps(floats.as_mut_ptr(), *codes);
                }
                self.clipped += encode_with(floats.as_flattened(), self.reversed, out, |code| code);
                return;
            }
            // Four vectors of codes into 32 bytes in sample order (or reversed):
            // the packs interleave the 128-bit halves, the permutation undoes it.
            let forward = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
            let backward = _mm256_setr_epi32(7, 3, 6, 2, 5, 1, 4, 0);
            let reverse_within_words = _mm256_setr_epi8(
                3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13,
                12,
            );
            let run = len.min(32);
            for g in 0..V.div_ceil(4) {
                // Fewer than four vectors: repeated, and only the first bytes kept.
                let c = |k: usize| rounded[(4 * g + k) % V];
                let packed = _mm256_packus_epi16(_mm256_packs_epi32(c(0), c(1)), _mm256_packs_epi32(c(2), c(3)));
                let (bytes, to) = if self.reversed {
                    let bytes = _mm256_permutevar8x32_epi32(packed, backward);
                    (_mm256_shuffle_epi8(bytes, reverse_within_words), len - (g + 1) * run)
                } else {
                    (_mm256_permutevar8x32_epi32(packed, forward), g * run)
                };
                let to = out[to..to + run].as_mut_ptr();
                match run {
                    32 => _mm256_storeu_si256(to.cast::<__m256i>(), bytes),
                    16 => _mm_storeu_si128(to.cast::<__m128i>(), _mm256_castsi256_si128(bytes)),
                    _ => _mm_storel_epi64(to.cast::<__m128i>(), _mm256_castsi256_si128(bytes)),
                }
            }
        }
    }
}

/// Blocks added into the lanes of a hololine (colours summed into one signal).
pub(super) struct Adder<'a>(pub &'a mut [Vec<f32>]);

impl LaneSink for Adder<'_> {
    const ANY_ORDER: bool = true;
}

impl BlockSink for Adder<'_> {
    #[inline(always)]
    fn put(&mut self, lane: usize, first: usize, values: &[f32]) {
        self.0[lane][first..first + values.len()].iter_mut().zip(values).for_each(|(s, v)| *s += v);
    }
}

/// What one frame-buffer line's task keeps between lines.
pub(super) struct LineScratch<T> {
    /// A zero signal (dark hololines).
    pub zeros: Vec<f32>,
    /// Per channel of the line, its codes in the order sent.
    pub codes: Vec<Vec<T>>,
    /// The weights of the hololine and colour at hand.
    pub weights: PaddedWeights,
    /// Colours summed: the sum, per lane.
    pub sum: [Vec<f32>; 2],
}

impl<T: Copy> LineScratch<T> {
    pub fn new(samples: usize, channels: usize, blank: T) -> Self {
        LineScratch {
            zeros: vec![0.0; samples],
            codes: vec![vec![blank; samples]; channels],
            weights: PaddedWeights::default(),
            sum: [vec![0.0; samples], vec![0.0; samples]],
        }
    }
}

/// Fill one row of pixels: component `k` from `sources[k]` (samples
/// `from ..`), components without a source left alone.
pub(super) fn interleave<T: FringeSample>(row: &mut [T], sources: &[Option<&[T]>], from: usize, simd: Simd) {
    let components = sources.len();
    let width = row.len() / components;
    match sources {
        [Some(a)] => row.copy_from_slice(&a[from..from + width]),
        [Some(a), Some(b), Some(c)] => {
            T::interleave3(row, &a[from..from + width], &b[from..from + width], &c[from..from + width], simd)
        }
        _ => {
            for (k, source) in sources.iter().enumerate() {
                if let Some(source) = source {
                    for (px, v) in row.chunks_exact_mut(components).zip(&source[from..from + width]) {
                        px[k] = *v;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn the_vector_and_portable_interleaves_give_the_same_pixels() {
        // Widths around the 16-pixel step of the SSSE3 loop, and a long row.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for width in [0, 1, 15, 16, 17, 31, 33, 4080] {
            let planes: Vec<Vec<u8>> = (0..3).map(|_| (0..width).map(|_| rng.gen()).collect()).collect();
            let [a, b, c] = [&planes[0][..], &planes[1][..], &planes[2][..]];
            let mut want = vec![0u8; 3 * width];
            for x in 0..width {
                want[3 * x..3 * x + 3].copy_from_slice(&[a[x], b[x], c[x]]);
            }
            for simd in [Simd::Detect, Simd::Portable] {
                let mut row = vec![0u8; 3 * width];
                u8::interleave3(&mut row, a, b, c, simd);
                assert_eq!(row, want, "width {width}, {simd:?}");
                let mut row = vec![0u8; 3 * width];
                interleave(&mut row, &[Some(a), Some(b), Some(c)], 0, simd);
                assert_eq!(row, want, "width {width}, {simd:?}, through interleave");
            }
        }
    }
}
