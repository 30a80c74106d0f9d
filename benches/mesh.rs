//! Mesh rendering speed: Mark III frames (440 hololines × 336 emitters ×
//! 96 views) of a ~500-triangle and a ~37k-triangle model with the fast EPI
//! rasteriser, the reference ray caster in the same run on a band of
//! hololines (its time scaled up to a frame, labelled so), and a table of
//! supersampling factor against run time and error; the same fast against
//! reference for full parallax (Mark III's emitters with 9 vertical views).
//! `cargo bench --bench mesh` (`-- --test`: one quick pass, as CI runs it).
//!
//! The models: the bundled 500-triangle textured Spot, the 37k-triangle
//! ClearCoatTest from `../shared/data` (skipped, and said so, without it),
//! and two procedural stand-ins without textures that take the vectorised
//! shading path ([`model`]). Two more tables: Spot behind and before panes
//! of glass (glTF BLEND) against the same panes opaque ([`panes`]), and
//! cooling fins finer than the emitters against supersampling ([`fins`]).

mod common;
use common::{band, process_cpu_time, time};

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use holo::geometry::Geometry;
use holo::mesh::place::{place, Placement};
use holo::mesh::render::{render, render_into, Engine, RenderOptions, Supersample};
use holo::mesh::{AlphaMode, Material, Object, Scene};
use holo::Modulation;

/// The two test models.
#[derive(Clone, Copy, Debug)]
enum Model {
    /// fixtures/mesh/spot: 500 triangles, textured, flat-shaded.
    Spot,
    /// Khronos ClearCoatTest: ~37k triangles, normal maps, several materials.
    ClearCoat,
    /// A ~500-triangle closed smooth sphere with a vertex-colour pattern.
    Small,
    /// A ~37k-triangle bumpy torus with vertex colours and a sharper highlight.
    Large,
}

impl Model {
    fn label(self) -> &'static str {
        match self {
            Model::Spot => "spot",
            Model::ClearCoat => "clearcoat",
            Model::Small => "sphere500",
            Model::Large => "torus37k",
        }
    }
}

/// The model, fitted to `g`; `None` (with a note) when its file is absent.
fn model(which: Model, g: &Geometry) -> Option<Scene> {
    let file = |path: std::path::PathBuf| -> Option<Scene> {
        if !path.exists() {
            println!("SKIPPED {which:?}: {} not present", path.display());
            return None;
        }
        let mut scene = holo::mesh::load::SceneSource::open(&path).and_then(|s| s.scene_at(0.0)).expect("load");
        place(&mut scene, g, &Placement::default()).expect("placement");
        Some(scene)
    };
    let root = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    let object = match which {
        Model::Spot => return file(root.join("fixtures/mesh/spot/spot.obj")),
        Model::ClearCoat => {
            let shared = std::env::var("HOLO_SHARED_DATA")
                .map(std::path::PathBuf::from)
                .unwrap_or_else(|_| root.join("../shared/data"));
            return file(shared.join("gltf_khronos_ClearCoatTest_normalmaps/glTF/ClearCoatTest.gltf"));
        }
        // 16 × 16 × 2 = 512 triangles.
        Model::Small => surface(16, 16, 30.0, |u, v| {
            let (th, ph) = (std::f64::consts::PI * v, 2.0 * std::f64::consts::PI * u);
            [th.sin() * ph.cos(), th.cos(), th.sin() * ph.sin()]
        }),
        // 192 × 96 × 2 = 36 864 triangles.
        Model::Large => surface(192, 96, 80.0, |u, v| {
            let (a, b) = (2.0 * std::f64::consts::PI * u, 2.0 * std::f64::consts::PI * v);
            let r = 0.35 * (1.0 + 0.12 * (7.0 * a).sin() * (5.0 * b).cos());
            let ring = 1.0 + r * b.cos();
            [ring * a.cos(), r * b.sin(), ring * a.sin()]
        }),
    };
    let mut scene = Scene { source: format!("procedural {which:?}"), objects: vec![object], ..Scene::default() };
    place(&mut scene, g, &Placement::default()).expect("placement");
    Some(scene)
}

