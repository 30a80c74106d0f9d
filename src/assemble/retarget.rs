//! Retargeting: a modulation resampled onto another display's geometry, by
//! rays (camera captures are resampled in `cameras::resample`; this is the
//! stored light field carried to a layout it was not made for): every target
//! sample (hololine, emitter, view) is the radiance along a ray (docs/optics.md
//! §1.3), and it takes the source's radiance along the same ray, interpolated
//! linearly between the source's hololines, emitters and views. Only on
//! request (`holo assemble --resample`): a file made for one display is never
//! silently bent to another.
//!
//! Horizontally the ray through target emitter `(x_e, z_e)` in direction `θ`
//! meets the source's emitter plane at `x_e + (z_s − z_e) tan θ`, in the same
//! direction. Vertically it keeps the height it has at the source's emitter
//! plane on its way to the target's viewer line (the two viewer lines need not
//! agree). Rays that leave the source's emitters, hololines or views are zero,
//! and counted. Colours are matched by name; a grey (`Y`) source feeds every
//! colour, and a grey target takes Rec. 709 luminance of an RGB source.

use crate::error::{Error, Result};
use crate::geometry::{Geometry, Views};
use crate::modulation::Modulation;

/// What a retargeting did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RetargetStats {
    /// Target samples whose ray the source does not hold (set to zero).
    pub outside: u64,
    /// Target samples.
    pub total: u64,
}

/// Fractional index of the view pointing at `theta_rad`, or `None` beyond
/// the first and last view.
fn view_index(views: &Views, theta_rad: f64) -> Option<f64> {
    let n = views.count;
    if n == 1 {
        return ((theta_rad - views.first_theta_rad).abs() < 1e-12).then_some(0.0);
    }
    let f = views.index_at(theta_rad);
    (-1e-9..=(n - 1) as f64 + 1e-9).contains(&f).then(|| f.clamp(0.0, (n - 1) as f64))
}

/// Linear interpolation weights of a fractional index inside `0..n`.
fn lerp(f: f64, n: usize) -> Option<[(usize, f64); 2]> {
    if !(f > -1e-9 && f < (n - 1) as f64 + 1e-9) {
        return None;
    }
    let f = f.clamp(0.0, (n - 1) as f64);
    let i = (f.floor() as usize).min(n.saturating_sub(2));
    let t = f - i as f64;
    Some([(i, 1.0 - t), ((i + 1).min(n - 1), t)])
}

