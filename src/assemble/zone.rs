//! The zoned-chirp assembler: the overlapping, zoned focusing-chirp basis of
//! Mark III (seed 004 §3.4, §5.1): per hololine and zone, the complex
//! baseband signal `Σ_e Σ_v sqrt(m[j][e][v]) · chirp_zone(x − x_e)` over the
//! view segments, normalised by the number of overlapping chirps. Its real
//! and imaginary parts are the I/Q (cosine/sine) pair a Weaver single-sideband
//! up-converter takes. Weights are `sqrt(m)`: the modulator's diffracted field
//! scales with drive amplitude and a viewer sees intensity (PHYSICS.md §4).
//!
//! [`ZoneAssembler::assemble`] is the fast path; [`ZoneAssembler::assemble_straightforward`]
//! the plain per-sample loop it is measured against; [`ZoneAssembler::assemble_reference`]
//! the f64, table-free reference the tests hold both to.

use rayon::prelude::*;

use super::chirp::ZonedChirp;
use crate::{Error, Modulation, Result};

/// The complex baseband signal of every zone of every hololine of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct ZoneSignals {
    /// Zones (channels of I/Q pairs).
    pub zones: usize,
    /// Hololines.
    pub hololines: usize,
    /// Samples per hololine.
    pub samples: usize,
    /// In-phase (cosine) part, index `(zone · hololines + j) · samples + n`.
    pub i: Vec<f32>,
    /// Quadrature (sine) part, same index.
    pub q: Vec<f32>,
}

/// Assembles modulations into zone signals for one zoned chirp basis.
#[derive(Clone, Debug)]
pub struct ZoneAssembler {
    basis: ZonedChirp,
    abutting_chirps: usize,
    tables: Vec<(Vec<f32>, Vec<f32>)>,
}

impl ZoneAssembler {
    /// An assembler for hololines of `abutting_chirps · chirp_samples` samples.
    pub fn new(basis: ZonedChirp, abutting_chirps: usize) -> Result<Self> {
        let ok = basis.slot_samples > 0
            && basis.views_per_zone > 0
            && basis.chirp_samples % basis.slot_samples == 0
            && basis.chirp_samples % basis.views_per_zone == 0
            && basis.slot_samples % basis.samples_per_view() == 0
            && abutting_chirps > basis.zones
            && basis.emitter_z_m != 0.0
            && basis.emitter_z_m.is_finite();
        if !ok {
            return Err(Error::Usage(format!(
                "inconsistent chirp basis {basis:?} with {abutting_chirps} abutting chirps"
            )));
        }
        let tables = (0..basis.zones).map(|k| basis.table(k)).collect();
        Ok(ZoneAssembler { basis, abutting_chirps, tables })
    }

    /// The basis.
    pub fn basis(&self) -> &ZonedChirp {
        &self.basis
    }
    /// Samples per hololine.
    pub fn samples_per_hololine(&self) -> usize {
        self.abutting_chirps * self.basis.chirp_samples
    }
    /// Emitters per hololine: every emitter needs `zones` subsequent chirps.
    pub fn emitters(&self) -> usize {
        (self.abutting_chirps - self.basis.zones) * self.basis.overlap()
    }

    fn check(&self, m: &Modulation, channel: usize) -> Result<()> {
        let g = m.geometry();
        if g.emitters != self.emitters() || g.views.count != self.basis.views() || channel >= g.channels.len() {
            return Err(Error::Usage(format!(
                "the modulation has {} emitters × {} views ({} channel(s)); this layout needs {} emitters × {} views",
                g.emitters,
                g.views.count,
                g.channels.len(),
                self.emitters(),
                self.basis.views()
            )));
        }
        Ok(())
    }

    fn empty(&self, hololines: usize) -> ZoneSignals {
        let n = self.basis.zones * hololines * self.samples_per_hololine();
        ZoneSignals {
            zones: self.basis.zones,
            hololines,
            samples: self.samples_per_hololine(),
            i: vec![0.0; n],
            q: vec![0.0; n],
        }
    }

    /// Fast path: tabulated basis, one view segment at a time (the weight is
    /// constant over it, so the inner loop is a vectorisable axpy into a
    /// register-sized accumulator), hololines in parallel. Emitters and views
    /// with zero modulation cost one comparison; all-zero hololines are skipped.
    pub fn assemble(&self, m: &Modulation, channel: usize) -> Result<ZoneSignals> {
        let mut out = self.empty(m.geometry().hololines);
        self.assemble_into(m, channel, &mut out)?;
        Ok(out)
    }

