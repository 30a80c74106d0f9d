//! `holo check` and `holo view` as library calls: from the frame-buffer
//! images of one frame, the modulation recovered two ways and compared with
//! the stored one, and the picture a viewer sees.
//!
//! - *Signal recovery* (`solve.rs`): least squares against the basis.
//!   Exact but for what the frame buffer loses (blanking, 8-bit rounding):
//!   it checks the assembly and the layout.
//! - *Optical recovery* ([`super::viewer`]): scalar diffraction to the
//!   emitter plane and each view's share of every emitter's light. It also
//!   counts what the optics cannot separate (a view's light spreads by the
//!   diffraction of its segment into its neighbours): it is what a viewer gets.
//!
//! Each report carries its [`Verdict`]: the errors against the bounds
//! spec/layouts.md §9.1 states ([`stated_bounds`]).

use std::ops::Range;

use rayon::prelude::*;
use serde::Serialize;

use super::picture::Picture;
use super::solve::HololineOperator;
use super::viewer::{ColourOptics, Eye};
use crate::assemble::{Assembler, FrameImages, Signals};
use crate::error::{Error, Result};
use crate::layout::{builtin, ColourSignals, Layout};
use crate::modulation::Modulation;
use crate::progress::{Progress, Steps};

/// How far a recovered modulation is from the stored one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RecoveryError {
    /// `‖m̂ − m‖ / ‖m‖` over every checked sample.
    pub relative_l2: f64,
    /// `10 log₁₀(peak² / mean squared error)`, dB.
    pub psnr_db: f64,
    /// The largest stored sample (the PSNR's peak).
    pub peak: f64,
    /// The emitter with the largest RMS error over its views.
    pub worst: WorstEmitter,
}

/// Where a recovery is worst.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WorstEmitter {
    /// Colour channel name.
    pub channel: String,
    /// Hololine.
    pub hololine: usize,
    /// Emitter.
    pub emitter: usize,
    /// RMS error over its views, relative to the RMS of the checked modulation.
    pub relative_rms: f64,
}

/// What `holo check` reports for one frame.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CheckReport {
    /// The layout's name.
    pub layout: String,
    /// Hololines checked.
    pub hololines: Range<usize>,
    /// Least-squares recovery from the signals.
    pub signal: RecoveryError,
    /// Recovery through the optics (what a viewer gets per view).
    pub optical: RecoveryError,
    /// Most conjugate-gradient iterations a hololine needed.
    pub iterations: usize,
    /// The errors against the bounds spec/layouts.md §9.1 states.
    pub verdict: Verdict,
}

/// The relative L2 errors spec/layouts.md §9.1 promises for a layout's
/// recovery ([`stated_bounds`]); `None` where it states none.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Bounds {
    /// The built-in layout the bounds are stated for (`mark3`, `mark1`), or
    /// `None` for float fringes, whose bound holds for every layout.
    pub stated_for: Option<&'static str>,
    /// Signal recovery (least squares).
    pub signal: Option<f64>,
    /// Optical recovery of any content: the bound of content that changes
    /// from view to view, the worst case the spec states.
    pub optical: Option<f64>,
    /// Optical recovery of content smooth across views (said beside the
    /// verdict; the verdict does not know the content's kind).
    pub optical_smooth: Option<f64>,
}

/// Every bound spec/layouts.md §9.1 states: (built-in layout, signal, optical
/// of any content, optical of smooth content), from 8-bit fringes.
const STATED: [(&str, f64, f64, f64); 2] = [("mark3", 0.03, 0.25, 0.10), ("mark1", 0.012, 0.06, 0.04)];

/// The signal-recovery bound from float fringes, every layout (§9.1).
const FLOAT_SIGNAL_BOUND: f64 = 1e-5;

