//! Read and write throughput of a Mark III-sized frame (440 hololines × 336
//! emitters × 96 views, RGB, f16) with every compression, in MB/s of raw f16
//! samples, against a plain memory copy of the same bytes in the same run.
//! Also prints each compression's size ratio. `cargo bench --bench format_io`
//!
//! Before the timed runs it prints a second table, on ordinary rendered
//! content: the bundled Spot converted for Mark III (black around the cow, so
//! lossy codecs meet dark edges), stored with every compression as f16 (and
//! pxr24 as f32, where it is lossy): size, the largest and mean error against
//! the f32 rendering, and write and read speed (median of three, one with
//! `--test`).
//!
//! Then a third: the deflates a ZIP writer could use, each on the same
//! predicted 16-line blocks of both contents, one thread: size and MiB/s of
//! raw samples. holo's ZIP writer uses libdeflate at [`holo::format::zip::LEVEL`].
//!
//! The group `full_parallax_frame` (spec §8): 96 rows × 96 emitters × 32 × 32
//! views, RGB, f16 (57 MB of raw f16): whole-frame write and read without
//! compression and with ZIP, and from the ZIP file one view, a window of 4 × 4
//! views and a band of 16 rows, each in MiB/s of the raw f16 it reads; the
//! reads' times against the whole frame's are the ratios BENCHMARKS.md keeps.

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

