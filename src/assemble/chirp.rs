//! Focusing chirps cut into view zones (seed 004 §3, §5.1; PHYSICS.md §2–3).
//!
//! An emitter at `(x_e, z_e)` is made by a chirp whose phase at hologram
//! point `x` is `φ(x) = ∓(2π/λ)·sqrt((x − x_e)² + z_e²)` (− for `z_e > 0`,
//! light converging through the emitter; + for `z_e < 0`, light diverging
//! from a virtual point). Its local frequency `(x_e − x)/(λ r)` is `sin θ / λ`:
//! the point at `x` sends light toward the emitter and on, in direction `θ`.
//! The chirp spans `zones × chirp_samples` samples centred on the emitter; it
//! is cut into `zones` pieces, each carried in baseband by its own channel
//! (the zone's centre frequency removed; the display's up-conversion puts it
//! back), and each piece into `views_per_zone` equal view segments.
//!
//! Phases are computed in f64 in coordinates local to the chirp, with the
//! difference of square roots taken in its cancellation-free form, so a
//! chirp's phase error does not grow with the hololine's length.

use std::f64::consts::PI;

/// The shape of a zoned chirp basis (Mark III: 1024, 64, 3, 32).
#[derive(Clone, Debug, PartialEq)]
pub struct ZonedChirp {
    /// Distance between hologram samples, metres.
    pub sample_pitch_m: f64,
    /// Wavelength the chirp is computed for, metres.
    pub wavelength_m: f64,
    /// `z` of the emitter plane, metres (not zero).
    pub emitter_z_m: f64,
    /// Samples of one zone piece of a chirp.
    pub chirp_samples: usize,
    /// Samples between the starts of adjacent chirps (= between emitters).
    pub slot_samples: usize,
    /// Zone pieces per emitter.
    pub zones: usize,
    /// Views per zone piece.
    pub views_per_zone: usize,
}

