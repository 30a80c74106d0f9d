//! Frame rates as files store them: an exact fraction `numerator /
//! denominator` (OpenEXR's `framesPerSecond` is a `rational`; a HoloFlick's
//! header holds the same two numbers). One rule turns a rate given as a
//! number into that fraction, for every file holo writes: whole rates are
//! `n/1`, the NTSC family exactly `n/1001` (24000/1001 is 23.976…, 30000/1001
//! is 29.97…), anything else to the thousandth (`n/1000`), or the hundredth
//! where that is exact.

use std::fmt;
use std::str::FromStr;

/// A frame rate as an exact fraction of whole numbers, both positive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRate {
    numerator: u32,
    denominator: u32,
}

impl FrameRate {
    /// `numerator / denominator` frames a second; `None` unless both are
    /// positive.
    pub const fn new(numerator: u32, denominator: u32) -> Option<FrameRate> {
        if numerator == 0 || denominator == 0 {
            None
        } else {
            Some(FrameRate { numerator, denominator })
        }
    }

    /// The fraction a file stores for `frames_per_second`: exact for whole
    /// rates and for the `n/1001` family, else to the thousandth. `None`
    /// for a rate that is not finite and positive, or whose fraction does
    /// not fit (past 4 294 967 frames a second).
    pub fn from_frames_per_second(frames_per_second: f64) -> Option<FrameRate> {
        if !(frames_per_second.is_finite() && frames_per_second > 0.0) {
            return None;
        }
        let fits = |n: f64| (1.0..=f64::from(u32::MAX)).contains(&n);
        for denominator in [1u32, 1001, 1000, 100] {
            let n = frames_per_second * f64::from(denominator);
            if (n - n.round()).abs() < 1e-6 && fits(n.round()) {
                return FrameRate::new(n.round() as u32, denominator);
            }
        }
        let n = (frames_per_second * 1000.0).round().max(1.0);
        if fits(n) {
            FrameRate::new(n as u32, 1000)
        } else {
            None
        }
    }

    /// Frames a second, as a number.
    pub fn frames_per_second(self) -> f64 {
        f64::from(self.numerator) / f64::from(self.denominator)
    }

    /// `(numerator, denominator)`, as files store them.
    pub fn fraction(self) -> (u32, u32) {
        (self.numerator, self.denominator)
    }
}

/// The fraction a file stores for a rate already checked
/// (`pipeline::check_frame_rate`); one that no fraction holds, as 1.
pub(crate) fn stored_fraction(frames_per_second: f64) -> (u32, u32) {
    FrameRate::from_frames_per_second(frames_per_second).map_or((1, 1), FrameRate::fraction)
}

impl fmt::Display for FrameRate {
    /// `24`, `24000/1001`: the fraction, or the whole number it is.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.denominator == 1 {
            write!(f, "{}", self.numerator)
        } else {
            write!(f, "{}/{}", self.numerator, self.denominator)
        }
    }
}

impl FromStr for FrameRate {
    type Err = String;

    /// A rate as a user writes it: a number (`30`, `23.976`, `12.5`) or an
    /// exact fraction (`24000/1001`), positive.
    fn from_str(text: &str) -> Result<FrameRate, String> {
        let bad = || format!("{text:?} is not a frame rate (a positive number, or a fraction such as 24000/1001)");
        match text.split_once('/') {
            Some((n, d)) => {
                let (n, d) = (n.trim().parse::<u32>().map_err(|_| bad())?, d.trim().parse::<u32>().map_err(|_| bad())?);
                FrameRate::new(n, d).ok_or_else(bad)
            }
            None => text.trim().parse::<f64>().ok().and_then(FrameRate::from_frames_per_second).ok_or_else(bad),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_ntsc_and_decimal_rates_are_exact_fractions() {
        let cases = [
            (30.0, (30, 1)),
            (24000.0 / 1001.0, (24000, 1001)),
            (30000.0 / 1001.0, (30000, 1001)),
            (60000.0 / 1001.0, (60000, 1001)),
            (23.976, (23976, 1000)),
            (12.5, (12500, 1000)),
            (1e-3, (1, 1000)),
        ];
        for (fps, fraction) in cases {
            let rate = FrameRate::from_frames_per_second(fps).unwrap();
            assert_eq!(rate.fraction(), fraction, "{fps}");
            assert!((rate.frames_per_second() - fps).abs() < 1e-9 * fps.max(1.0), "{fps}");
        }
        for bad in [0.0, -24.0, f64::NAN, f64::INFINITY, 5e9] {
            assert_eq!(FrameRate::from_frames_per_second(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_rate_is_read_as_written_and_written_as_read() {
        for (text, fraction, shown) in
            [("24000/1001", (24000, 1001), "24000/1001"), ("30", (30, 1), "30"), ("12.5", (12500, 1000), "12500/1000")]
        {
            let rate: FrameRate = text.parse().unwrap();
            assert_eq!((rate.fraction(), rate.to_string().as_str()), (fraction, shown), "{text}");
        }
        for bad in ["0", "-30", "30/0", "a/b", "", "1/2/3"] {
            assert!(bad.parse::<FrameRate>().unwrap_err().contains("not a frame rate"), "{bad}");
        }
    }
}
