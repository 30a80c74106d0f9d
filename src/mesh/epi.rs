//! The fast renderer: one epipolar-plane image per hololine (Halle, "Multiple Viewpoint Rendering", SIGGRAPH 1998).
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
//! Culls (Nelson 1993 §2.1.1): a triangle takes part only in the hololines its
//! projected height covers; a one-sided triangle whose normal faces away from
//! every ray direction of a hololine is dropped before any work (the
//! "widened" back-face cull: one view seeing it keeps it), and inside the
//! hololine only for the views it faces away from.
//!
//! See-through materials (glTF `alphaMode` MASK and BLEND,
//! [`super::AlphaMode`]) take no part in the depth test: once a column's
//! opaque surfaces are drawn, each see-through segment leaves a fragment at
//! every sub-emitter where it is in front of them, and a sub-emitter's
//! fragments are composited nearest first over the opaque surface, each
//! weighted by its coverage and by what those in front let through, as the
//! reference ray caster does (`trace::along_ray`). A hololine
//! without them is drawn as it always was.

use rayon::prelude::*;

use super::fastshade::{self, Attrs, Batch, Column, FastLights, FastMaterial, LightGroups, Run, SegmentTable};
use super::rays::{HololineRenderer, Rays, RenderStats, Shading};
use super::Scene;
use crate::math::{cross, narrow, normalize, sub};

/// One triangle as the rasteriser sees it, made from the scene when a
/// hololine needs it ([`EpiRenderer::triangle`]): a frame of micropolygons
/// has millions, and a copy of them all is memory first touched every frame.
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
    /// Index into the scene's objects (and the fast materials).
    object: u32,
    /// The object's light group ([`LightGroups`]).
    group: u32,
    /// The object has vertex normals / tangents.
    has_normals: bool,
    has_tangents: bool,
    /// The interpolated vertex normal never nears zero ([`fastshade::normals_nonzero`]).
    normals_nonzero: bool,
    /// `(X, Z)` of the ends.
    a: [f64; 2],
    b: [f64; 2],
    /// Surface attributes at the start, and their change to the end.
    attrs_a: Attrs,
    attrs_delta: Attrs,
    /// Unit face normal.
    face: [f32; 3],
    /// Facing: the triangle faces the ray of slope `s` when `nx·s + c > 0`.
    nx: f64,
    c: f64,
    double_sided: bool,
}

pub(crate) struct EpiRenderer<'a> {
    s: Shading<'a>,
    /// Every triangle: (object, triangle in it).
    tris: Vec<(u32, u32)>,
    /// The global id of each object's first vertex.
    vertex_offset: Vec<u64>,
    /// Triangles per hololine, compressed: `bucket[start[j]..start[j+1]]`.
    start: Vec<usize>,
    bucket: Vec<u32>,
    materials: Vec<FastMaterial>,
    /// The lights each object receives, by group.
    lights: LightGroups,
    /// The CPU has AVX2 and FMA.
    lights_avx2: bool,
}

impl<'a> EpiRenderer<'a> {
    pub(crate) fn new(s: Shading<'a>) -> Self {
        let r = s.rays;
        let mut tris = Vec::with_capacity(s.scene.triangle_count());
        let mut vertex_offset = Vec::with_capacity(s.scene.objects.len());
        let mut offset = 0u64;
        for (oi, o) in s.scene.objects.iter().enumerate() {
            tris.extend((0..o.triangles.len() as u32).map(|ti| (oi as u32, ti)));
            vertex_offset.push(offset);
            offset += o.positions.len() as u64;
        }
        // The planes each triangle cuts ([`Rays::plane`]), family by family,
        // counted first and then listed: plane `f·n + i` cuts the triangle
        // when `lo ≤ y_i ≤ hi`, its vertices' heights projected along the
        // family's rays onto the emitter plane.
        let (families, n) = (r.plane_families(), r.sub_hololines());
        let mut start = vec![0usize; families * n + 1];
        for f in 0..families {
            for (a, b) in tris.par_iter().map(|&t| plane_range(s.scene, r, f, t)).collect::<Vec<_>>() {
                for i in a..b {
                    start[f * n + i + 1] += 1;
                }
            }
        }
        for p in 0..families * n {
            start[p + 1] += start[p];
        }
        let mut fill = start.clone();
        let mut bucket = vec![0u32; start[families * n]];
        for f in 0..families {
            let ranges: Vec<(usize, usize)> = tris.par_iter().map(|&t| plane_range(s.scene, r, f, t)).collect();
            for (ti, (a, b)) in ranges.into_iter().enumerate() {
                for i in a..b {
                    bucket[fill[f * n + i]] = ti as u32;
                    fill[f * n + i] += 1;
                }
            }
        }
        let lights = LightGroups::new(s.scene, s.lighting);
        let materials = s
            .scene
            .objects
            .iter()
            .zip(&lights.of_object)
            .map(|(o, &group)| FastMaterial::new(&o.material, lights.groups[group as usize].model()))
            .collect();
        let lights_avx2 = lights.groups[0].avx2();
        EpiRenderer { s, tris, vertex_offset, start, bucket, materials, lights, lights_avx2 }
    }

    /// Triangle `i` of [`EpiRenderer::tris`].
    fn triangle(&self, i: u32) -> Tri {
        let (object, triangle) = self.tris[i as usize];
        let o = &self.s.scene.objects[object as usize];
        let t = o.triangles[triangle as usize];
        let p = t.map(|v| o.positions[v as usize]);
        let offset = self.vertex_offset[object as usize];
        Tri {
            object,
            triangle,
            ids: t.map(|v| offset + v as u64),
            normal: cross(sub(p[1], p[0]), sub(p[2], p[0])),
            p,
            double_sided: o.material.double_sided,
        }
    }

