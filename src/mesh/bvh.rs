//! A bounding-volume hierarchy over every triangle of a scene, in f64, for
//! the reference ray caster. Median split on the longest axis of the
//! centroids: simple, and good enough for a reference.

use super::Scene;
use crate::math::{cross, dot, sub};

/// One triangle: its object and index, and its vertices.
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    /// Index into [`Scene::objects`].
    pub object: u32,
    /// Index into the object's triangles.
    pub triangle: u32,
    /// Vertex positions.
    pub p: [[f64; 3]; 3],
}

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Leaf: first triangle; inner: index of the left child (right = left + 1).
    start: u32,
    /// Leaf: triangle count; inner: 0.
    count: u32,
}

/// The hierarchy.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    triangles: Vec<Triangle>,
}

/// The nearest acceptable intersection found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// Ray parameter.
    pub t: f64,
    /// Object index.
    pub object: u32,
    /// Triangle index within the object.
    pub triangle: u32,
    /// Barycentric weight of vertex 1.
    pub b1: f64,
    /// Barycentric weight of vertex 2.
    pub b2: f64,
}

const LEAF: usize = 4;

impl Bvh {
    /// Build over every triangle of the scene.
    pub fn new(scene: &Scene) -> Bvh {
        let mut triangles = Vec::with_capacity(scene.triangle_count());
        for (oi, o) in scene.objects.iter().enumerate() {
            for (ti, t) in o.triangles.iter().enumerate() {
                let p = [o.positions[t[0] as usize], o.positions[t[1] as usize], o.positions[t[2] as usize]];
                triangles.push(Triangle { object: oi as u32, triangle: ti as u32, p });
            }
        }
        let mut bvh = Bvh { nodes: Vec::with_capacity(2 * triangles.len() / LEAF + 1), triangles };
        let n = bvh.triangles.len();
        bvh.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], start: 0, count: 0 });
        bvh.build(0, 0, n);
        bvh
    }

    fn build(&mut self, node: usize, start: usize, end: usize) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        let (mut clo, mut chi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for t in &self.triangles[start..end] {
            for p in &t.p {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let c = centroid(t);
            for k in 0..3 {
                clo[k] = clo[k].min(c[k]);
                chi[k] = chi[k].max(c[k]);
            }
        }
        self.nodes[node].lo = lo;
        self.nodes[node].hi = hi;
        let axis = (0..3).max_by(|&a, &b| (chi[a] - clo[a]).total_cmp(&(chi[b] - clo[b]))).unwrap_or(0);
        if end - start <= LEAF || chi[axis] <= clo[axis] {
            self.nodes[node].start = start as u32;
            self.nodes[node].count = (end - start) as u32;
            return;
        }
        let mid = (start + end) / 2;
        self.triangles[start..end]
            .select_nth_unstable_by(mid - start, |a, b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
        let left = self.nodes.len();
        self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], start: 0, count: 0 });
        self.nodes.push(Node { lo: [0.0; 3], hi: [0.0; 3], start: 0, count: 0 });
        self.nodes[node].start = left as u32;
        self.nodes[node].count = 0;
        self.build(left, start, mid);
        self.build(left + 1, mid, end);
    }

    /// The nearest intersection with `t > t_min` of the ray `origin + t·dir`
    /// that `accept(triangle, geometric normal)` allows.
    pub fn nearest(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        t_min: f64,
        accept: impl Fn(&Triangle, [f64; 3]) -> bool,
    ) -> Option<RayHit> {
        if self.triangles.is_empty() {
            return None;
        }
        let inv = [1.0 / dir[0], 1.0 / dir[1], 1.0 / dir[2]];
        let mut best: Option<RayHit> = None;
        let mut stack = vec![0usize];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n];
            let t_max = best.map_or(f64::INFINITY, |b| b.t);
            if !slab(&node, origin, inv, t_min, t_max) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.start as usize);
                stack.push(node.start as usize + 1);
                continue;
            }
            for tri in &self.triangles[node.start as usize..(node.start + node.count) as usize] {
                if let Some((t, b1, b2)) = intersect(tri, origin, dir) {
                    if t > t_min && best.map_or(true, |b| t < b.t) {
                        let n = cross(sub(tri.p[1], tri.p[0]), sub(tri.p[2], tri.p[0]));
                        if accept(tri, n) {
                            best = Some(RayHit { t, object: tri.object, triangle: tri.triangle, b1, b2 });
                        }
                    }
                }
            }
        }
        best
    }
}

fn centroid(t: &Triangle) -> [f64; 3] {
    std::array::from_fn(|k| (t.p[0][k] + t.p[1][k] + t.p[2][k]) / 3.0)
}

fn slab(n: &Node, o: [f64; 3], inv: [f64; 3], t_min: f64, t_max: f64) -> bool {
    let (mut t0, mut t1) = (t_min, t_max);
    for k in 0..3 {
        let a = (n.lo[k] - o[k]) * inv[k];
        let b = (n.hi[k] - o[k]) * inv[k];
        // NaN (0 · ∞ for a ray in a box face) fails neither test: keep the node.
        let (near, far) = if a <= b { (a, b) } else { (b, a) };
        if near > t0 {
            t0 = near;
        }
        if far < t1 {
            t1 = far;
        }
    }
    t0 <= t1
}

/// Möller–Trumbore in f64: `(t, b1, b2)` for a hit inside the triangle
/// (edges included), whatever the side.
fn intersect(tri: &Triangle, o: [f64; 3], d: [f64; 3]) -> Option<(f64, f64, f64)> {
    let e1 = sub(tri.p[1], tri.p[0]);
    let e2 = sub(tri.p[2], tri.p[0]);
    let p = cross(d, e2);
    let det = dot(e1, p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = sub(o, tri.p[0]);
    let b1 = dot(s, p) * inv;
    if !(0.0..=1.0).contains(&b1) {
        return None;
    }
    let q = cross(s, e1);
    let b2 = dot(d, q) * inv;
    if b2 < 0.0 || b1 + b2 > 1.0 {
        return None;
    }
    Some((dot(e2, q) * inv, b1, b2))
}
