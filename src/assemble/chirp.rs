//! Focusing chirps cut into view zones (Smithwick et al. 2009 §3, §5.1; docs/optics.md §4).
//!
//! An emitter at `(x_e, z_e)` is made by a chirp whose phase at hologram
//! point `x` is `φ(x) = ∓(2π/λ)·sqrt((x − x_e)² + z_e²)` (− for `z_e > 0`,
//! light converging through the emitter; + for `z_e < 0`, light diverging
//! from a virtual point). Its local frequency `(x_e − x)/(λ r)` (for
//! `z_e > 0`) is `sin θ / λ`: the point at `x` sends light toward the emitter
//! and on, in direction `θ`. The chirp spans `zones × chirp_samples` samples
//! centred on the emitter; it is cut into `zones` pieces, each carried by its
//! own signal, and each piece into `views_per_zone` equal view segments.
//!
//! Each zone piece is shifted in frequency before it becomes a signal:
//! down by the zone's *shift* (the display's up-converter puts it back;
//! Mark III) and up by the layout's in-signal *carrier* (real signals, which
//! must keep their band between 0 and half the sampling rate; the reference
//! beam undoes it). Their difference is the zone's *signal carrier*.
//!
//! Phases are computed in f64 in coordinates local to the chirp, with the
//! difference of square roots taken in its cancellation-free form and the
//! carrier's cycles reduced before they are scaled, so a chirp's phase error
//! does not grow with the hololine's length (docs/optics.md §9).

use std::f64::consts::PI;

/// The shape of a zoned chirp basis for one wavelength (Mark III: 1024, 64, 3, 32).
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
    /// In-signal carrier, cycles per sample (zero for I/Q signals).
    pub carrier_cycles_per_sample: f64,
    /// Samples over which adjacent segments cross-fade (even, at most a
    /// segment; 0: hard edges).
    pub taper_samples: usize,
    /// Samples over which the ends of every zone piece fade instead (even;
    /// 0: as `taper_samples` says): where two pieces of one chirp meet they
    /// cross-fade over this many, each widened by half of it, and the
    /// chirp's own two ends rise over half of it inside their segments. The
    /// piece ends are the band edges of every zone's signal, where a hard
    /// edge's sidelobes fold past half the sampling rate (spec/layouts.md §4.7).
    pub piece_taper_samples: usize,
}

/// What lies beyond one end of a view segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Edge {
    /// Another segment of the same zone piece.
    Segment,
    /// The neighbouring zone's piece of the same chirp (carried by another signal).
    Piece,
    /// Nothing: the chirp's own end.
    Chirp,
}

