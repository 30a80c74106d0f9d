//! What the display shows, emitter by emitter (docs/optics.md §8.3): the
//! hologram-plane field of a hololine (`field.rs`) is propagated to the
//! emitter plane; the field in a window one emitter pitch wide around each
//! emitter is the light that emitter sends, and its angular spectrum says
//! how much goes in every direction. Summed over a view's interval of
//! directions that is the view's reconstructed brightness; summed over the
//! directions that enter a viewer's pupil it is what that viewer sees of the
//! emitter, with the eye focused on the emitter plane.
//!
//! Brightness is calibrated against the same pipeline: an emitter with
//! every view at 1 is reconstructed once per layout and colour, and each
//! figure is divided by the calibration emitter's figure for the same
//! interval of directions, so a fully lit emitter reads 1 in every view and
//! from every eye position.

use std::sync::Arc;

use holo_fft::{Complex64, Fft};

use super::coherent::{CoherentImage, FocusedEye};
use super::field::FieldPlan;
use super::propagate::{Field1d, Propagator};
use crate::assemble::{Assembler, ColourBasis};
use crate::error::{Error, Result};
use crate::geometry::Geometry;
use crate::layout::ColourSignals;
use crate::modulation::Modulation;

/// A viewer: eye position on the viewer's side of the display and pupil.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eye {
    /// Horizontal position, metres.
    pub x_m: f64,
    /// Height, metres (horizontal-parallax displays show every height the
    /// same picture; kept for the record).
    pub y_m: f64,
    /// Distance from the hologram plane, metres.
    pub z_m: f64,
    /// Pupil diameter, metres.
    pub pupil_m: f64,
    /// Whether the light of neighbouring emitters adds as amplitudes (the
    /// eye images the emitter plane through its pupil, spec/layouts.md §9.2)
    /// rather than as powers (§9).
    pub coherent: bool,
}

/// Power per direction of one emitter's light, on a uniform grid of `sin θ`.
#[derive(Clone, Debug, PartialEq)]
pub struct EmitterSpectrum {
    /// `sin θ` of bin 0.
    pub sin_first: f64,
    /// Spacing of bins in `sin θ`.
    pub sin_step: f64,
    /// Power per bin (arbitrary units: only ratios to the calibration count).
    pub power: Vec<f64>,
}

impl EmitterSpectrum {
    /// Power with `sin θ` in `[lo, hi)`, each bin spread evenly over its width.
    pub fn between(&self, lo: f64, hi: f64) -> f64 {
        let n = self.power.len() as f64;
        let u = |s: f64| ((s - self.sin_first) / self.sin_step + 0.5).clamp(0.0, n);
        let (a, b) = (u(lo), u(hi));
        if b <= a {
            return 0.0;
        }
        (a.floor() as usize..(b.ceil() as usize).min(self.power.len()))
            .map(|k| self.power[k] * (b.min(k as f64 + 1.0) - a.max(k as f64)))
            .sum()
    }
}

/// The optics of one colour channel of a layout.
#[derive(Clone)]
pub struct ColourOptics {
    basis: ColourBasis,
    geometry: Geometry,
    /// Emitter window, fine samples.
    window: usize,
    fft: Arc<dyn Fft<f64>>,
    /// The calibration emitter's spectrum.
    calibration: EmitterSpectrum,
    /// The calibration emitter's power in each view's interval.
    view_gain: Vec<f64>,
    /// The hologram-plane field from signals.
    field: FieldPlan,
    /// From the hologram to the emitter plane (none for hogels).
    to_emitters: Option<Propagator>,
    /// The calibration emitter (alone on its hololine) and its field on the
    /// emitter plane, for the coherent eye.
    calibration_emitter: usize,
    calibration_field: Field1d,
}

impl std::fmt::Debug for ColourOptics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ColourOptics").field("window", &self.window).field("view_gain", &self.view_gain).finish()
    }
}