    /// The segments of hololine `j`, and how many triangles the widened
    /// back-face cull dropped.
    fn segments(&self, j: usize) -> (Vec<Segment>, u64) {
        let r = self.s.rays;
        let (y, k) = r.plane(j);
        let z_max = r.viewer_distance_m;
        let (s_first, s_last) = (r.sub_view_slope[0], r.sub_view_slope[r.sub_view_slope.len() - 1]);
        let mut out = Vec::new();
        let mut culled = 0;
        for &ti in &self.bucket[self.start[j]..self.start[j + 1]] {
            let t = self.triangle(ti);
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
            let face = normalize(t.normal);
            let attrs_a = Attrs::at(o, t.triangle as usize, wa, face);
            let attrs_b = Attrs::at(o, t.triangle as usize, wb, face);
            let attrs_delta = attrs_a.delta(&attrs_b);
            out.push(Segment {
                object: t.object,
                group: self.lights.of_object[t.object as usize],
                has_normals: !o.normals.is_empty(),
                has_tangents: !o.tangents.is_empty(),
                a: [pa[0], pa[2]],
                b: [pb[0], pb[2]],
                normals_nonzero: fastshade::normals_nonzero(&attrs_a, &attrs_delta),
                attrs_delta,
                attrs_a,
                face: narrow(face),
                nx,
                c,
                double_sided: t.double_sided,
            });
        }
        (out, culled)
    }
}

const NONE: u32 = u32::MAX;

/// The segments as the rasterising loop reads them, one list per quantity:
/// the ends `(X, Z − z_e)` (`a0, a1`, `b0, b1`), the depth `Z` at `a` and its
/// change to `b`, the facing `nx·s + c` (see [`Segment`]), and double-sided
/// (all bits set) or not (zero).
struct SpanColumns {
    a0: Vec<f64>,
    a1: Vec<f64>,
    b0: Vec<f64>,
    b1: Vec<f64>,
    z_a: Vec<f64>,
    dz: Vec<f64>,
    nx: Vec<f64>,
    c: Vec<f64>,
    double_sided: Vec<f64>,
}

/// One view column: its ray slope and the sub-emitters `x_first + i/inv_dx`,
/// `i < n_sub`.
struct ViewColumn {
    s: f64,
    x_first: f64,
    inv_dx: f64,
    n_sub: u32,
}

impl SpanColumns {
    fn new(segments: &[Segment], z_e: f64) -> Self {
        let column = |f: &dyn Fn(&Segment) -> f64| segments.iter().map(f).collect::<Vec<f64>>();
        SpanColumns {
            a0: column(&|seg| seg.a[0]),
            a1: column(&|seg| seg.a[1] - z_e),
            b0: column(&|seg| seg.b[0]),
            b1: column(&|seg| seg.b[1] - z_e),
            z_a: column(&|seg| seg.a[1]),
            dz: column(&|seg| seg.b[1] - seg.a[1]),
            nx: column(&|seg| seg.nx),
            c: column(&|seg| seg.c),
            double_sided: column(&|seg| f64::from_bits(if seg.double_sided { u64::MAX } else { 0 })),
        }
    }

    /// Each segment's facing in column `at` (into `facing`, 1 or −1), and
    /// the segments that cover a sub-emitter there, in order: `(segment,
    /// first sub-emitter, end)` into `out`, how many returned. A segment
    /// covers the sub-emitters `lo ≤ x < hi` between its ends' crossings
    /// `u = X − (Z − z_e)·s`, when it faces the ray or is double-sided.
    fn cover(&self, at: &ViewColumn, facing: &mut [f32], out: &mut [(u32, u32, u32)], avx2: bool) -> usize {
        #[cfg(target_arch = "x86_64")]
        {
            if avx2 {
                // SAFETY: the CPU has AVX2 (the caller's check, FastLights::chosen).
                let (done, count) = unsafe { self.cover_avx2(at, facing, out) };
                return count + self.cover_scalar(done, count, at, facing, out);
            }
        }
        let _ = avx2;
        self.cover_scalar(0, 0, at, facing, out)
    }

    /// [`SpanColumns::cover`] of segments `first..`, appended to `out` after
    /// `count` entries; returns how many it added.
    #[allow(clippy::needless_range_loop)] // one index into nine columns reads best
    fn cover_scalar(
        &self,
        first: usize,
        count: usize,
        at: &ViewColumn,
        facing: &mut [f32],
        out: &mut [(u32, u32, u32)],
    ) -> usize {
        let mut n = count;
        for i in first..self.a0.len() {
            let front = self.nx[i] * at.s + self.c[i] > 0.0;
            facing[i] = if front { 1.0 } else { -1.0 };
            let ua = self.a0[i] - self.a1[i] * at.s;
            let ub = self.b0[i] - self.b1[i] * at.s;
            let du = ub - ua;
            let i0 = ceil_clamped((ua.min(ub) - at.x_first) * at.inv_dx, at.n_sub);
            let i1 = ceil_clamped((ua.max(ub) - at.x_first) * at.inv_dx, at.n_sub);
            let double_sided = self.double_sided[i].to_bits() != 0;
            let drawn = (double_sided | front) & (du != 0.0) & du.is_finite() & (i0 < i1);
            out[n] = (i as u32, i0, i1);
            n += usize::from(drawn);
        }
        n - count
    }

