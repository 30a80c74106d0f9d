//! The basis of one colour channel as physics: where each (emitter, view)
//! element lies on the hololine, which signal carries it, and its exact value
//! at every sample, in f64 and without tables. The fast path (`plan.rs`)
//! tabulates these values; the tests and [`ColourBasis::reference`] use them
//! directly.
//!
//! A hololine's signals are `s_k(n) = Σ_{e,v} sqrt(m[e][v]) · B_{e,v}(n) / N`
//! over the elements of zone `k` that cover sample `n`, with `N` the
//! normalisation ([`ColourBasis::normalisation`]); I/Q signals carry the real
//! and imaginary parts, real signals the real part. Weights are `sqrt(m)`: the
//! modulator's diffracted field scales with drive amplitude and a viewer sees
//! intensity (docs/optics.md §4.3).

use std::f64::consts::{FRAC_PI_2, PI};

use holo_fft::Complex64;

use super::chirp::ZonedChirp;
use super::hogel::{pseudo_random_phase_rad, HogelGratings};
use crate::geometry::Geometry;
use crate::layout::{Basis, EmitterPhases, Fringe, Layout, SignalKind};

/// The element shapes of a basis.
#[derive(Clone, Debug, PartialEq)]
pub enum Elements {
    /// Overlapping focusing chirps cut into zones and view segments.
    Chirp(ZonedChirp),
    /// Abutting hogels of gratings.
    Hogel(HogelGratings),
}

/// Where one (emitter, view) element lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Segment {
    /// The zone whose signal carries it.
    pub zone: usize,
    /// Its first sample on the hololine.
    pub start: usize,
    /// Its length in samples.
    pub len: usize,
}

/// The basis of one colour channel of a layout.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourBasis {
    /// The element shapes.
    pub elements: Elements,
    /// I/Q or real signals.
    pub signal: SignalKind,
    /// Samples per hololine and signal.
    pub samples: usize,
    /// Emitters per hololine.
    pub emitters: usize,
    /// Views per emitter.
    pub views: usize,
    /// Samples between adjacent emitters.
    pub step: usize,
    /// Sample pitch, metres.
    pub pitch_m: f64,
    /// Wavelength, metres.
    pub wavelength_m: f64,
    /// `sin θ` of the edges of every view's interval (hogels; for chirps the
    /// segment edges), ascending.
    pub view_sin_edges: Vec<(f64, f64)>,
    /// The in-signal carrier, cycles per sample (zero for I/Q).
    pub carrier: f64,
    /// The constant phase of each emitter's elements, radians (§4.6); empty
    /// when every phase is 0.
    pub emitter_phases_rad: Vec<f64>,
}

/// A chirp basis's shape as the layout gives it.
#[derive(Clone, Copy)]
struct ChirpShape {
    chirp_samples: usize,
    slot_samples: usize,
    zones: usize,
    views_per_zone: usize,
    segment_taper_samples: usize,
    piece_taper_samples: usize,
}

