//! The assembly knobs: run time against recovery error, on Mark III.
//!
//! Each row is one combination of
//! - basis: the tabulated f32 fast path ([`Assembler::assemble_into`]), or the
//!   computed f64 reference ([`Assembler::signals_reference`], no tables),
//!   hololines in parallel, its signals encoded into the same frame buffer;
//! - input: the modulation's samples as f32, or rounded through f16 (a file
//!   stored as f16, the default; the rounding itself is not timed);
//! - output: a float frame buffer, or 8-bit codes with the layout's quantization.
//!
//! Run time: criterion's median for one 16-hololine frame, scaled linearly to a
//! full 440-hololine frame. Error: least-squares signal recovery from the frame
//! buffer ([`check`]), relative L2 against the ORIGINAL f32 modulation.
//! Prints a markdown table and writes `docs/knobs.svg` (log-log, time against error;
//! a quick pass writes `target/knobs.svg` instead).
//!
//! `cargo bench --bench knobs` (about 75 s; `-- --test` for a quick pass, timed by hand)

use std::path::PathBuf;
use std::time::{Duration, Instant, SystemTime};

use criterion::{criterion_group, Criterion, SamplingMode};
use holo::assemble::{Assembler, FrameImages, FringeSample};
use holo::layout::ColourSignals;
use holo::reconstruct::check::{check, FrameRef};
use holo::Modulation;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;

/// Hololines assembled and checked (the f64 reference is slow).
const HOLOLINES: usize = 16;
/// Hololines of a full Mark III frame, for the scaled run time.
const FULL_FRAME: usize = 440;

/// A layout option (spec/layouts.md §4.6, §4.7), tried with the product's
/// own knobs (tabulated basis, f16 input, 8-bit output).
#[derive(Clone, Copy, PartialEq)]
enum Shape {
    /// The layout as built in.
    Plain,
    /// `segment_taper_samples = 32`: no ghosts.
    Taper,
    /// `emitter_phases = "viewer"`: a coherent eye sees no ripple.
    Phases,
    /// Without the blanking gains (`--raw-blanking`): dark columns at the
    /// horizontal blanking.
    RawBlanking,
}

/// One combination of knobs: the computed f64 basis (else the tabulated f32
/// one), f16 input (else f32), an 8-bit frame buffer (else float), and the
/// layout's shape.
#[derive(Clone, Copy)]
struct Knobs {
    computed: bool,
    f16: bool,
    bytes: bool,
    shape: Shape,
}

impl Knobs {
    fn all() -> impl Iterator<Item = Knobs> {
        let plain =
            (0..8).map(|k| Knobs { computed: k & 4 != 0, bytes: k & 2 != 0, f16: k & 1 != 0, shape: Shape::Plain });
        let shaped = [Shape::Taper, Shape::Phases, Shape::RawBlanking].map(|shape| Knobs {
            computed: false,
            f16: true,
            bytes: true,
            shape,
        });
        plain.chain(shaped)
    }
    fn words(self) -> [&'static str; 4] {
        [
            if self.computed { "computed f64" } else { "tabulated f32" },
            if self.f16 { "f16" } else { "f32" },
            if self.bytes { "8-bit" } else { "float" },
            match self.shape {
                Shape::Plain => "",
                Shape::Taper => "segment taper 32",
                Shape::Phases => "viewer emitter phases",
                Shape::RawBlanking => "raw blanking",
            },
        ]
    }
    /// Criterion's function id (also its directory under target/criterion/knobs).
    fn id(self) -> String {
        let [b, i, o, shape] = self.words();
        let id = format!("{}_in-{i}_out-{}", b.replace(' ', "-"), o.replace("8-bit", "u8"));
        if shape.is_empty() {
            id
        } else {
            format!("{id}_{}", shape.replace(' ', "-"))
        }
    }
}

/// The assembler, the original modulation and its f16-rounded copy, and frame
/// buffers to reuse (timing without allocation).
struct Setup {
    a: Assembler,
    tapered: Assembler,
    phased: Assembler,
    raw: Assembler,
    original: Modulation,
    rounded: Modulation,
    floats: FrameImages<f32>,
    bytes: FrameImages<u8>,
}

