//! Read and write throughput of a Mark III-sized frame (440 hololines × 336
//! emitters × 96 views, RGB, f16) with every compression, in MB/s of raw f16
//! samples, against a plain memory copy of the same bytes in the same run.
//! Also prints each compression's size ratio. `cargo bench --bench format_io`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use holo::format::{read, write, Compression, SampleType, WriteOptions};
use holo::geometry::rgb_channels;
use holo::Modulation;

/// Smooth content with a little noise, as rendered scenes have.
fn frame() -> Modulation {
    let mut g = holo::layout::mark3().geometry;
    g.channels = rgb_channels();
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    Modulation::from_fn(g, |c, j, e, v| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let noise = (state >> 40) as f32 / (1u64 << 24) as f32;
        let smooth = 0.5 + 0.4 * ((e as f32 * 0.05 + j as f32 * 0.03 + c as f32).sin() * (v as f32 * 0.02).cos());
        smooth + 0.01 * noise
    })
    .unwrap()
}

fn bench(c: &mut Criterion) {
    let m = frame();
    let raw_bytes = m.samples().len() as u64 * 2;
    let dir = tempfile::tempdir().unwrap();
    let mut group = c.benchmark_group("mark3_rgb_f16_frame");
    group
        .sample_size(10)
        .measurement_time(std::time::Duration::from_secs(4))
        .warm_up_time(std::time::Duration::from_secs(1));
    group.throughput(Throughput::Bytes(raw_bytes));

    let source = vec![0x3c00u16; m.samples().len()];
    let mut target = vec![0u16; m.samples().len()];
    group.bench_function("memcpy", |b| b.iter(|| target.copy_from_slice(std::hint::black_box(&source))));

    for compression in Compression::ALL {
        let path = dir.path().join(format!("{}.holo", compression.name()));
        let options =
            WriteOptions { sample_type: SampleType::F16, compression, overwrite: true, ..WriteOptions::default() };
        let report = write(&path, &m, &options).unwrap();
        eprintln!(
            "size {:>6}: {:>10} bytes = {:5.1}% of raw f16",
            compression.name(),
            report.file_bytes,
            100.0 * report.file_bytes as f64 / raw_bytes as f64
        );
        group.bench_function(format!("write_{}", compression.name()), |b| {
            b.iter(|| write(&path, &m, &options).unwrap())
        });
        group.bench_function(format!("read_{}", compression.name()), |b| b.iter(|| read(&path).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
