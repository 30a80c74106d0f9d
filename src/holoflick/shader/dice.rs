//! Dicing surfaces into micropolygons (Deering, *HoloFlicks* §8): every triangle is split
//! until no edge is longer than the budget at its midpoint, optionally
//! bending new vertices onto the smooth surface the vertex normals describe
//! (Phong tessellation: Boubekeur and Alexa, "Phong Tessellation", SIGGRAPH
//! Asia 2008, shape factor α = 3/4).
//!
//! Cracks: neighbouring patches must dice their shared edge identically, or
//! rays slip between them. Here every decision about an edge — whether to
//! split it and where its midpoint goes — is a function of that edge alone,
//! keyed by its endpoints' positions (not their indices), and symmetric in
//! its two ends; so two triangles that share an edge in space, in one object
//! or in two, with shared or duplicated vertices, put bit-identical vertices
//! on it. Where the two sides of an edge disagree about the surface (a hard
//! edge: different normals at the same positions, or an edge on one side
//! only, the boundary of an open surface), a bent midpoint would open a gap,
//! so such edges are split flat: the stitch. Splits are longest-edge
//! bisections by pattern (one, two or three edges split at once), so a
//! triangle never has a T-junction with its neighbours.
//!
//! No work where the scene needs none: when the light to be baked is affine
//! across a flat triangle (only directional and ambient light, no shadows,
//! no textures: [`DiceOptions::affine_shading`]), a triangle whose three
//! normals are equal is drawn exactly as it is, so an edge is split only if
//! some triangle on it is not such a one. The decision stays a function of
//! the edge (its sides are known before dicing, halves of a split edge
//! inherit it, edges inside a triangle follow the triangle), so cracks stay
//! impossible.

use std::collections::HashMap;

use crate::error::{Error, Result};
use crate::math::{distance, midpoint, narrow, unit};
use crate::mesh::Object;

/// How to dice.
#[derive(Clone, Copy, Debug)]
pub struct DiceOptions {
    /// Bend new vertices onto the surface the normals describe (needs normals).
    pub smooth: bool,
    /// Split hard and boundary edges flat (the stitch). Off only to show
    /// what it prevents: bent hard edges open cracks.
    pub stitch: bool,
    /// Refuse to produce more than this many triangles per object.
    pub max_triangles: usize,
    /// The light to be baked is affine across a flat triangle (directional
    /// and ambient lights only, no shadows): untextured triangles with equal
    /// normals at their corners are left whole unless a neighbour needs
    /// their edge split.
    pub affine_shading: bool,
}

impl Default for DiceOptions {
    fn default() -> Self {
        DiceOptions { smooth: true, stitch: true, max_triangles: 50_000_000, affine_shading: false }
    }
}

/// Whether triangle `t` of `o` shades affinely when the light does
/// ([`DiceOptions::affine_shading`]): no texture on its material, and its
/// corners' normals equal (or none: flat).
fn shades_affinely(o: &Object, t: &[u32; 3]) -> bool {
    let m = &o.material;
    let untextured = m.base_colour_texture.is_none() && m.normal_texture.is_none() && m.emissive_texture.is_none();
    let normals = t.map(|i| o.normals.get(i as usize).copied());
    untextured && normals[0] == normals[1] && normals[1] == normals[2]
}

/// What dicing did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DiceReport {
    /// Triangles in and out.
    pub triangles_in: usize,
    /// Triangles out.
    pub triangles_out: usize,
    /// Edges split flat because their sides disagree or one is missing.
    pub stitched_edges: usize,
    /// Input triangles left whole or split only where a neighbour needed it,
    /// their shading being exact as it is.
    pub affine_triangles: usize,
}

/// The bits of a position, so edges are keyed by where they are.
type PositionKey = [u64; 3];

fn key(p: [f64; 3]) -> PositionKey {
    // +0.0 and −0.0 are one place.
    p.map(|x| if x == 0.0 { 0 } else { x.to_bits() })
}

/// An edge keyed by its endpoints' positions, in order.
fn edge_key(a: [f64; 3], b: [f64; 3]) -> (PositionKey, PositionKey) {
    let (ka, kb) = (key(a), key(b));
    if ka <= kb {
        (ka, kb)
    } else {
        (kb, ka)
    }
}