    /// [`SpanColumns::cover`] of the segments in whole fours, with AVX2: the
    /// same operations in the same order (no fused multiply-adds), so the
    /// same answers. Returns the segments done and the entries written.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn cover_avx2(&self, at: &ViewColumn, facing: &mut [f32], out: &mut [(u32, u32, u32)]) -> (usize, usize) {
        use std::arch::x86_64::*;
        let n4 = self.a0.len() / 4 * 4;
        let (s, x_first, inv_dx) = (_mm256_set1_pd(at.s), _mm256_set1_pd(at.x_first), _mm256_set1_pd(at.inv_dx));
        let (zero, one, n_sub) = (_mm256_setzero_pd(), _mm256_set1_pd(1.0), _mm256_set1_pd(at.n_sub as f64));
        let (plus, minus) = (_mm256_set1_pd(1.0), _mm256_set1_pd(-1.0));
        let (infinity, magnitude) = (_mm256_set1_pd(f64::INFINITY), _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX)));
        // ⌈x⌉ clamped to 0..=n, NaN to 0 (`max` gives its second operand for NaN), as ceil_clamped.
        let ceil = |x: __m256d| {
            let x = _mm256_min_pd(_mm256_max_pd(x, zero), n_sub);
            let whole = _mm256_cvtepi32_pd(_mm256_cvttpd_epi32(x));
            _mm256_add_pd(whole, _mm256_and_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(whole, x), one))
        };
        let mut count = 0;
        let (mut first, mut end) = ([0.0f64; 4], [0.0f64; 4]);
        for i in (0..n4).step_by(4) {
            // SAFETY: i + 4 ≤ n4 ≤ every column's length.
            let load = |v: &[f64]| unsafe { _mm256_loadu_pd(v.as_ptr().add(i)) };
            let front =
                _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_add_pd(_mm256_mul_pd(load(&self.nx), s), load(&self.c)), zero);
            // SAFETY: as the loads; `facing` has a place per segment.
            unsafe {
                _mm_storeu_ps(facing[i..i + 4].as_mut_ptr(), _mm256_cvtpd_ps(_mm256_blendv_pd(minus, plus, front)))
            };
            let ua = _mm256_sub_pd(load(&self.a0), _mm256_mul_pd(load(&self.a1), s));
            let ub = _mm256_sub_pd(load(&self.b0), _mm256_mul_pd(load(&self.b1), s));
            let du = _mm256_sub_pd(ub, ua);
            let i0 = ceil(_mm256_mul_pd(_mm256_sub_pd(_mm256_min_pd(ua, ub), x_first), inv_dx));
            let i1 = ceil(_mm256_mul_pd(_mm256_sub_pd(_mm256_max_pd(ua, ub), x_first), inv_dx));
            let shown = _mm256_or_pd(load(&self.double_sided), front);
            let nonzero = _mm256_cmp_pd::<_CMP_NEQ_OQ>(du, zero);
            let finite = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_and_pd(du, magnitude), infinity);
            let covers = _mm256_cmp_pd::<_CMP_LT_OQ>(i0, i1);
            let drawn = _mm256_movemask_pd(_mm256_and_pd(_mm256_and_pd(shown, nonzero), _mm256_and_pd(finite, covers)));
            if drawn != 0 {
                // SAFETY: four f64 each.
                unsafe {
                    _mm256_storeu_pd(first.as_mut_ptr(), i0);
                    _mm256_storeu_pd(end.as_mut_ptr(), i1);
                }
                for lane in 0..4 {
                    out[count] = ((i + lane) as u32, first[lane] as u32, end[lane] as u32);
                    count += (drawn >> lane & 1) as usize;
                }
            }
        }
        (n4, count)
    }
}

/// One segment's span in one sub-view: `t = t_first + i·dt` at sub-emitter
/// `i`, depth `z = z_a + t·dz`.
#[derive(Clone, Copy)]
struct Span {
    t_first: f64,
    dt: f64,
    z_a: f64,
    dz: f64,
    owner: u32,
}

