//! The camera surface's interpolation: the cameras' points on the surface
//! (one, a line, or a Delaunay triangulation by `spade`) and the weights of a
//! ray's point among them by the chosen [`Blend`]; the fast walk that keeps
//! each view's last triangle, and the brute-force reference the tests
//! compare it with.

use spade::handles::FixedVertexHandle;
use spade::{DelaunayTriangulation, Point2, PositionInTriangulation, Triangulation};

use super::Blend;
use crate::cameras::Rig;
use crate::error::{Error, Result};

/// A worker's reusable state for [`Interpolator::weights`].
#[derive(Default)]
pub(super) struct Scratch {
    pub(super) weights: Vec<(FixedVertexHandle, f64)>,
    /// The vertex to start the next walk from.
    pub(super) hint: usize,
    /// The triangle each view's last ray fell in. Along a hololine at one
    /// view a ray's point on the camera surface moves by a small, constant
    /// step from emitter to emitter, so it usually stays in its triangle:
    /// the weights are stepped (evaluated from the triangle's affine
    /// barycentric functions) and spade's walk runs only when a ray leaves
    /// the triangle.
    pub(super) triangles: Vec<Option<Triangle>>,
    /// The worker's copy of the cameras' triangulation ([`Blend::NaturalNeighbour`]).
    pub(super) triangulation: Option<DelaunayTriangulation<Point2<f64>>>,
    /// The vertex nearest each view's last ray ([`Blend::Nearest`]).
    pub(super) nearest: Vec<usize>,
    /// Which of `triangles` and `nearest` the next ray uses (its view).
    pub(super) view: usize,
}

impl Scratch {
    /// Scratch for rays of `views` views.
    pub(super) fn new(views: usize) -> Scratch {
        Scratch { triangles: vec![None; views], nearest: vec![0; views], ..Scratch::default() }
    }
}

/// A Delaunay triangle with its barycentric coordinates as affine functions
/// of the surface point: `λ_k(q) = a_k + b_k q_x + c_k q_y`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Triangle {
    pub(super) cameras: [usize; 3],
    pub(super) affine: [[f64; 3]; 3],
}

impl Triangle {
    /// The triangle of vertices `p` (counter-clockwise or not; not
    /// degenerate) for cameras `cameras`.
    pub(super) fn new(p: [[f64; 2]; 3], cameras: [usize; 3]) -> Triangle {
        let det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        // λ1 = ((q − p0) × (p2 − p0)) / det, λ2 = ((p1 − p0) × (q − p0)) / det.
        let (b1, c1) = ((p[2][1] - p[0][1]) / det, -(p[2][0] - p[0][0]) / det);
        let (b2, c2) = (-(p[1][1] - p[0][1]) / det, (p[1][0] - p[0][0]) / det);
        let a1 = -(p[0][0] * b1 + p[0][1] * c1);
        let a2 = -(p[0][0] * b2 + p[0][1] * c2);
        Triangle { cameras, affine: [[1.0 - a1 - a2, -b1 - b2, -c1 - c2], [a1, b1, c1], [a2, b2, c2]] }
    }

    /// The barycentric coordinates of `q`.
    pub(super) fn coordinates(&self, q: [f64; 2]) -> [f64; 3] {
        self.affine.map(|[a, b, c]| a + b * q[0] + c * q[1])
    }
}

