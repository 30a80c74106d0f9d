//! The fast renderer: one epipolar-plane image per hololine (DESIGN.md §6;
//! Halle, "Multiple Viewpoint Rendering", SIGGRAPH 1998).
//!
//! Every ray of hololine `j` lies in one plane, the plane through the line
//! `y = y_j, z = z_e` and the viewer line. A point `P` is on it when
//! `f_j(P) = P_y − y_j − (P_z − z_e)·k_j = 0`, so a triangle whose vertices
//! change sign of `f_j` is cut in a segment `AB`. In the plane, ray `(x, s)`
//! (emitter-plane crossing `x`, slope `s = tan θ`) meets the point `(X, Z)`
//! when `x = X − (Z − z_e)·s`: for a fixed view the segment covers the
//! emitters between `u_A = X_A − (Z_A − z_e)s` and `u_B`, and depth and
//! surface position are affine along it. So each hololine is drawn column by
//! column (one view at a time) as 1-D spans with a depth test (largest `Z`,
//! nearest the viewer, wins), exactly and with no perspective division: rays
//! through the centre of projection are not special.
//!
//! Culls (seed 000 §2.1.1): a triangle takes part only in the hololines its
//! projected height covers; a one-sided triangle whose normal faces away from
//! every ray direction of a hololine is dropped before any work (the
//! "widened" back-face cull: one view seeing it keeps it), and inside the
//! hololine only for the views it faces away from.

use super::fastshade::{self, Attrs, FastLights, FastMaterial};
use super::render::{HololineRenderer, RenderStats, Shading};
use super::shade::{cross, normalize_or, sub};

/// One triangle as the rasteriser sees it.
struct Tri {
    object: u32,
    triangle: u32,
    /// Global vertex ids (object-offset), to order shared edges the same way.
    ids: [u64; 3],
    p: [[f64; 3]; 3],
    normal: [f64; 3],
    double_sided: bool,
}

/// A triangle cut by one hololine's plane.
#[derive(Clone, Copy)]
struct Segment {
    tri: u32,
    /// `(X, Z)` of the ends.
    a: [f64; 2],
    b: [f64; 2],
    /// Surface attributes at the ends.
    attrs_a: Attrs,
    attrs_b: Attrs,
    /// Unit face normal.
    face: [f32; 3],
    /// Facing: the triangle faces the ray of slope `s` when `nx·s + c > 0`.
    nx: f64,
    c: f64,
    double_sided: bool,
}

pub(crate) struct EpiRenderer<'a> {
    s: Shading<'a>,
    tris: Vec<Tri>,
    /// Triangles per hololine, compressed: `bucket[start[j]..start[j+1]]`.
    start: Vec<usize>,
    bucket: Vec<u32>,
    materials: Vec<FastMaterial>,
    lights: FastLights,
}

impl<'a> EpiRenderer<'a> {
    pub(crate) fn new(s: Shading<'a>) -> Self {
        let r = s.rays;
        let span = r.viewer_distance_m - r.emitter_z_m;
        let mut tris = Vec::with_capacity(s.scene.triangle_count());
        let mut offset = 0u64;
        for (oi, o) in s.scene.objects.iter().enumerate() {
            for (ti, t) in o.triangles.iter().enumerate() {
                let p = [o.positions[t[0] as usize], o.positions[t[1] as usize], o.positions[t[2] as usize]];
                tris.push(Tri {
                    object: oi as u32,
                    triangle: ti as u32,
                    ids: [offset + t[0] as u64, offset + t[1] as u64, offset + t[2] as u64],
                    normal: cross(sub(p[1], p[0]), sub(p[2], p[0])),
                    p,
                    double_sided: o.material.double_sided,
                });
            }
            offset += o.positions.len() as u64;
        }
        // Hololine range of each triangle: a vertex projects from the viewer
        // line onto the emitter plane at height y_p = (Y − a·y_v)/(1 − a),
        // a = (Z − z_e)/(D − z_e), and f_j has the sign of y_p − y_j.
        let h = r.hololine_y_m.len();
        let top = r.hololine_y_m.first().copied().unwrap_or(0.0);
        let pitch = if h > 1 { r.hololine_y_m[0] - r.hololine_y_m[1] } else { 1.0 };
        let ranges: Vec<(usize, usize)> = tris
            .iter()
            .map(|t| {
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                for p in &t.p {
                    let a = (p[2] - r.emitter_z_m) / span;
                    if a >= 1.0 - 1e-12 {
                        return (0, h); // reaches the viewer line: every hololine, clipped later
                    }
                    let yp = (p[1] - a * r.viewer_height_m) / (1.0 - a);
                    lo = lo.min(yp);
                    hi = hi.max(yp);
                }
                // Hololine j (y_j = top − j·pitch) is cut when lo ≤ y_j ≤ hi.
                let first = ((top - hi) / pitch).ceil().max(0.0);
                let last = ((top - lo) / pitch).floor();
                if !(first.is_finite() && last.is_finite()) || last < first || first >= h as f64 || last < 0.0 {
                    return (0, 0);
                }
                (first as usize, (last as usize + 1).min(h))
            })
            .collect();
        let mut start = vec![0usize; h + 1];
        for &(a, b) in &ranges {
            for j in a..b {
                start[j + 1] += 1;
            }
        }
        for j in 0..h {
            start[j + 1] += start[j];
        }
        let mut fill = start.clone();
        let mut bucket = vec![0u32; start[h]];
        for (i, &(a, b)) in ranges.iter().enumerate() {
            for j in a..b {
                bucket[fill[j]] = i as u32;
                fill[j] += 1;
            }
        }
        let materials =
            s.scene.objects.iter().map(|o| FastMaterial::new(&o.material, s.lighting.model)).collect();
        let lights = FastLights::new(s.lighting);
        EpiRenderer { s, tris, start, bucket, materials, lights }
    }