impl Span {
    /// Depth-test sub-emitters `i0..i0 + depth.len()`: the largest `z` wins.
    #[inline]
    fn draw(&self, i0: usize, depth: &mut [f64], owner: &mut [u32], param: &mut [f64], avx2: bool) {
        #[cfg(target_arch = "x86_64")]
        {
            // (A micropolygon's span is a sub-emitter or two: not worth a call.)
            if avx2 && depth.len() > 4 {
                // SAFETY: the CPU has AVX2 and FMA (checked in FastLights::chosen).
                unsafe { self.draw_avx2(i0, depth, owner, param) };
                return;
            }
        }
        self.draw_kernel(i0, depth, owner, param);
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn draw_avx2(&self, i0: usize, depth: &mut [f64], owner: &mut [u32], param: &mut [f64]) {
        self.draw_kernel(i0, depth, owner, param);
    }

    /// Branch-free, so it vectorises.
    #[inline(always)]
    fn draw_kernel(&self, i0: usize, depth: &mut [f64], owner: &mut [u32], param: &mut [f64]) {
        let n = depth.len();
        let (owner, param) = (&mut owner[..n], &mut param[..n]);
        for k in 0..n {
            let t = self.t_first + (i0 + k) as f64 * self.dt;
            let z = self.z_a + t * self.dz;
            let nearer = z > depth[k];
            depth[k] = if nearer { z } else { depth[k] };
            owner[k] = if nearer { self.owner } else { owner[k] };
            param[k] = if nearer { t } else { param[k] };
        }
    }
}

/// A see-through segment in front of a column's opaque surfaces at one
/// sub-emitter: its depth and parameter there.
#[derive(Clone, Copy, Default)]
struct Fragment {
    pixel: u32,
    owner: u32,
    z: f64,
    t: f64,
}

/// One column's see-through segments, reused from column to column.
#[derive(Default)]
struct SeeThrough {
    /// Their spans, drawn after the opaque ones: (span, first sub-emitter, end).
    later: Vec<(Span, usize, usize)>,
    /// The fragments as found, then grouped by sub-emitter, nearest first
    /// in each group (a counting sort: `start` holds where each
    /// sub-emitter's group begins, `next` is its cursor).
    found: Vec<Fragment>,
    grouped: Vec<Fragment>,
    start: Vec<u32>,
    next: Vec<u32>,
    /// One group's (fragment, weight) pairs.
    weights: Vec<(Fragment, f32)>,
}

impl SeeThrough {
    /// The fragments of the spans in `later` in front of the opaque depth
    /// `depth` (sub-emitters `lo..hi`), grouped by sub-emitter and sorted
    /// nearest first (ties by segment).
    fn fragments(&mut self, depth: &[f64], lo: usize, hi: usize) {
        self.found.clear();
        for (span, i0, i1) in self.later.drain(..) {
            for (i, &d) in depth.iter().enumerate().take(i1).skip(i0) {
                // As `Span::draw` steps it.
                let t = span.t_first + i as f64 * span.dt;
                let z = span.z_a + t * span.dz;
                if z > d {
                    self.found.push(Fragment { pixel: i as u32, owner: span.owner, z, t });
                }
            }
        }
        self.start.clear();
        self.start.resize(hi - lo + 1, 0);
        for f in &self.found {
            self.start[f.pixel as usize - lo + 1] += 1;
        }
        for i in 1..self.start.len() {
            self.start[i] += self.start[i - 1];
        }
        self.next.clear();
        self.next.extend_from_slice(&self.start);
        self.grouped.clear();
        self.grouped.resize(self.found.len(), Fragment::default());
        for f in &self.found {
            let at = &mut self.next[f.pixel as usize - lo];
            self.grouped[*at as usize] = *f;
            *at += 1;
        }
        for w in self.start.windows(2) {
            let group = &mut self.grouped[w[0] as usize..w[1] as usize];
            if group.len() > 1 {
                group.sort_unstable_by(|a, b| b.z.total_cmp(&a.z).then(a.owner.cmp(&b.owner)));
            }
        }
    }

