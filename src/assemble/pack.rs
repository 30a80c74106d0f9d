//! Packing signals into the frame buffer: the sample types a frame buffer
//! holds ([`FringeSample`]: 8-bit codes or floats), the kernel's sink that
//! encodes blocks as they are made, and the interleaving of channels into
//! pixels. These run on every sample of every frame, so they are written to
//! vectorise.

use super::plan::BlockSink;
use crate::layout::Quantization;

/// A frame-buffer sample type: 8-bit codes, or the float signal itself.
pub trait FringeSample: Copy + Send + Sync + 'static {
    /// Encode a piece of a hololine signal in the order it is sent
    /// (`reversed`: last sample first) into `out`; returns the number of
    /// clipped samples.
    fn encode_line(signal: &[f32], reversed: bool, out: &mut [Self], q: &Quantization) -> u64;
    /// The signal a stored value stands for.
    fn decode(self, q: &Quantization) -> f32;
    /// The value of pixels no signal reaches.
    fn blank(q: &Quantization) -> Self;
    /// `row[3x + k] = [a, b, c][k][x]`: three components into pixels.
    fn interleave3(row: &mut [Self], a: &[Self], b: &[Self], c: &[Self]) {
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
    fn decode(self, q: &Quantization) -> f32 {
        ((f64::from(self) - q.offset) / q.gain) as f32
    }
    fn blank(q: &Quantization) -> u8 {
        q.offset.round().clamp(0.0, 255.0) as u8
    }
    fn interleave3(row: &mut [u8], a: &[u8], b: &[u8], c: &[u8]) {
        assert!(row.len() == 3 * a.len() && a.len() == b.len() && a.len() == c.len());
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("ssse3") {
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
    use std::arch::x86_64::{__m128i, _mm_loadu_si128, _mm_or_si128, _mm_shuffle_epi8, _mm_storeu_si128};
    // masks[o][s][j]: output vector o, byte j takes source s's byte
    // (16o + j) / 3 when (16o + j) mod 3 = s, else zero (0x80).
    let mut masks = [[[0x80u8; 16]; 3]; 3];
    for (o, per_output) in masks.iter_mut().enumerate() {
        for (j, i) in (16 * o..16 * o + 16).enumerate() {
            per_output[i % 3][j] = (i / 3) as u8;
        }
    }
    let load = |m: &[u8; 16]| _mm_loadu_si128(m.as_ptr().cast::<__m128i>());
    let m = masks.map(|per_output| per_output.map(|mask| load(&mask)));
    let pixels = a.len();
    let mut x = 0;
    while x + 16 <= pixels {
        let src = [a, b, c].map(|s| _mm_loadu_si128(s.as_ptr().add(x).cast::<__m128i>()));
        for (o, m) in m.iter().enumerate() {
            let v = _mm_or_si128(
                _mm_or_si128(_mm_shuffle_epi8(src[0], m[0]), _mm_shuffle_epi8(src[1], m[1])),
                _mm_shuffle_epi8(src[2], m[2]),
            );
            _mm_storeu_si128(row.as_mut_ptr().add(3 * x + 16 * o).cast::<__m128i>(), v);
        }
        x += 16;
    }
    for x in x..pixels {
        row[3 * x..3 * x + 3].copy_from_slice(&[a[x], b[x], c[x]]);
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
    let encode = |x: &f32, o: &mut u8| -> u32 {
        let code = offset + gain * x;
        let clamped = code.clamp(0.0, 255.0);
        // Adding 2²³ leaves the integer nearest (ties to even) in the low
        // mantissa bits: a rounding that vectorises, unlike `as`.
        *o = (clamped + 8_388_608.0).to_bits() as u8;
        u32::from(code < -0.5) + u32::from(code > 255.5)
    };
    let clipped: u32 = if reversed {
        signal.iter().rev().zip(out.iter_mut()).map(|(x, o)| encode(x, o)).sum()
    } else {
        signal.iter().zip(out.iter_mut()).map(|(x, o)| encode(x, o)).sum()
    };
    u64::from(clipped)
}

/// The kernel's sink in frame assembly: each lane's blocks encoded straight
/// into the codes of the channel that carries it, in the order they are sent.
pub(super) struct Encoder<'a, T> {
    /// The channel that carries lane 0 and lane 1, if any.
    pub lane_channel: [Option<usize>; 2],
    /// The codes of every channel of the line, in the order sent.
    pub codes: &'a mut [Vec<T>],
    /// Samples per hololine.
    pub samples: usize,
    /// Whether this line is sent backwards.
    pub reversed: bool,
    /// The quantization.
    pub q: &'a Quantization,
    /// Samples clipped so far.
    pub clipped: u64,
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

/// Blocks added into the lanes of a hololine (colours summed into one signal).
pub(super) struct Adder<'a>(pub &'a mut [Vec<f32>]);

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
    pub weights: Vec<f32>,
    /// Colours summed: the sum, per lane.
    pub sum: [Vec<f32>; 2],
}

impl<T: Copy> LineScratch<T> {
    pub fn new(samples: usize, channels: usize, blank: T) -> Self {
        LineScratch {
            zeros: vec![0.0; samples],
            codes: vec![vec![blank; samples]; channels],
            weights: Vec::new(),
            sum: [vec![0.0; samples], vec![0.0; samples]],
        }
    }
}

/// Fill one row of pixels: component `k` from `sources[k]` (samples
/// `from ..`), components without a source left alone.
pub(super) fn interleave<T: FringeSample>(row: &mut [T], sources: &[Option<&[T]>], from: usize) {
    let components = sources.len();
    let width = row.len() / components;
    match sources {
        [Some(a)] => row.copy_from_slice(&a[from..from + width]),
        [Some(a), Some(b), Some(c)] => {
            T::interleave3(row, &a[from..from + width], &b[from..from + width], &c[from..from + width])
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