impl Setup {
    fn new() -> Setup {
        let mut layout = holo::layout::mark3();
        layout.geometry.hololines = HOLOLINES;
        layout.fringe.as_mut().unwrap().frame_buffer.height = HOLOLINES * 6;
        let a = Assembler::new(&layout).unwrap();
        let mut shaped = layout.clone();
        if let holo::layout::Basis::Chirp { segment_taper_samples, piece_taper_samples, .. } =
            &mut shaped.fringe.as_mut().unwrap().basis
        {
            // Every segment edge cross-faded, the zone pieces' ends as well.
            *segment_taper_samples = 32;
            *piece_taper_samples = 0;
        }
        let tapered = Assembler::new(&shaped).unwrap();
        let mut shaped = layout.clone();
        shaped.fringe.as_mut().unwrap().emitter_phases = holo::layout::EmitterPhases::Viewer;
        let phased = Assembler::new(&shaped).unwrap();
        let mut shaped = layout.clone();
        shaped.fringe.as_mut().unwrap().blanking_gains = None;
        let raw = Assembler::new(&shaped).unwrap();
        let g = &layout.geometry;
        // Smooth content with a random phase per (channel, hololine), lit everywhere.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2024);
        let phases: Vec<f32> = (0..g.channels.len() * g.hololines).map(|_| rng.gen_range(0.0..6.3)).collect();
        let original = Modulation::from_fn(g.clone(), |c, j, e, v| {
            0.5 + 0.4 * (phases[c * g.hololines + j] + e as f32 * 0.05 + v as f32 * 0.07 + j as f32).sin()
        })
        .unwrap();
        let f16 = |x: &f32| half::f16::from_f32(*x).to_f32();
        let rounded = Modulation::from_samples(g.clone(), original.samples().iter().map(f16).collect()).unwrap();
        let (floats, bytes) = (a.blank_images(), a.blank_images());
        Setup { a, tapered, phased, raw, original, rounded, floats, bytes }
    }

    /// The assembler of knobs `k`'s layout shape.
    fn assembler(&self, k: Knobs) -> &Assembler {
        [&self.a, &self.tapered, &self.phased, &self.raw][k.shape as usize]
    }

    /// Assemble one frame with knobs `k` into the frame buffer of its kind.
    fn run(&mut self, k: Knobs) {
        let a = [&self.a, &self.tapered, &self.phased, &self.raw][k.shape as usize];
        let m = if k.f16 { &self.rounded } else { &self.original };
        match (k.computed, k.bytes) {
            (false, false) => drop(a.assemble_into(m, &mut self.floats).unwrap()),
            (false, true) => drop(a.assemble_into(m, &mut self.bytes).unwrap()),
            (true, false) => computed_into(a, m, &mut self.floats),
            (true, true) => computed_into(a, m, &mut self.bytes),
        }
    }
}

/// Frame images through the computed f64 basis: every hololine's reference
/// signals (hololines in parallel, as the fast path runs them), each sample
/// rounded to f32 and encoded as the fast path encodes it, at the pixel the
/// layout puts it (samples in the horizontal blanking are dropped, as there,
/// and those beside them take the layout's blanking gains).
fn computed_into<T: FringeSample>(a: &Assembler, m: &Modulation, out: &mut FrameImages<T>) {
    let fringe = a.layout().fringe.as_ref().unwrap();
    assert_eq!(fringe.colours, ColourSignals::Separate, "summed colours are not handled here");
    let (fb, q, signals) = (&fringe.frame_buffer, &fringe.quantization, a.layout().signals_per_hololine());
    for colour in 0..m.geometry().channels.len() {
        let per_colour = a.plan(colour).basis().signals();
        let reference: Vec<Vec<Vec<f64>>> = (0..m.geometry().hololines)
            .into_par_iter()
            .map(|j| a.signals_reference(m, colour, j..j + 1).unwrap().remove(0))
            .collect();
        for (j, hololine) in reference.into_iter().enumerate() {
            let mut hololine = hololine;
            // The blanking gains, as the fast path applies them.
            a.blanking_gains_reference(m, j, colour, &mut hololine);
            for (s, signal) in hololine.iter().enumerate() {
                let s = colour * per_colour + s;
                for (n, x) in signal.iter().enumerate() {
                    if let Some(p) = fb.place(j, s, n, signals, signal.len()) {
                        let at = (p.row * out.width + p.column) * out.components + p.component;
                        T::encode_line(&[*x as f32], false, &mut out.images[p.image][at..at + 1], q);
                    }
                }
            }
        }
    }
}

