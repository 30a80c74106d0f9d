//! Frozen fringe vectors (spec/layouts.md §5.6): two small chirp profiles
//! whose blanking gains meet the rules a second implementation can read two
//! ways, the `.holo` frame they assemble, and the fringes `holo assemble`
//! makes of it (float signals as EXR, 8-bit codes as raw bytes).
//!
//! - `reversed-lines.toml`: odd lines sent from their last sample; every
//!   I/Q pair on one line. The gains beside each run are indexed by the
//!   signal order `n` (the table's first half on the lower-`n` side), not by
//!   the order in which samples are sent.
//! - `mixed-directions.toml`: three channels for four signals a hololine,
//!   odd lines reversed, so the pairs of zone 1 are split across two lines
//!   sent opposite ways: each lane takes the runs of its own line
//!   (`I′ = Re(g_I s)`, `Q′ = Im(g_Q s)`).
//!
//! Both carry a flat-field table, and the frame has evenly lit and uneven
//! hololines, so both tables are used. The fringes are checked against the
//! f64 reference (the spec read straight) and against the frozen files.
//! Regenerate only on a deliberate change of the rules:
//! `HOLO_BLESS=1 cargo test --test assemble vectors` (then update the spec).

use std::borrow::Cow;
use std::path::{Path, PathBuf};

use holo::assemble::output::{assemble_file, AssembleOptions, FringeFormat};
use holo::assemble::Assembler;
use holo::format::{write_frames, WriteOptions};
use holo::geometry::{mono_channel, Geometry};
use holo::layout::{
    segment_centre_views, Basis, BlankingGains, ChannelSlot, ColourSignals, EmitterPhases, FlatFieldGains, FrameBuffer,
    Fringe, Layout, Quantization, SignalKind,
};
use holo::Modulation;
use rand::{Rng, SeedableRng};

const PROFILES: [&str; 2] = ["reversed-lines", "mixed-directions"];

fn folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("fixtures").join("layouts")
}

fn blessing() -> bool {
    std::env::var_os("HOLO_BLESS").is_some()
}

/// 4 hololines of 16 emitters × 16 views; 512 samples a hololine of 3.72 µm,
/// two zones of 128-sample chirps, a chirp slot every 16 samples (16
/// emitters); 128-sample video lines of which 120 are shown, so every line
/// has an 8-sample hole. `channels` components take the four signals of a
/// hololine (zone 0 I, Q, zone 1 I, Q) in turn.
fn profile(name: &str, channels: usize) -> Layout {
    let (emitters, slot, chirp, zones, views_per_zone, samples) = (16usize, 16usize, 128usize, 2usize, 8usize, 512);
    assert_eq!(samples, emitters * slot + zones * chirp);
    let sample_pitch_m = 80e-3 / (336.0 * 64.0);
    let half_fan = 8f64.to_radians();
    let emitter_z_m = (zones * chirp) as f64 * sample_pitch_m / (2.0 * half_fan.tan());
    let mut geometry = Geometry::centred(
        4,
        emitters,
        segment_centre_views(zones * views_per_zone, half_fan),
        0.25e-3,
        slot as f64 * sample_pitch_m,
        emitter_z_m,
        0.6,
        mono_channel(),
    );
    geometry.emitter_left_x_m = ((zones * chirp / 2) as f64 - (samples / 2) as f64) * sample_pitch_m;
    // Gains of no table anyone would choose: distinct, complex, away from 1,
    // so that a gain taken from the wrong place shows.
    let table = |k: usize, seed: f64| -> Vec<Vec<[f64; 2]>> {
        (0..zones)
            .map(|z| {
                (0..2 * k)
                    .map(|i| {
                        let t = seed + z as f64 * 0.37 + i as f64 * 0.23;
                        [1.0 + 0.4 * t.sin(), 0.3 * (1.7 * t).cos()]
                    })
                    .collect()
            })
            .collect()
    };
    let lines = (4 * 2 * zones).div_ceil(channels);
    let fringe = Fringe {
        sample_pitch_m,
        samples_per_hololine: samples,
        basis: Basis::Chirp {
            chirp_samples: chirp,
            slot_samples: slot,
            zones,
            views_per_zone,
            segment_taper_samples: 0,
            piece_taper_samples: 0,
        },
        signal: SignalKind::Iq,
        carrier_cycles_per_sample: Vec::new(),
        colours: ColourSignals::Separate,
        emitter_phases: EmitterPhases::Zero,
        blanking_gains: Some(BlankingGains {
            samples_each_side: 4,
            zones: table(4, 0.0),
            flat_field: Some(FlatFieldGains { max_spread: 0.05, samples_each_side: 8, zones: table(8, 1.9) }),
        }),
        max_folded_energy: None,
        frame_buffer: FrameBuffer {
            image_names: vec!["fb".into()],
            width: 120,
            height: lines * 4,
            components: channels,
            line_samples: 128,
            rows_per_hololine: 4,
            first_row: 0,
            gap_rows: 0,
            channels: (0..channels).map(|component| ChannelSlot { image: 0, component }).collect(),
            reverse_odd_lines: true,
        },
        quantization: Quantization { bits: 8, offset: 128.0, gain: 127.0 },
    };
    Layout {
        name: name.into(),
        description: format!(
            "test vector of spec/layouts.md §5.6: {channels} channels for 4 signals a hololine, odd lines reversed"
        ),
        geometry,
        fringe: Some(fringe),
    }
}

