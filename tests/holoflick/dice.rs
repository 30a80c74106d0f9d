//! Dicing into micropolygons (Deering, *HoloFlicks* §8): closed surfaces stay closed.
//! Checked two ways on a smooth sphere cut into two objects with duplicated
//! seam vertices and on a cylinder with hard rims: every edge of the diced surface
//! has exactly two triangles (no T-junction, no gap), and rays from outside
//! aimed close to the coarse edges, where cracks would open, all hit the
//! surface before reaching its centre. Without the stitch, the same tests
//! find the cracks.

use std::collections::HashMap;

use holo::holoflick::shader::dice::{dice, DiceOptions};
use holo::mesh::Object;
use rand::{Rng, SeedableRng};

/// An icosphere (radius 1, `levels` subdivisions) with exact sphere normals.
fn icosphere(levels: usize) -> Object {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut p: Vec<[f64; 3]> = vec![
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ];
    let unit = |v: [f64; 3]| {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    };
    p.iter_mut().for_each(|v| *v = unit(*v));
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..levels {
        let mut mids = HashMap::new();
        let mut next = Vec::new();
        for t in &tris {
            let mut mid = |a: u32, b: u32| {
                *mids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    let (pa, pb) = (p[a as usize], p[b as usize]);
                    p.push(unit([pa[0] + pb[0], pa[1] + pb[1], pa[2] + pb[2]]));
                    p.len() as u32 - 1
                })
            };
            let (ab, bc, ca) = (mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0]));
            next.extend([[t[0], ab, ca], [t[1], bc, ab], [t[2], ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    let normals = p.iter().map(|v| v.map(|x| x as f32)).collect();
    Object { name: "sphere".into(), positions: p, normals, triangles: tris, ..Object::default() }
}

/// The sphere cut into two objects by z, each with its own copy of the seam vertices.
fn two_hemispheres(levels: usize) -> Vec<Object> {
    let s = icosphere(levels);
    let mut halves = vec![
        Object { name: "north".into(), ..Object::default() },
        Object { name: "south".into(), ..Object::default() },
    ];
    let mut maps = [HashMap::new(), HashMap::new()];
    for t in &s.triangles {
        let z: f64 = t.iter().map(|&i| s.positions[i as usize][2]).sum();
        let h = usize::from(z < 0.0);
        let tri = t.map(|i| {
            *maps[h].entry(i).or_insert_with(|| {
                halves[h].positions.push(s.positions[i as usize]);
                halves[h].normals.push(s.normals[i as usize]);
                halves[h].positions.len() as u32 - 1
            })
        });
        halves[h].triangles.push(tri);
    }
    halves
}

/// A closed cylinder (radius 1, height 2, `n` sides) with smooth sides
/// (radial normals) and flat caps (axial normals, their own vertices): its
/// rims are hard edges whose two sides describe different surfaces.
fn cylinder(n: usize) -> Object {
    let mut o = Object { name: "cylinder".into(), ..Object::default() };
    let ring = |k: usize| {
        let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
        (a.cos(), a.sin())
    };
    // Sides: two rings with radial normals.
    for z in [-1.0, 1.0] {
        for k in 0..n {
            let (x, y) = ring(k);
            o.positions.push([x, y, z]);
            o.normals.push([x as f32, y as f32, 0.0]);
        }
    }
    let n32 = n as u32;
    for k in 0..n32 {
        let k1 = (k + 1) % n32;
        o.triangles.extend([[k, k1, n32 + k1], [k, n32 + k1, n32 + k]]);
    }
    // Caps: a centre and a ring each, axial normals.
    for (z, up) in [(-1.0, false), (1.0, true)] {
        let centre = o.positions.len() as u32;
        o.positions.push([0.0, 0.0, z]);
        o.normals.push([0.0, 0.0, z as f32]);
        for k in 0..n {
            let (x, y) = ring(k);
            o.positions.push([x, y, z]);
            o.normals.push([0.0, 0.0, z as f32]);
        }
        for k in 0..n32 {
            let (a, b) = (centre + 1 + k, centre + 1 + (k + 1) % n32);
            o.triangles.push(if up { [centre, a, b] } else { [centre, b, a] });
        }
    }
    o
}

/// A budget that changes fast across space: fine on the −x side.
fn budget(p: [f64; 3]) -> f64 {
    0.03 + 0.15 * (p[0] + 1.2).abs()
}

/// Edges (by positions) with other than two triangles.
fn open_edges(objects: &[Object]) -> usize {
    let mut count: HashMap<([u64; 3], [u64; 3]), u32> = HashMap::new();
    for o in objects {
        for t in &o.triangles {
            for k in 0..3 {
                let (a, b) = (o.positions[t[k] as usize], o.positions[t[(k + 1) % 3] as usize]);
                let (ka, kb) = (a.map(f64::to_bits), b.map(f64::to_bits));
                *count.entry(if ka < kb { (ka, kb) } else { (kb, ka) }).or_default() += 1;
            }
        }
    }
    count.values().filter(|&&n| n != 2).count()
}

/// Whether the segment from `o` to `e` meets triangle (a, b, c), tolerantly
/// (a ray along a shared edge counts for both sides).
fn segment_hits(o: [f64; 3], e: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> bool {
    let sub = |x: [f64; 3], y: [f64; 3]| [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
    let cross =
        |x: [f64; 3], y: [f64; 3]| [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]];
    let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let d = sub(e, o);
    let (e1, e2) = (sub(b, a), sub(c, a));
    let pv = cross(d, e2);
    let det = dot(e1, pv);
    if det.abs() < 1e-300 {
        return false;
    }
    let tv = sub(o, a);
    let u = dot(tv, pv) / det;
    let qv = cross(tv, e1);
    let v = dot(d, qv) / det;
    let t = dot(e2, qv) / det;
    let eps = 1e-9;
    u >= -eps && v >= -eps && u + v <= 1.0 + eps && (-eps..=1.0 + eps).contains(&t)
}

/// Rays from outside toward the centre through points just inside the
/// coarse mesh's edges; returns how many pass through the diced surface.
fn rays_through(coarse: &[Object], diced: &[Object], rays: usize, seed: u64) -> usize {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let edges: Vec<([f64; 3], [f64; 3])> = coarse
        .iter()
        .flat_map(|o| {
            o.triangles.iter().flat_map(move |t| {
                (0..3).map(move |k| (o.positions[t[k] as usize], o.positions[t[(k + 1) % 3] as usize]))
            })
        })
        .collect();
    let tris: Vec<[[f64; 3]; 3]> =
        diced.iter().flat_map(|o| o.triangles.iter().map(move |t| t.map(|i| o.positions[i as usize]))).collect();
    let mut through = 0;
    for _ in 0..rays {
        let (a, b) = edges[rng.gen_range(0..edges.len())];
        let s: f64 = rng.gen();
        let shrink = 1.0 - rng.gen_range(0.0..0.02);
        let q: [f64; 3] = std::array::from_fn(|k| (a[k] + s * (b[k] - a[k])) * shrink);
        let ql = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
        let origin = loop {
            let u: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..1.0));
            let ul = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
            if ul > 0.1 && ul <= 1.0 && (u[0] * q[0] + u[1] * q[1] + u[2] * q[2]) / (ul * ql) > 0.5 {
                break std::array::from_fn(|k| q[k] + 4.0 * u[k] / ul);
            }
        };
        // Through q and on to the centre: the surface must be crossed.
        let end: [f64; 3] = std::array::from_fn(|k| q[k] * 0.2);
        if !tris.iter().any(|t| segment_hits(origin, end, t[0], t[1], t[2])) {
            through += 1;
        }
    }
    through
}

#[test]
#[ignore = "slow: the full run takes it (README, Development)"]
fn diced_closed_surfaces_have_no_cracks() {
    for (name, coarse) in
        [("sphere in two objects", two_hemispheres(1)), ("cylinder with hard rims", vec![cylinder(8)])]
    {
        let (diced, report) = dice(&coarse, &budget, &DiceOptions::default()).unwrap();
        let open = open_edges(&diced);
        let through = rays_through(&coarse, &diced, 3000, 7);
        println!(
            "{name}: {} → {} triangles, {} edges stitched flat; open edges {open}; rays through {through} of 3000",
            report.triangles_in, report.triangles_out, report.stitched_edges
        );
        assert!(report.triangles_out > 20 * report.triangles_in, "{name}: the budget must dice finely");
        assert_eq!(open, 0, "{name}: every edge has two triangles");
        assert_eq!(through, 0, "{name}: rays slip through");
    }
    // Without the stitch the cylinder's rims bend one way from the side and
    // stay flat from the caps: they open.
    let coarse = vec![cylinder(8)];
    let (diced, _) = dice(&coarse, &budget, &DiceOptions { stitch: false, ..DiceOptions::default() }).unwrap();
    let (open, through) = (open_edges(&diced), rays_through(&coarse, &diced, 3000, 7));
    println!("cylinder without the stitch: open edges {open}; rays through {through} of 3000");
    assert!(open > 0 && through > 0, "the test must see cracks when there are some");
}

#[test]
fn smooth_dicing_approaches_the_surface_the_normals_describe() {
    let coarse = vec![icosphere(1)];
    let radial_error = |smooth: bool| {
        let (diced, _) = dice(&coarse, &|_| 0.05, &DiceOptions { smooth, ..DiceOptions::default() }).unwrap();
        diced[0]
            .positions
            .iter()
            .map(|p| ((p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let (flat, smooth) = (radial_error(false), radial_error(true));
    println!("largest distance from the sphere: flat {flat:.4}, smooth {smooth:.4}");
    assert!(smooth < flat / 2.0, "flat {flat}, smooth {smooth}");
    // Attributes follow: every vertex has a unit normal.
    let (diced, _) = dice(&coarse, &|_| 0.05, &DiceOptions::default()).unwrap();
    assert_eq!(diced[0].normals.len(), diced[0].positions.len());
    assert!(diced[0].normals.iter().all(|n| ((n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt() - 1.0).abs() < 1e-5));
}

#[test]
fn dicing_is_bounded() {
    let e = dice(&[icosphere(0)], &|_| 1e-6, &DiceOptions { max_triangles: 10_000, ..DiceOptions::default() })
        .unwrap_err()
        .to_string();
    assert!(e.contains("sphere") && e.contains("10000"), "{e}");
    // Budgets that are not finite or positive leave the surface alone.
    for b in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
        let (d, _) = dice(&[icosphere(0)], &move |_| b, &DiceOptions::default()).unwrap();
        assert_eq!(d[0].triangles.len(), 20);
    }
}

/// A cube of 12 triangles, each face with its own vertices and normal.
fn flat_cube() -> Object {
    let mut o = Object { name: "cube".into(), ..Object::default() };
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let n: [f64; 3] = std::array::from_fn(|k| if k == axis { sign } else { 0.0 });
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = o.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                let mut p = n;
                p[u] = a;
                p[v] = b;
                o.positions.push(p);
                o.normals.push(n.map(|x| x as f32));
            }
            let quad = [[base, base + 1, base + 2], [base, base + 2, base + 3]];
            o.triangles.extend(if sign > 0.0 { quad } else { quad.map(|[a, b, c]| [a, c, b]) });
        }
    }
    o
}

/// Under light that is affine across flat faces, flat untextured triangles
/// are drawn whole; beside curved ones they split only where their edge is
/// shared, and no crack opens.
#[test]
fn flat_faces_under_affine_light_are_left_whole() {
    let affine = DiceOptions { affine_shading: true, ..DiceOptions::default() };
    let (diced, report) = dice(&[flat_cube()], &budget, &affine).unwrap();
    assert_eq!((report.triangles_in, report.triangles_out, report.affine_triangles), (12, 12, 12));
    let sorted = |mut t: Vec<[u32; 3]>| {
        t.sort();
        t
    };
    assert_eq!(sorted(diced[0].triangles.clone()), sorted(flat_cube().triangles));
    // A textured cube is diced as before.
    let mut textured = flat_cube();
    textured.material.base_colour_texture =
        Some(holo::mesh::TextureRef { texture: 0, uv_set: 0, transform: Default::default() });
    let (_, report) = dice(&[textured], &budget, &affine).unwrap();
    assert!(report.triangles_out > 20 * report.triangles_in, "{report:?}");
    // The cylinder: flat caps beside curved sides.
    let coarse = vec![cylinder(8)];
    let (whole, report) = dice(&coarse, &budget, &affine).unwrap();
    let (all, _) = dice(&coarse, &budget, &DiceOptions::default()).unwrap();
    let count = |d: &[Object]| d.iter().map(|o| o.triangles.len()).sum::<usize>();
    let (open, through) = (open_edges(&whole), rays_through(&coarse, &whole, 3000, 7));
    println!(
        "cylinder, caps whole: {} triangles ({} affine in), every triangle diced: {}; open edges {open}; rays through {through}",
        count(&whole),
        report.affine_triangles,
        count(&all)
    );
    assert_eq!(report.affine_triangles, 16, "the caps' triangles");
    assert!(count(&whole) < count(&all), "the caps are diced less");
    assert_eq!((open, through), (0, 0), "no crack between whole caps and diced sides");
}
