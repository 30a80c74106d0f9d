//! HoloFlick playback into modulation: one frame of about 400 000 lit
//! micropolygons (the bundled Spot, encoded for Mark III by `holoflick
//! encode`) drawn into a Mark III frame — decode, place, cull, render — in
//! frames per second, beside the 15 frames/s Deering reports for real-time
//! playback of such frames on 1998 graphics hardware (Deering, *HoloFlicks*
//! §10, one view; here every view of every emitter).
//!
//! Then the micropolygon size against error (the table behind
//! `holoflick encode`'s default): the bundled Spot and morphing cube encoded
//! for Mark III at each size, drawn, and compared with `convert mesh` of the
//! same frame.
//!
//! Last, a whole movie as a user makes one: the bundled animated glTF
//! (Khronos' AnimatedMorphCube) converted for Mark III, 30 frames into one
//! `.holo` file, then assembled into PNG fringes, with the time per frame in
//! every stage the commands' `--timings` report.
//!
//! `cargo bench --bench movie` (`-- --test`: one quick pass, sizes 8 and 4
//! only, 3 frames of the movie).

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use holo::holoflick::container::HoloFlickReader;
use holo::holoflick::convert::{HoloFlickConvertOptions, HoloFlickSource};
use holo::holoflick::encode::{encode_holoflick, HoloFlickEncodeOptions};
use holo::holoflick::objects::decode_block;
use holo::mesh::render::{Engine, RenderOptions, Supersample};
use holo::pipeline::{Source, Warnings};
use holo::{Band, Modulation};

#[allow(dead_code)] // `band` is for the benchmarks that time slow references on a band
mod common;

/// Draw frame 0 into `band` as `holo convert holoflick` does (read, decode,
/// place, cull, render; the source keeps its objects' lists from frame to
/// frame, as it does through a movie).
fn play(source: &mut HoloFlickSource, band: &mut Band) {
    source.render(0, band, &holo::progress::Silent, &mut Warnings::default()).expect("render");
}

