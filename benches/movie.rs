//! HoloFlick playback into modulation (issue 7): one frame of about 400 000
//! lit micropolygons (the bundled Spot, encoded for Mark III by `holoflick
//! encode`) drawn into a Mark III frame — decode, place, cull, render — in
//! frames per second, beside the 15 frames/s Deering reports for real-time
//! playback of such frames on 1998 graphics hardware (seed 001 §10, one
//! view; here every view of every emitter).
//!
//! `cargo bench --bench movie` (`-- --test`: one quick pass).

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use holo::holoflick::container::HoloFlickReader;
use holo::holoflick::encode::{encode_holoflick, HoloFlickEncodeOptions};
use holo::holoflick::objects::{decode_block, mesh_light, to_world};
use holo::mesh::render::{render_into, Engine, RenderOptions, Supersample};
use holo::mesh::shade::Lighting;
use holo::mesh::{Light, Scene};
use holo::Modulation;

#[allow(dead_code)] // `band` is for the benchmarks that time slow references on a band
mod common;

/// Decode, place and draw frame 0 into `frame`.
fn play(reader: &mut HoloFlickReader, frame: &mut Modulation, options: &RenderOptions) -> usize {
    let f = reader.read_frame(0).expect("frame");
    let mut scene = Scene::default();
    for o in &f.objects {
        let (local, _) = decode_block("object", &o.block).expect("decode");
        let mut world = to_world(&local, &o.world_from_object, o.radiance_scale).expect("place");
        world.material.specular = [0.2; 3];
        world.material.shininess = 30.0;
        scene.objects.push(world);
    }
    let lights: Vec<Light> = f.frame.lights.iter().map(mesh_light).collect();
    // The frame's lights exactly, as `holo convert holoflick` renders it.
    let exact = RenderOptions::lit_exactly(Lighting { lights, ..options.lighting.clone() });
    let options = RenderOptions { supersample: options.supersample, engine: options.engine, ..exact };
    render_into(&scene, &options, &holo::progress::Silent, frame).expect("render");
    scene.triangle_count()
}

fn bench(c: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    let layout = holo::layout::Layout::load("mark3").expect("mark3");
    let g = &layout.geometry;
    let dir = tempfile::tempdir().expect("temp dir");
    let spot = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/mesh/spot/spot.obj");
    let hflk = dir.path().join("spot.hflk");
    // 2.2× what Mark III resolves gives about 400 000 micropolygons.
    let options = HoloFlickEncodeOptions { micropolygon: 2.2, ..HoloFlickEncodeOptions::default() };
    let encoded = encode_holoflick(&spot, g, &hflk, &options, &holo::progress::Silent).expect("encode");
    let mut reader = HoloFlickReader::open(&hflk).expect("open");
    let mut frame = Modulation::zeros(g.clone()).expect("frame");
    let render = RenderOptions {
        supersample: Supersample { emitter: 1, view: 1 },
        engine: Engine::Fast,
        ..RenderOptions::default()
    };
    let runs = if quick { 1 } else { 3 };
    let mut drawn = 0;
    let seconds = common::time(runs, || drawn = play(&mut reader, &mut frame, &render));
    let decode_seconds = common::time(runs, || {
        let f = reader.read_frame(0).expect("frame");
        for o in &f.objects {
            criterion::black_box(decode_block("object", &o.block).expect("decode"));
        }
    });
    println!(
        "\nHoloFlick frame of {} micropolygons ({} bytes) → Mark III {}×{}×{}: {:.3} s/frame = {:.2} frames/s \
         (decode alone {:.3} s = {:.1} M micropolygons/s); Deering, one view in real time: 15 frames/s\n",
        encoded.micropolygons,
        encoded.pack.file_bytes,
        g.hololines,
        g.emitters,
        g.views.count,
        seconds,
        1.0 / seconds,
        decode_seconds,
        drawn as f64 / decode_seconds / 1e6
    );
    let mut group = c.benchmark_group("movie");
    group.sample_size(10);
    group.bench_function("spot_400k_micropolygons_mark3", |b| b.iter(|| play(&mut reader, &mut frame, &render)));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
