//! Mark III assembly speed: frames per second for a full frame (3 zones × 440
//! hololines × 24576 samples × 16 overlapping chirps, I and Q), the fast path
//! against the straightforward per-sample loop in the same run.
//! `cargo bench --bench assemble`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use holo::assemble::mark3_assembler;
use holo::Modulation;

fn frame() -> Modulation {
    let g = holo::layout::mark3().geometry;
    Modulation::from_fn(g, |_, j, e, v| 0.5 + 0.5 * ((e as f32 * 0.07 + v as f32 * 0.11 + j as f32 * 0.3).sin()))
        .unwrap()
}

fn bench(c: &mut Criterion) {
    let a = mark3_assembler();
    let m = frame();
    let mut group = c.benchmark_group("mark3_frame");
    group.sample_size(10).measurement_time(std::time::Duration::from_secs(10));
    group.throughput(Throughput::Elements(1));
    let mut out = a.assemble(&m, 0).unwrap();
    group.bench_function("fast", |b| b.iter(|| a.assemble_into(&m, 0, &mut out).unwrap()));
    group.bench_function("straightforward", |b| b.iter(|| a.assemble_straightforward(&m, 0).unwrap()));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