/// A closed parametric surface over `[0, 1)²` (`nu × nv` quads, wrapping in
/// `u`; in `v` it wraps too unless the ends are poles), with smooth normals
/// averaged from the faces and a colour pattern.
fn surface(nu: usize, nv: usize, shininess: f32, f: impl Fn(f64, f64) -> [f64; 3]) -> Object {
    let mut o = Object {
        name: "procedural".into(),
        material: Material { base_colour: [1.0; 4], specular: [0.3; 3], shininess, ..Material::default() },
        ..Object::default()
    };
    for j in 0..nv {
        for i in 0..nu {
            let (u, v) = (i as f64 / nu as f64, j as f64 / nv as f64);
            o.positions.push(f(u, v));
            let c = 0.5 + 0.4 * (12.0 * u).sin() as f32 * (9.0 * v).cos() as f32;
            o.colours.push([c, 0.6 * (1.0 - c) + 0.2, 0.3 + 0.5 * v as f32, 1.0]);
        }
    }
    let at = |i: usize, j: usize| ((j % nv) * nu + i % nu) as u32;
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            o.triangles.push([a, d, b]);
            o.triangles.push([b, d, c]);
        }
    }
    // Smooth normals: area-weighted face normals, summed per vertex.
    let mut n = vec![[0.0f64; 3]; o.positions.len()];
    for t in &o.triangles {
        let p = t.map(|i| o.positions[i as usize]);
        let (e1, e2) = ([0, 1, 2].map(|k| p[1][k] - p[0][k]), [0, 1, 2].map(|k| p[2][k] - p[0][k]));
        let c = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
        for &i in t {
            for k in 0..3 {
                n[i as usize][k] += c[k];
            }
        }
    }
    o.normals = n
        .iter()
        .map(|v| {
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-30);
            [(v[0] / l) as f32, (v[1] / l) as f32, (v[2] / l) as f32]
        })
        .collect();
    // Make the front faces face outward: flip every triangle if most normals point in.
    let centre: Vec<f64> =
        (0..3).map(|k| o.positions.iter().map(|p| p[k]).sum::<f64>() / o.positions.len() as f64).collect();
    let inward = o
        .positions
        .iter()
        .zip(&o.normals)
        .filter(|(p, nn)| (0..3).map(|k| (p[k] - centre[k]) * nn[k] as f64).sum::<f64>() < 0.0)
        .count();
    if inward * 2 > o.positions.len() {
        for t in &mut o.triangles {
            t.swap(1, 2);
        }
        for nn in &mut o.normals {
            *nn = nn.map(|x| -x);
        }
    }
    o
}

/// Three panes across the display in front of, through and behind the
/// placed scene, tinted, double-sided, seen through as `mode` says (the
/// alpha of each is 0.5).
fn panes(scene: &mut Scene, mode: AlphaMode) {
    for (k, (z, tint)) in
        [(0.012, [0.9, 0.5, 0.4]), (0.0, [0.4, 0.9, 0.5]), (-0.012, [0.5, 0.4, 0.9])].into_iter().enumerate()
    {
        let (x, y) = ([-0.03 + 0.004 * k as f64, 0.03], [-0.02, 0.022 - 0.004 * k as f64]);
        scene.objects.push(Object {
            name: format!("pane {k}"),
            positions: vec![[x[0], y[0], z], [x[1], y[0], z], [x[1], y[1], z], [x[0], y[1], z]],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            material: Material {
                base_colour: [tint[0], tint[1], tint[2], 0.5],
                specular: [0.04; 3],
                shininess: 200.0,
                double_sided: true,
                alpha_mode: mode,
                ..Material::default()
            },
            ..Object::default()
        });
    }
}