/// Size, error and speed of every compression on the bundled Spot.
fn compression_table(repeats: usize) -> Modulation {
    use holo::mesh::convert::{convert_mesh, ConvertOptions};
    use std::time::Instant;
    let dir = tempfile::tempdir().unwrap();
    let spot = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("fixtures/mesh/spot/spot.obj");
    let exact_path = dir.path().join("exact.holo");
    let options = ConvertOptions {
        write: WriteOptions { sample_type: SampleType::F32, ..WriteOptions::default() },
        ..ConvertOptions::default()
    };
    let g = holo::layout::mark3().geometry;
    convert_mesh(&spot, &g, &exact_path, &options, &holo::progress::Silent).unwrap();
    let exact = read(&exact_path).unwrap();
    let peak = exact.samples().iter().fold(0f32, |a, &b| a.max(b));
    let f16_bytes = exact.samples().len() as f64 * 2.0;
    let median = |mut t: Vec<f64>| {
        t.sort_by(f64::total_cmp);
        t[t.len() / 2]
    };
    println!(
        "\nThe bundled Spot for Mark III ({} samples, peak {peak:.3}), every compression:\n",
        exact.samples().len()
    );
    println!(
        "| compression | sample type | size of raw f16 | max error (of peak) | mean error (of peak) | decoded below zero \
         (most negative) | write MiB/s | read MiB/s |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let mut rows: Vec<(Compression, SampleType)> = Compression::ALL.iter().map(|&c| (c, SampleType::F16)).collect();
    rows.push((Compression::Pxr24, SampleType::F32));
    for (compression, sample_type) in rows {
        let path = dir.path().join(format!("{}-{sample_type:?}.holo", compression.name()));
        let options = WriteOptions { sample_type, compression, overwrite: true, ..WriteOptions::default() };
        let mut writes = Vec::new();
        let mut reads = Vec::new();
        let mut got = None;
        let mut bytes = 0;
        for _ in 0..repeats {
            let t = Instant::now();
            bytes = write(&path, &exact, &options).unwrap().file_bytes;
            writes.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            got = Some(read(&path).unwrap());
            reads.push(t.elapsed().as_secs_f64());
        }
        let got = got.unwrap();
        let (mut worst, mut sum) = (0f32, 0f64);
        for (a, b) in exact.samples().iter().zip(got.samples()) {
            worst = worst.max((a - b).abs());
            sum += f64::from((a - b).abs());
        }
        let mean = sum / exact.samples().len() as f64;
        // What the codec itself returned, before a reader sets negatives to zero.
        let file = holo::format::HoloFile::open(&path).unwrap();
        let decoded = file.read_decoded(0, &holo::format::Region::all(&file.info().geometry)).unwrap();
        let below: Vec<f32> = decoded.samples().iter().copied().filter(|&x| x < 0.0).collect();
        let lowest = below.iter().fold(0f32, |a, &b| a.min(b));
        let mib = f16_bytes / (1 << 20) as f64;
        println!(
            "| {} | {sample_type:?} | {:.1}% | {worst:.2e} ({:.2}%) | {mean:.2e} ({:.4}%) | {} ({lowest:.1e}) | {:.0} | {:.0} |",
            compression.name(),
            100.0 * bytes as f64 / f16_bytes,
            100.0 * worst / peak,
            100.0 * mean / f64::from(peak),
            below.len(),
            mib / median(writes),
            mib / median(reads),
        );
    }
    println!();
    exact
}

/// Every ZIP block of `m` (f16, 16 lines), predicted as OpenEXR's ZIP
/// does before deflating: the blocks of an uncompressed file, as stored.
fn predicted_blocks(m: &Modulation) -> Vec<Vec<u8>> {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("none.holo");
    let options = WriteOptions { compression: Compression::None, ..WriteOptions::default() };
    write(&path, m, &options).unwrap();
    let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
    let reader = exr::block::read(file, true).unwrap();
    let meta = reader.meta_data().clone();
    let lines: Vec<Vec<u8>> = reader
        .all_chunks(true)
        .unwrap()
        .map(|c| exr::block::UncompressedBlock::decompress_chunk(c.unwrap(), &meta, true).unwrap().data)
        .collect();
    // An uncompressed file has one line a block; ZIP blocks are 16.
    lines.chunks(16).map(|ls| holo::format::zip::predict(&ls.concat())).collect()
}

/// Size and one-thread speed of each deflate on the predicted blocks of the
/// Spot and of the synthetic frame.
fn deflate_table(contents: &[(&str, &Modulation)]) {
    use std::time::Instant;
    type Deflate = Box<dyn Fn(&[u8]) -> usize>;
    let libdeflate = |level: i32| -> Deflate {
        Box::new(move |b: &[u8]| {
            let mut c = libdeflater::Compressor::new(libdeflater::CompressionLvl::new(level).unwrap());
            let mut out = vec![0u8; c.zlib_compress_bound(b.len())];
            c.zlib_compress(b, &mut out).unwrap()
        })
    };
    let zlib_rs = |level: u32| -> Deflate {
        Box::new(move |b: &[u8]| {
            use std::io::Write;
            let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::new(level));
            e.write_all(b).unwrap();
            e.finish().unwrap().len()
        })
    };
    let miniz =
        |level: u8| -> Deflate { Box::new(move |b: &[u8]| miniz_oxide::deflate::compress_to_vec_zlib(b, level).len()) };
    let candidates: Vec<(String, Deflate)> = vec![
        ("exr crate (miniz_oxide 4), before".into(), miniz(4)),
        ("miniz_oxide 1".into(), miniz(1)),
        ("zlib-rs 1".into(), zlib_rs(1)),
        ("zlib-rs 4".into(), zlib_rs(4)),
        ("zlib-rs 6".into(), zlib_rs(6)),
        ("libdeflate 1".into(), libdeflate(1)),
        ("libdeflate 4".into(), libdeflate(4)),
        ("libdeflate 6".into(), libdeflate(6)),
        ("libdeflate 9".into(), libdeflate(9)),
    ];
    let ours = format!("libdeflate {}", holo::format::zip::LEVEL);
    let candidates: Vec<(String, Deflate)> = candidates
        .into_iter()
        .map(|(name, d)| if name == ours { (format!("{name} (holo's)"), d) } else { (name, d) })
        .collect();
    let blocks: Vec<(&str, Vec<Vec<u8>>)> = contents.iter().map(|(n, m)| (*n, predicted_blocks(m))).collect();
    println!("\nDeflates for ZIP blocks, one thread (size of raw f16, MiB/s of raw):\n");
    println!(
        "| deflate | {} |",
        contents.iter().map(|(n, _)| format!("{n}: size | {n}: MiB/s")).collect::<Vec<_>>().join(" | ")
    );
    println!("|---|{}", "---|---|".repeat(contents.len()));
    for (name, deflate) in &candidates {
        let mut row = format!("| {name} |");
        for (_, bs) in &blocks {
            let raw: usize = bs.iter().map(Vec::len).sum();
            let t = Instant::now();
            let size: usize = bs.iter().map(|b| deflate(b).min(b.len())).sum();
            let s = t.elapsed().as_secs_f64();
            row += &format!(" {:.1}% | {:.0} |", 100.0 * size as f64 / raw as f64, raw as f64 / (1 << 20) as f64 / s);
        }
        println!("{row}");
    }
    println!();
}

