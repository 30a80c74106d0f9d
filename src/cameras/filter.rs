//! Picture sampling with a prefilter: a box-filtered mip pyramid and
//! trilinear lookups, so a camera picture much finer than the display's ray
//! spacing is averaged over each ray's footprint instead of aliased.

/// A camera's picture in linear RGB, row by row from the top, with its
/// halvings.
pub struct Pyramid {
    /// Level 0 is the picture; level `k + 1` averages 2 × 2 pixels of level
    /// `k` (an odd last row or column is averaged with itself).
    levels: Vec<Level>,
}

struct Level {
    width: usize,
    height: usize,
    rgb: Vec<[f32; 3]>,
}

impl Pyramid {
    /// The pyramid of a `width × height` picture (non-empty).
    pub fn new(width: usize, height: usize, rgb: Vec<[f32; 3]>) -> Pyramid {
        assert_eq!(rgb.len(), width * height, "picture size");
        let mut levels = vec![Level { width, height, rgb }];
        while let Some(last) = levels.last() {
            if last.width == 1 && last.height == 1 {
                break;
            }
            let (w, h) = (last.width.div_ceil(2), last.height.div_ceil(2));
            let mut rgb = Vec::with_capacity(w * h);
            for y in 0..h {
                for x in 0..w {
                    let (x0, y0) = (2 * x, 2 * y);
                    let (x1, y1) = ((x0 + 1).min(last.width - 1), (y0 + 1).min(last.height - 1));
                    let p = [
                        last.rgb[y0 * last.width + x0],
                        last.rgb[y0 * last.width + x1],
                        last.rgb[y1 * last.width + x0],
                        last.rgb[y1 * last.width + x1],
                    ];
                    rgb.push(std::array::from_fn(|c| 0.25 * (p[0][c] + p[1][c] + p[2][c] + p[3][c])));
                }
            }
            levels.push(Level { width: w, height: h, rgb });
        }
        Pyramid { levels }
    }

    /// Size of the picture (level 0).
    pub fn size(&self) -> (usize, usize) {
        (self.levels[0].width, self.levels[0].height)
    }

    /// The picture at pixel position `(u, v)` (pixel centres at integers),
    /// averaged over a footprint `footprint_px` pixels wide: bilinear in
    /// the two levels around `log₂ footprint`, blended. `None` when `(u, v)`
    /// is outside the picture (more than half a pixel beyond the edge
    /// centres) or not finite.
    pub fn sample(&self, u: f64, v: f64, footprint_px: f64) -> Option<[f32; 3]> {
        let (w, h) = self.size();
        if !(u >= -0.5 && v >= -0.5 && u <= w as f64 - 0.5 && v <= h as f64 - 0.5) {
            return None;
        }
        let lod = if footprint_px > 1.0 { footprint_px.log2().min((self.levels.len() - 1) as f64) } else { 0.0 };
        let k = lod.floor() as usize;
        let f = (lod - k as f64) as f32;
        let a = self.bilinear(k, u, v);
        if f == 0.0 || k + 1 >= self.levels.len() {
            return Some(a);
        }
        let b = self.bilinear(k + 1, u, v);
        Some(std::array::from_fn(|c| a[c] + (b[c] - a[c]) * f))
    }

    /// Bilinear lookup at level `k` of level-0 position `(u, v)`, edges held.
    fn bilinear(&self, k: usize, u: f64, v: f64) -> [f32; 3] {
        let l = &self.levels[k];
        // Level-k pixel i covers level-0 pixels 2^k·i ..; its centre is at 2^k·i + (2^k − 1)/2.
        let s = (1u64 << k) as f64;
        let x = ((u + 0.5) / s - 0.5).clamp(0.0, (l.width - 1) as f64);
        let y = ((v + 0.5) / s - 0.5).clamp(0.0, (l.height - 1) as f64);
        let (x0, y0) = (x.floor() as usize, y.floor() as usize);
        let (x1, y1) = ((x0 + 1).min(l.width - 1), (y0 + 1).min(l.height - 1));
        let (fx, fy) = ((x - x0 as f64) as f32, (y - y0 as f64) as f32);
        let at = |x: usize, y: usize| l.rgb[y * l.width + x];
        let (a, b, c, d) = (at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1));
        std::array::from_fn(|i| {
            let top = a[i] + (b[i] - a[i]) * fx;
            let bottom = c[i] + (d[i] - c[i]) * fx;
            top + (bottom - top) * fy
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_average_and_lookups_interpolate() {
        // A 4 × 2 ramp in x.
        let rgb: Vec<[f32; 3]> = (0..8).map(|i| [(i % 4) as f32; 3]).collect();
        let p = Pyramid::new(4, 2, rgb);
        assert_eq!(p.levels.len(), 3);
        assert_eq!(p.levels[1].rgb, vec![[0.5; 3], [2.5; 3]]);
        assert_eq!(p.levels[2].rgb, vec![[1.5; 3]]);
        assert_eq!(p.sample(1.5, 0.0, 1.0).unwrap()[0], 1.5);
        // Level 1's centres are at level-0 x = 0.5 and 2.5.
        assert_eq!(p.sample(1.5, 0.5, 2.0).unwrap()[0], 1.5);
        assert_eq!(p.sample(0.5, 0.5, 2.0).unwrap()[0], 0.5);
        // Footprint 4: the whole picture's mean.
        assert_eq!(p.sample(3.0, 1.0, 4.0).unwrap()[0], 1.5);
        assert!(p.sample(-0.6, 0.0, 1.0).is_none() && p.sample(0.0, 1.6, 1.0).is_none());
        assert!(p.sample(f64::NAN, 0.0, 1.0).is_none());
    }
}