/// An engine's cooling fins in display metres: `count` white fins 0.06 mm
/// thick, `pitch_m` apart across the middle of the display, 8 mm deep,
/// standing on a dark plate (their tops and sides seen, edge-on in the
/// central views).
fn fins(count: usize, pitch_m: f64) -> Scene {
    let mut o = Object {
        name: "fins".into(),
        material: Material {
            base_colour: [0.9, 0.9, 0.9, 1.0],
            specular: [0.2; 3],
            shininess: 30.0,
            ..Material::default()
        },
        ..Object::default()
    };
    let (y, z) = ([-0.02, 0.02], [-0.008, 0.0]);
    let quad = |o: &mut Object, p: [[f64; 3]; 4]| {
        let base = o.positions.len() as u32;
        o.positions.extend(p);
        o.triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
    };
    let half = 0.03e-3;
    for k in 0..count {
        let x = (k as f64 - (count as f64 - 1.0) / 2.0) * pitch_m;
        let (l, r) = (x - half, x + half);
        // Top (+z), right side (+x), left side (−x), counter-clockwise from outside.
        quad(&mut o, [[l, y[0], z[1]], [r, y[0], z[1]], [r, y[1], z[1]], [l, y[1], z[1]]]);
        quad(&mut o, [[r, y[0], z[1]], [r, y[0], z[0]], [r, y[1], z[0]], [r, y[1], z[1]]]);
        quad(&mut o, [[l, y[0], z[0]], [l, y[0], z[1]], [l, y[1], z[1]], [l, y[1], z[0]]]);
    }
    let w = pitch_m * count as f64 / 2.0 + 0.002;
    let plate = Object {
        name: "plate".into(),
        positions: vec![[-w, y[0], z[0]], [w, y[0], z[0]], [w, y[1], z[0]], [-w, y[1], z[0]]],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        material: Material { base_colour: [0.08, 0.08, 0.08, 1.0], ..Material::default() },
        ..Object::default()
    };
    Scene { source: "procedural fins".into(), objects: vec![o, plate], ..Scene::default() }
}

fn options(ss: usize, engine: Engine) -> RenderOptions {
    RenderOptions { supersample: Supersample::new(ss, ss), engine, ..RenderOptions::default() }
}

fn frame(scene: &Scene, g: &Geometry, o: &RenderOptions) -> Modulation {
    render(scene, g, o, &holo::progress::Silent).expect("render").0
}

/// Render into `reused`, as a movie does frame after frame (no fresh
/// 57 MB frame to fault in each time).
fn frame_into(scene: &Scene, o: &RenderOptions, reused: &mut Modulation) {
    render_into(scene, o, &holo::progress::Silent, reused).expect("render");
}

/// (mean |a − b| / mean b, fraction of samples off by > 1% of b's peak), as in tests/mesh/render.rs.
fn error(a: &Modulation, b: &Modulation) -> (f64, f64) {
    let peak = b.samples().iter().fold(0.0f32, |x, &y| x.max(y)) as f64;
    let mean = b.samples().iter().map(|&v| v as f64).sum::<f64>() / b.samples().len() as f64;
    let (mut sum, mut off) = (0.0, 0usize);
    for (x, y) in a.samples().iter().zip(b.samples()) {
        let d = (*x as f64 - *y as f64).abs();
        sum += d;
        off += (d > 0.01 * peak) as usize;
    }
    let n = a.samples().len() as f64;
    (sum / n / mean.max(1e-30), off as f64 / n)
}