/// Dice `objects` together (shared edges between objects dice alike) so no
/// micropolygon edge is longer than `max_edge_m(midpoint)`. Attributes
/// (normals, tangents, texture coordinates, colours) are interpolated at
/// new vertices; normals and tangents renormalised.
pub fn dice(
    objects: &[Object],
    max_edge_m: &(dyn Fn([f64; 3]) -> f64 + Sync),
    options: &DiceOptions,
) -> Result<(Vec<Object>, DiceReport)> {
    dice_reporting(objects, max_edge_m, options, &crate::progress::Silent)
}

/// [`dice`], counting the input triangles diced in the phase
/// `triangles diced` of `progress`.
pub fn dice_reporting(
    objects: &[Object],
    max_edge_m: &(dyn Fn([f64; 3]) -> f64 + Sync),
    options: &DiceOptions,
    progress: &dyn crate::progress::Progress,
) -> Result<(Vec<Object>, DiceReport)> {
    let mut report = DiceReport::default();
    progress.phase("triangles diced", objects.iter().map(|o| o.triangles.len() as u64).sum());
    let mut done = 0u64;
    // The normals each side of every edge gives its ends: edges whose sides
    // agree (and that have two sides) may bend; the rest are stitched flat.
    let mut sides: HashMap<(PositionKey, PositionKey), EdgeSides> = HashMap::new();
    for o in objects {
        for t in &o.triangles {
            for k in 0..3 {
                let (i, j) = (t[k] as usize, t[(k + 1) % 3] as usize);
                let (Some(&a), Some(&b)) = (o.positions.get(i), o.positions.get(j)) else {
                    return Err(Error::argument(
                        "object",
                        format!("object \"{}\": triangle {t:?} names a missing vertex", o.name),
                    ));
                };
                let (na, nb) = (o.normals.get(i).copied(), o.normals.get(j).copied());
                let ends = if key(a) <= key(b) { (na, nb) } else { (nb, na) };
                let side = sides.entry(edge_key(a, b)).or_default();
                side.add(ends);
                side.curved |= !(options.affine_shading && shades_affinely(o, t));
            }
        }
    }
    // Halves of an edge split flat are split flat too, in whichever object.
    let mut flat: std::collections::HashSet<(PositionKey, PositionKey)> = Default::default();
    // Whether each edge of the input (and, as they are made, each half of
    // one) is curved: some triangle on it does not shade affinely.
    let mut curved: HashMap<(PositionKey, PositionKey), bool> = sides.iter().map(|(k, s)| (*k, s.curved)).collect();
    let mut out = Vec::with_capacity(objects.len());
    for o in objects {
        report.triangles_in += o.triangles.len();
        let mut d = Dicer {
            o: o.clone(),
            midpoints: HashMap::new(),
            sides: &sides,
            flat: &mut flat,
            curved: &mut curved,
            smooth: options.smooth,
            stitch: options.stitch,
            stitched: 0,
        };
        d.o.triangles.clear();
        // Each triangle to do, with whether its shading is affine (children
        // inherit it from the input triangle).
        // One input triangle at a time, so progress counts them.
        let mut work: Vec<([u32; 3], bool)> = Vec::new();
        for input in &o.triangles {
            let affine = options.affine_shading && shades_affinely(o, input);
            report.affine_triangles += usize::from(affine);
            work.push((*input, affine));
            while let Some((t, affine)) = work.pop() {
                if d.o.triangles.len() + work.len() > options.max_triangles {
                    return Err(Error::argument(
                        "micropolygon budget",
                        format!(
                            "object \"{}\": dicing makes more than {} micropolygons; coarsen the budget",
                            o.name, options.max_triangles
                        ),
                    ));
                }
                let p = t.map(|i| d.o.positions[i as usize]);
                let split: [bool; 3] = std::array::from_fn(|k| {
                    let (a, b) = (p[k], p[(k + 1) % 3]);
                    // An edge of the input, or half of one, is curved when a
                    // triangle on either side is; one inside a triangle when it is.
                    let curved = d.curved.get(&edge_key(a, b)).copied().unwrap_or(!affine);
                    let m = midpoint(a, b);
                    let length = distance(a, b);
                    let budget = max_edge_m(m);
                    // Not finite or not positive: leave the edge alone.
                    curved && length > budget && budget > 0.0 && budget.is_finite()
                });
                match split.iter().filter(|s| **s).count() {
                    0 => d.o.triangles.push(t),
                    1 => {
                        // Rotate so the split edge is (a, b).
                        let k = split.iter().position(|s| *s).unwrap_or(0);
                        let [a, b, c] = [t[k], t[(k + 1) % 3], t[(k + 2) % 3]];
                        let m = d.midpoint(a, b)?;
                        work.extend([([a, m, c], affine), ([m, b, c], affine)]);
                    }
                    2 => {
                        // Rotate so the unsplit edge is (c, a): split (a, b) and (b, c).
                        let k = (split.iter().position(|s| !*s).unwrap_or(0) + 1) % 3;
                        let [a, b, c] = [t[k], t[(k + 1) % 3], t[(k + 2) % 3]];
                        let (mab, mbc) = (d.midpoint(a, b)?, d.midpoint(b, c)?);
                        work.push(([mab, b, mbc], affine));
                        // The quad (a, mab, mbc, c) along its shorter diagonal.
                        let pos = |i: u32| d.o.positions[i as usize];
                        if distance(pos(a), pos(mbc)) <= distance(pos(mab), pos(c)) {
                            work.extend([([a, mab, mbc], affine), ([a, mbc, c], affine)]);
                        } else {
                            work.extend([([a, mab, c], affine), ([mab, mbc, c], affine)]);
                        }
                    }
                    _ => {
                        let [a, b, c] = t;
                        let (mab, mbc, mca) = (d.midpoint(a, b)?, d.midpoint(b, c)?, d.midpoint(c, a)?);
                        work.extend(
                            [[a, mab, mca], [mab, b, mbc], [mca, mbc, c], [mab, mbc, mca]].map(|t| (t, affine)),
                        );
                    }
                }
            }
            done += 1;
            progress.advance(done);
        }
        report.triangles_out += d.o.triangles.len();
        report.stitched_edges += d.stitched;
        out.push(d.o);
    }
    Ok((out, report))
}