fn profiles() -> [Layout; 2] {
    [profile(PROFILES[0], 4), profile(PROFILES[1], 3)]
}

/// Hololines 0 and 3 evenly lit (the flat-field table beside every run),
/// 1 and 2 pseudo-random in (0, 1] (the general table).
fn frame(g: &Geometry) -> Modulation {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(56);
    // Values f16 holds exactly, so the file holds the frame itself.
    let mut random = move || half::f16::from_f32(rng.gen_range(0.01..1.0)).to_f32();
    Modulation::from_fn(g.clone(), |_, j, _, _| if j == 0 || j == 3 { 0.5 } else { random() }).unwrap()
}

/// Assemble the frozen input with `layout` into `out`, as `format`.
fn assemble(layout: &Layout, out: &Path, format: FringeFormat) -> PathBuf {
    let options = AssembleOptions { frames: None, format, overwrite: true, resample: false };
    assemble_file(&folder().join("input.holo"), layout, out, &options, &holo::progress::Silent).unwrap();
    out.join(format!("frame0000-fb.{}", format.extension()))
}

/// The samples of a one-channel-per-component float EXR, component by
/// component (R, G, B, A), row by row.
fn exr_samples(path: &Path) -> Vec<Vec<f32>> {
    use exr::prelude::*;
    let image = read_all_flat_layers_from_file(path).unwrap();
    let layer = &image.layer_data[0];
    let mut channels: Vec<(String, Vec<f32>)> =
        layer.channel_data.list.iter().map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect())).collect();
    channels.sort_by_key(|(n, _)| "RGBA".find(n.as_str()));
    channels.into_iter().map(|(_, s)| s).collect()
}

#[test]
fn the_frozen_profiles_load_as_made() {
    if blessing() {
        std::fs::create_dir_all(folder()).unwrap();
        let layout = &profiles()[0];
        let m = frame(&layout.geometry);
        let options = WriteOptions { source: "spec/layouts.md §5.6 test vector".into(), ..WriteOptions::default() };
        write_frames(
            folder().join("input.holo"),
            &layout.geometry,
            1,
            &WriteOptions { overwrite: true, ..options },
            |_| Ok(Cow::Borrowed(&m)),
        )
        .unwrap();
        for layout in profiles() {
            std::fs::write(folder().join(format!("{}.toml", layout.name)), layout.to_toml()).unwrap();
        }
    }
    for layout in profiles() {
        let path = folder().join(format!("{}.toml", layout.name));
        let loaded = Layout::load(path.to_str().unwrap()).unwrap();
        assert_eq!(loaded, layout, "{}", path.display());
        holo::assemble::load_layout(path.to_str().unwrap()).unwrap();
    }
    let stored = holo::HoloFile::open(folder().join("input.holo")).unwrap().read_frame(0).unwrap();
    assert!(stored == frame(&profiles()[0].geometry), "input.holo holds the frame (exact in f16)");
}