/// A full-parallax frame: smooth content with a little noise.
fn full_parallax_frame() -> Modulation {
    use holo::geometry::{Geometry, ViewSpacing, Views};
    let views = Views { count: 32, first_theta_rad: -0.25, last_theta_rad: 0.25, spacing: ViewSpacing::Tan };
    let g = Geometry::centred(96, 96, views.clone(), 5e-4, 5e-4, 0.0, 0.5, rgb_channels()).with_vertical_views(views);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    Modulation::from_fn(g, |c, j, e, v| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let noise = (state >> 40) as f32 / (1u64 << 24) as f32;
        0.5 + 0.4 * ((e as f32 * 0.05 + j as f32 * 0.03 + c as f32).sin() * (v as f32 * 0.002).cos()) + 0.01 * noise
    })
    .unwrap()
}

fn bench_full_parallax(c: &mut Criterion) {
    use holo::format::Region;
    let m = full_parallax_frame();
    let g = m.geometry().clone();
    let raw = |samples: u64| samples * 2;
    let dir = tempfile::tempdir().unwrap();
    let mut group = c.benchmark_group("full_parallax_frame");
    group
        .sample_size(10)
        .measurement_time(std::time::Duration::from_secs(4))
        .warm_up_time(std::time::Duration::from_secs(1));
    for compression in [Compression::None, Compression::Zip] {
        let path = dir.path().join(format!("{}.holo", compression.name()));
        let options = WriteOptions { compression, overwrite: true, ..WriteOptions::default() };
        let report = write(&path, &m, &options).unwrap();
        eprintln!(
            "full parallax {}: {} bytes = {:.1}% of raw f16",
            compression.name(),
            report.file_bytes,
            100.0 * report.file_bytes as f64 / raw(g.samples_per_frame()) as f64
        );
        group.throughput(Throughput::Bytes(raw(g.samples_per_frame())));
        group.bench_function(format!("write_{}", compression.name()), |b| {
            b.iter(|| write(&path, &m, &options).unwrap())
        });
        group.bench_function(format!("read_{}", compression.name()), |b| b.iter(|| read(&path).unwrap()));
        if compression == Compression::Zip {
            let file = holo::HoloFile::open(&path).unwrap();
            let all = Region::all(&g);
            for (name, region) in [
                ("read_zip_one_view", Region { views: 16..17, vertical_views: 16..17, ..all.clone() }),
                ("read_zip_4x4_views", Region { views: 14..18, vertical_views: 14..18, ..all.clone() }),
                ("read_zip_16_rows", Region { hololines: 40..56, ..all.clone() }),
            ] {
                let samples = (region.hololines.len()
                    * region.emitters.len()
                    * region.views.len()
                    * region.vertical_views.len()
                    * g.channels.len()) as u64;
                group.throughput(Throughput::Bytes(raw(samples)));
                group.bench_function(name, |b| b.iter(|| file.read_region(0, &region).unwrap()));
            }
        }
    }
    group.finish();
}

fn bench(c: &mut Criterion) {
    let quick = std::env::args().any(|a| a == "--test");
    let spot = compression_table(if quick { 1 } else { 3 });
    let m = frame();
    deflate_table(&[("Spot", &spot), ("synthetic RGB", &m)]);
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
        if matches!(compression, Compression::None | Compression::Zip) {
            // The stored f16 samples as they are, no f32 pass (Python's `dtype=numpy.float16`).
            let file = holo::HoloFile::open(&path).unwrap();
            group.bench_function(format!("read_{}_as_f16", compression.name()), |b| {
                b.iter(|| file.read_frame_samples::<half::f16>(0).unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench, bench_full_parallax);
criterion_main!(benches);