impl ZonedChirp {
    /// Chirps overlapping at each sample within one zone channel.
    pub fn overlap(&self) -> usize {
        self.chirp_samples / self.slot_samples
    }
    /// Samples per view segment.
    pub fn samples_per_view(&self) -> usize {
        self.chirp_samples / self.views_per_zone
    }
    /// Views of one emitter.
    pub fn views(&self) -> usize {
        self.zones * self.views_per_zone
    }
    /// `x − x_e` of the centre of sample `u` of zone `zone`'s piece, in samples.
    pub fn offset_samples(&self, zone: usize, u: f64) -> f64 {
        (zone * self.chirp_samples) as f64 + u + 0.5 - (self.zones * self.chirp_samples) as f64 / 2.0
    }
    /// `sin θ` of the light leaving offset `x − x_e = d` (samples).
    pub fn sin_theta(&self, d_samples: f64) -> f64 {
        let d = d_samples * self.sample_pitch_m;
        let z = self.emitter_z_m;
        // Toward the emitter when it is in front (z > 0), away from it when behind.
        -d * z.signum() / (d * d + z * z).sqrt()
    }
    /// Middle of a zone's band, cycles per sample: halfway between its two
    /// edges' `sin θ / λ`.
    pub fn zone_centre_cycles_per_sample(&self, zone: usize) -> f64 {
        let lo = self.sin_theta(self.offset_samples(zone, -0.5));
        let hi = self.sin_theta(self.offset_samples(zone, self.chirp_samples as f64 - 0.5));
        (lo + hi) / 2.0 * self.sample_pitch_m / self.wavelength_m
    }
    /// The carrier that shifts a zone to baseband (and the display's
    /// up-conversion shifts back), cycles per sample: the zone centre rounded
    /// to a multiple of `1 / slot_samples`. Chirps start on slot boundaries,
    /// so the carrier then has the same phase at every chirp's start and one
    /// table serves every emitter, with its zone pieces joining into one
    /// continuous chirp after up-conversion.
    pub fn carrier_cycles_per_sample(&self, zone: usize) -> f64 {
        let slots = self.slot_samples as f64;
        (self.zone_centre_cycles_per_sample(zone) * slots).round() / slots
    }
    /// Phase of the whole focusing chirp at `x − x_e = d` (samples), relative
    /// to its centre: `∓(2π/λ)(r − |z|)`, with `r − |z| = d²/(r + |z|)` so
    /// that nothing cancels.
    pub fn chirp_phase_rad(&self, d_samples: f64) -> f64 {
        let d = d_samples * self.sample_pitch_m;
        let z = self.emitter_z_m;
        let r = (d * d + z * z).sqrt();
        -z.signum() * 2.0 * PI / self.wavelength_m * (d * d / (r + z.abs()))
    }
    /// Baseband phase of zone `zone` at sample `u` of its piece: the chirp's
    /// phase less the carrier's, the carrier counted from the chirp's first
    /// sample (`zone · chirp_samples + u` samples earlier).
    pub fn baseband_phase_rad(&self, zone: usize, u: f64) -> f64 {
        let n = (zone * self.chirp_samples) as f64 + u;
        // Reduce the carrier's cycles before scaling so the angle stays small.
        let carrier_cycles = (self.carrier_cycles_per_sample(zone) * n).rem_euclid(1.0);
        self.chirp_phase_rad(self.offset_samples(zone, u)) - 2.0 * PI * carrier_cycles
    }
    /// The complex baseband table of one zone piece, (cos φ, sin φ) per sample.
    pub fn table(&self, zone: usize) -> (Vec<f32>, Vec<f32>) {
        (0..self.chirp_samples)
            .map(|u| {
                let phi = self.baseband_phase_rad(zone, u as f64);
                (phi.cos() as f32, phi.sin() as f32)
            })
            .unzip()
    }
    /// The emitter-global view shown by sample `u` of zone `zone`: views
    /// ascend with `θ`, and `θ` falls along the chirp, so the last view is
    /// at the start of zone 0.
    pub fn view_of(&self, zone: usize, u: usize) -> usize {
        self.views() - 1 - (zone * self.views_per_zone + u / self.samples_per_view())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mark3() -> ZonedChirp {
        let p = 0.080 / (336.0 * 64.0);
        ZonedChirp {
            sample_pitch_m: p,
            wavelength_m: 633e-9,
            emitter_z_m: 1536.0 * p / 12f64.to_radians().tan(),
            chirp_samples: 1024,
            slot_samples: 64,
            zones: 3,
            views_per_zone: 32,
        }
    }

    #[test]
    fn local_frequency_is_sin_theta_over_lambda() {
        let c = mark3();
        for zone in 0..3 {
            for u in [1.0, 100.0, 511.0, 1000.0] {
                // Numerical derivative of the phase vs the grating equation.
                let h = 1e-3;
                let f =
                    (c.baseband_phase_rad(zone, u + h) - c.baseband_phase_rad(zone, u - h)) / (2.0 * h) / (2.0 * PI);
                let expected = c.sin_theta(c.offset_samples(zone, u)) * c.sample_pitch_m / c.wavelength_m
                    - c.carrier_cycles_per_sample(zone);
                assert!((f - expected).abs() < 1e-6, "zone {zone} u {u}: {f} vs {expected}");
                // Every zone's baseband stays inside ±0.5 cycles/sample (I/Q Nyquist).
                assert!(f.abs() < 0.45, "{f}");
            }
        }
    }

    #[test]
    fn up_converted_zone_pieces_join_into_one_chirp_for_every_emitter() {
        let c = mark3();
        for zone in 0..3 {
            assert_eq!((c.carrier_cycles_per_sample(zone) * 64.0).fract(), 0.0);
        }
        // Emitter e's piece of zone k starts at slot e + 16k; after the
        // up-conversion exp(i2πF_k n) the field must be the emitter's chirp.
        for e in [0usize, 1, 17, 335] {
            let start = 64 * e;
            for zone in 0..3 {
                for u in [0usize, 1, 511, 1023] {
                    let n = start + zone * 1024 + u;
                    let up =
                        c.baseband_phase_rad(zone, u as f64) + 2.0 * PI * c.carrier_cycles_per_sample(zone) * n as f64;
                    let want = c.chirp_phase_rad(c.offset_samples(zone, u as f64));
                    let diff = (up - want).rem_euclid(2.0 * PI);
                    let diff = diff.min(2.0 * PI - diff);
                    assert!(diff < 1e-9, "emitter {e} zone {zone} u {u}: {diff}");
                }
            }
        }
    }

    #[test]
    fn the_chirp_spans_the_field_of_view_and_the_views_are_ordered() {
        let c = mark3();
        let top = c.sin_theta(c.offset_samples(0, -0.5)).asin().to_degrees();
        let bottom = c.sin_theta(c.offset_samples(2, 1023.5)).asin().to_degrees();
        assert!((top - 12.0).abs() < 1e-9 && (bottom + 12.0).abs() < 1e-9, "{top} {bottom}");
        assert_eq!(c.view_of(0, 0), 95);
        assert_eq!(c.view_of(2, 1023), 0);
        assert_eq!(c.view_of(1, 32), 95 - 33);
    }
}