    /// [`ZoneAssembler::assemble`] into a buffer kept from an earlier frame
    /// (a frame is 260 MB for Mark III: reusing it saves the page faults).
    pub fn assemble_into(&self, m: &Modulation, channel: usize, out: &mut ZoneSignals) -> Result<()> {
        self.check(m, channel)?;
        let b = &self.basis;
        let (hololines, samples) = (m.geometry().hololines, self.samples_per_hololine());
        if (out.zones, out.hololines, out.samples) != (b.zones, hololines, samples) {
            *out = self.empty(hololines);
        }
        let rows = out.i.par_chunks_mut(samples).zip(out.q.par_chunks_mut(samples)).enumerate();
        rows.for_each(|(row, (out_i, out_q))| {
            let (zone, j) = (row / hololines, row % hololines);
            match Self::weights(m.hololine(channel, j)) {
                Some(weights) => self.zone_row(&weights, zone, out_i, out_q),
                None => {
                    out_i.fill(0.0);
                    out_q.fill(0.0);
                }
            }
        });
        Ok(())
    }

    /// The basis weights `sqrt(m)` of one hololine's modulation (emitter-major,
    /// as stored), or `None` when the hololine is dark.
    pub fn weights(hololine: &[f32]) -> Option<Vec<f32>> {
        if hololine.iter().all(|x| *x == 0.0) {
            return None;
        }
        Some(hololine.iter().map(|x| x.max(0.0).sqrt()).collect())
    }

    /// One zone of one hololine (fast path, one thread): the I and Q
    /// signals from the hololine's [`ZoneAssembler::weights`].
    pub fn zone_row(&self, weights: &[f32], zone: usize, out_i: &mut [f32], out_q: &mut [f32]) {
        let b = &self.basis;
        let spv = b.samples_per_view();
        let norm = 1.0 / b.overlap() as f32;
        let segment_view: Vec<usize> = (0..b.views_per_zone).map(|k| b.view_of(zone, k * spv)).collect();
        let row = RowJob { assembler: self, segment_view: &segment_view, zone, weights, norm };
        if spv == 32 {
            row.run_dispatch::<32>(out_i, out_q);
        } else {
            row.run_dynamic(out_i, out_q, spv);
        }
    }

    /// The straightforward loop: for every output sample, gather its
    /// overlapping chirps from the tables, one thread. The baseline the
    /// benchmark compares the fast path with.
    pub fn assemble_straightforward(&self, m: &Modulation, channel: usize) -> Result<ZoneSignals> {
        self.check(m, channel)?;
        let b = &self.basis;
        let (hololines, samples) = (m.geometry().hololines, self.samples_per_hololine());
        let mut out = self.empty(hololines);
        for zone in 0..b.zones {
            let (table_i, table_q) = &self.tables[zone];
            for j in 0..hololines {
                let row = (zone * hololines + j) * samples;
                for n in 0..samples {
                    let (mut si, mut sq) = (0f32, 0f32);
                    for k in 0..b.overlap() {
                        let Some(slot) = (n / b.slot_samples).checked_sub(k) else { break };
                        let Some(e) = slot.checked_sub(zone * b.overlap()).filter(|e| *e < self.emitters()) else {
                            continue;
                        };
                        let u = n - slot * b.slot_samples;
                        let w = m.get(channel, j, e, b.view_of(zone, u)).max(0.0).sqrt();
                        si += w * table_i[u];
                        sq += w * table_q[u];
                    }
                    out.i[row + n] = si / b.overlap() as f32;
                    out.q[row + n] = sq / b.overlap() as f32;
                }
            }
        }
        Ok(out)
    }