/// The bounds spec/layouts.md §9.1 states for `layout`'s recovery errors:
/// from float fringes (`float_fringes`), signal recovery within 1e-5 for
/// every layout (the optics' bounds are stated for 8-bit fringes only);
/// from 8-bit fringes, Mark III's and Mark I's, for a layout that is the
/// built-in one in every number but its name (a profile saved from it
/// included). Other layouts have none.
pub fn stated_bounds(layout: &Layout, float_fringes: bool) -> Bounds {
    let none = Bounds { stated_for: None, signal: None, optical: None, optical_smooth: None };
    if float_fringes {
        return Bounds { signal: Some(FLOAT_SIGNAL_BOUND), ..none };
    }
    let same = |name: &str| builtin(name).is_some_and(|b| b.geometry == layout.geometry && b.fringe == layout.fringe);
    match STATED.iter().find(|(name, ..)| same(name)) {
        Some(&(name, signal, optical, smooth)) => Bounds {
            stated_for: Some(name),
            signal: Some(signal),
            optical: Some(optical),
            optical_smooth: Some(smooth),
        },
        None => none,
    }
}

/// A report's errors against [`Bounds`]: each figure passes when below its
/// bound; the whole passes when every bound stated is kept, and is `None`
/// when none is stated.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// The bounds compared with.
    pub bounds: Bounds,
    /// Signal recovery within its bound.
    pub signal: Option<bool>,
    /// Optical recovery within its bound.
    pub optical: Option<bool>,
    /// Every stated bound kept (`None`: none stated).
    pub pass: Option<bool>,
}

impl Verdict {
    /// `signal` and `optical` relative L2 errors against `bounds`.
    pub fn of(bounds: Bounds, signal: f64, optical: f64) -> Verdict {
        // NaN is not below any bound.
        let within = |bound: Option<f64>, x: f64| bound.map(|b| x < b);
        let (signal, optical) = (within(bounds.signal, signal), within(bounds.optical, optical));
        let pass = match (signal, optical) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or(true) && b.unwrap_or(true)),
        };
        Verdict { bounds, signal, optical, pass }
    }
}

/// The images of a frame as the frame buffer holds them, whichever type.
pub enum FrameRef<'a> {
    /// 8-bit codes.
    Bytes(&'a FrameImages<u8>),
    /// Float signals.
    Floats(&'a FrameImages<f32>),
}

impl FrameRef<'_> {
    fn unpack(&self, a: &Assembler, hololines: usize) -> Result<Vec<Signals>> {
        match self {
            FrameRef::Bytes(i) => a.unpack(i, hololines),
            FrameRef::Floats(i) => a.unpack(i, hololines),
        }
    }
}

/// The colours whose signals group `g` of the unpacked signals holds.
fn group_colours(a: &Assembler, group: usize) -> Range<usize> {
    let colours = a.layout().geometry.channels.len();
    match a.layout().fringe.as_ref().map(|f| f.colours) {
        Some(ColourSignals::Summed) => 0..colours,
        _ => group..group + 1,
    }
}

/// The unpacked group holding colour `c`.
fn group_of(a: &Assembler, c: usize) -> usize {
    match a.layout().fringe.as_ref().map(|f| f.colours) {
        Some(ColourSignals::Summed) => 0,
        _ => c,
    }
}

/// `shown[s][n]` for the signals of group `group` of hololine `j`.
fn shown(a: &Assembler, group: usize, j: usize, per_group: usize, samples: usize) -> Vec<Vec<bool>> {
    let fb = &a.layout().fringe.as_ref().expect("an assembler's layout has a fringe side").frame_buffer;
    let signals = a.layout().signals_per_hololine();
    (0..per_group)
        .map(|s| (0..samples).map(|n| fb.place(j, group * per_group + s, n, signals, samples).is_some()).collect())
        .collect()
}