    /// The segments of hololine `j`, and how many triangles the widened
    /// back-face cull dropped.
    fn segments(&self, j: usize) -> (Vec<Segment>, u64) {
        let r = self.s.rays;
        let (y, k) = (r.hololine_y_m[j], r.hololine_slope[j]);
        let z_max = r.viewer_distance_m;
        let (s_first, s_last) = (r.sub_view_slope[0], r.sub_view_slope[r.sub_view_slope.len() - 1]);
        let mut out = Vec::new();
        let mut culled = 0;
        for &ti in &self.bucket[self.start[j]..self.start[j + 1]] {
            let t = &self.tris[ti as usize];
            let (nx, c) = (t.normal[0], t.normal[1] * k + t.normal[2]);
            // Widened cull: n·d is linear in s, so the end slopes decide.
            if !t.double_sided && nx * s_first + c <= 0.0 && nx * s_last + c <= 0.0 {
                culled += 1;
                continue;
            }
            let f = t.p.map(|p| p[1] - y - (p[2] - r.emitter_z_m) * k);
            let above = f.map(|v| v >= 0.0);
            let mut ends: [([f64; 3], [f64; 3]); 2] = Default::default();
            let mut n = 0;
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                if above[a] == above[b] {
                    continue;
                }
                // The same edge of two triangles is cut the same way: order by vertex id.
                let (a, b) = if t.ids[a] < t.ids[b] { (a, b) } else { (b, a) };
                let tau = f[a] / (f[a] - f[b]);
                let mut p = [0.0; 3];
                for (q, pq) in p.iter_mut().enumerate() {
                    *pq = t.p[a][q] + tau * (t.p[b][q] - t.p[a][q]);
                }
                let mut w = [0.0; 3];
                w[a] = 1.0 - tau;
                w[b] = tau;
                if n < 2 {
                    ends[n] = (p, w);
                }
                n += 1;
            }
            if n != 2 {
                continue;
            }
            let (mut pa, mut wa) = ends[0];
            let (mut pb, mut wb) = ends[1];
            // Never behind the viewer: clip at the viewer line.
            if pa[2] >= z_max && pb[2] >= z_max {
                continue;
            }
            if pa[2] >= z_max || pb[2] >= z_max {
                if pb[2] >= z_max {
                    std::mem::swap(&mut pa, &mut pb);
                    std::mem::swap(&mut wa, &mut wb);
                }
                // pa is behind the viewer: move it to just in front.
                let z_clip = z_max - 1e-9 * (z_max - pb[2]).abs().max(1e-12);
                let tau = (z_clip - pb[2]) / (pa[2] - pb[2]);
                for q in 0..3 {
                    pa[q] = pb[q] + tau * (pa[q] - pb[q]);
                    wa[q] = wb[q] + tau * (wa[q] - wb[q]);
                }
            }
            let o = &self.s.scene.objects[t.object as usize];
            let face = normalize_or(t.normal, [0.0, 0.0, 1.0]);
            out.push(Segment {
                tri: ti,
                a: [pa[0], pa[2]],
                b: [pb[0], pb[2]],
                attrs_a: Attrs::at(o, t.triangle as usize, wa, face),
                attrs_b: Attrs::at(o, t.triangle as usize, wb, face),
                face: [face[0] as f32, face[1] as f32, face[2] as f32],
                nx,
                c,
                double_sided: t.double_sided,
            });
        }
        (out, culled)
    }
}