/// `source` resampled onto `target` (which must be valid), and what it did.
pub fn retarget(source: &Modulation, target: &Geometry) -> Result<(Modulation, RetargetStats)> {
    let s = source.geometry();
    // How each target colour is made from the source's colours.
    let mix: Vec<Vec<(usize, f32)>> = target
        .channels
        .iter()
        .map(|c| match (s.channel_index(&c.name), s.channel_index("Y")) {
            (Some(i), _) => Ok(vec![(i, 1.0)]),
            (None, Some(y)) => Ok(vec![(y, 1.0)]),
            (None, None) if c.name == "Y" => {
                let rgb = ["R", "G", "B"].map(|n| s.channel_index(n));
                match rgb {
                    [Some(r), Some(g), Some(b)] => Ok(vec![(r, 0.2126), (g, 0.7152), (b, 0.0722)]),
                    _ => Err(Error::argument("channels", "a grey target needs an R, G, B or Y source")),
                }
            }
            _ => Err(Error::argument(
                "channels",
                format!("the source has no colour {} (nor Y) to resample from", c.name),
            )),
        })
        .collect::<Result<_>>()?;
    let mut stats = RetargetStats::default();
    let mut out = Modulation::zeros(target.clone())?;
    let dz = s.emitter_z_m - target.emitter_z_m;
    for j in 0..target.hololines {
        let y = target.hololine_y_m(j);
        // The ray's height at the source's emitter plane, on its way to the viewer line.
        let slope = target.ray_slope_y(y);
        let rows = lerp((s.hololine_top_y_m - (y + dz * slope)) / s.hololine_pitch_m, s.hololines);
        for e in 0..target.emitters {
            for v in 0..target.views.count {
                stats.total += target.channels.len() as u64;
                let theta = target.views.theta_rad(v);
                let x = target.emitter_x_m(e) + dz * theta.tan();
                let columns = lerp((x - s.emitter_left_x_m) / s.emitter_pitch_m, s.emitters);
                let views = view_index(&s.views, theta).and_then(|f| lerp(f, s.views.count));
                let (Some(rows), Some(columns), Some(views)) = (rows, columns, views) else {
                    stats.outside += target.channels.len() as u64;
                    continue;
                };
                for (c, mix) in mix.iter().enumerate() {
                    let mut value = 0f64;
                    for &(sc, w) in mix {
                        for (jj, wj) in rows {
                            for (ee, we) in columns {
                                for (vv, wv) in views {
                                    value += f64::from(w) * wj * we * wv * f64::from(source.get(sc, jj, ee, vv));
                                }
                            }
                        }
                    }
                    out.set(c, j, e, v, value as f32);
                }
            }
        }
    }
    Ok((out, stats))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{mark1, mark1_hogel, mark3};

    #[test]
    fn resampling_onto_its_own_geometry_is_the_identity() {
        let g = mark1().geometry;
        let m = Modulation::from_fn(g.clone(), |c, j, e, v| ((c * 7 + j * 3 + e * 5 + v) % 11) as f32 / 10.0).unwrap();
        let (r, stats) = retarget(&m, &g).unwrap();
        assert_eq!(stats.outside, 0);
        let worst = m.samples().iter().zip(r.samples()).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
        assert!(worst < 1e-6, "{worst}");
    }

    #[test]
    fn rays_keep_their_radiance_when_the_emitter_plane_moves() {
        // A scene whose radiance depends on the ray only through its direction
        // is the same in every geometry; one that depends on where the ray
        // crosses z = 0 is shifted by (z_s − z_e) tan θ.
        let source = mark1().geometry;
        let target = mark1_hogel().geometry;
        let by_direction = Modulation::from_fn(source.clone(), |_, _, _, v| 0.2 * v as f32).unwrap();
        let (r, stats) = retarget(&by_direction, &target).unwrap();
        assert!(stats.outside < stats.total / 10, "{stats:?}");
        let inside = |j: usize, e: usize| {
            let x = target.emitter_x_m(e);
            x.abs() < 8e-3 && j > 2 && j < 60
        };
        for (j, e, v) in [(10, 128, 0), (30, 60, 2), (50, 200, 4)] {
            assert!(inside(j, e));
            assert!((r.get(1, j, e, v) - 0.2 * v as f32).abs() < 1e-5, "{j} {e} {v}: {}", r.get(1, j, e, v));
        }
        let along_x = |g: &crate::geometry::Geometry| {
            let g2 = g.clone();
            Modulation::from_fn(g.clone(), move |_, _, e, v| {
                // x where the ray crosses the hologram plane.
                let x0 = g2.emitter_x_m(e) - g2.emitter_z_m * g2.views.theta_rad(v).tan();
                (0.5 + 30.0 * x0) as f32
            })
            .unwrap()
        };
        let (r, _) = retarget(&along_x(&source), &target).unwrap();
        let want = along_x(&target);
        for (j, e, v) in [(10, 128, 0), (30, 60, 2), (50, 200, 4)] {
            assert!((r.get(0, j, e, v) - want.get(0, j, e, v)).abs() < 2e-3, "{j} {e} {v}");
        }
    }

    #[test]
    fn colours_are_matched_or_mixed_and_missing_ones_named() {
        let rgb = mark1().geometry;
        let mut grey = mark1().geometry;
        grey.channels = crate::geometry::mono_channel();
        let m = Modulation::from_fn(rgb.clone(), |c, _, _, _| [1.0, 0.5, 0.25][c]).unwrap();
        let (y, _) = retarget(&m, &grey).unwrap();
        assert!((y.get(0, 5, 5, 2) - (0.2126 + 0.7152 * 0.5 + 0.0722 * 0.25)).abs() < 1e-6);
        let (back, _) = retarget(&y, &rgb).unwrap();
        assert_eq!(back.get(2, 5, 5, 2), y.get(0, 5, 5, 2));
        let m3 = Modulation::zeros(mark3().geometry).unwrap();
        let mut odd = mark1().geometry;
        odd.channels = vec![crate::geometry::ColourChannel::new("R", 633e-9)];
        let mut g_only = mark3().geometry;
        g_only.channels = vec![crate::geometry::ColourChannel::new("G", 532e-9)];
        let m_g = Modulation::zeros(g_only).unwrap();
        let err = retarget(&m_g, &odd).unwrap_err().to_string();
        assert!(err.contains("no colour R"), "{err}");
        assert!(retarget(&m3, &odd).is_ok());
    }
}