/// The tables: fast against reference, and supersampling, printed as markdown.
fn tables(quick: bool) {
    let g = holo::layout::mark3().geometry;
    let runs = if quick { 1 } else { 3 };
    const BAND: usize = 8;
    let scale = g.hololines as f64 / BAND as f64;
    let b = band(&g, BAND);
    println!(
        "\n## Mark III ({} × {} × {} views), fast path against the reference ray caster",
        g.hololines, g.emitters, g.views.count
    );
    println!("Reference: a band of {BAND} central hololines, its time × {scale:.0} = per frame. Best of {runs}; {} threads.\n", rayon::current_num_threads());
    println!("Fast: rendering into one reused frame, as a movie conversion does; \"new frame\": allocating (and faulting in) a fresh frame each time.\n");
    println!("| model | triangles | ss | fast s/frame | fast frames/s | new frame s/frame | reference s/frame (band × {scale:.0}) | fast/reference speed-up | fast vs reference on the band: mean abs diff / mean, samples off >1% of peak |");
    println!("|---|---|---|---|---|---|---|---|---|");
    let mut reused = Modulation::zeros(g.clone()).expect("frame");
    reused.samples_mut().fill(0.0); // faulted in once, as a movie's frame is after its first
    for which in [Model::Spot, Model::ClearCoat, Model::Small, Model::Large] {
        let Some(scene) = model(which, &g) else { continue };
        for ss in [1, 2] {
            let fast = time(runs, || frame_into(&scene, &options(ss, Engine::Fast), &mut reused));
            let fresh = time(runs, || drop(frame(&scene, &g, &options(ss, Engine::Fast))));
            let mut reference_band = None;
            let reference =
                time(runs, || reference_band = Some(frame(&scene, &b, &options(ss, Engine::Reference)))) * scale;
            let (mean, off) = error(&frame(&scene, &b, &options(ss, Engine::Fast)), &reference_band.unwrap());
            println!(
                "| {} | {} | {ss}×{ss} | {fast:.3} | {:.1} | {fresh:.3} | {reference:.2} | {:.0}× | {mean:.1e}, {:.3}% |",
                which.label(),
                scene.triangle_count(),
                1.0 / fast,
                reference / fast,
                off * 100.0
            );
        }
    }
    full_parallax_table(runs);
    // Supersampling: error against the fast path at 8 × 8 with 8 lines per
    // hololine on the band (the fast path equals the reference within the
    // tests' bounds, and that much of the reference would take minutes).
    let scene = model(Model::ClearCoat, &g).or_else(|| model(Model::Large, &g)).expect("a procedural model");
    let with_lines = |ss: usize, lines: usize| RenderOptions {
        supersample: Supersample { emitter: ss, view: ss, hololine: lines },
        ..options(ss, Engine::Fast)
    };
    let truth = frame(&scene, &b, &with_lines(8, 8));
    println!(
        "\n## Supersampling (emitter × view, lines per hololine), {}-triangle model, fast path",
        scene.triangle_count()
    );
    println!("Time: full Mark III frames into a reused frame, best of {runs}. Error: against the fast path at 8×8 with 8 lines per hololine on the band of {BAND} central hololines.\n");
    println!("| ss | lines per hololine | s/frame | frames/s | mean abs error / mean | samples off >1% of peak |");
    println!("|---|---|---|---|---|---|");
    let mut reused = Modulation::zeros(g.clone()).expect("frame");
    reused.samples_mut().fill(0.0); // faulted in once, as a movie's frame is after its first
    for (ss, lines) in [(1, 1), (2, 1), (3, 1), (4, 1), (2, 2), (2, 4)] {
        let o = with_lines(ss, lines);
        let t = time(runs, || frame_into(&scene, &o, &mut reused));
        let (mean, off) = error(&frame(&scene, &b, &o), &truth);
        println!("| {ss}×{ss} | {lines} | {t:.3} | {:.1} | {mean:.2e} | {:.2}% |", 1.0 / t, off * 100.0);
    }
    println!();

    // See-through materials: the cost of compositing, against the same
    // scene opaque, both engines in the same run.
    println!("## Spot with three panes of glass (BLEND, alpha 0.5) against the same panes opaque");
    println!("Times in CPU seconds of the whole process (every thread), so that other work on the machine counts less; the best of {} runs, opaque and BLEND alternated. Fast: full frames into a reused frame; reference: the band × {scale:.0}; error: fast against reference on the band (BLEND).\n", if quick { 1 } else { 5 });
    println!("| panes | ss | fast CPU s/frame | fast BLEND / opaque | reference CPU s/frame | reference BLEND / opaque | fast vs reference: mean abs diff / mean, samples off >1% of peak |");
    println!("|---|---|---|---|---|---|---|");
    if let Some(spot) = model(Model::Spot, &g) {
        for ss in [1, 2] {
            let scenes = [AlphaMode::Opaque, AlphaMode::Blend].map(|mode| {
                let mut scene = spot.clone();
                panes(&mut scene, mode);
                scene
            });
            // Best of `turns` each, the two scenes taking turns.
            let turns = if quick { 1 } else { 5 };
            let (mut fast, mut reference) = ([f64::INFINITY; 2], [f64::INFINITY; 2]);
            for _ in 0..turns {
                for (k, scene) in scenes.iter().enumerate() {
                    let f = process_cpu_time(1, || frame_into(scene, &options(ss, Engine::Fast), &mut reused));
                    let r = process_cpu_time(1, || drop(frame(scene, &b, &options(ss, Engine::Reference))));
                    fast[k] = fast[k].min(f);
                    reference[k] = reference[k].min(r * scale);
                }
            }
            let blend = &scenes[1];
            let (mean, off) = error(
                &frame(blend, &b, &options(ss, Engine::Fast)),
                &frame(blend, &b, &options(ss, Engine::Reference)),
            );
            println!("| opaque | {ss}×{ss} | {:.3} | | {:.2} | | |", fast[0], reference[0]);
            println!(
                "| BLEND | {ss}×{ss} | {:.3} | {:.2}× | {:.2} | {:.2}× | {mean:.1e}, {:.3}% |",
                fast[1],
                fast[1] / fast[0],
                reference[1],
                reference[1] / reference[0],
                off * 100.0
            );
        }
    }
    println!();

    // Fine, dense geometry: fins 0.25 mm apart (Mark III's emitters are
    // 0.238 mm apart) against supersampling. The truth at 16 × 16 (8 × 8
    // still beats with the fins: 8.4 sub-rays a fin); one line per hololine,
    // as the fins run across the hololines.
    let fins = fins(160, 0.25e-3);
    let truth = frame(&fins, &b, &options(16, Engine::Fast));
    println!(
        "## Cooling fins ({} triangles, 0.25 mm apart, 0.06 mm thick) against supersampling, fast path",
        fins.triangle_count()
    );
    println!("Time: full Mark III frames into a reused frame, best of {runs}. Error: against the fast path at 16×16 on the band of {BAND} central hololines.\n");
    println!("| ss | lines per hololine | s/frame | mean abs error / mean | samples off >1% of peak |");
    println!("|---|---|---|---|---|");
    for (ss, lines) in [(1, 1), (2, 1), (3, 1), (4, 1), (6, 1), (2, 4)] {
        let o = with_lines(ss, lines);
        let t = time(runs, || frame_into(&fins, &o, &mut reused));
        let (mean, off) = error(&frame(&fins, &b, &o), &truth);
        println!("| {ss}×{ss} | {lines} | {t:.3} | {mean:.2e} | {:.2}% |", off * 100.0);
    }
    println!();
}