    /// Composite each sub-emitter's fragments over the opaque radiance
    /// `layer` holds there: `L = Σ L_i α_i Π_{k<i} (1 − α_k) + L_opaque Π_k (1 − α_k)`,
    /// a fragment of coverage 1 ending it. The opaque radiance is scaled
    /// here; each fragment that covers anything is handed to `shade` with
    /// its weight `α_i Π_{k<i} (1 − α_k)`, to add its radiance × that to
    /// `layer`. Returns the fragments handed on.
    fn composite(
        &mut self,
        scene: &super::Scene,
        segments: &[Segment],
        materials: &[FastMaterial],
        layer: [&mut [f32]; 3],
        shade: &mut impl FnMut(&Fragment, f32, [&mut [f32]; 3]),
    ) -> u64 {
        let [r, g, b] = layer;
        let mut shaded = 0;
        for group in self.grouped.chunk_by(|a, b| a.pixel == b.pixel) {
            let p = group[0].pixel as usize;
            self.weights.clear();
            let mut through = 1.0f32;
            for f in group {
                let seg = &segments[f.owner as usize];
                let material = &materials[seg.object as usize];
                let t = f.t.clamp(0.0, 1.0) as f32;
                let alpha = fastshade::coverage(scene, material, &seg.attrs_a, &seg.attrs_delta, t);
                if alpha <= 0.0 {
                    continue;
                }
                self.weights.push((*f, through * alpha));
                through *= 1.0 - alpha;
                if through <= 0.0 {
                    break;
                }
            }
            for layer in [&mut *r, &mut *g, &mut *b] {
                layer[p] *= through;
            }
            for &(f, weight) in &self.weights {
                shade(&f, weight, [&mut *r, &mut *g, &mut *b]);
            }
            shaded += self.weights.len() as u64;
        }
        shaded
    }
}

/// `⌈x⌉` clamped to `0..=n` (NaN gives 0), without libm's `ceil` and in
/// 32 bits, whose conversions from f64 are one instruction (a sub-emitter
/// count is far below 2³¹).
#[inline]
/// The sub-hololines `a..b` of plane family `f` ([`Rays::plane`]) whose
/// planes cut triangle `(object, triangle)`. A vertex `(X, Y, Z)` lies in
/// the plane of sub-hololine `i` when `Y − y_i = k (Z − z_e)`: for full
/// parallax `k` is the family's, and the vertex projects along it onto the
/// emitter plane at `y_p = Y − k (Z − z_e)`; for horizontal parallax every
/// plane passes through the viewer line, and the vertex projects from it at
/// `y_p = (Y − a·y_v)/(1 − a)`, `a = (Z − z_e)/(D − z_e)`. Plane `i` cuts
/// the triangle when `y_i` lies between its vertices' `y_p`.
fn plane_range(scene: &Scene, r: &Rays, f: usize, (oi, ti): (u32, u32)) -> (usize, usize) {
    let o = &scene.objects[oi as usize];
    let span = r.viewer_distance_m - r.emitter_z_m;
    let n = r.sub_hololines();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &vi in &o.triangles[ti as usize] {
        let p = o.positions[vi as usize];
        let yp = match r.vertical_view_slope.get(f) {
            Some(&k) => p[1] - k * (p[2] - r.emitter_z_m),
            None => {
                let a = (p[2] - r.emitter_z_m) / span;
                if a >= 1.0 - 1e-12 {
                    return (0, n); // reaches the viewer line: every hololine, clipped later
                }
                (p[1] - a * r.viewer_height_m) / (1.0 - a)
            }
        };
        lo = lo.min(yp);
        hi = hi.max(yp);
    }
    let top = r.hololine_y_m.first().copied().unwrap_or(0.0);
    let pitch = if n > 1 { r.hololine_y_m[0] - r.hololine_y_m[1] } else { 1.0 };
    // Sub-hololine i (y_i = top − i·pitch) is cut when lo ≤ y_i ≤ hi.
    let first = ((top - hi) / pitch).ceil().max(0.0);
    let last = ((top - lo) / pitch).floor();
    if !(first.is_finite() && last.is_finite()) || last < first || first >= n as f64 || last < 0.0 {
        return (0, 0);
    }
    (first as usize, (last as usize + 1).min(n))
}

fn ceil_clamped(x: f64, n: u32) -> u32 {
    let x = x.clamp(0.0, n as f64); // NaN stays NaN and converts to 0
    let i = x as i32;
    (i + i32::from((i as f64) < x)) as u32
}

impl HololineRenderer for EpiRenderer<'_> {
    fn render_hololine(&self, j: usize, rows: &mut [&mut [f32]]) -> RenderStats {
        let g = self.s.geometry;
        let (e_count, v_count, c_count) = (g.emitters, g.views.count, self.s.weights.len());
        let (segments, culled) = self.segments(j);
        let mut stats = RenderStats { segments: segments.len() as u64, back_face_culled: culled, shaded: 0 };
        if segments.is_empty() {
            for row in rows.iter_mut() {
                row.fill(0.0);
            }
            return stats;
        }
        // The finished columns, view by view, transposed into `rows` at the
        // end (writing a row column by column strides through it V apart).
        BY_VIEW.with_borrow_mut(|by_view| {
            by_view.clear();
            by_view.resize(v_count * c_count * e_count, 0.0);
            self.draw(j, &segments, by_view, &mut stats);
            for (ch, row) in rows.iter_mut().enumerate() {
                transpose(&by_view[ch * e_count..], c_count * e_count, row, e_count, v_count);
            }
        });
        stats
    }
}

/// `out[e·V + v] = by_view[v·stride + e]` for `e < E`, `v < V`, in blocks
/// that stay in cache on both sides.
fn transpose(by_view: &[f32], stride: usize, out: &mut [f32], e_count: usize, v_count: usize) {
    const B: usize = 16;
    for e0 in (0..e_count).step_by(B) {
        let e1 = (e0 + B).min(e_count);
        for v0 in (0..v_count).step_by(B) {
            let v1 = (v0 + B).min(v_count);
            for e in e0..e1 {
                let out = &mut out[e * v_count + v0..e * v_count + v1];
                for (v, o) in (v0..v1).zip(out) {
                    *o = by_view[v * stride + e];
                }
            }
        }
    }
}