    /// Reference: f64 throughout, every phase computed from the physics, no
    /// tables, no skipping. Slow; for tests on a few hololines.
    pub fn assemble_reference(&self, m: &Modulation, channel: usize) -> Result<ZoneSignals> {
        self.check(m, channel)?;
        let b = &self.basis;
        let (hololines, samples) = (m.geometry().hololines, self.samples_per_hololine());
        let mut out = self.empty(hololines);
        for zone in 0..b.zones {
            for j in 0..hololines {
                for n in 0..samples {
                    let (mut si, mut sq) = (0f64, 0f64);
                    for e in 0..self.emitters() {
                        let start = (e + zone * b.overlap()) * b.slot_samples;
                        if n < start || n >= start + b.chirp_samples {
                            continue;
                        }
                        let u = n - start;
                        let w = f64::from(m.get(channel, j, e, b.view_of(zone, u))).max(0.0).sqrt();
                        let phi = b.baseband_phase_rad(zone, u as f64);
                        si += w * phi.cos();
                        sq += w * phi.sin();
                    }
                    let at = (zone * hololines + j) * samples + n;
                    out.i[at] = (si / b.overlap() as f64) as f32;
                    out.q[at] = (sq / b.overlap() as f64) as f32;
                }
            }
        }
        Ok(out)
    }
}

/// One zone of one hololine for the fast path.
struct RowJob<'a> {
    assembler: &'a ZoneAssembler,
    /// `segment_view[k]`: the view shown by view segment `k` of this zone's piece.
    segment_view: &'a [usize],
    zone: usize,
    weights: &'a [f32],
    norm: f32,
}

impl RowJob<'_> {
    /// The (emitter-view weight, table offset) of every chirp overlapping the
    /// view segment that starts at sample `n0`; zero weights are left out.
    fn terms(&self, n0: usize, out: &mut Vec<(f32, usize)>) {
        let b = &self.assembler.basis;
        let (spv, views, emitters) = (b.samples_per_view(), b.views(), self.assembler.emitters());
        out.clear();
        let last_slot = n0 / b.slot_samples;
        let first_slot = (last_slot + 1).saturating_sub(b.overlap());
        for slot in first_slot..=last_slot {
            let Some(e) = slot.checked_sub(self.zone * b.overlap()).filter(|e| *e < emitters) else {
                continue;
            };
            let u0 = n0 - slot * b.slot_samples;
            let w = self.weights[e * views + self.segment_view[u0 / spv]];
            if w != 0.0 {
                out.push((w, u0));
            }
        }
    }

    /// Segments of `SPV` samples with fixed-size accumulators, compiled for
    /// AVX2 + FMA when the processor has them (checked at run time).
    fn run_dispatch<const SPV: usize>(&self, out_i: &mut [f32], out_q: &mut [f32]) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            // SAFETY: the features the function is compiled for are present.
            unsafe { self.run_avx2::<SPV>(out_i, out_q) };
            return;
        }
        self.run_fixed::<SPV, false>(out_i, out_q);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_avx2<const SPV: usize>(&self, out_i: &mut [f32], out_q: &mut [f32]) {
        self.run_fixed::<SPV, true>(out_i, out_q);
    }

    /// `FUSED`: use fused multiply-adds (only where the hardware has them;
    /// elsewhere `mul_add` is a slow library call).
    #[inline(always)]
    fn run_fixed<const SPV: usize, const FUSED: bool>(&self, out_i: &mut [f32], out_q: &mut [f32]) {
        let (table_i, table_q) = &self.assembler.tables[self.zone];
        let mut terms = Vec::with_capacity(self.assembler.basis.overlap());
        for n0 in (0..out_i.len()).step_by(SPV) {
            self.terms(n0, &mut terms);
            let mut acc_i = [0f32; SPV];
            let mut acc_q = [0f32; SPV];
            for &(w, u0) in &terms {
                let ti: &[f32; SPV] = table_i[u0..u0 + SPV].try_into().expect("segment inside the table");
                let tq: &[f32; SPV] = table_q[u0..u0 + SPV].try_into().expect("segment inside the table");
                for t in 0..SPV {
                    if FUSED {
                        acc_i[t] = w.mul_add(ti[t], acc_i[t]);
                        acc_q[t] = w.mul_add(tq[t], acc_q[t]);
                    } else {
                        acc_i[t] += w * ti[t];
                        acc_q[t] += w * tq[t];
                    }
                }
            }
            for t in 0..SPV {
                out_i[n0 + t] = acc_i[t] * self.norm;
                out_q[n0 + t] = acc_q[t] * self.norm;
            }
        }
    }

    fn run_dynamic(&self, out_i: &mut [f32], out_q: &mut [f32], spv: usize) {
        let (table_i, table_q) = &self.assembler.tables[self.zone];
        let mut terms = Vec::new();
        for n0 in (0..out_i.len()).step_by(spv) {
            self.terms(n0, &mut terms);
            let (oi, oq) = (&mut out_i[n0..n0 + spv], &mut out_q[n0..n0 + spv]);
            oi.fill(0.0);
            oq.fill(0.0);
            for &(w, u0) in &terms {
                oi.iter_mut().zip(&table_i[u0..u0 + spv]).for_each(|(a, t)| *a += w * t);
                oq.iter_mut().zip(&table_q[u0..u0 + spv]).for_each(|(a, t)| *a += w * t);
            }
            oi.iter_mut().chain(oq.iter_mut()).for_each(|a| *a *= self.norm);
        }
    }
}