/// Mark III's emitters with [`FULL_PARALLAX_VERTICAL_VIEWS`] vertical views
/// over its horizontal cone: the geometry of the full-parallax rows.
fn mark3_full_parallax() -> Geometry {
    holo::layout::mark3().geometry.with_centred_vertical_views(FULL_PARALLAX_VERTICAL_VIEWS, None)
}

/// Vertical views of [`mark3_full_parallax`] (as the demo's full-parallax step).
const FULL_PARALLAX_VERTICAL_VIEWS: usize = 9;

/// Full parallax: the fast path against the reference on a band, as for
/// horizontal parallax (each emitter row and vertical view a plane of rays).
fn full_parallax_table(runs: usize) {
    let g = mark3_full_parallax();
    const BAND: usize = 8;
    let scale = g.hololines as f64 / BAND as f64;
    let b = band(&g, BAND);
    println!(
        "\n## Full parallax: Mark III's emitters, {} × {} views, fast path against the reference ray caster",
        g.views.count,
        g.vertical_view_count()
    );
    println!("Reference: a band of {BAND} central rows, its time × {scale:.0} = per frame. Best of {runs}. ss: sub-rays across each emitter and each view in both directions.\n");
    println!("| model | triangles | ss | fast s/frame | reference s/frame (band × {scale:.0}) | fast/reference speed-up | fast vs reference on the band: mean abs diff / mean, samples off >1% of peak |");
    println!("|---|---|---|---|---|---|---|");
    let mut reused = Modulation::zeros(g.clone()).expect("frame");
    reused.samples_mut().fill(0.0);
    for which in [Model::Spot, Model::Small] {
        let Some(scene) = model(which, &g) else { continue };
        for ss in [1, 2] {
            let fast = time(runs, || frame_into(&scene, &options(ss, Engine::Fast), &mut reused));
            let mut reference_band = None;
            let reference =
                time(runs, || reference_band = Some(frame(&scene, &b, &options(ss, Engine::Reference)))) * scale;
            let (mean, off) = error(&frame(&scene, &b, &options(ss, Engine::Fast)), &reference_band.unwrap());
            println!(
                "| {} | {} | {ss}×{ss} | {fast:.2} | {reference:.1} | {:.0}× | {mean:.1e}, {:.3}% |",
                which.label(),
                scene.triangle_count(),
                reference / fast,
                off * 100.0
            );
        }
    }
}