impl ColourOptics {
    /// The optics of colour channel `colour` of the assembler's layout, with
    /// its calibration emitter reconstructed.
    pub fn new(assembler: &Assembler, colour: usize) -> Result<Self> {
        let basis = assembler.plan(colour).basis().clone();
        let mut geometry = assembler.layout().geometry.clone();
        let fine_pitch = basis.pitch_m / super::field::oversampling(&basis) as f64;
        let window = ((geometry.emitter_pitch_m / fine_pitch).round() as usize).max(1);
        let fft = holo_fft::forward((8 * window).next_power_of_two());
        let summed = assembler.layout().fringe.as_ref().map(|f| f.colours) == Some(ColourSignals::Summed);
        let pass: Option<Vec<(f64, f64)>> = summed.then(|| {
            let colours = geometry.channels.len();
            (0..basis.zones())
                .map(|zone| {
                    let bands: Vec<(f64, f64)> =
                        (0..colours).map(|c| assembler.plan(c).basis().signal_band(zone)).collect();
                    let (lo, hi) = bands[colour];
                    let below = bands.iter().filter(|b| b.1 <= lo).map(|b| b.1).fold(0.0, f64::max);
                    let above = bands.iter().filter(|b| b.0 >= hi).map(|b| b.0).fold(0.5, f64::min);
                    ((lo + below) / 2.0, (hi + above) / 2.0)
                })
                .collect()
        });
        // Per zone, the signal frequencies this colour reads when colours
        // share a signal: its band, widened halfway to the neighbouring
        // colours' bands (to 0 and ½ at the ends).
        let field = FieldPlan::new(&basis, pass.as_deref());
        let to_emitters = match geometry.emitter_z_m {
            0.0 => None,
            z => {
                let (count, pitch_m, x0_m) = field.grid();
                Some(Propagator::new(count, pitch_m, x0_m, basis.wavelength_m, z)?)
            }
        };
        let mut optics = ColourOptics {
            basis,
            geometry: geometry.clone(),
            window,
            fft,
            calibration: EmitterSpectrum { sin_first: 0.0, sin_step: 1.0, power: Vec::new() },
            view_gain: Vec::new(),
            field,
            to_emitters,
            calibration_emitter: 0,
            calibration_field: Field1d { samples: Vec::new(), pitch_m: 1.0, x0_m: 0.0 },
        };
        // Calibration: the middle emitter of one hololine, every view at 1.
        geometry.hololines = 1;
        let e = geometry.emitters / 2;
        let m = Modulation::from_fn(geometry.clone(), |c, _, k, _| if c == colour && k == e { 1.0 } else { 0.0 })?;
        let mut one = assembler.layout().clone();
        one.geometry = geometry;
        let signals = Assembler::new(&one)?.signals(&m, colour)?;
        let rows: Vec<&[f32]> = (0..signals.signals).map(|s| signals.row(s, 0)).collect();
        let field = optics.emitter_plane(&rows)?;
        optics.calibration = optics.spectrum(&field, e);
        optics.calibration_emitter = e;
        optics.calibration_field = field;
        optics.view_gain = (0..optics.basis.views)
            .map(|v| {
                let (lo, hi) = optics.basis.view_sin_edges[v];
                optics.calibration.between(lo, hi)
            })
            .collect();
        if let Some(v) = optics.view_gain.iter().position(|g| g.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater))
        {
            return Err(Error::argument("modulation", format!("view {v} of the calibration emitter carries no light")));
        }
        Ok(optics)
    }

    /// The basis.
    pub fn basis(&self) -> &ColourBasis {
        &self.basis
    }

    /// The field on the emitter plane of one hololine, from its signals (one
    /// slice per signal of this colour, in the layout's order).
    pub fn emitter_plane(&self, signals: &[&[f32]]) -> Result<Field1d> {
        let field = self.field.field(signals);
        match &self.to_emitters {
            None => Ok(field),
            Some(p) => p.apply(&field),
        }
    }

    /// The angular spectrum of emitter `e`'s window of an emitter-plane field.
    pub fn spectrum(&self, field: &Field1d, e: usize) -> EmitterSpectrum {
        let first = self.window_start(field, e);
        let len = self.fft.len();
        let mut buf = vec![Complex64::new(0.0, 0.0); len];
        for (k, b) in buf.iter_mut().enumerate().take(self.window) {
            if let Some(x) = usize::try_from(first + k as i64).ok().and_then(|i| field.samples.get(i)) {
                *b = *x;
            }
        }
        self.fft.process(&mut buf);
        // Increasing frequency: bin s from −len/2; sin θ = λ s / (len · pitch).
        let sin_step = self.basis.wavelength_m / (len as f64 * field.pitch_m);
        let power = (0..len).map(|i| buf[(i + len / 2) % len].norm_sqr()).collect();
        EmitterSpectrum { sin_first: -((len / 2) as f64) * sin_step, sin_step, power }
    }

    /// Every view's reconstructed brightness from an emitter's spectrum,
    /// calibrated (a fully lit emitter reads 1).
    pub fn views(&self, spectrum: &EmitterSpectrum) -> Vec<f64> {
        (0..self.basis.views)
            .map(|v| {
                let (lo, hi) = self.basis.view_sin_edges[v];
                spectrum.between(lo, hi) / self.view_gain[v]
            })
            .collect()
    }

    /// The `sin θ` interval of the directions from emitter `e` into the eye's pupil.
    pub fn pupil_interval(&self, e: usize, eye: &Eye) -> (f64, f64) {
        let (x_e, z_e) = (self.geometry.emitter_x_m(e), self.geometry.emitter_z_m);
        let sin = |x: f64| (x - x_e) / ((x - x_e).powi(2) + (eye.z_m - z_e).powi(2)).sqrt();
        (sin(eye.x_m - eye.pupil_m / 2.0), sin(eye.x_m + eye.pupil_m / 2.0))
    }

    /// How bright emitter `e` looks from `eye`, calibrated (a fully lit
    /// emitter looks 1).
    pub fn seen(&self, spectrum: &EmitterSpectrum, e: usize, eye: &Eye) -> f64 {
        let (lo, hi) = self.pupil_interval(e, eye);
        let reference = self.calibration.between(lo, hi);
        if reference > 0.0 {
            spectrum.between(lo, hi) / reference
        } else {
            0.0
        }
    }

    /// The calibration emitter's power in each view's interval.
    pub fn view_gain(&self) -> &[f64] {
        &self.view_gain
    }

    /// The eye in the emitter plane's coordinates.
    fn focused(&self, eye: &Eye) -> FocusedEye {
        FocusedEye { x_m: eye.x_m, distance_m: eye.z_m - self.geometry.emitter_z_m, pupil_m: eye.pupil_m }
    }

    /// The first fine sample of emitter `e`'s window on `field`'s grid.
    fn window_start(&self, field: &Field1d, e: usize) -> i64 {
        let x_lo = self.geometry.emitter_x_m(e) - self.geometry.emitter_pitch_m / 2.0;
        ((x_lo - field.x0_m) / field.pitch_m).round() as i64
    }

    /// What a fully lit emitter alone looks like to a coherent `eye`, for
    /// every emitter `e` (spec/layouts.md §9.2): the calibration emitter
    /// imaged by an eye moved so that it sees it as `eye` sees `e`, its
    /// image's power over its own window. Computed once per eye: it does not
    /// depend on the hololine.
    pub fn coherent_calibration(&self, eye: &Eye) -> Result<Vec<f64>> {
        let c = self.calibration_emitter;
        let field = &self.calibration_field;
        let x_c = self.geometry.emitter_x_m(c);
        // The calibration emitter's light is all within a few pitches of it
        // (the chirp focuses there); ±32 windows hold it to far below 1e-4.
        let reach = 32 * self.window as i64;
        let first = self.window_start(field, c);
        let lo = (first - reach).max(0) as usize;
        let hi = ((first + self.window as i64 + reach) as usize).min(field.samples.len());
        let crop = Field1d { samples: field.samples[lo..hi].to_vec(), pitch_m: field.pitch_m, x0_m: field.x_m(lo) };
        let lambda = self.basis.wavelength_m;
        (0..self.geometry.emitters)
            .map(|e| {
                let moved = Eye { x_m: eye.x_m + x_c - self.geometry.emitter_x_m(e), ..*eye };
                let focused = self.focused(&moved);
                let band = focused.band(x_c, lambda);
                let image = CoherentImage::new(&crop, &focused, lambda, band)?;
                Ok(image.power(first - lo as i64, self.window, band, crop.pitch_m))
            })
            .collect()
    }

    /// How bright every emitter looks to a coherent `eye` (spec/layouts.md
    /// §9.2): the emitter-plane field imaged through the pupil, the image's
    /// power over each emitter's window, divided by `calibration`
    /// ([`ColourOptics::coherent_calibration`] for the same eye).
    pub fn seen_coherently(&self, field: &Field1d, eye: &Eye, calibration: &[f64]) -> Result<Vec<f64>> {
        let focused = self.focused(eye);
        let lambda = self.basis.wavelength_m;
        let emitters = self.geometry.emitters;
        let bands: Vec<(f64, f64)> =
            (0..emitters).map(|e| focused.band(self.geometry.emitter_x_m(e), lambda)).collect();
        let union = bands.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |u, b| (u.0.min(b.0), u.1.max(b.1)));
        let image = CoherentImage::new(field, &focused, lambda, union)?;
        Ok((0..emitters)
            .map(|e| {
                let power = image.power(self.window_start(field, e), self.window, bands[e], field.pitch_m);
                if calibration[e] > 0.0 {
                    power / calibration[e]
                } else {
                    0.0
                }
            })
            .collect())
    }
}