/// The zoned-chirp assembler of a layout's colour channel `channel`.
pub fn for_layout(layout: &crate::layout::Layout, channel: usize) -> Result<ZoneAssembler> {
    let g = &layout.geometry;
    let Some(f) = &layout.fringe else {
        return Err(Error::Usage(format!("layout {} has no fringe side: it cannot be assembled", layout.name)));
    };
    let crate::layout::Basis::ZonedChirp { chirp_samples, slot_samples, zones, views_per_zone } = f.basis;
    let basis = ZonedChirp {
        sample_pitch_m: f.sample_pitch_m,
        wavelength_m: g.channels[channel].wavelength_m,
        emitter_z_m: g.emitter_z_m,
        chirp_samples,
        slot_samples,
        zones,
        views_per_zone,
    };
    ZoneAssembler::new(basis, f.samples_per_hololine / chirp_samples)
}

/// The Mark III basis (seed 004 §5.1): 1024-sample chirps every 64 samples,
/// three zones of 32 views, 24 abutting chirps per 24576-sample hololine, at
/// the pitch and emitter plane of [`crate::layout::mark3`].
pub fn mark3_assembler() -> ZoneAssembler {
    for_layout(&crate::layout::mark3(), 0).expect("the Mark III numbers are consistent")
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    fn random_mark3(hololines: usize, seed: u64, rough: bool) -> Modulation {
        let mut g = crate::layout::mark3().geometry;
        g.hololines = hololines;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        Modulation::from_fn(g, |_, j, e, v| {
            if rough {
                rng.gen_range(0.0..1.0)
            } else {
                0.5 + 0.5 * ((e as f32 * 0.07 + v as f32 * 0.11 + j as f32).sin())
            }
        })
        .unwrap()
    }

    #[test]
    fn fast_and_straightforward_agree_with_the_f64_reference() {
        let a = mark3_assembler();
        assert_eq!((a.emitters(), a.samples_per_hololine()), (336, 24576));
        for (seed, rough) in [(1, true), (2, false)] {
            let m = random_mark3(2, seed, rough);
            let reference = a.assemble_reference(&m, 0).unwrap();
            for (name, got) in
                [("fast", a.assemble(&m, 0).unwrap()), ("straightforward", a.assemble_straightforward(&m, 0).unwrap())]
            {
                let worst = got
                    .i
                    .iter()
                    .chain(&got.q)
                    .zip(reference.i.iter().chain(&reference.q))
                    .map(|(x, y)| (x - y).abs())
                    .fold(0f32, f32::max);
                assert!(worst < 2e-6, "{name}: worst difference {worst}");
            }
            assert!(reference.i.iter().any(|x| x.abs() > 0.1), "the signal is not trivially small");
        }
    }

    #[test]
    fn zero_modulation_gives_zero_and_geometry_mismatch_is_an_error() {
        let a = mark3_assembler();
        let mut m = random_mark3(3, 3, true);
        for e in 0..336 {
            for v in 0..96 {
                m.set(0, 1, e, v, 0.0);
            }
        }
        let s = a.assemble(&m, 0).unwrap();
        for zone in 0..3 {
            let row = (zone * 3 + 1) * s.samples;
            assert!(s.i[row..row + s.samples].iter().all(|x| *x == 0.0));
        }
        let small = Modulation::zeros(crate::layout::mark1().geometry).unwrap();
        let err = a.assemble(&small, 0).unwrap_err().to_string();
        assert!(err.contains("336 emitters × 96 views"), "{err}");
    }
}