fn bench(c: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    tables(quick);
    let g = holo::layout::mark3().geometry;
    for which in [Model::Spot, Model::ClearCoat] {
        let Some(scene) = model(which, &g) else { continue };
        let mut group = c.benchmark_group(format!("mark3_mesh_{}", which.label()));
        group.sample_size(10).measurement_time(std::time::Duration::from_secs(10));
        group.throughput(Throughput::Elements(1));
        let mut reused = Modulation::zeros(g.clone()).expect("frame");
        reused.samples_mut().fill(0.0); // faulted in once, as a movie's frame is after its first
        for ss in [1, 2] {
            group.bench_function(format!("fast_frame_ss{ss}"), |bch| {
                bch.iter(|| frame_into(&scene, &options(ss, Engine::Fast), &mut reused))
            });
        }
        // Not a frame: 8 hololines of 440 (so its "elements/s" are bands, ×55 for frames).
        let b = band(&g, 8);
        group.bench_function("reference_band_of_8_hololines_ss1", |bch| {
            bch.iter(|| frame(&scene, &b, &options(1, Engine::Reference)))
        });
        group.finish();
    }
    let g = mark3_full_parallax();
    if let Some(scene) = model(Model::Spot, &g) {
        let mut group = c.benchmark_group("mark3_full_parallax_mesh_spot");
        group.sample_size(10).measurement_time(std::time::Duration::from_secs(20));
        group.throughput(Throughput::Elements(1));
        let mut reused = Modulation::zeros(g.clone()).expect("frame");
        reused.samples_mut().fill(0.0);
        group.bench_function("fast_frame_ss1", |bch| {
            bch.iter(|| frame_into(&scene, &options(1, Engine::Fast), &mut reused))
        });
        // Not a frame: 8 rows of 440 (×55 for frames).
        let b = band(&g, 8);
        group.bench_function("reference_band_of_8_rows_ss1", |bch| {
            bch.iter(|| frame(&scene, &b, &options(1, Engine::Reference)))
        });
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