impl ZonedChirp {
    /// Chirps overlapping at a sample of one zone's signal.
    pub fn overlap(&self) -> usize {
        self.chirp_samples.div_ceil(self.slot_samples)
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
    /// `tan θ` of the light leaving offset `d` (samples).
    pub fn tan_theta(&self, d_samples: f64) -> f64 {
        -d_samples * self.sample_pitch_m * self.emitter_z_m.signum() / self.emitter_z_m.abs()
    }
    /// Middle of a zone's band, cycles per sample: halfway between its two
    /// edges' `sin θ · pitch / λ`.
    pub fn zone_centre_cycles_per_sample(&self, zone: usize) -> f64 {
        let lo = self.sin_theta(self.offset_samples(zone, -0.5));
        let hi = self.sin_theta(self.offset_samples(zone, self.chirp_samples as f64 - 0.5));
        (lo + hi) / 2.0 * self.sample_pitch_m / self.wavelength_m
    }
    /// The shift that moves a zone to the middle of its signal's band (and
    /// the display's up-conversion moves back), cycles per sample: the zone
    /// centre rounded to a multiple of `1 / slot_samples`. Chirps start on
    /// slot boundaries, so the shift then has the same phase at every chirp's
    /// start and one table serves every emitter, with its zone pieces joining
    /// into one continuous chirp after up-conversion.
    pub fn zone_shift_cycles_per_sample(&self, zone: usize) -> f64 {
        let slots = self.slot_samples as f64;
        (self.zone_centre_cycles_per_sample(zone) * slots).round() / slots
    }
    /// The zone's signal carrier: in-signal carrier less the zone's shift.
    /// A signal frequency `f` (cycles per sample) in zone `zone` is light
    /// leaving at `sin θ = (f − signal carrier) · λ / pitch`.
    pub fn signal_carrier_cycles_per_sample(&self, zone: usize) -> f64 {
        self.carrier_cycles_per_sample - self.zone_shift_cycles_per_sample(zone)
    }
    /// The signal's frequency band in zone `zone`, cycles per sample (low, high).
    pub fn signal_band(&self, zone: usize) -> (f64, f64) {
        let c = self.signal_carrier_cycles_per_sample(zone);
        let to_signal =
            |u: f64| self.sin_theta(self.offset_samples(zone, u)) * self.sample_pitch_m / self.wavelength_m + c;
        let (a, b) = (to_signal(-0.5), to_signal(self.chirp_samples as f64 - 0.5));
        (a.min(b), a.max(b))
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
    /// Signal phase of zone `zone` at sample `u` of its piece: the chirp's
    /// phase plus the signal carrier, the carrier counted from the chirp's
    /// first sample (`zone · chirp_samples + u` samples earlier).
    pub fn phase_rad(&self, zone: usize, u: f64) -> f64 {
        let n = (zone * self.chirp_samples) as f64 + u;
        // Reduce the carrier's cycles before scaling so the angle stays small.
        let carrier_cycles = (self.signal_carrier_cycles_per_sample(zone) * n).rem_euclid(1.0);
        self.chirp_phase_rad(self.offset_samples(zone, u)) + 2.0 * PI * carrier_cycles
    }
    /// The emitter-global view shown by sample `u` of zone `zone`. Views
    /// ascend with `θ`; for an emitter in front of the hologram `θ` falls
    /// along the chirp (the last view is at its start), behind it `θ` rises.
    #[cfg(test)]
    fn view_of(&self, zone: usize, u: usize) -> usize {
        let along = zone * self.views_per_zone + u / self.samples_per_view();
        if self.emitter_z_m > 0.0 {
            self.views() - 1 - along
        } else {
            along
        }
    }
    /// Zone and first sample (within the zone piece) of view `v`'s segment.
    pub fn segment_of_view(&self, v: usize) -> (usize, usize) {
        let along = if self.emitter_z_m > 0.0 { self.views() - 1 - v } else { v };
        (along / self.views_per_zone, (along % self.views_per_zone) * self.samples_per_view())
    }
    /// Where view `v`'s element lies, in samples from the start of its
    /// zone piece: `[first, first + len)`, its segment widened by half the
    /// cross-fade on every side that has a neighbour (another segment, or the
    /// next zone's piece); `first` is negative for a zone piece's first
    /// segment that fades in from the zone before.
    pub fn element_extent(&self, v: usize) -> (usize, i64, usize) {
        let (zone, first) = self.segment_of_view(v);
        let [(up, up_width), (down, down_width)] = self.edges(zone, first);
        let half = |edge: Edge, width: usize| if edge == Edge::Chirp { 0 } else { (width / 2) as i64 };
        let lo = first as i64 - half(up, up_width);
        let hi = (first + self.samples_per_view()) as i64 + half(down, down_width);
        (zone, lo, (hi - lo) as usize)
    }
    /// What lies beyond each end of the segment starting at `first` of zone
    /// `zone` (its start, then its end), and the samples its fade takes.
    fn edges(&self, zone: usize, first: usize) -> [(Edge, usize); 2] {
        let last = first + self.samples_per_view();
        let piece = if self.piece_taper_samples > 0 { self.piece_taper_samples } else { self.taper_samples };
        let up = match (zone, first) {
            (0, 0) => (Edge::Chirp, piece),
            (_, 0) => (Edge::Piece, piece),
            _ => (Edge::Segment, self.taper_samples),
        };
        let down = match (zone + 1 == self.zones, last == self.chirp_samples) {
            (true, true) => (Edge::Chirp, piece),
            (false, true) => (Edge::Piece, piece),
            _ => (Edge::Segment, self.taper_samples),
        };
        [up, down]
    }
    /// The weight of view `v`'s element at sample `u` of its zone piece
    /// (`u` may lie before or after the piece, within
    /// [`ZonedChirp::element_extent`]): 1 inside the segment away from its
    /// edges; across each boundary with a neighbour a raised cosine
    /// `½ (1 + sin(π t / T))`, `t` the sample centre's distance past the
    /// boundary and `T` that boundary's fade (the piece taper where two zone
    /// pieces meet, when there is one; the segment taper elsewhere), so that
    /// two neighbours' weights add to 1; at the chirp's own two ends the same
    /// shape over `T/2` samples, inside the segment.
    pub fn window(&self, v: usize, u: i64) -> f64 {
        if self.taper_samples == 0 && self.piece_taper_samples == 0 {
            return 1.0;
        }
        let (zone, first) = self.segment_of_view(v);
        let rise = |t: f64, width: usize| {
            if width == 0 {
                // A hard edge: the element's extent already ends there.
                return 1.0;
            }
            0.5 * (1.0 + (PI * (t / width as f64).clamp(-0.5, 0.5)).sin())
        };
        // t past an edge of this kind, into the element.
        let weight = |t: f64, (edge, width): (Edge, usize)| match edge {
            Edge::Chirp => rise(t - width as f64 / 4.0, width / 2),
            Edge::Piece | Edge::Segment => rise(t, width),
        };
        let centre = u as f64 + 0.5;
        let (a, b) = (first as f64, (first + self.samples_per_view()) as f64);
        let [up, down] = self.edges(zone, first);
        weight(centre - a, up) * weight(b - centre, down)
    }
    /// The largest sum of element weights at one sample of a zone's signal
    /// over all the chirps that overlap it (every view lit at 1): what the
    /// signal is normalised by. Without a taper, the overlap.
    pub fn largest_window_sum(&self) -> f64 {
        if self.taper_samples == 0 && self.piece_taper_samples == 0 {
            return self.overlap() as f64;
        }
        let half = (self.taper_samples.max(self.piece_taper_samples) / 2) as i64;
        let (l, s) = (self.chirp_samples as i64, self.slot_samples as i64);
        let mut largest: f64 = 0.0;
        for zone in 0..self.zones {
            let views: Vec<usize> = (0..self.views()).filter(|&v| self.segment_of_view(v).0 == zone).collect();
            // Per sample of the piece (and its fades): the sum over its views.
            let piece = |u: i64| -> f64 {
                views
                    .iter()
                    .filter(|&&v| {
                        let (_, lo, len) = self.element_extent(v);
                        u >= lo && u < lo + len as i64
                    })
                    .map(|&v| self.window(v, u))
                    .sum()
            };
            // Sample n of one slot period, every chirp that reaches it.
            for n in 0..s {
                let mut total = 0.0;
                let mut k = -((l + 2 * half) / s + 2);
                while k * s <= l + half {
                    let u = n - k * s;
                    if u >= -half && u < l + half {
                        total += piece(u);
                    }
                    k += 1;
                }
                largest = largest.max(total);
            }
        }
        largest
    }
    /// `tan θ` at the middle of view `v`'s segment: the direction the
    /// modulation of view `v` must have been rendered for.
    pub fn view_centre_tan(&self, v: usize) -> f64 {
        let (zone, first) = self.segment_of_view(v);
        let middle = first as f64 + self.samples_per_view() as f64 / 2.0 - 0.5;
        self.tan_theta(self.offset_samples(zone, middle))
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
            carrier_cycles_per_sample: 0.0,
            taper_samples: 0,
            piece_taper_samples: 0,
        }
    }

    #[test]
    fn a_piece_taper_fades_the_zone_pieces_ends_alone() {
        let hard = mark3();
        let c = ZonedChirp { piece_taper_samples: 64, ..mark3() };
        // Only the elements at a piece's end change: views 31, 32, 63, 64
        // widened by 32 samples across their zone boundary, views 0 and 95
        // (the chirp's ends) not widened; every other element as it was.
        for v in 0..96 {
            let (zone, first, len) = c.element_extent(v);
            let (_, hard_first, hard_len) = hard.element_extent(v);
            let widened = match v {
                31 | 63 => (hard_first - 32, hard_len + 32),
                32 | 64 => (hard_first, hard_len + 32),
                _ => (hard_first, hard_len),
            };
            assert_eq!((first, len), widened, "view {v}");
            if !matches!(v, 0 | 31 | 32 | 63 | 64 | 95) {
                for u in first..first + len as i64 {
                    assert_eq!(c.window(v, u), 1.0, "view {v} sample {u} of zone {zone}");
                }
            }
        }
        // The weights of spec/layouts.md §4.2, worked by hand: view 31 is
        // zone 2's first segment, u = −32 … 31 about the boundary at u = 0;
        // view 0 is the chirp's end, rising over its whole 32-sample segment.
        let rise = |t: f64, w: f64| 0.5 * (1.0 + (PI * t / w).sin());
        for u in [-32i64, -1, 0, 17, 31] {
            let want = rise(u as f64 + 0.5, 64.0);
            assert!((c.window(31, u) - want).abs() < 1e-15, "view 31 u {u}: {} against {want}", c.window(31, u));
        }
        for u in [992i64, 1000, 1023] {
            let want = rise(1024.0 - (u as f64 + 0.5) - 16.0, 32.0);
            assert!((c.window(0, u) - want).abs() < 1e-15, "view 0 u {u}");
        }
        // Inside the chirp the weights add to 1 at every sample, across the
        // zone boundaries too: a fully lit emitter's chirp is unchanged but
        // for its two ends.
        for x in 32..3 * 1024 - 32 {
            let sum: f64 = (0..96)
                .filter_map(|v| {
                    let (zone, first, len) = c.element_extent(v);
                    let u = x - (zone * 1024) as i64;
                    (u >= first && u < first + len as i64).then(|| c.window(v, u))
                })
                .sum();
            assert!((sum - 1.0).abs() < 1e-12, "chirp sample {x}: {sum}");
        }
        assert_eq!(c.largest_window_sum(), 16.0);
    }

    #[test]
    fn local_frequency_is_sin_theta_over_lambda_plus_the_signal_carrier() {
        for carrier in [0.0, 0.25] {
            let c = ZonedChirp { carrier_cycles_per_sample: carrier, ..mark3() };
            for zone in 0..3 {
                for u in [1.0, 100.0, 511.0, 1000.0] {
                    // Numerical derivative of the phase vs the grating equation.
                    let h = 1e-3;
                    let step = (c.phase_rad(zone, u + h) - c.phase_rad(zone, u - h) + PI).rem_euclid(2.0 * PI) - PI;
                    let f = step / (2.0 * h) / (2.0 * PI);
                    let expected = c.sin_theta(c.offset_samples(zone, u)) * c.sample_pitch_m / c.wavelength_m
                        + c.signal_carrier_cycles_per_sample(zone);
                    assert!((f - expected).abs() < 1e-6, "zone {zone} u {u}: {f} vs {expected}");
                    if carrier == 0.0 {
                        // Every zone's baseband stays inside ±0.5 cycles/sample (I/Q Nyquist).
                        assert!(f.abs() < 0.45, "{f}");
                    }
                }
            }
        }
    }

    #[test]
    fn up_converted_zone_pieces_join_into_one_chirp_for_every_emitter() {
        let c = mark3();
        for zone in 0..3 {
            assert_eq!((c.zone_shift_cycles_per_sample(zone) * 64.0).fract(), 0.0);
        }
        // Emitter e's piece of zone k starts at slot e + 16k; after the
        // up-conversion exp(i2πF_k n) the field must be the emitter's chirp.
        for e in [0usize, 1, 17, 335] {
            let start = 64 * e;
            for zone in 0..3 {
                for u in [0usize, 1, 511, 1023] {
                    let n = start + zone * 1024 + u;
                    let up = c.phase_rad(zone, u as f64) + 2.0 * PI * c.zone_shift_cycles_per_sample(zone) * n as f64;
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
        for v in 0..96 {
            let (zone, first) = c.segment_of_view(v);
            assert_eq!(c.view_of(zone, first), v);
            if v > 0 {
                assert!(c.view_centre_tan(v) > c.view_centre_tan(v - 1));
            }
        }
        // Behind the hologram the order flips: θ rises along the chirp.
        let behind = ZonedChirp { emitter_z_m: -c.emitter_z_m, ..c.clone() };
        assert_eq!(behind.view_of(0, 0), 0);
        assert!((behind.view_centre_tan(7) - c.view_centre_tan(7)).abs() < 1e-12);
    }
}
