//! Assembly speed: frames per second for full frames of the built-in layouts,
//! the fast path against the straightforward per-sample loop in the same run
//! (Mark III, Mark I), and the fast path alone for Mark IV and Mark II.
//! Mark III: 6 signals × 440 hololines × 24576 samples × 16 overlapping chirps.
//! `cargo bench --bench assemble`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use holo::assemble::{Assembler, Plan};
use holo::layout::Layout;
use holo::Modulation;

/// Smooth content lit everywhere (no emitter or hololine skipped).
fn frame(layout: &Layout) -> Modulation {
    Modulation::from_fn(layout.geometry.clone(), |c, j, e, v| {
        0.5 + 0.5 * ((e as f32 * 0.07 + v as f32 * 0.11 + j as f32 * 0.3 + c as f32).sin())
    })
    .unwrap()
}

/// Every signal of every hololine through the straightforward loop, one thread.
fn straightforward(a: &Assembler, m: &Modulation) -> f32 {
    let mut checksum = 0f32;
    for colour in 0..m.geometry().channels.len() {
        let plan = a.plan(colour);
        let samples = plan.basis().samples;
        let (mut re, mut im) = (vec![0f32; samples], vec![0f32; samples]);
        for j in 0..m.geometry().hololines {
            let w = Plan::weights(m.hololine(colour, j)).unwrap();
            for zone in 0..plan.basis().zones() {
                plan.zone_straightforward(&w, zone, &mut re, &mut im);
                checksum += re[samples / 2] + im[samples / 2];
            }
        }
    }
    checksum
}

fn bench(c: &mut Criterion) {
    for name in ["mark3", "mark1"] {
        let layout = holo::layout::builtin(name).unwrap();
        let a = Assembler::new(&layout).unwrap();
        let m = frame(&layout);
        let mut group = c.benchmark_group(format!("{name}_frame"));
        group.sample_size(10).measurement_time(std::time::Duration::from_secs(10));
        group.throughput(Throughput::Elements(1));
        let mut bytes = a.blank_images::<u8>();
        group.bench_function("fast_u8_frame_buffer", |b| b.iter(|| a.assemble_into(&m, &mut bytes).unwrap()));
        // Emitter phases other than zero (spec/layouts.md §4.6) cost a
        // second kernel pass per zone: side by side with the line above.
        let mut phased_layout = layout.clone();
        phased_layout.fringe.as_mut().unwrap().emitter_phases = holo::layout::EmitterPhases::Viewer;
        let phased = Assembler::new(&phased_layout).unwrap();
        group.bench_function("fast_u8_frame_buffer_viewer_phases", |b| {
            b.iter(|| phased.assemble_into(&m, &mut bytes).unwrap())
        });
        // Segments cross-faded over a whole segment (spec/layouts.md §4.7).
        let mut tapered_layout = layout.clone();
        if let holo::layout::Basis::Chirp {
            segment_taper_samples,
            piece_taper_samples,
            views_per_zone,
            chirp_samples,
            ..
        } = &mut tapered_layout.fringe.as_mut().unwrap().basis
        {
            *segment_taper_samples = *chirp_samples / *views_per_zone;
            *piece_taper_samples = 0;
        }
        let tapered = Assembler::new(&tapered_layout).unwrap();
        group.bench_function("fast_u8_frame_buffer_segment_taper", |b| {
            b.iter(|| tapered.assemble_into(&m, &mut bytes).unwrap())
        });
        // Hard zone-piece ends (`piece_taper_samples = 0`, Mark III's basis
        // before its piece taper, spec/layouts.md §4.2), against the default.
        let mut hard_layout = layout.clone();
        if let holo::layout::Basis::Chirp { piece_taper_samples, .. } = &mut hard_layout.fringe.as_mut().unwrap().basis
        {
            if *piece_taper_samples > 0 {
                *piece_taper_samples = 0;
                let hard = Assembler::new(&hard_layout).unwrap();
                group.bench_function("fast_u8_frame_buffer_hard_piece_ends", |b| {
                    b.iter(|| hard.assemble_into(&m, &mut bytes).unwrap())
                });
            }
        }
        // Without the layout's blanking gains (spec/layouts.md §5.5; `--raw-blanking`).
        if layout.fringe.as_ref().unwrap().blanking_gains.is_some() {
            let mut raw_layout = layout.clone();
            raw_layout.fringe.as_mut().unwrap().blanking_gains = None;
            let raw = Assembler::new(&raw_layout).unwrap();
            group.bench_function("fast_u8_frame_buffer_raw_blanking", |b| {
                b.iter(|| raw.assemble_into(&m, &mut bytes).unwrap())
            });
            // An evenly lit frame: every run takes the flat-field gains (twice
            // the samples each side on Mark III), with them and without.
            let flat = Modulation::from_fn(layout.geometry.clone(), |_, _, _, _| 0.5).unwrap();
            group.bench_function("fast_u8_frame_buffer_flat_field", |b| {
                b.iter(|| a.assemble_into(&flat, &mut bytes).unwrap())
            });
            group.bench_function("fast_u8_frame_buffer_flat_field_raw_blanking", |b| {
                b.iter(|| raw.assemble_into(&flat, &mut bytes).unwrap())
            });
        }
        group.bench_function("fast_f32_signals", |b| b.iter(|| a.signals(&m, 0).unwrap()));
        group.bench_function("straightforward_one_thread", |b| b.iter(|| straightforward(&a, &m)));
        group.finish();
    }
    // The long hololines: the fast path only (the straightforward loop would take minutes a frame).
    for name in ["mark4", "mark2"] {
        let layout = holo::layout::builtin(name).unwrap();
        let a = Assembler::new(&layout).unwrap();
        let m = frame(&layout);
        let mut group = c.benchmark_group(format!("{name}_frame"));
        group.sample_size(10).measurement_time(std::time::Duration::from_secs(10));
        group.throughput(Throughput::Elements(1));
        let mut bytes = a.blank_images::<u8>();
        group.bench_function("fast_u8_frame_buffer", |b| b.iter(|| a.assemble_into(&m, &mut bytes).unwrap()));
        group.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
