//! The transforms against their definition. (An integration test, not a
//! unit test: a unit test would compile rustfft's planner a second time.)

use holo_fft::{forward, inverse, Complex64};

/// Both directions against the defining sum on a non-trivial signal, and
/// their round trip scaled by the length.
#[test]
fn transforms_match_the_defining_sum_and_invert() {
    for len in [1usize, 6, 16, 27, 31] {
        let x: Vec<Complex64> = (0..len)
            .map(|n| Complex64::new((n as f64 * 0.7).sin() + 0.3, (n as f64 * 1.3).cos() - 0.1 * n as f64))
            .collect();
        let mut got = x.clone();
        forward(len).process(&mut got);
        for (k, g) in got.iter().enumerate() {
            let want: Complex64 = (0..len)
                .map(|n| x[n] * Complex64::from_polar(1.0, -2.0 * std::f64::consts::PI * (k * n) as f64 / len as f64))
                .sum();
            assert!((g - want).norm() < 1e-9 * len as f64, "len {len} k {k}: {g} vs {want}");
        }
        inverse(len).process(&mut got);
        for (g, x) in got.iter().zip(&x) {
            assert!((g / len as f64 - x).norm() < 1e-12 * len as f64, "len {len}");
        }
    }
}