/// The normals one triangle gives an edge's two ends (ends in key order).
type EndNormals = (Option<[f32; 3]>, Option<[f32; 3]>);

/// The normals the triangles on each side of an edge give its two ends.
#[derive(Default)]
struct EdgeSides {
    count: u32,
    ends: Option<EndNormals>,
    agree: bool,
    /// A triangle on it does not shade affinely: split it by the budget.
    curved: bool,
}

impl EdgeSides {
    fn add(&mut self, ends: EndNormals) {
        self.count += 1;
        match self.ends {
            None => {
                self.ends = Some(ends);
                self.agree = ends.0.is_some() && ends.1.is_some();
            }
            Some(first) => self.agree &= first == ends,
        }
    }
    /// Two sides that agree on the normals at both ends.
    fn may_bend(&self) -> bool {
        self.count == 2 && self.agree
    }
}

struct Dicer<'a> {
    o: Object,
    /// New vertex of each split edge (by vertex indices, either order).
    midpoints: HashMap<(u32, u32), u32>,
    sides: &'a HashMap<(PositionKey, PositionKey), EdgeSides>,
    flat: &'a mut std::collections::HashSet<(PositionKey, PositionKey)>,
    curved: &'a mut HashMap<(PositionKey, PositionKey), bool>,
    smooth: bool,
    stitch: bool,
    stitched: usize,
}

impl Dicer<'_> {
    /// The vertex in the middle of edge (i, j), made once per edge.
    fn midpoint(&mut self, i: u32, j: u32) -> Result<u32> {
        let pair = (i.min(j), i.max(j));
        if let Some(&m) = self.midpoints.get(&pair) {
            return Ok(m);
        }
        // Work in key order so both sides compute the same bits.
        let (pa, pb) = (self.o.positions[i as usize], self.o.positions[j as usize]);
        let (i, j) = if key(pa) <= key(pb) { (i as usize, j as usize) } else { (j as usize, i as usize) };
        let o = &mut self.o;
        let (a, b) = (o.positions[i], o.positions[j]);
        let mut p = midpoint(a, b);
        // An edge of the input bends when its two sides agree; an edge made
        // by dicing bends unless it is half of one split flat (edges made
        // inside a triangle have that triangle's children on both sides,
        // which share its normals).
        let here = edge_key(a, b);
        let flat = self.stitch && (self.flat.contains(&here) || self.sides.get(&here).is_some_and(|s| !s.may_bend()));
        if self.smooth && !flat && o.normals.len() == o.positions.len() {
            p = phong_midpoint(a, b, o.normals[i], o.normals[j]);
        } else if flat && self.smooth {
            self.stitched += 1;
            self.flat.insert(edge_key(a, p));
            self.flat.insert(edge_key(p, b));
        }
        if let Some(&curved) = self.curved.get(&here) {
            self.curved.insert(edge_key(a, p), curved);
            self.curved.insert(edge_key(p, b), curved);
        }
        let m = u32::try_from(o.positions.len()).map_err(|_| {
            Error::argument("object", format!("object \"{}\": more than 2³² vertices after dicing", o.name))
        })?;
        o.positions.push(p);
        if o.normals.len() + 1 == o.positions.len() {
            let n = midpoint(o.normals[i], o.normals[j]);
            o.normals.push(unit(n).unwrap_or(n));
        }
        if o.tangents.len() + 1 == o.positions.len() {
            let (ta, tb) = (o.tangents[i], o.tangents[j]);
            let t = midpoint([ta[0], ta[1], ta[2]], [tb[0], tb[1], tb[2]]);
            let t = unit(t).unwrap_or(t);
            o.tangents.push([t[0], t[1], t[2], ta[3]]);
        }
        for set in &mut o.uv_sets {
            if set.len() + 1 == o.positions.len() {
                let (ua, ub) = (set[i], set[j]);
                set.push([(ua[0] + ub[0]) * 0.5, (ua[1] + ub[1]) * 0.5]);
            }
        }
        if o.colours.len() + 1 == o.positions.len() {
            let (ca, cb) = (o.colours[i], o.colours[j]);
            o.colours.push(std::array::from_fn(|k| (ca[k] + cb[k]) * 0.5));
        }
        self.midpoints.insert(pair, m);
        Ok(m)
    }
}