fn bench(c: &mut Criterion) {
    let mut s = Setup::new();
    let mut group = c.benchmark_group("knobs");
    group.sample_size(10).warm_up_time(Duration::from_secs(1));
    for k in Knobs::all() {
        // The f64 reference takes about 0.4 s for 16 hololines: few runs per sample.
        if k.computed {
            group.sampling_mode(SamplingMode::Flat).measurement_time(Duration::from_secs(8));
        } else {
            group.sampling_mode(SamplingMode::Auto).measurement_time(Duration::from_secs(3));
        }
        group.bench_function(k.id(), |bench| bench.iter(|| s.run(k)));
    }
    group.finish();
}

criterion_group!(benches, bench);

/// `criterion_main!(benches)` followed by the report.
fn main() {
    let started = SystemTime::now();
    benches();
    Criterion::default().configure_from_args().final_summary();
    if !std::env::args().any(|a| a == "--list") {
        report(started);
    }
}

/// Median run time of knobs `k` for one 16-hololine frame, ms: criterion's
/// estimate when this run wrote one, otherwise the median of 5 timed runs.
fn measured_ms(s: &mut Setup, k: Knobs, started: SystemTime) -> (f64, &'static str) {
    let dir = std::env::var_os("CRITERION_HOME").map(PathBuf::from).unwrap_or_else(|| {
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| "target".into(), PathBuf::from).join("criterion")
    });
    let file = dir.join("knobs").join(k.id()).join("new").join("estimates.json");
    let fresh = std::fs::metadata(&file).and_then(|m| m.modified()).is_ok_and(|t| t >= started);
    let estimate = fresh.then(|| std::fs::read_to_string(&file).ok()).flatten().and_then(|text| {
        let json: serde_json::Value = serde_json::from_str(&text).ok()?;
        json["median"]["point_estimate"].as_f64()
    });
    if let Some(ns) = estimate {
        return (ns / 1e6, "criterion median");
    }
    let mut times: Vec<f64> = (0..5)
        .map(|_| {
            let t = Instant::now();
            s.run(k);
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    (times[2], "median of 5 timed runs")
}

/// One row of the result.
struct Row {
    knobs: Knobs,
    ms_per_frame: f64,
    relative_l2: f64,
    psnr_db: f64,
    optical_l2: f64,
}

fn report(started: SystemTime) {
    let mut s = Setup::new();
    let (mut rows, mut optical, mut source) = (Vec::new(), 0.0, "");
    for k in Knobs::all() {
        let (ms, how) = measured_ms(&mut s, k, started);
        source = if source.is_empty() || source == how { how } else { "criterion medians and timed runs" };
        s.run(k);
        let images = if k.bytes { FrameRef::Bytes(&s.bytes) } else { FrameRef::Floats(&s.floats) };
        // Against the original f32 modulation, whatever the input knob.
        let r = check(s.assembler(k), &s.original, images, 0..HOLOLINES, &holo::progress::Silent).unwrap();
        if k.shape == Shape::Plain {
            optical = r.optical.relative_l2;
        }
        let ms_per_frame = ms * FULL_FRAME as f64 / HOLOLINES as f64;
        rows.push(Row {
            knobs: k,
            ms_per_frame,
            relative_l2: r.signal.relative_l2,
            psnr_db: r.signal.psnr_db,
            optical_l2: r.optical.relative_l2,
        });
    }
    // The bases themselves, before any frame buffer (Mark III has one colour):
    // the float-output rows sit on the floor of the least-squares solver
    // (tolerance 1e-7) and the f32 frame buffer, which hides this difference.
    let (fast, mut diff2, mut ref2) = (s.a.signals(&s.original, 0).unwrap(), 0.0, 0.0);
    for (j, hololine) in s.a.signals_reference(&s.original, 0, 0..HOLOLINES).unwrap().iter().enumerate() {
        for (sig, want) in hololine.iter().enumerate() {
            for (got, want) in fast.row(sig, j).iter().zip(want) {
                (diff2, ref2) = (diff2 + (f64::from(*got) - want).powi(2), ref2 + want * want);
            }
        }
    }
    let threads = rayon::current_num_threads();
    println!("\nMark III, {HOLOLINES} hololines timed ({source}, {threads} threads), scaled to {FULL_FRAME}.");
    println!("Signal-recovery error (least squares) against the original f32 modulation.\n");
    println!("| basis | input | output | layout | ms per full frame | relative L2 | PSNR (dB) | optical L2 |");
    println!("|---|---|---|---|---:|---:|---:|---:|");
    for r in &rows {
        let [b, i, o, shape] = r.knobs.words();
        let shape = if shape.is_empty() { "as built in" } else { shape };
        println!(
            "| {b} | {i} | {o} | {shape} | {:.0} | {:.2e} | {:.1} | {:.3} |",
            r.ms_per_frame, r.relative_l2, r.psnr_db, r.optical_l2
        );
    }
    println!("\nTabulated against computed signals: relative L2 {:.1e}.", (diff2 / ref2).sqrt());
    println!(
        "Optical recovery (view crosstalk, the same for every knob of the built-in layout): relative L2 {optical:.3}."
    );
    let note = format!(
        "Mark III, {HOLOLINES} hololines timed ({threads} threads) and scaled to {FULL_FRAME}; \
         optical recovery error {optical:.2} for every knob of the built-in layout"
    );
    // Only a full run redraws the README's plot; a quick pass (`-- --test`, as
    // CI runs it) draws its hand-timed figures under target/.
    let quick = std::env::args().any(|a| a == "--test");
    let path = if quick {
        std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| "target".into(), PathBuf::from).join("knobs.svg")
    } else {
        PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("docs").join("knobs.svg")
    };
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(&path, svg(&rows, &note)).unwrap();
    println!("wrote {}", path.display());
}