/// Recover the modulation of `hololines` from a frame's images both ways and
/// compare with `m`, the modulation that was assembled; `progress` counts
/// the hololines.
pub fn check(
    a: &Assembler,
    m: &Modulation,
    images: FrameRef<'_>,
    hololines: Range<usize>,
    progress: &dyn Progress,
) -> Result<CheckReport> {
    a.check_geometry(m)?;
    let g = m.geometry();
    if hololines.is_empty() || hololines.end > g.hololines {
        return Err(Error::argument(
            "hololines",
            format!("hololines {}..{} asked for; the frame has {}", hololines.start, hololines.end, g.hololines),
        ));
    }
    let unpacked = images.unpack(a, g.hololines)?;
    let colours = g.channels.len();
    let optics = (0..colours).map(|c| ColourOptics::new(a, c)).collect::<Result<Vec<_>>>()?;
    let steps = Steps::begin(progress, "hololines", hololines.len());
    let per_line: Vec<Recovered> = hololines
        .clone()
        .into_par_iter()
        .map(|j| -> Result<_> {
            let mut signal = vec![Vec::new(); colours];
            let mut iterations = 0;
            for (group, signals) in unpacked.iter().enumerate() {
                let members = group_colours(a, group);
                let mut rows: Vec<Vec<f32>> = (0..signals.signals).map(|s| signals.row(s, j).to_vec()).collect();
                a.undo_blanking_gains(m, group, j, &mut rows);
                let op = HololineOperator {
                    plans: members.clone().map(|c| a.plan(c)).collect(),
                    shown: shown(a, group, j, signals.signals, signals.samples),
                };
                let (w, its) = op.solve(&rows);
                iterations = iterations.max(its);
                let n = g.emitters * g.views.count;
                for (k, c) in members.enumerate() {
                    signal[c] = w[k * n..(k + 1) * n].iter().map(|w| w.max(0.0).powi(2)).collect();
                }
            }
            let mut optical = Vec::with_capacity(colours);
            for (c, optics) in optics.iter().enumerate() {
                let signals = &unpacked[group_of(a, c)];
                let rows: Vec<&[f32]> = (0..signals.signals).map(|s| signals.row(s, j)).collect();
                let field = optics.emitter_plane(&rows)?;
                optical.push((0..g.emitters).flat_map(|e| optics.views(&optics.spectrum(&field, e))).collect());
            }
            steps.step();
            Ok(Recovered { signal, optical, iterations })
        })
        .collect::<Result<_>>()?;
    let signal = compare(m, &hololines, |k, c| &per_line[k].signal[c]);
    let optical = compare(m, &hololines, |k, c| &per_line[k].optical[c]);
    let bounds = stated_bounds(a.layout(), matches!(images, FrameRef::Floats(_)));
    Ok(CheckReport {
        layout: a.layout().name.clone(),
        hololines: hololines.clone(),
        verdict: Verdict::of(bounds, signal.relative_l2, optical.relative_l2),
        signal,
        optical,
        iterations: per_line.iter().map(|l| l.iterations).max().unwrap_or(0),
    })
}

/// One hololine's modulation recovered both ways, per colour (emitter-major).
struct Recovered {
    signal: Vec<Vec<f64>>,
    optical: Vec<Vec<f64>>,
    iterations: usize,
}

/// Error figures of recovered hololines (`recovered(k, c)`: the k-th checked
/// hololine's colour `c`, emitter-major) against `m`.
fn compare<'a>(
    m: &Modulation,
    hololines: &Range<usize>,
    recovered: impl Fn(usize, usize) -> &'a Vec<f64>,
) -> RecoveryError {
    let g = m.geometry();
    let views = g.views.count;
    let (mut err2, mut ref2, mut peak, mut count) = (0f64, 0f64, 0f64, 0usize);
    let mut per_emitter = Vec::new();
    for (k, j) in hololines.clone().enumerate() {
        for c in 0..g.channels.len() {
            let got = recovered(k, c);
            for e in 0..g.emitters {
                let mut e2 = 0.0;
                for (v, want) in m.views_of(c, j, e).iter().enumerate() {
                    let want = f64::from(*want);
                    let d = got[e * views + v] - want;
                    e2 += d * d;
                    ref2 += want * want;
                    peak = peak.max(want);
                }
                err2 += e2;
                count += views;
                per_emitter.push((e2 / views as f64, c, j, e));
            }
        }
    }
    let rms_ref = (ref2 / count as f64).sqrt();
    let worst = per_emitter.iter().fold((0.0, 0, 0, 0), |w, x| if x.0 > w.0 { *x } else { w });
    RecoveryError {
        relative_l2: if ref2 > 0.0 { (err2 / ref2).sqrt() } else { err2.sqrt() },
        psnr_db: 10.0 * (peak * peak / (err2 / count as f64)).log10(),
        peak,
        worst: WorstEmitter {
            channel: g.channels[worst.1].name.clone(),
            hololine: worst.2,
            emitter: worst.3,
            relative_rms: if rms_ref > 0.0 { worst.0.sqrt() / rms_ref } else { worst.0.sqrt() },
        },
    }
}