thread_local! {
    /// A hololine's finished columns (V, C × E), reused between hololines.
    static BY_VIEW: std::cell::RefCell<Vec<f32>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl EpiRenderer<'_> {
    /// Segment `seg` as a run of the shader, seen from the `front` or back.
    fn run<'s>(&'s self, seg: &'s Segment, front: bool) -> Run<'s> {
        Run {
            material: &self.materials[seg.object as usize],
            a: &seg.attrs_a,
            delta: &seg.attrs_delta,
            face: if front { seg.face } else { seg.face.map(|x| -x) },
            flip: !front,
            has_normals: seg.has_normals,
            has_tangents: seg.has_tangents,
            normals_nonzero: seg.normals_nonzero,
        }
    }

    /// Rasterise and shade hololine `j`'s `segments` into `out`.
    fn draw(&self, j: usize, segments: &[Segment], by_view: &mut [f32], stats: &mut RenderStats) {
        let r = self.s.rays;
        let g = self.s.geometry;
        let (e_count, v_count) = (g.emitters, g.views.count);
        let (se, sv) = (r.supersample.emitter, r.supersample.view);
        let k = r.plane(j).1;
        let z_e = r.emitter_z_m;
        let n_sub = r.sub_emitter_x_m.len();
        let x_first = r.sub_emitter_x_m[0];
        let dx = if n_sub > 1 { r.sub_emitter_x_m[1] - x_first } else { 1.0 };
        let norm = 1.0 / (se * sv) as f64;
        let inv_dx = 1.0 / dx;
        let mut depth = vec![f64::NEG_INFINITY; n_sub];
        let mut owner = vec![NONE; n_sub];
        let mut param = vec![0.0f64; n_sub];
        // Radiance summed over a view's sub-views, per sub-emitter.
        let mut acc = [vec![0.0f32; n_sub], vec![0.0f32; n_sub], vec![0.0f32; n_sub]];
        // The light groups the hololine shows, each with its own column
        // set-up and batch (`slot`: a segment's group's place among them).
        let mut shown: Vec<usize> = segments.iter().map(|seg| seg.group as usize).collect();
        shown.sort_unstable();
        shown.dedup();
        let slot: Vec<u32> =
            segments.iter().map(|seg| shown.binary_search(&(seg.group as usize)).unwrap_or(0) as u32).collect();
        let lights: Vec<&FastLights> = shown.iter().map(|&g| &self.lights.groups[g]).collect();
        let mut columns: Vec<Column> = shown.iter().map(|_| Column::default()).collect();
        let mut batches: Vec<Batch> = shown.iter().map(|_| Batch::default()).collect();
        let mut table = SegmentTable::default();
        for (seg, &k) in segments.iter().zip(&slot) {
            table.push(self.s.scene, lights[k as usize], &self.run(seg, true));
        }
        let all_simple = (0..segments.len()).all(|si| table.simple(si));
        let c_count = self.s.weights.len();
        let mut reduced = [vec![0.0f32; e_count], vec![0.0f32; e_count], vec![0.0f32; e_count]];
        // Channel weights with the supersampling average folded in.
        let weights: Vec<[f32; 3]> = self.s.weights.iter().map(|w| w.map(|x| (x * norm) as f32)).collect();
        // What the rasterising loop reads of each segment, in columns: it
        // runs through every segment once a view, and a segment is mostly
        // shading attributes it does not need there.
        let spans = SpanColumns::new(segments, z_e);
        // (segment, first sub-emitter, end) of the segments a view's column draws.
        let mut covering = vec![(0u32, 0u32, 0u32); segments.len()];
        // See-through segments: their spans are kept for after the opaque
        // ones, their fragments composited over a sub-view's opaque radiance
        // (`layer`) before it joins `acc`.
        let see_through: Vec<bool> =
            segments.iter().map(|seg| self.materials[seg.object as usize].see_through()).collect();
        let any_see_through = see_through.contains(&true);
        let mut layer = if any_see_through { acc.clone() } else { Default::default() };
        let mut see = SeeThrough::default();
        for v in 0..v_count {
            for a in &mut acc {
                a.fill(0.0);
            }
            for b in 0..sv {
                let s = r.sub_view_slope[v * sv + b];
                // Sub-emitters drawn in this column (`depth` and `owner` are
                // reset there afterwards, not everywhere).
                let (mut drawn_lo, mut drawn_hi) = (n_sub, 0);
                // First every segment's facing and sub-emitters, without a
                // branch (whether a micropolygon covers a sub-emitter in a view
                // is a coin toss a branch predictor loses), the segments that
                // do listed in order; then their spans.
                let at = ViewColumn { s, x_first, inv_dx, n_sub: n_sub as u32 };
                let count = spans.cover(&at, table.facing_mut(), &mut covering, self.lights_avx2);
                for &(si, i0, i1) in &covering[..count] {
                    let (i, i0, i1) = (si as usize, i0 as usize, i1 as usize);
                    (drawn_lo, drawn_hi) = (drawn_lo.min(i0), drawn_hi.max(i1));
                    let ua = spans.a0[i] - spans.a1[i] * s;
                    let du = (spans.b0[i] - spans.b1[i] * s) - ua;
                    // t = (x_i − u_A)/du, stepped without a division per pixel.
                    let inv_du = 1.0 / du;
                    let t_first = (x_first - ua) * inv_du;
                    let dt = dx * inv_du;
                    let span = Span { t_first, dt, z_a: spans.z_a[i], dz: spans.dz[i], owner: si };
                    if any_see_through && see_through[i] {
                        see.later.push((span, i0, i1));
                        continue;
                    }
                    span.draw(i0, &mut depth[i0..i1], &mut owner[i0..i1], &mut param[i0..i1], self.lights_avx2);
                }
                if any_see_through {
                    see.fragments(&depth, drawn_lo, drawn_hi.max(drawn_lo));
                }
                let view = normalize([s as f32, k as f32, 1.0]);
                for (column, l) in columns.iter_mut().zip(&lights) {
                    column.set(l, view);
                }
                // Pixels of simple segments go to their group's batch one by one ...
                let (lo, hi) = (drawn_lo, drawn_hi.max(drawn_lo));
                if all_simple && batches.len() == 1 {
                    batches[0].push_all(lo, &owner[lo..hi], &param[lo..hi], NONE);
                } else {
                    for (i, (&o, &t)) in owner.iter().zip(param.iter()).enumerate().take(hi).skip(lo) {
                        if o != NONE && table.simple(o as usize) {
                            batches[slot[o as usize] as usize].push(i, o, t);
                        }
                    }
                }
                let [ar, ag, ab] = if any_see_through { &mut layer } else { &mut acc };
                for (batch, l) in batches.iter_mut().zip(&lights) {
                    stats.shaded += batch.len() as u64;
                    batch.gather(self.s.scene, &table, l, [&mut ar[..], &mut ag[..], &mut ab[..]]);
                }
                // ... the others are shaded run by run, neighbours showing one segment.
                let mut i = lo;
                while !all_simple && i < hi {
                    let o = owner[i];
                    let mut end = i + 1;
                    while end < hi && owner[end] == o {
                        end += 1;
                    }
                    if o != NONE && !table.simple(o as usize) {
                        let seg = &segments[o as usize];
                        let run = self.run(seg, seg.nx * s + seg.c > 0.0);
                        let acc = [&mut ar[i..end], &mut ag[i..end], &mut ab[i..end]];
                        let k = slot[o as usize] as usize;
                        fastshade::shade_run(self.s.scene, lights[k], &columns[k], &run, &param[i..end], acc);
                        stats.shaded += (end - i) as u64;
                    }
                    i = end;
                }
                for ((batch, l), column) in batches.iter_mut().zip(&lights).zip(&columns) {
                    batch.shade(l, column, [&mut ar[..], &mut ag[..], &mut ab[..]]);
                }
                if any_see_through {
                    // The fragments over the opaque radiance, those of simple
                    // segments through the batches (weighted), the others run by run.
                    let [ar, ag, ab] = &mut layer;
                    let [ar, ag, ab] = [&mut ar[..], &mut ag[..], &mut ab[..]];
                    let mut weighted = |f: &Fragment, weight: f32, layer: [&mut [f32]; 3]| {
                        let (o, k) = (f.owner as usize, slot[f.owner as usize] as usize);
                        if table.simple(o) {
                            batches[k].push_weighted(f.pixel as usize, f.owner, f.t, weight);
                            return;
                        }
                        let seg = &segments[o];
                        let run = self.run(seg, seg.nx * s + seg.c > 0.0);
                        let mut l = [[0.0f32]; 3];
                        let [r, g, b] = &mut l;
                        fastshade::shade_run(self.s.scene, lights[k], &columns[k], &run, &[f.t], [r, g, b]);
                        let p = f.pixel as usize;
                        for (layer, l) in layer.into_iter().zip(l) {
                            layer[p] += weight * l[0];
                        }
                    };
                    stats.shaded += see.composite(self.s.scene, segments, &self.materials, [ar, ag, ab], &mut weighted);
                    for ((batch, l), column) in batches.iter_mut().zip(&lights).zip(&columns) {
                        batch.gather(self.s.scene, &table, l, [&mut ar[..], &mut ag[..], &mut ab[..]]);
                        batch.shade(l, column, [&mut ar[..], &mut ag[..], &mut ab[..]]);
                    }
                    for (acc, layer) in acc.iter_mut().zip(&mut layer) {
                        for (a, l) in acc[lo..hi].iter_mut().zip(&mut layer[lo..hi]) {
                            *a += *l;
                            *l = 0.0;
                        }
                    }
                }
                depth[lo..hi].fill(f64::NEG_INFINITY);
                owner[lo..hi].fill(NONE);
            }
            let column_out = &mut by_view[v * c_count * e_count..(v + 1) * c_count * e_count];
            // Sum each emitter's sub-emitters (f32: at most 64 × 64 terms of
            // one sign, relative error < 4096 · 2⁻²⁴ < 3e-4, typically far less).
            let sums: [&[f32]; 3] = if se == 1 {
                [&acc[0], &acc[1], &acc[2]]
            } else {
                for (r, a) in reduced.iter_mut().zip(&acc) {
                    // Sub-emitter by sub-emitter, so the sums do not wait on each other.
                    r.fill(0.0);
                    for k in 0..se {
                        for (e, r) in r.iter_mut().enumerate() {
                            *r += a[e * se + k];
                        }
                    }
                }
                [&reduced[0], &reduced[1], &reduced[2]]
            };
            for (w, column_out) in weights.iter().zip(column_out.chunks_exact_mut(e_count)) {
                for (e, o) in column_out.iter_mut().enumerate() {
                    *o = w[0] * sums[0][e] + w[1] * sums[1][e] + w[2] * sums[2][e];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{channel_weights, rgb_channels, Geometry, Views};
    use crate::mesh::rays::{Rays, Supersample};
    use crate::mesh::shade::{Lighting, SpecularModel};
    use crate::mesh::{
        AlphaMode, Light, Material, MetallicRoughness, Object, Scene, Texture, TextureRef, UvTransform, Wrap,
    };
    use rand::{Rng, SeedableRng};

    /// The AVX2 + FMA loops and the portable ones give the same bits (the
    /// compiler does not contract into FMA), on random textured,
    /// smooth-shaded triangles with two directional lights, some
    /// metallic-rough, blended or masked.
    #[test]
    fn simd_and_portable_loops_agree_bit_for_bit() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(21);
        let texels = (0..19 * 11).map(|_| std::array::from_fn(|_| rng.gen_range(0.0..1.0))).collect();
        let texture = Texture {
            name: "random".into(),
            width: 19,
            height: 11,
            texels,
            wrap: [Wrap::Repeat, Wrap::MirroredRepeat],
        };
        let mut objects = Vec::new();
        let textured = || Some(TextureRef { texture: 0, uv_set: 0, transform: UvTransform::default() });
        for k in 0..4 {
            let mut o = Object {
                name: format!("random {k}"),
                material: Material {
                    base_colour: [0.9, 0.7, 0.5, 1.0],
                    specular: [0.4; 3],
                    shininess: 40.0,
                    base_colour_texture: (k != 1).then(textured).flatten(),
                    double_sided: k == 1,
                    // Metallic-rough and blended; masked by the texture's alpha.
                    metallic_roughness: (k == 2).then(|| MetallicRoughness {
                        metallic: 0.8,
                        roughness: 0.6,
                        texture: textured(),
                    }),
                    alpha_mode: [
                        AlphaMode::Opaque,
                        AlphaMode::Opaque,
                        AlphaMode::Blend,
                        AlphaMode::Mask { cutoff: 0.5 },
                    ][k],
                    ..Material::default()
                },
                ..Object::default()
            };
            for t in 0..40u32 {
                let c = [rng.gen_range(-0.02..0.02), rng.gen_range(-0.01..0.01), rng.gen_range(-0.02..0.02)];
                for _ in 0..3 {
                    o.positions.push(std::array::from_fn(|q| c[q] + rng.gen_range(-0.008..0.008)));
                    let n: [f32; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
                    o.normals.push([n[0], n[1], n[2] + 2.0]);
                    o.colours.push([rng.gen_range(0.2..1.0), 1.0, rng.gen_range(0.2..1.0), 1.0]);
                }
                o.triangles.push([3 * t, 3 * t + 1, 3 * t + 2]);
            }
            o.uv_sets =
                vec![(0..o.positions.len()).map(|_| [rng.gen_range(-0.5..1.5), rng.gen_range(-0.5..1.5)]).collect()];
            objects.push(o);
        }
        let scene = Scene { source: "random".into(), objects, textures: vec![texture], ..Scene::default() };
        let g = Geometry::centred(15, 40, Views::tan_spaced(24, -0.3, 0.3), 1e-3, 1e-3, 0.0, 0.5, rgb_channels());
        for model in [SpecularModel::Blinn, SpecularModel::Phong] {
            let lighting = Lighting {
                lights: vec![
                    Light::Directional { direction: [0.3, -0.5, -1.0], irradiance: [2.0; 3], name: "key".into() },
                    Light::Directional {
                        direction: [-0.5, 0.1, -0.6],
                        irradiance: [0.4, 0.6, 0.8],
                        name: "fill".into(),
                    },
                    Light::Ambient { radiance: [0.05; 3] },
                ],
                model,
            };
            let rays = Rays::new(&g, Supersample::new(2, 2)).unwrap();
            let weights = channel_weights(&["R", "G", "B"]);
            let shading =
                || Shading { scene: &scene, lighting: &lighting, weights: &weights, rays: &rays, geometry: &g };
            let simd = EpiRenderer::new(shading());
            let mut portable = EpiRenderer::new(shading());
            portable.lights.groups.iter_mut().for_each(|l| l.portable());
            portable.lights_avx2 = false;
            let line = g.emitters * g.views.count;
            let (mut a, mut b) = (vec![0.0f32; 3 * line], vec![0.0f32; 3 * line]);
            let mut shaded = 0;
            for j in 0..g.hololines {
                let mut rows_a: Vec<&mut [f32]> = a.chunks_exact_mut(line).collect();
                shaded += simd.render_hololine(j, &mut rows_a).shaded;
                let mut rows_b: Vec<&mut [f32]> = b.chunks_exact_mut(line).collect();
                portable.render_hololine(j, &mut rows_b);
                assert_eq!(
                    a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    b.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    "hololine {j}"
                );
            }
            assert!(shaded > 1000, "the scene is seen ({shaded} samples)");
        }
    }

    /// The four-at-a-time facing and coverage pass gives the scalar pass's
    /// answers to the bit: random segments (one- and double-sided, some of
    /// zero width, some huge or not finite), every count of segments modulo
    /// four, many view slopes.
    #[test]
    fn cover_avx2_equals_the_scalar_pass() {
        if !crate::simd::Simd::Detect.avx2() {
            return;
        }
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for n in [1usize, 3, 4, 5, 8, 37, 650] {
            let value = |rng: &mut rand_chacha::ChaCha8Rng| match rng.gen_range(0..40) {
                0 => f64::NAN,
                1 => f64::INFINITY,
                2 => 1e300,
                _ => rng.gen_range(-0.03..0.03),
            };
            let mut columns = SpanColumns {
                a0: vec![],
                a1: vec![],
                b0: vec![],
                b1: vec![],
                z_a: vec![],
                dz: vec![],
                nx: vec![],
                c: vec![],
                double_sided: vec![],
            };
            for _ in 0..n {
                let (a0, a1) = (value(&mut rng), rng.gen_range(-0.05..0.05));
                let zero_width = rng.gen_range(0..8) == 0;
                columns.a0.push(a0);
                columns.a1.push(a1);
                columns.b0.push(if zero_width { a0 } else { a0 + rng.gen_range(-0.003..0.003) });
                columns.b1.push(if zero_width { a1 } else { value(&mut rng) });
                columns.z_a.push(0.0);
                columns.dz.push(0.0);
                columns.nx.push(rng.gen_range(-1.0..1.0));
                columns.c.push(rng.gen_range(-1.0..1.0));
                columns.double_sided.push(f64::from_bits(if rng.gen_range(0..4) == 0 { u64::MAX } else { 0 }));
            }
            for _ in 0..50 {
                let at = ViewColumn {
                    s: rng.gen_range(-0.8..0.8),
                    x_first: -0.02,
                    inv_dx: 1.0 / rng.gen_range(1e-4..2e-3),
                    n_sub: rng.gen_range(1..700),
                };
                let (mut facing_a, mut facing_b) = (vec![0.0f32; n], vec![0.0f32; n]);
                let (mut out_a, mut out_b) = (vec![(0, 0, 0); n], vec![(0, 0, 0); n]);
                let count_a = columns.cover(&at, &mut facing_a, &mut out_a, true);
                let count_b = columns.cover(&at, &mut facing_b, &mut out_b, false);
                assert_eq!(facing_a, facing_b);
                assert_eq!(out_a[..count_a], out_b[..count_b]);
            }
        }
    }
}