/// Decades `[10^lo, 10^hi]` that hold every value.
fn decades(values: impl Iterator<Item = f64>) -> (i32, i32) {
    let (lo, hi) = values.fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)));
    (lo.log10().floor() as i32, (hi.log10().ceil() as i32).max(lo.log10().floor() as i32 + 1))
}

/// The colours of the two bases in the plot.
const BLUE: &str = "#1f77b4";
const RED: &str = "#d62728";

/// The log-log plot of the rows, written by hand.
fn svg(rows: &[Row], note: &str) -> String {
    let (w, h, left, right, top, bottom) = (760.0, 500.0, 70.0, 20.0, 80.0, 58.0);
    let (x0, x1) = decades(rows.iter().map(|r| r.ms_per_frame));
    let (y0, y1) = decades(rows.iter().map(|r| r.relative_l2.max(1e-12)));
    let px = |ms: f64| left + (ms.log10() - f64::from(x0)) / f64::from(x1 - x0) * (w - left - right);
    let py = |e: f64| h - bottom - (e.max(1e-12).log10() - f64::from(y0)) / f64::from(y1 - y0) * (h - top - bottom);
    let (cx, cy) = ((left + w - right) / 2.0, (top + h - bottom) / 2.0);
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" font-family=\"sans-serif\" \
         font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n\
         <text x=\"{cx}\" y=\"22\" text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\">\
         Assembly knobs: run time against recovery error</text>\n\
         <text x=\"{cx}\" y=\"40\" text-anchor=\"middle\" fill=\"#555\">{note}</text>\n\
         <text x=\"{cx}\" y=\"60\" text-anchor=\"middle\"><tspan fill=\"{BLUE}\">● tabulated f32 basis \
         (fast path)</tspan><tspan dx=\"24\" fill=\"{RED}\">● computed f64 basis (reference)</tspan></text>\n\
         <text x=\"{cx}\" y=\"{}\" text-anchor=\"middle\">run time per full 440-hololine frame (ms)</text>\n\
         <text transform=\"translate(16 {cy}) rotate(-90)\" text-anchor=\"middle\">\
         signal-recovery error (relative L2)</text>\n",
        h - 14.0
    );
    // Grid lines at 1..9 × every decade (darker at the decades), tick labels at the decades.
    let line = |(a, b, c, d): (f64, f64, f64, f64), m: i32| {
        let grey = if m == 1 { "#bbb" } else { "#eee" };
        format!("<line x1=\"{a:.1}\" y1=\"{b:.1}\" x2=\"{c:.1}\" y2=\"{d:.1}\" stroke=\"{grey}\"/>\n")
    };
    for k in x0..=x1 {
        for m in (1..10).take(if k < x1 { 9 } else { 1 }) {
            let x = px(f64::from(m) * 10f64.powi(k));
            out += &line((x, top, x, h - bottom), m);
        }
        let (x, y) = (px(10f64.powi(k)), h - bottom + 16.0);
        out += &format!("<text x=\"{x:.1}\" y=\"{y}\" text-anchor=\"middle\">{}</text>\n", 10f64.powi(k));
    }
    for k in y0..=y1 {
        for m in (1..10).take(if k < y1 { 9 } else { 1 }) {
            let y = py(f64::from(m) * 10f64.powi(k));
            out += &line((left, y, w - right, y), m);
        }
        let (x, y) = (left - 6.0, py(10f64.powi(k)) + 4.0);
        out += &format!("<text x=\"{x}\" y=\"{y:.1}\" text-anchor=\"end\">1e{k}</text>\n");
    }
    out += &format!(
        "<rect x=\"{left}\" y=\"{top}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>\n",
        w - left - right,
        h - top - bottom
    );
    // Points coloured by basis; each label at the first spot near its point
    // (right, then left, further up or down) that is inside the plot and free.
    let mut taken: Vec<[f64; 4]> = Vec::new();
    for r in rows {
        let [_, input, output, shape] = r.knobs.words();
        let colour = if r.knobs.computed { RED } else { BLUE };
        let (x, y) = (px(r.ms_per_frame), py(r.relative_l2));
        let text = if shape.is_empty() {
            format!("{input} in · {output} out")
        } else {
            format!("{input} · {output} · {shape}")
        };
        let tw = 6.3 * text.chars().count() as f64;
        let boxes = [4.0, 18.0, -10.0, 32.0, -24.0, 46.0, -38.0]
            .into_iter()
            .flat_map(|dy| [(x + 8.0, y + dy), (x - 8.0 - tw, y + dy)])
            .map(|(a, b)| [a, b - 11.0, a + tw, b + 2.0]);
        let inside = |b: &[f64; 4]| b[0] > left && b[1] > top && b[2] < w - right && b[3] < h - bottom;
        let free = |b: &[f64; 4]| taken.iter().all(|t| b[2] < t[0] || b[0] > t[2] || b[3] < t[1] || b[1] > t[3]);
        let spot = boxes.clone().find(|b| inside(b) && free(b)).unwrap_or([x + 8.0, y - 7.0, x + 8.0 + tw, y + 6.0]);
        taken.push(spot);
        out += &format!(
            "<circle cx=\"{x:.1}\" cy=\"{y:.1}\" r=\"4.5\" fill=\"{colour}\"/>\n\
             <text x=\"{:.1}\" y=\"{:.1}\" fill=\"{colour}\">{text}</text>\n",
            spot[0],
            spot[3] - 2.0
        );
    }
    out + "</svg>\n"
}