/// The zoned chirp of one colour, or `None` when its shape cannot be built;
/// every reason it does not fit the geometry goes to `problems`.
fn chirp_elements(
    shape: ChirpShape,
    f: &Fringe,
    g: &Geometry,
    wavelength_m: f64,
    carrier: f64,
    problems: &mut Vec<String>,
) -> Option<ZonedChirp> {
    let ChirpShape { chirp_samples, slot_samples, zones, views_per_zone, segment_taper_samples, piece_taper_samples } =
        shape;
    let shape_ok = zones > 0
        && views_per_zone > 0
        && chirp_samples > 0
        && chirp_samples % views_per_zone == 0
        && g.emitter_z_m != 0.0
        && g.emitter_z_m.is_finite();
    if !shape_ok {
        problems.push(format!(
            "a chirp of {chirp_samples} samples in {zones} zone(s) of {views_per_zone} views needs views that \
             divide it and an emitter plane off the hologram (z = {} m)",
            g.emitter_z_m
        ));
        return None;
    }
    let c = ZonedChirp {
        sample_pitch_m: f.sample_pitch_m,
        wavelength_m,
        emitter_z_m: g.emitter_z_m,
        chirp_samples,
        slot_samples,
        zones,
        views_per_zone,
        carrier_cycles_per_sample: carrier,
        taper_samples: segment_taper_samples,
        piece_taper_samples,
    };
    if segment_taper_samples % 2 == 1 || segment_taper_samples > c.samples_per_view() {
        problems.push(format!(
            "segment_taper_samples {segment_taper_samples} must be even and at most a view segment ({} samples)",
            c.samples_per_view()
        ));
    }
    // A segment at a piece's end fades over half the piece taper there and
    // half of its other edge's fade (the piece taper too when the piece is
    // one segment): both must fit in it, so that neighbours' weights add to 1.
    let piece = if piece_taper_samples > 0 { piece_taper_samples } else { segment_taper_samples };
    let other = if views_per_zone > 1 { segment_taper_samples } else { piece };
    if piece_taper_samples % 2 == 1 || piece.saturating_add(other) / 2 > c.samples_per_view() {
        problems.push(format!(
            "piece_taper_samples {piece_taper_samples} must be even, and half of it and half of the segment's other \
             fade ({other} samples) must fit in a view segment ({} samples)",
            c.samples_per_view()
        ));
    }
    if zones.checked_mul(views_per_zone) != Some(g.views.count) {
        // Every check below walks the zones or the views: a hostile zone
        // count must not make it walk for hours.
        problems.push(format!("{zones} zone(s) × {views_per_zone} views ≠ the geometry's {} views", g.views.count));
        return None;
    } else if let Some(v) =
        (0..g.views.count).find(|&v| (c.view_centre_tan(v).atan() - g.views.theta_rad(v)).abs() > 1e-9)
    {
        problems.push(format!(
            "view {v} of the chirp points at {:.6}°, the geometry's at {:.6}°: the emitter plane z, the chirp \
             length and the views must agree (views at the centres of equal tan θ segments)",
            c.view_centre_tan(v).atan().to_degrees(),
            g.views.theta_rad(v).to_degrees()
        ));
    }
    for zone in 0..zones {
        let (lo, hi) = c.signal_band(zone);
        let (min, what) = match f.signal {
            SignalKind::Iq => (-0.5, "an I/Q signal keeps its band inside ±0.5"),
            SignalKind::Real => (0.0, "a real signal keeps its band between 0 and 0.5"),
        };
        if lo <= min || hi >= 0.5 {
            problems.push(format!(
                "zone {} spans {lo:.4} to {hi:.4} cycles per sample at {:.0} nm; {what}",
                zone + 1,
                wavelength_m * 1e9
            ));
        }
    }
    Some(c)
}

/// Every emitter's phase at `wavelength_m`, radians (spec/layouts.md
/// §4.6); empty for [`EmitterPhases::Zero`].
fn emitter_phases_rad(phases: EmitterPhases, g: &Geometry, wavelength_m: f64) -> Vec<f64> {
    if phases == EmitterPhases::Zero || g.emitters == 0 {
        return Vec::new();
    }
    let centre_m = (g.emitter_x_m(0) + g.emitter_x_m(g.emitters - 1)) / 2.0;
    let distance_m = g.viewer_distance_m - g.emitter_z_m;
    (0..g.emitters)
        .map(|e| match phases {
            EmitterPhases::Zero => 0.0,
            EmitterPhases::Random => pseudo_random_phase_rad(e as i64),
            EmitterPhases::Quadrature => FRAC_PI_2 * (e % 2) as f64,
            EmitterPhases::Viewer => {
                // Minus the emitter's path to the viewer line's centre beyond
                // the distance (`r − d` without cancellation), reduced to
                // whole turns before scaling.
                let u = g.emitter_x_m(e) - centre_m;
                let turns = u * u / ((u * u + distance_m * distance_m).sqrt() + distance_m) / wavelength_m;
                -2.0 * PI * turns.fract()
            }
        })
        .collect()
}