fn bench(c: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    let layout = holo::layout::Layout::load("mark3").expect("mark3");
    let g = &layout.geometry;
    let dir = tempfile::tempdir().expect("temp dir");
    let spot = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("fixtures/mesh/spot/spot.obj");
    let hflk = dir.path().join("spot.hflk");
    // 2.2× what Mark III resolves gives about 400 000 micropolygons.
    let options = HoloFlickEncodeOptions { micropolygon: 2.2, ..HoloFlickEncodeOptions::default() };
    let encoded = encode_holoflick(&spot, g, &hflk, &options, &holo::progress::Silent).expect("encode");
    let mut reader = HoloFlickReader::open(&hflk).expect("open");
    let render =
        RenderOptions { supersample: Supersample::new(1, 1), engine: Engine::Fast, ..RenderOptions::default() };
    let convert = HoloFlickConvertOptions { render, ..HoloFlickConvertOptions::default() };
    let mut source = HoloFlickSource::open(&hflk, g, &convert).expect("open");
    source.place(&(0..1), &mut Warnings::default()).expect("place");
    let mut band = Band::zeros(g.clone(), 0..g.hololines).expect("frame");
    let runs = if quick { 1 } else { 3 };
    play(&mut source, &mut band);
    let seconds = common::time(runs, || play(&mut source, &mut band));
    let mut drawn = 0;
    let decode_seconds = common::time(runs, || {
        let f = reader.read_frame(0).expect("frame");
        drawn = 0;
        for o in &f.objects {
            drawn += criterion::black_box(decode_block("object", &o.block).expect("decode")).0.triangles.len();
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
    group.bench_function("spot_400k_micropolygons_mark3", |b| b.iter(|| play(&mut source, &mut band)));
    group.finish();
}

/// Σ|a − b| / Σ|b| over every sample.
fn relative_error(a: &Modulation, b: &Modulation) -> f64 {
    let diff: f64 = a.samples().iter().zip(b.samples()).map(|(x, y)| (*x as f64 - *y as f64).abs()).sum();
    diff / b.samples().iter().map(|y| (*y as f64).abs()).sum::<f64>()
}

/// Micropolygon size against error, bytes and time, frame 0 of each scene on Mark III.
fn micropolygon_table(quick: bool) {
    use holo::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
    use holo::mesh::convert::{convert_mesh, ConvertOptions, SceneFramesOptions};
    let g = holo::layout::Layout::load("mark3").expect("mark3").geometry;
    let dir = tempfile::tempdir().expect("temp dir");
    let fixtures = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("fixtures/mesh");
    let frames = SceneFramesOptions { frames: Some(0..1), ..SceneFramesOptions::default() };
    println!(
        "scene | micropolygon size | micropolygons | .hflk bytes | encode s | draw s | error against convert mesh"
    );
    for scene in ["spot/spot.obj", "AnimatedMorphCube.glb"] {
        let input = fixtures.join(scene);
        let direct = dir.path().join("direct.holo");
        let mut options = ConvertOptions { scene: frames.clone(), ..ConvertOptions::default() };
        options.write.overwrite = true;
        convert_mesh(&input, &g, &direct, &options, &holo::progress::Silent).expect("convert mesh");
        let truth = holo::read(&direct).expect("read");
        let sizes: &[f64] = if quick { &[8.0, 4.0] } else { &[8.0, 4.0, 2.0, 1.0] };
        for &size in sizes {
            let (hflk, out) = (dir.path().join("f.hflk"), dir.path().join("f.holo"));
            let options = HoloFlickEncodeOptions {
                micropolygon: size,
                scene: frames.clone(),
                overwrite: true,
                ..HoloFlickEncodeOptions::default()
            };
            let started = std::time::Instant::now();
            let encoded = encode_holoflick(&input, &g, &hflk, &options, &holo::progress::Silent).expect("encode");
            let encode_s = started.elapsed().as_secs_f64();
            let mut convert = HoloFlickConvertOptions::default();
            convert.write.overwrite = true;
            let started = std::time::Instant::now();
            convert_holoflick(&hflk, &g, &out, &convert, &holo::progress::Silent).expect("draw");
            let draw_s = started.elapsed().as_secs_f64();
            let error = relative_error(&holo::read(&out).expect("read"), &truth);
            println!(
                "{scene} | {size} | {} | {} | {encode_s:.2} | {draw_s:.2} | {error:.4}",
                encoded.micropolygons, encoded.pack.file_bytes
            );
        }
    }
}

/// A 30-frame movie through `convert mesh` and `assemble`, timed by stage.
fn whole_movie_table(quick: bool) {
    use holo::assemble::output::{assemble_file, AssembleOptions, FringeFormat};
    use holo::mesh::convert::{convert_mesh, ConvertOptions, SceneFramesOptions};
    let frames = if quick { 3 } else { 30 };
    let layout = holo::layout::Layout::load("mark3").expect("mark3");
    let dir = tempfile::tempdir().expect("temp dir");
    let cube = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("fixtures/mesh/AnimatedMorphCube.glb");
    let movie = dir.path().join("cube.holo");
    let options = ConvertOptions {
        scene: SceneFramesOptions { frames: Some(0..frames), frames_per_second: 30.0, ..SceneFramesOptions::default() },
        ..ConvertOptions::default()
    };
    let started = std::time::Instant::now();
    let converted = convert_mesh(&cube, &layout.geometry, &movie, &options, &holo::progress::Silent).expect("convert");
    let converting = started.elapsed();
    let assemble = AssembleOptions { frames: None, format: FringeFormat::Png, overwrite: false, resample: false };
    let started = std::time::Instant::now();
    let assembled = assemble_file(&movie, &layout, &dir.path().join("fringes"), &assemble, &holo::progress::Silent)
        .expect("assemble");
    let assembling = started.elapsed();
    println!(
        "\nA whole movie: AnimatedMorphCube, {frames} frames at 30/s, Mark III (2×2 sub-rays), .holo {} bytes, \
         then PNG fringes; ms per frame:\n",
        converted.written.file_bytes
    );
    println!("| command | stage | ms per frame |");
    println!("|---|---|---:|");
    let per_frame = |t: std::time::Duration| 1e3 * t.as_secs_f64() / frames as f64;
    for (command, timings, total) in
        [("convert mesh", &converted.timings, converting), ("assemble", &assembled.timings, assembling)]
    {
        for (stage, t) in timings.stages() {
            println!("| {command} | {stage} | {:.1} |", per_frame(*t));
        }
        println!("| {command} | **whole command** | **{:.1}** |", per_frame(total));
    }
    println!(
        "| both | **end to end** | **{:.1}** ({:.2} frames/s) |",
        per_frame(converting + assembling),
        frames as f64 / (converting + assembling).as_secs_f64()
    );
    println!();
}

fn table(_: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    micropolygon_table(quick);
    whole_movie_table(quick);
}

criterion_group!(benches, bench, table);
criterion_main!(benches);