/// Barycentric weights of `p` in its Delaunay triangle (two on an edge,
/// one on a vertex, none outside the hull), located by a walk from vertex
/// `hint`, which is moved to a vertex of the triangle found. Returns the
/// triangle when `p` is inside one.
pub(super) fn barycentric_with_hint(
    t: &DelaunayTriangulation<Point2<f64>>,
    p: Point2<f64>,
    hint: &mut usize,
    out: &mut Vec<(FixedVertexHandle, f64)>,
) -> Option<[FixedVertexHandle; 3]> {
    out.clear();
    let start = FixedVertexHandle::from_index((*hint).min(t.num_vertices() - 1));
    match t.locate_with_hint(p, start) {
        PositionInTriangulation::OnVertex(v) => {
            *hint = v.index();
            out.push((v, 1.0));
        }
        PositionInTriangulation::OnEdge(e) => {
            let e = t.directed_edge(e);
            let (a, b) = (e.from(), e.to());
            *hint = a.fix().index();
            let (pa, pb) = (a.position(), b.position());
            let (dx, dy) = (pb.x - pa.x, pb.y - pa.y);
            let s = (((p.x - pa.x) * dx + (p.y - pa.y) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            out.push((a.fix(), 1.0 - s));
            out.push((b.fix(), s));
        }
        PositionInTriangulation::OnFace(f) => {
            let v = t.face(f).vertices();
            *hint = v[0].fix().index();
            let q = v.map(|v| v.position());
            let det = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
            let l1 = ((p.x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (p.y - q[0].y)) / det;
            let l2 = ((q[1].x - q[0].x) * (p.y - q[0].y) - (p.x - q[0].x) * (q[1].y - q[0].y)) / det;
            out.extend([(v[0].fix(), 1.0 - l1 - l2), (v[1].fix(), l1), (v[2].fix(), l2)]);
            return Some(v.map(|v| v.fix()));
        }
        PositionInTriangulation::OutsideOfConvexHull(e) => *hint = t.directed_edge(e).from().fix().index(),
        PositionInTriangulation::NoTriangulation => {}
    }
    None
}

/// The vertex of `t` nearest `q` (the first by index among equals), walked
/// to from vertex `start`: a vertex no Delaunay neighbour of which is nearer
/// is the nearest of all (its Voronoi cell is bounded by its neighbours').
pub(super) fn nearest_vertex(t: &DelaunayTriangulation<Point2<f64>>, start: usize, q: [f64; 2]) -> usize {
    let key = |v: FixedVertexHandle| {
        let p = t.vertex(v).position();
        ((q[0] - p.x).powi(2) + (q[1] - p.y).powi(2), v.index())
    };
    let mut best = FixedVertexHandle::from_index(start.min(t.num_vertices() - 1));
    let mut best_key = key(best);
    loop {
        let nearer = t.vertex(best).out_edges().map(|e| e.to().fix()).map(|v| (key(v), v)).fold(None, |a, b| match a {
            Some((ka, _)) if ka <= b.0 => a,
            _ => Some(b),
        });
        match nearer {
            Some((k, v)) if k < best_key => (best, best_key) = (v, k),
            _ => return best.index(),
        }
    }
}

/// Cameras' points on the surface and the weights of a query point.
/// [`Interpolator::weights`] locates the point by binary search or by
/// spade's walk; [`Interpolator::weights_reference`] by trying every
/// interval or triangle, the slow and obvious way the tests compare with.
pub(super) enum Interpolator {
    /// One camera: it takes every ray.
    Single,
    /// Cameras on a line: their coordinate along `axis` from `origin`, sorted, with camera indices.
    Line { origin: [f64; 2], axis: [f64; 2], sorted: Vec<(f64, usize)> },
    /// Scattered: the Delaunay triangulation; vertex `k` is camera `cameras[k]`;
    /// `margin`: how far beyond the cameras a ray still takes their light.
    Triangles { triangulation: DelaunayTriangulation<Point2<f64>>, cameras: Vec<usize>, margin: Option<Margin> },
}

/// A planar grid's cover beyond its outer cameras (full parallax): each
/// camera stands for the rays within half the cameras' spacing of it, as each
/// view and emitter of a file stands for ±½ of its own
/// (`sampling::linear_taps`), so a ray landing up to half a spacing beyond
/// the cameras' rectangle takes the outer cameras' light instead of none.
/// Without it, an eye at an outer camera reads between a captured ray and a
/// black one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Margin {
    lo: [f64; 2],
    hi: [f64; 2],
    half_spacing: f64,
}

impl Margin {
    /// `q` moved onto the cameras' rectangle when it lies within half a
    /// spacing outside it, along each axis; as it is otherwise.
    fn clamp(&self, q: [f64; 2]) -> [f64; 2] {
        let mut out = q;
        for k in 0..2 {
            if q[k] < self.lo[k] && q[k] >= self.lo[k] - self.half_spacing {
                out[k] = self.lo[k];
            }
            if q[k] > self.hi[k] && q[k] <= self.hi[k] + self.half_spacing {
                out[k] = self.hi[k];
            }
        }
        out
    }
}

/// The coordinate of `p` along the line through `origin` with unit
/// direction `axis`: how cameras on a line are sorted and rays located
/// among them.
pub(super) fn along_line(p: [f64; 2], origin: [f64; 2], axis: [f64; 2]) -> f64 {
    (p[0] - origin[0]) * axis[0] + (p[1] - origin[1]) * axis[1]
}

/// The weights at coordinate `s` on a line of the neighbouring cameras `a`
/// and `b` (coordinate, camera index) around it: the nearest, or both in
/// proportion (natural-neighbour weights on a line are linear).
pub(super) fn pair_weights(a: (f64, usize), b: (f64, usize), s: f64, blend: Blend, out: &mut Vec<(usize, f64)>) {
    let t = ((s - a.0) / (b.0 - a.0)).clamp(0.0, 1.0);
    match blend {
        Blend::Nearest => out.push((if t < 0.5 { a.1 } else { b.1 }, 1.0)),
        Blend::Linear | Blend::NaturalNeighbour => {
            out.push((a.1, 1.0 - t));
            out.push((b.1, t));
        }
    }
}

impl Interpolator {
    /// [`Interpolator::weights`] found by brute force: every pair of
    /// neighbours on a line, every Delaunay triangle (barycentric
    /// coordinates in f64 from the vertices), every camera for the nearest.
    /// Natural-neighbour weights have no second implementation here and
    /// come from spade.
    pub(super) fn weights_reference(
        &self,
        q: [f64; 2],
        blend: Blend,
        out: &mut Vec<(usize, f64)>,
        scratch: &mut Scratch,
    ) {
        out.clear();
        let q = self.covered(q);
        match self {
            Interpolator::Single => out.push((0, 1.0)),
            Interpolator::Line { origin, axis, sorted } => {
                let s = along_line(q, *origin, *axis);
                for pair in sorted.windows(2) {
                    let (a, b) = (pair[0], pair[1]);
                    if s >= a.0 && s <= b.0 {
                        pair_weights(a, b, s, blend, out);
                        return;
                    }
                }
            }
            Interpolator::Triangles { triangulation, cameras, .. } => {
                if blend == Blend::NaturalNeighbour {
                    return self.weights(q, blend, out, scratch);
                }
                for face in triangulation.inner_faces() {
                    let v = face.vertices();
                    let p = v.map(|v| [v.position().x, v.position().y]);
                    let det = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
                    let l1 = ((q[0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (q[1] - p[0][1])) / det;
                    let l2 = ((p[1][0] - p[0][0]) * (q[1] - p[0][1]) - (q[0] - p[0][0]) * (p[1][1] - p[0][1])) / det;
                    let l0 = 1.0 - l1 - l2;
                    let eps = -1e-12;
                    if l0 >= eps && l1 >= eps && l2 >= eps {
                        let ids = v.map(|v| cameras[v.fix().index()]);
                        if blend == Blend::Nearest {
                            let d = |i: usize| {
                                (q[0] - triangulation.vertex(FixedVertexHandle::from_index(i)).position().x).powi(2)
                                    + (q[1] - triangulation.vertex(FixedVertexHandle::from_index(i)).position().y)
                                        .powi(2)
                            };
                            let best = (0..cameras.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).expect("cameras");
                            out.push((cameras[best], 1.0));
                        } else {
                            out.extend(
                                [(ids[0], l0.max(0.0)), (ids[1], l1.max(0.0)), (ids[2], l2.max(0.0))]
                                    .into_iter()
                                    .filter(|w| w.1 > 0.0),
                            );
                        }
                        return;
                    }
                }
            }
        }
    }

    pub(super) fn new(points: &[[f64; 2]], rig: &Rig) -> Result<Interpolator> {
        let n = points.len();
        if n == 1 {
            return Ok(Interpolator::Single);
        }
        // Coincident points first: every method needs them distinct.
        let extent = points.iter().flat_map(|p| p.iter()).fold(0.0f64, |a, &b| a.max(b.abs()));
        for a in 0..n {
            for b in a + 1..n {
                let d = ((points[a][0] - points[b][0]).powi(2) + (points[a][1] - points[b][1]).powi(2)).sqrt();
                if d <= 1e-9 * extent.max(1e-300) {
                    return Err(Error::rig(
                        &rig.source,
                        format!(
                            "cameras {} and {} are at the same place on the camera surface (the same position{})",
                            rig.cameras[a].name,
                            rig.cameras[b].name,
                            if extent > 0.0 { " or direction" } else { "" }
                        ),
                    ));
                }
            }
        }
        // Collinear: a 1-D list along the principal direction.
        let c =
            [points.iter().map(|p| p[0]).sum::<f64>() / n as f64, points.iter().map(|p| p[1]).sum::<f64>() / n as f64];
        let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
        for p in points {
            let (x, y) = (p[0] - c[0], p[1] - c[1]);
            sxx += x * x;
            sxy += x * y;
            syy += y * y;
        }
        let tr = sxx + syy;
        let det = sxx * syy - sxy * sxy;
        let l1 = tr / 2.0 + (tr * tr / 4.0 - det).max(0.0).sqrt();
        let l2 = (tr - l1).max(0.0);
        if l2 <= 1e-10 * l1 {
            let axis = if sxy.abs() > 1e-300 || sxx >= syy {
                let a = if sxy.abs() > 1e-300 { [l1 - syy, sxy] } else { [1.0, 0.0] };
                let l = (a[0] * a[0] + a[1] * a[1]).sqrt();
                [a[0] / l, a[1] / l]
            } else {
                [0.0, 1.0]
            };
            let mut sorted: Vec<(f64, usize)> =
                points.iter().enumerate().map(|(i, &p)| (along_line(p, c, axis), i)).collect();
            sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
            return Ok(Interpolator::Line { origin: c, axis, sorted });
        }
        let mut triangulation = DelaunayTriangulation::<Point2<f64>>::new();
        let mut cameras: Vec<usize> = Vec::with_capacity(n);
        for (i, p) in points.iter().enumerate() {
            let h: FixedVertexHandle = triangulation
                .insert(Point2::new(p[0], p[1]))
                .map_err(|e| Error::rig(&rig.source, format!("camera {}: {e:?}", rig.cameras[i].name)))?;
            if h.index() != cameras.len() {
                return Err(Error::rig(
                    &rig.source,
                    format!(
                        "cameras {} and {} are at the same place on the camera surface",
                        rig.cameras[cameras[h.index()]].name,
                        rig.cameras[i].name
                    ),
                ));
            }
            cameras.push(i);
        }
        Ok(Interpolator::Triangles { triangulation, cameras, margin: None })
    }

    /// Let rays up to half the cameras' spacing beyond their rectangle take
    /// the outer cameras' light ([`Margin`]; scattered cameras only). The
    /// spacing is the median distance from a camera to its nearest.
    pub(super) fn cover_half_a_spacing_beyond(&mut self) {
        let Interpolator::Triangles { triangulation, margin, .. } = self else { return };
        let points: Vec<[f64; 2]> = triangulation.vertices().map(|v| [v.position().x, v.position().y]).collect();
        let mut nearest: Vec<f64> = points
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let others = points.iter().enumerate().filter(|&(j, _)| j != i);
                others
                    .map(|(_, b)| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt())
                    .fold(f64::INFINITY, f64::min)
            })
            .collect();
        nearest.sort_by(f64::total_cmp);
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &points {
            for k in 0..2 {
                (lo[k], hi[k]) = (lo[k].min(p[k]), hi[k].max(p[k]));
            }
        }
        *margin = Some(Margin { lo, hi, half_spacing: 0.5 * nearest[nearest.len() / 2] });
    }

    /// `q` as the weights take it: moved onto the cameras' rectangle within
    /// the [`Margin`], if there is one.
    fn covered(&self, q: [f64; 2]) -> [f64; 2] {
        match self {
            Interpolator::Triangles { margin: Some(m), .. } => m.clamp(q),
            _ => q,
        }
    }

    /// Camera weights at `q` (summing to 1), empty outside the cameras' hull.
    pub(super) fn weights(&self, q: [f64; 2], blend: Blend, out: &mut Vec<(usize, f64)>, scratch: &mut Scratch) {
        out.clear();
        let q = self.covered(q);
        match self {
            Interpolator::Single => out.push((0, 1.0)),
            Interpolator::Line { origin, axis, sorted } => {
                let s = along_line(q, *origin, *axis);
                let (first, last) = (sorted[0].0, sorted[sorted.len() - 1].0);
                if !(s >= first && s <= last) {
                    return;
                }
                // The last camera at or before s.
                let i = sorted.partition_point(|&(x, _)| x <= s).saturating_sub(1).min(sorted.len() - 2);
                pair_weights(sorted[i], sorted[i + 1], s, blend, out);
            }
            Interpolator::Triangles { triangulation, cameras, .. } => {
                let p = Point2::new(q[0], q[1]);
                if !(q[0].is_finite() && q[1].is_finite()) {
                    return;
                }
                // spade's weights (by vertex) as camera weights, zeros left out.
                let from_spade = |weights: &[(FixedVertexHandle, f64)], out: &mut Vec<(usize, f64)>| {
                    out.extend(weights.iter().filter(|w| w.1 > 0.0).map(|&(h, w)| (cameras[h.index()], w)))
                };
                if blend == Blend::NaturalNeighbour {
                    // On the worker's own copy: spade's walks start from the
                    // last vertex it found, kept in the triangulation, which
                    // threads sharing one would keep taking from each other.
                    let own = scratch.triangulation.get_or_insert_with(|| triangulation.clone());
                    own.natural_neighbor().get_weights(p, &mut scratch.weights);
                    return from_spade(&scratch.weights, out);
                }
                // Barycentric in the triangle of this view's last ray, usually;
                // else located by walking from the last ray's vertex (spade's
                // own hint is shared between threads).
                let cached = match scratch.triangles.get(scratch.view) {
                    Some(Some(t)) => Some((t.cameras, t.coordinates(q))).filter(|(_, l)| l.iter().all(|&l| l >= 0.0)),
                    _ => None,
                };
                let found = cached.or_else(|| {
                    let face = barycentric_with_hint(triangulation, p, &mut scratch.hint, &mut scratch.weights)?;
                    let at = face.map(|v| {
                        let p = triangulation.vertex(v).position();
                        [p.x, p.y]
                    });
                    let t = Triangle::new(at, face.map(|v| cameras[v.index()]));
                    if let Some(slot) = scratch.triangles.get_mut(scratch.view) {
                        *slot = Some(t);
                    }
                    Some((t.cameras, t.coordinates(q)))
                });
                match found {
                    Some((ids, l)) => out.extend(ids.into_iter().zip(l).filter(|w| w.1 > 0.0)),
                    // On an edge or a vertex, or outside the hull (none).
                    None => from_spade(&scratch.weights, out),
                }
                if blend == Blend::Nearest && !out.is_empty() {
                    // Inside the hull: the nearest camera, walked to from this
                    // view's last one.
                    let start = scratch.nearest.get(scratch.view).copied().unwrap_or(0);
                    let v = nearest_vertex(triangulation, start, q);
                    if let Some(slot) = scratch.nearest.get_mut(scratch.view) {
                        *slot = v;
                    }
                    out.clear();
                    out.push((cameras[v], 1.0));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Margin;

    /// Half a spacing beyond the rectangle, along each axis (corners too),
    /// moves onto it; further out, or inside, stays where it is.
    #[test]
    fn a_margin_covers_half_a_spacing_beyond_the_cameras() {
        let m = Margin { lo: [-4.0, -4.0], hi: [4.0, 4.0], half_spacing: 0.5 };
        assert_eq!(m.clamp([4.3, 0.7]), [4.0, 0.7]);
        assert_eq!(m.clamp([-4.5, 4.49]), [-4.0, 4.0]);
        assert_eq!(m.clamp([4.51, 0.0]), [4.51, 0.0]);
        assert_eq!(m.clamp([1.25, -3.9]), [1.25, -3.9]);
        assert_eq!(m.clamp([-4.2, -7.0]), [-4.0, -7.0]);
    }
}