impl ColourBasis {
    /// The basis of colour channel `colour` of `layout`, or every reason the
    /// layout's fringe side does not fit its geometry at that wavelength.
    pub fn new(layout: &Layout, colour: usize) -> Result<Self, Vec<String>> {
        let g = &layout.geometry;
        let Some(f) = &layout.fringe else {
            return Err(vec![format!("layout {} has no fringe side: it cannot be assembled", layout.name)]);
        };
        let Some(channel) = g.channels.get(colour) else {
            return Err(vec![format!("the layout has no colour channel {colour}")]);
        };
        let wavelength_m = channel.wavelength_m;
        let carrier = f.carrier(colour);
        let mut p = Vec::new();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-12);
        if !(f.sample_pitch_m.is_finite() && f.sample_pitch_m > 0.0) {
            return Err(vec![format!("sample_pitch_m {} must be positive", f.sample_pitch_m)]);
        }
        match (f.signal, f.carrier_cycles_per_sample.len()) {
            (SignalKind::Iq, 0) => {}
            (SignalKind::Iq, _) => {
                p.push("I/Q signals take no carrier_cycles_per_sample (the zones are shifted)".into())
            }
            (SignalKind::Real, n) if n == 1 || n == g.channels.len() => {
                if !(carrier.is_finite() && carrier > 0.0 && carrier < 0.5) {
                    p.push(format!("carrier {carrier} cycles per sample must be between 0 and 0.5"));
                }
            }
            (SignalKind::Real, n) => p.push(format!(
                "real signals need carrier_cycles_per_sample: one value, or one per colour channel ({}); {n} given",
                g.channels.len()
            )),
        }
        let step = f.emitter_step_samples();
        if step == 0 || f.samples_per_hololine == 0 {
            return Err(vec!["the basis needs at least one sample per emitter and hololine".into()]);
        }
        if g.emitters > f.max_emitters() {
            p.push(format!(
                "{} emitters do not fit: a hololine of {} samples holds {} emitters whose {}-sample basis starts every {step} samples",
                g.emitters,
                f.samples_per_hololine,
                f.max_emitters(),
                f.emitter_span_samples()
            ));
        }
        if !close(step as f64 * f.sample_pitch_m, g.emitter_pitch_m) {
            p.push(format!(
                "emitters every {step} samples × {} m are not the emitter pitch {} m",
                f.sample_pitch_m, g.emitter_pitch_m
            ));
        }
        if !close(f.emitter_x_m(0), g.emitter_left_x_m) {
            p.push(format!(
                "emitter 0's basis is centred at x = {} m; the geometry puts emitter 0 at {} m",
                f.emitter_x_m(0),
                g.emitter_left_x_m
            ));
        }
        let elements = match f.basis {
            Basis::Chirp {
                chirp_samples,
                slot_samples,
                zones,
                views_per_zone,
                segment_taper_samples,
                piece_taper_samples,
            } => {
                let shape = ChirpShape {
                    chirp_samples,
                    slot_samples,
                    zones,
                    views_per_zone,
                    segment_taper_samples,
                    piece_taper_samples,
                };
                match chirp_elements(shape, f, g, wavelength_m, carrier, &mut p) {
                    Some(c) => Elements::Chirp(c),
                    None => return Err(p),
                }
            }
            Basis::Hogel { hogel_samples } => {
                if g.emitter_z_m != 0.0 {
                    p.push(format!(
                        "hogels are emitters on the hologram plane: the geometry's emitter plane must be z = 0, not {} m",
                        g.emitter_z_m
                    ));
                }
                match HogelGratings::new(
                    hogel_samples,
                    f.sample_pitch_m,
                    wavelength_m,
                    carrier,
                    f.signal,
                    &view_sin_edges(&g.views),
                ) {
                    Ok(h) => Elements::Hogel(h),
                    Err(e) => {
                        p.push(e.to_string());
                        return Err(p);
                    }
                }
            }
        };
        if !p.is_empty() {
            return Err(p);
        }
        let view_sin_edges = match &elements {
            Elements::Chirp(c) => (0..c.views())
                .map(|v| {
                    let (zone, first) = c.segment_of_view(v);
                    let a = c.sin_theta(c.offset_samples(zone, first as f64 - 0.5));
                    let b = c.sin_theta(c.offset_samples(zone, (first + c.samples_per_view()) as f64 - 0.5));
                    (a.min(b), a.max(b))
                })
                .collect(),
            Elements::Hogel(_) => view_sin_edges(&g.views),
        };
        let basis = ColourBasis {
            elements,
            signal: f.signal,
            samples: f.samples_per_hololine,
            emitters: g.emitters,
            views: g.views.count,
            step,
            pitch_m: f.sample_pitch_m,
            wavelength_m,
            view_sin_edges,
            carrier,
            emitter_phases_rad: emitter_phases_rad(f.emitter_phases, g, wavelength_m),
        };
        if let Some(limit) = f.max_folded_energy {
            if !(0.0..=1.0).contains(&limit) {
                return Err(vec![format!("max_folded_energy {limit} must be a fraction between 0 and 1")]);
            }
            let (worst, v) = basis.largest_folded_energy();
            if worst > limit {
                return Err(vec![format!(
                    "view {v}'s elements fold {worst:.2e} of their energy past half the sampling rate at {:.0} nm; \
                     the layout accepts {limit:.2e} (segment_taper_samples and piece_taper_samples shape the segments to fold less)",
                    wavelength_m * 1e9
                )]);
            }
        }
        Ok(basis)
    }

    /// Zones (signals, or I/Q pairs, per hololine).
    pub fn zones(&self) -> usize {
        match &self.elements {
            Elements::Chirp(c) => c.zones,
            Elements::Hogel(_) => 1,
        }
    }
    /// Float lanes per zone: 2 for I/Q, 1 for real.
    pub fn lanes(&self) -> usize {
        match self.signal {
            SignalKind::Iq => 2,
            SignalKind::Real => 1,
        }
    }
    /// Signals per hololine.
    pub fn signals(&self) -> usize {
        self.zones() * self.lanes()
    }

    /// The divisor of every signal. Chirps: the number of overlapping chirps,
    /// so the sum never exceeds one chirp's amplitude for `m ≤ 1` (Smithwick et al. 2009
    /// §3.4). Hogels: `3 · sqrt(views)`, which puts a fully lit hogel's real
    /// signal at an RMS of 0.24, three standard deviations of headroom below
    /// full scale for a sum of gratings with random phases.
    pub fn normalisation(&self) -> f64 {
        match &self.elements {
            Elements::Chirp(c) => c.largest_window_sum(),
            Elements::Hogel(_) => 3.0 * (self.views as f64).sqrt(),
        }
    }

    /// The signal carrier of zone `zone`, cycles per sample: a frequency `f`
    /// of that zone's signal is light leaving at `sin θ = (f − carrier) · λ / pitch`.
    pub fn signal_carrier(&self, zone: usize) -> f64 {
        match &self.elements {
            Elements::Chirp(c) => c.signal_carrier_cycles_per_sample(zone),
            Elements::Hogel(_) => self.carrier,
        }
    }

    /// The band of zone `zone`'s signal, cycles per sample (low, high): the
    /// frequencies its elements use, the signal carrier included.
    pub fn signal_band(&self, zone: usize) -> (f64, f64) {
        let c = self.signal_carrier(zone);
        let to_signal = |sin: f64| sin * self.pitch_m / self.wavelength_m + c;
        if let Elements::Chirp(chirp) = &self.elements {
            // Every sample an element covers, its cross-fades included.
            let (lo, hi) = (0..self.views).filter(|&v| self.segment(0, v).zone == zone).fold(
                (f64::INFINITY, f64::NEG_INFINITY),
                |(lo, hi), v| {
                    let (_, first, len) = chirp.element_extent(v);
                    let edge = |u: f64| to_signal(chirp.sin_theta(chirp.offset_samples(zone, u)));
                    let (a, b) = (edge(first as f64 - 0.5), edge((first + len as i64) as f64 - 0.5));
                    (lo.min(a.min(b)), hi.max(a.max(b)))
                },
            );
            return (lo, hi);
        }
        let in_zone = (0..self.views).filter(|&v| self.segment(0, v).zone == zone);
        let (lo, hi) = in_zone.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            let (a, b) = self.view_sin_edges[v];
            (lo.min(to_signal(a)), hi.max(to_signal(b)))
        });
        (lo, hi)
    }

    /// The fraction of element (`e`, `v`)'s energy that its samples fold
    /// past half the sampling rate (spec/layouts.md §4.7): for I/Q signals
    /// the energy at frequencies more than ½ cycle per sample from the
    /// element's own (the middle of its view's interval in the signal), for
    /// real signals at negative frequencies (the display's first order
    /// shows them mirrored). Exact: the spectrum's energy over an interval
    /// from the samples' products, in f64.
    pub fn folded_energy(&self, e: usize, v: usize) -> f64 {
        let seg = self.segment(e, v);
        let x: Vec<Complex64> = (seg.start..seg.start + seg.len).map(|n| self.value(e, v, n)).collect();
        let zone = seg.zone;
        let (lo, hi) = self.view_sin_edges[v];
        let own = ((lo + hi) / 2.0) * self.pitch_m / self.wavelength_m + self.signal_carrier(zone);
        let (a, b) = match self.signal {
            SignalKind::Real => (-0.5, 0.0),
            SignalKind::Iq if own >= 0.0 => (-0.5, own - 0.5),
            SignalKind::Iq => (own + 0.5, 0.5),
        };
        // ∫_a^b |Σ x_n e^{−i2πfn}|² df = Σ_{n,m} x_n x̄_m ∫_a^b e^{−i2πf(n−m)} df.
        let kernel = |k: i64| -> Complex64 {
            if k == 0 {
                Complex64::new(b - a, 0.0)
            } else {
                let w = -2.0 * PI * k as f64;
                (Complex64::from_polar(1.0, w * b) - Complex64::from_polar(1.0, w * a)) / Complex64::new(0.0, w)
            }
        };
        let mut folded = Complex64::new(0.0, 0.0);
        for (n, xn) in x.iter().enumerate() {
            for (m, xm) in x.iter().enumerate() {
                folded += xn * xm.conj() * kernel(n as i64 - m as i64);
            }
        }
        let total: f64 = x.iter().map(|x| x.norm_sqr()).sum();
        if total > 0.0 {
            folded.re / total
        } else {
            0.0
        }
    }

    /// The largest [`ColourBasis::folded_energy`] of an emitter's elements,
    /// and its view, for an emitter away from the hololine's ends.
    pub fn largest_folded_energy(&self) -> (f64, usize) {
        let e = self.emitters / 2;
        (0..self.views).map(|v| (self.folded_energy(e, v), v)).fold((0.0, 0), |w, x| if x.0 > w.0 { x } else { w })
    }

    /// Where element (`e`, `v`) lies.
    pub fn segment(&self, e: usize, v: usize) -> Segment {
        match &self.elements {
            Elements::Chirp(c) => {
                // The element's extent lies within the chirp's span, so the
                // start is never before the emitter's first sample.
                let (zone, first, len) = c.element_extent(v);
                let start = (e * self.step + zone * c.chirp_samples) as i64 + first;
                Segment { zone, start: start as usize, len }
            }
            Elements::Hogel(h) => Segment { zone: 0, start: e * self.step, len: h.hogel_samples },
        }
    }

    /// The exact value of element (`e`, `v`) at hololine sample `n` (inside
    /// its segment), from the physics in f64, with its emitter's phase.
    /// Real signals use the real part.
    pub fn value(&self, e: usize, v: usize, n: usize) -> Complex64 {
        self.unphased_value(e, v, n) * Complex64::from_polar(1.0, self.emitter_phase_rad(e))
    }

    /// The constant phase of emitter `e`'s elements, radians (spec/layouts.md §4.6).
    pub fn emitter_phase_rad(&self, e: usize) -> f64 {
        self.emitter_phases_rad.get(e).copied().unwrap_or(0.0)
    }

    /// [`ColourBasis::value`] without the emitter's phase: the same for every
    /// emitter, shifted (what the fast path tabulates once).
    pub fn unphased_value(&self, e: usize, v: usize, n: usize) -> Complex64 {
        match &self.elements {
            Elements::Chirp(c) => {
                let (zone, _) = c.segment_of_view(v);
                let u = n as i64 - (e * self.step + zone * c.chirp_samples) as i64;
                Complex64::from_polar(c.window(v, u), c.phase_rad(zone, u as f64))
            }
            Elements::Hogel(h) => h.value(v, n - e * self.step),
        }
    }

    /// Reference assembly of one hololine: f64 throughout, every value from
    /// the physics, no tables, every element scattered into its signal.
    /// `modulation` is the hololine's (emitter, view) samples; returns one
    /// vector per signal. Slow; for tests.
    #[allow(clippy::needless_range_loop)] // `n` is the physical sample index `value` takes
    pub fn reference(&self, modulation: &[f32]) -> Vec<Vec<f64>> {
        let mut out = vec![vec![0f64; self.samples]; self.signals()];
        let norm = self.normalisation();
        for e in 0..self.emitters {
            for v in 0..self.views {
                let w = f64::from(modulation[e * self.views + v]).max(0.0).sqrt();
                let s = self.segment(e, v);
                for n in s.start..s.start + s.len {
                    let x = w * self.value(e, v, n) / norm;
                    let lanes = [x.re, x.im];
                    for (lane, value) in lanes.iter().take(self.lanes()).enumerate() {
                        out[s.zone * self.lanes() + lane][n] += value;
                    }
                }
            }
        }
        out
    }
}

/// `sin θ` edges of every view's interval: halfway in `tan θ` between
/// adjacent view directions, the outer edges as far beyond the first and last
/// views as their neighbours' halfway points are inside.
pub fn view_sin_edges(views: &crate::geometry::Views) -> Vec<(f64, f64)> {
    let n = views.count;
    let tan = |v: usize| views.theta_rad(v).tan();
    let edge = |k: usize| -> f64 {
        // Edge k lies between view k − 1 and view k.
        let t = if n == 1 {
            tan(0) + if k == 0 { -0.05 } else { 0.05 }
        } else if k == 0 {
            tan(0) - (tan(1) - tan(0)) / 2.0
        } else if k == n {
            tan(n - 1) + (tan(n - 1) - tan(n - 2)) / 2.0
        } else {
            (tan(k - 1) + tan(k)) / 2.0
        };
        t.atan().sin()
    };
    (0..n).map(|v| (edge(v), edge(v + 1))).collect()
}