/// The Phong-tessellation point halfway along edge (a, b): the flat midpoint
/// moved toward its projections onto the tangent planes at both ends.
fn phong_midpoint(a: [f64; 3], b: [f64; 3], na: [f32; 3], nb: [f32; 3]) -> [f64; 3] {
    const ALPHA: f64 = 0.75;
    let p = midpoint(a, b);
    let project = |q: [f64; 3], n: [f32; 3]| {
        let n = n.map(|x| x as f64);
        let d = (p[0] - q[0]) * n[0] + (p[1] - q[1]) * n[1] + (p[2] - q[2]) * n[2];
        [p[0] - d * n[0], p[1] - d * n[1], p[2] - d * n[2]]
    };
    let (pa, pb) = (project(a, na), project(b, nb));
    std::array::from_fn(|k| (1.0 - ALPHA) * p[k] + ALPHA * (pa[k] + pb[k]) * 0.5)
}

/// The budget for a display: a micropolygon no wider than what the display
/// resolves at that depth — the emitter pitch on the emitter plane, growing
/// as `|z − z_e| · Δθ` away from it (a point at depth `z` is spread over that
/// width by the view spacing `Δθ`) — and no taller than a hololine, times
/// `factor` (1 = one sample; smaller is finer).
pub fn display_budget(g: &crate::geometry::Geometry, factor: f64) -> impl Fn([f64; 3]) -> f64 + Sync {
    let views = g.views.count;
    let dtheta =
        if views < 2 { 0.0 } else { (g.views.theta_rad(views - 1) - g.views.theta_rad(0)).abs() / (views - 1) as f64 };
    let (pitch, line, z_e) = (g.emitter_pitch_m, g.hololine_pitch_m, g.emitter_z_m);
    move |p: [f64; 3]| factor * line.min(pitch.max((p[2] - z_e).abs() * dtheta))
}

/// An object without vertex normals is shaded flat (each triangle with its
/// face normal); per-vertex data cannot say that while faces share
/// vertices, so give every corner its own vertex carrying the face normal.
/// Objects with normals are returned as they are.
pub fn with_flat_normals(o: &Object) -> Object {
    if !o.normals.is_empty() {
        return o.clone();
    }
    let mut out = Object {
        name: o.name.clone(),
        material: o.material.clone(),
        uv_sets: vec![Vec::new(); o.uv_sets.len()],
        ..Object::default()
    };
    for (t, tri) in o.triangles.iter().enumerate() {
        let f = crate::mesh::shade::face_normal(o, t);
        let n = unit(f).map_or([0.0, 0.0, 1.0], narrow);
        let first = out.positions.len() as u32;
        for &i in tri {
            let i = i as usize;
            out.positions.push(o.positions[i]);
            out.normals.push(n);
            if let Some(&tg) = o.tangents.get(i) {
                out.tangents.push(tg);
            }
            for (set, src) in out.uv_sets.iter_mut().zip(&o.uv_sets) {
                if let Some(&uv) = src.get(i) {
                    set.push(uv);
                }
            }
            if let Some(&c) = o.colours.get(i) {
                out.colours.push(c);
            }
        }
        out.triangles.push([first, first + 1, first + 2]);
    }
    out
}