/// The pictures viewers at `eyes` see of a frame's images (the emitter
/// spectra are computed once for all of them); `progress` counts the
/// hololines.
pub fn view(a: &Assembler, images: FrameRef<'_>, eyes: &[Eye], progress: &dyn Progress) -> Result<Vec<Picture>> {
    let g = &a.layout().geometry;
    for eye in eyes {
        let sensible =
            eye.z_m.is_finite() && eye.z_m > g.emitter_z_m.max(0.0) && eye.pupil_m > 0.0 && eye.x_m.is_finite();
        if !sensible {
            return Err(Error::argument(
                "eye",
                format!(
                    "an eye at x = {} m, z = {} m with a {} m pupil: it must be in front of the emitters (z > {} m) \
                 with a positive pupil",
                    eye.x_m,
                    eye.z_m,
                    eye.pupil_m,
                    g.emitter_z_m.max(0.0)
                ),
            ));
        }
        // A pupil wider than the stretch the views reach at its distance
        // gathers no more light, only more work (a coherent eye's imaging
        // grows with it); such a width means no eye.
        let (lo, hi) = g.reach_at_m(eye.z_m);
        let widest_m = hi - lo;
        if widest_m.is_nan() || eye.pupil_m > widest_m {
            return Err(Error::argument(
                "pupil",
                format!(
                    "a pupil {} m wide is wider than the views reach at {} m from the display ({} m across, from x = \
                     {} to {} m): it must be at most {} m",
                    eye.pupil_m, eye.z_m, widest_m, lo, hi, widest_m
                ),
            ));
        }
    }
    let unpacked = images.unpack(a, g.hololines)?;
    let colours = g.channels.len();
    let optics = (0..colours).map(|c| ColourOptics::new(a, c)).collect::<Result<Vec<_>>>()?;
    // What a lone emitter looks like to each coherent eye, per colour.
    let calibrations: Vec<Vec<Option<Vec<f64>>>> = optics
        .iter()
        .map(|o| eyes.iter().map(|eye| eye.coherent.then(|| o.coherent_calibration(eye)).transpose()).collect())
        .collect::<Result<_>>()?;
    let steps = Steps::begin(progress, "hololines", g.hololines);
    // rows[j][eye][e · colours + c]
    let rows: Vec<Vec<Vec<f32>>> = (0..g.hololines)
        .into_par_iter()
        .map(|j| -> Result<Vec<Vec<f32>>> {
            let mut rows = vec![vec![0f32; g.emitters * colours]; eyes.len()];
            for (c, optics) in optics.iter().enumerate() {
                let signals = &unpacked[group_of(a, c)];
                let slices: Vec<&[f32]> = (0..signals.signals).map(|s| signals.row(s, j)).collect();
                // A dark hololine sends no light: its row stays black, and
                // the propagation and spectra (most of the work) are skipped.
                if slices.iter().all(|s| s.iter().all(|&v| v == 0.0)) {
                    continue;
                }
                let field = optics.emitter_plane(&slices)?;
                for (k, eye) in eyes.iter().enumerate() {
                    if let Some(calibration) = &calibrations[c][k] {
                        for (e, seen) in optics.seen_coherently(&field, eye, calibration)?.into_iter().enumerate() {
                            rows[k][e * colours + c] = seen as f32;
                        }
                    }
                }
                if eyes.iter().any(|eye| !eye.coherent) {
                    for e in 0..g.emitters {
                        let spectrum = optics.spectrum(&field, e);
                        for (row, eye) in rows.iter_mut().zip(eyes).filter(|(_, eye)| !eye.coherent) {
                            row[e * colours + c] = optics.seen(&spectrum, e, eye) as f32;
                        }
                    }
                }
            }
            steps.step();
            Ok(rows)
        })
        .collect::<Result<_>>()?;
    Ok((0..eyes.len())
        .map(|k| Picture {
            emitters: g.emitters,
            hololines: g.hololines,
            channels: g.channels.iter().map(|c| c.name.clone()).collect(),
            column_aspect: g.emitter_pitch_m / g.hololine_pitch_m,
            data: rows.iter().flat_map(|r| r[k].iter().copied()).collect(),
        })
        .collect())
}
