//! What an eye sees of a light field itself, before any fringe: the
//! geometric picture a perfect display of the stored rays shows. A
//! full-parallax file has no fringe side yet (spec/layouts.md §7.6), so
//! `holo view` of one shows this.
//!
//! Each emitter `(j, e)` sends toward a point `P = (X, Y, Z)` of the eye's
//! pupil the ray of direction `tan θ = (X − x_e)/(Z − z_e)`,
//! `tan φ = (Y − y_j)/(Z − z_e)` (spec §8); its brightness there is the
//! file's, read between views linearly in both view indices by each axis's
//! spacing rule ([`crate::geometry::Views::index_at`]), and black beyond
//! half a view past the first or last (no view reaches there). The eye sees
//! an emitter as the mean over its pupil: a pupil a few views wide blurs
//! what lies off the emitter plane, as an eye's pupil does. A pupil of
//! zero diameter is a pinhole.

use rayon::prelude::*;

use super::picture::Picture;
use crate::error::{Error, Result};
use crate::modulation::Modulation;
use crate::sampling::linear_taps;

/// Points across a pupil's diameter at which it is sampled (a square grid
/// clipped to the disc: 21 points for 5).
const PUPIL_SAMPLES_ACROSS: usize = 5;

/// An eye in front of the display.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyePoint {
    /// Centre of the pupil, `(x, y, z)` in display metres.
    pub centre_m: [f64; 3],
    /// Pupil diameter, metres (0: a pinhole).
    pub pupil_m: f64,
}

impl EyePoint {
    /// Where the pupil is sampled: its centre for a pinhole, else the points
    /// of a square grid ([`PUPIL_SAMPLES_ACROSS`] across) inside the disc.
    fn points(&self) -> Vec<[f64; 3]> {
        let [x, y, z] = self.centre_m;
        if self.pupil_m <= 0.0 {
            return vec![self.centre_m];
        }
        let n = PUPIL_SAMPLES_ACROSS;
        let at = |i: usize| ((i as f64 + 0.5) / n as f64 - 0.5) * self.pupil_m;
        (0..n * n)
            .map(|i| (at(i % n), at(i / n)))
            .filter(|(dx, dy)| dx * dx + dy * dy <= 0.25 * self.pupil_m * self.pupil_m)
            .map(|(dx, dy)| [x + dx, y + dy, z])
            .collect()
    }
}

/// What an eye at `eye` sees of the light field `m`, and how many of the
/// picture's emitters it sees no view of (black: the eye is beyond the
/// views' reach there). A horizontal-parallax file is read as what its rays
/// are: each emitter's views reach the viewer line, whatever the eye's height.
pub fn eye_view(m: &Modulation, eye: &EyePoint) -> Result<(Picture, usize)> {
    let g = m.geometry();
    let span = eye.centre_m[2] - g.emitter_z_m;
    if !(span > 0.0 && eye.centre_m.iter().all(|v| v.is_finite()) && eye.pupil_m.is_finite()) {
        return Err(Error::argument(
            "eye",
            format!(
                "an eye at z = {} mm is not in front of the emitter plane (z = {} mm)",
                eye.centre_m[2] * 1e3,
                g.emitter_z_m * 1e3
            ),
        ));
    }
    let points = eye.points();
    let share = 1.0 / points.len() as f32;
    let (v_count, c_count) = (g.views.count, g.channels.len());
    let rows: Vec<(Vec<f32>, usize)> = (0..g.hololines)
        .into_par_iter()
        .map(|j| {
            let y = g.hololine_y_m(j);
            let mut row = vec![0f32; g.emitters * c_count];
            let mut unseen = 0;
            for e in 0..g.emitters {
                let x = g.emitter_x_m(e);
                let mut seen = false;
                for p in &points {
                    let (dz, out) = (p[2] - g.emitter_z_m, &mut row[e * c_count..(e + 1) * c_count]);
                    let h = g.views.index_at(((p[0] - x) / dz).atan());
                    let w = g.vertical_views.as_ref().map_or(0.0, |v| v.index_at(((p[1] - y) / dz).atan()));
                    let (Some(th), Some(tw)) = (linear_taps(h, v_count), linear_taps(w, g.vertical_view_count()))
                    else {
                        continue;
                    };
                    seen = true;
                    for (c, out) in out.iter_mut().enumerate() {
                        let views = m.views_of(c, j, e);
                        let mut value = 0f32;
                        for (wi, ww) in tw {
                            for (hi, wh) in th {
                                value += ww * wh * views[g.view_index(hi, wi)];
                            }
                        }
                        *out += share * value;
                    }
                }
                unseen += usize::from(!seen);
            }
            (row, unseen)
        })
        .collect();
    let unseen = rows.iter().map(|r| r.1).sum();
    let picture = Picture {
        emitters: g.emitters,
        hololines: g.hololines,
        channels: g.channels.iter().map(|c| c.name.clone()).collect(),
        column_aspect: g.emitter_pitch_m / g.hololine_pitch_m,
        data: rows.into_iter().flat_map(|r| r.0).collect(),
    };
    Ok((picture, unseen))
}