/// The ambiguous rules are really exercised: on `reversed-lines` a reversed
/// line's runs are elsewhere in signal order than a forward line's; on
/// `mixed-directions` some pair's lanes go out on lines sent opposite ways.
#[test]
fn the_profiles_exercise_the_rules_they_are_for() {
    let [reversed, mixed] = profiles();
    let fb = &reversed.fringe.as_ref().unwrap().frame_buffer;
    assert_ne!(fb.blanked_runs(512, false), fb.blanked_runs(512, true));
    let fb = &mixed.fringe.as_ref().unwrap().frame_buffer;
    let split = (0..4).any(|j| {
        (0..2usize).any(|zone| {
            let line = |lane: usize| fb.channel_and_line(j, 2 * zone + lane, 4).1;
            fb.line_reversed(line(0)) != fb.line_reversed(line(1))
        })
    });
    assert!(split, "no pair is split across lines sent opposite ways");
}

#[test]
fn the_fringes_are_the_spec_read_straight_and_the_frozen_files() {
    let dir = tempfile::tempdir().unwrap();
    let stored = holo::HoloFile::open(folder().join("input.holo")).unwrap().read_frame(0).unwrap();
    for layout in profiles() {
        let name = layout.name.clone();
        let exr = assemble(&layout, &dir.path().join(format!("{name}-exr")), FringeFormat::Exr);
        let raw = assemble(&layout, &dir.path().join(format!("{name}-raw")), FringeFormat::Raw);
        let frozen = folder().join(&name);
        if blessing() {
            std::fs::create_dir_all(&frozen).unwrap();
            std::fs::copy(&exr, frozen.join("frame0000-fb.exr")).unwrap();
            std::fs::copy(&raw, frozen.join("frame0000-fb.raw")).unwrap();
        }
        // The f64 reference: every signal of every hololine, with the gains.
        let a = Assembler::new(&layout).unwrap();
        let mut want = a.signals_reference(&stored, 0, 0..4).unwrap();
        for (j, hololine) in want.iter_mut().enumerate() {
            a.blanking_gains_reference(&stored, j, 0, hololine);
        }
        // Where each sample of each signal lands: channel (component) c, row, column.
        let fringe = layout.fringe.as_ref().unwrap();
        let fb = &fringe.frame_buffer;
        let place = |j: usize, s: usize, n: usize| fb.place(j, s, n, 4, 512).map(|p| (p.component, p.row, p.column));
        let got = exr_samples(&exr);
        let peak = want.iter().flatten().flatten().fold(0f64, |m, x| m.max(x.abs()));
        let mut worst = 0f64;
        let mut placed = 0;
        for (j, signals) in want.iter().enumerate() {
            for (s, signal) in signals.iter().enumerate() {
                for (n, &x) in signal.iter().enumerate() {
                    if let Some((c, row, column)) = place(j, s, n) {
                        worst = worst.max((f64::from(got[c][row * fb.width + column]) - x).abs());
                        placed += 1;
                    }
                }
            }
        }
        assert_eq!(placed, 4 * 4 * 512 * 120 / 128, "{name}: every shown sample placed once");
        assert!(peak > 0.1 && worst < 2e-7 * peak.max(1.0), "{name}: worst {worst} of peak {peak}");
        // The frozen files: raw codes byte for byte, EXR samples to f32 rounding.
        assert_eq!(std::fs::read(&raw).unwrap(), std::fs::read(frozen.join("frame0000-fb.raw")).unwrap(), "{name}");
        let frozen_exr = exr_samples(&frozen.join("frame0000-fb.exr"));
        for (c, (a, b)) in got.iter().zip(&frozen_exr).enumerate() {
            let diff = a.iter().zip(b).fold(0f32, |m, (x, y)| m.max((x - y).abs()));
            assert!(a.len() == b.len() && diff <= 2e-7 * peak as f32, "{name} component {c}: {diff}");
        }
    }
}