const NONE: u32 = u32::MAX;

impl HololineRenderer for EpiRenderer<'_> {
    fn render_hololine(&self, j: usize, out: &mut [f32]) -> RenderStats {
        let r = self.s.rays;
        let g = self.s.geometry;
        let (e_count, v_count) = (g.emitters, g.views.count);
        let (se, sv) = (r.supersample.emitter, r.supersample.view);
        let (segments, culled) = self.segments(j);
        let mut stats = RenderStats { segments: segments.len() as u64, back_face_culled: culled, shaded: 0 };
        if segments.is_empty() {
            return stats;
        }
        let k = r.hololine_slope[j];
        let z_e = r.emitter_z_m;
        let n_sub = r.sub_emitter_x_m.len();
        let x_first = r.sub_emitter_x_m[0];
        let dx = if n_sub > 1 { r.sub_emitter_x_m[1] - x_first } else { 1.0 };
        let norm = 1.0 / (se * sv) as f64;
        let mut depth = vec![f64::NEG_INFINITY; n_sub];
        let mut owner = vec![NONE; n_sub];
        let mut param = vec![0.0f64; n_sub];
        let mut sums = vec![[0.0f64; 3]; e_count];
        for v in 0..v_count {
            for x in sums.iter_mut() {
                *x = [0.0; 3];
            }
            for b in 0..sv {
                let s = r.sub_view_slope[v * sv + b];
                depth.fill(f64::NEG_INFINITY);
                owner.fill(NONE);
                for (si, seg) in segments.iter().enumerate() {
                    if !seg.double_sided && seg.nx * s + seg.c <= 0.0 {
                        continue;
                    }
                    let ua = seg.a[0] - (seg.a[1] - z_e) * s;
                    let ub = seg.b[0] - (seg.b[1] - z_e) * s;
                    let du = ub - ua;
                    if du == 0.0 || !du.is_finite() {
                        continue;
                    }
                    let (lo, hi) = if ua < ub { (ua, ub) } else { (ub, ua) };
                    // Sub-emitters with lo ≤ x < hi.
                    let i0 = ((lo - x_first) / dx).ceil().max(0.0);
                    let i1 = ((hi - x_first) / dx).ceil().min(n_sub as f64);
                    if i0 >= i1 || i0.is_nan() || i1.is_nan() {
                        continue;
                    }
                    let (i0, i1) = (i0 as usize, i1 as usize);
                    let dz = seg.b[1] - seg.a[1];
                    for i in i0..i1 {
                        let t = (x_first + i as f64 * dx - ua) / du;
                        let z = seg.a[1] + t * dz;
                        if z > depth[i] {
                            depth[i] = z;
                            owner[i] = si as u32;
                            param[i] = t;
                        }
                    }
                }
                let view = fastshade::normalize([s as f32, k as f32, 1.0]);
                for i in 0..n_sub {
                    if owner[i] == NONE {
                        continue;
                    }
                    let seg = &segments[owner[i] as usize];
                    let t = param[i].clamp(0.0, 1.0) as f32;
                    let tri = &self.tris[seg.tri as usize];
                    let o = &self.s.scene.objects[tri.object as usize];
                    let front = seg.nx * s + seg.c > 0.0;
                    let face = if front { seg.face } else { seg.face.map(|x| -x) };
                    let a = seg.attrs_a.lerp(&seg.attrs_b, t);
                    let rgb = fastshade::radiance(
                        self.s.scene,
                        &self.lights,
                        &self.materials[tri.object as usize],
                        !o.normals.is_empty(),
                        !o.tangents.is_empty(),
                        &a,
                        face,
                        !front,
                        view,
                    );
                    let e = i / se;
                    for c in 0..3 {
                        sums[e][c] += rgb[c] as f64;
                    }
                    stats.shaded += 1;
                }
            }
            for (ch, w) in self.s.weights.iter().enumerate() {
                for (e, sum) in sums.iter().enumerate() {
                    let value = (w[0] * sum[0] + w[1] * sum[1] + w[2] * sum[2]) * norm;
                    out[(ch * e_count + e) * v_count + v] = value as f32;
                }
            }
        }
        stats
    }
}
