//! The built-in layouts. Every number states its source; numbers no source
//! gives are marked *assumption* here and in spec/layouts.md, with the
//! reasoning.

use super::{
    Basis, BlankingGains, ChannelSlot, ColourSignals, EmitterPhases, FlatFieldGains, FrameBuffer, Fringe, Layout,
    Quantization, SignalKind,
};
use crate::geometry::{mono_channel, rgb_channels, ColourChannel, Geometry, ViewSpacing, Views};

/// Names of the built-in layouts: the horizontal-parallax displays, then the
/// full-parallax geometries (spec/layouts.md §7).
pub const BUILTIN: [&str; 7] = ["mark3", "mark1", "mark1-hogel", "mark2", "mark4", "pluto2-hogels", "chimera"];

/// A built-in layout by name.
pub fn builtin(name: &str) -> Option<Layout> {
    match name.to_ascii_lowercase().as_str() {
        "mark3" | "mark-iii" | "markiii" => Some(mark3()),
        "mark1" | "mark-i" | "marki" => Some(mark1()),
        "mark1-hogel" => Some(mark1_hogel()),
        "mark2" | "mark-ii" | "markii" => Some(mark2()),
        "mark4" | "mark-iv" | "markiv" => Some(mark4()),
        "pluto2-hogels" => Some(pluto2_hogels()),
        "chimera" => Some(chimera()),
        _ => None,
    }
}

/// Views whose directions are the centres of `count` equal segments of
/// `tan θ` over a fan of ±`half_fan_rad`: a perspective camera's pixel
/// columns, and equal-length segments of an exact focusing chirp.
pub fn segment_centre_views(count: usize, half_fan_rad: f64) -> Views {
    let t = half_fan_rad.tan();
    let step = 2.0 * t / count as f64;
    Views::tan_spaced(count, (-t + step / 2.0).atan(), (t - step / 2.0).atan())
}

/// MIT Mark III (Smithwick et al. 2009 §5.1).
///
/// Stated: 336 emitters × 440 hololines × 96 views, 80 mm × 60 mm, 24° field
/// of view in three 8° zones; 24576 samples per hololine, a chirp slot every
/// 64 samples, three 1024-sample zone chirps per emitter.
/// Derived: emitter pitch 80 mm / 336; hololine pitch 60 mm / 440; sample
/// pitch 80 mm / (336 · 64) = 3.72 µm; the emitter plane where one emitter's
/// three zone chirps (3 × 1024 samples) span the 24° fan:
/// z = 3072 · 3.72 µm / (2 tan 12°) = 26.9 mm.
/// Assumptions: emitters in front of the hologram (+z); viewer at 600 mm (the
/// Mark I figure, Nelson 1993); one channel at 633 nm (a HeNe red; the paper
/// gives no wavelength, and its six video channels are zones and I/Q, not
/// colours).
pub fn mark3() -> Layout {
    let emitters = 336;
    let width_m = 0.080;
    let sample_pitch_m = width_m / (emitters as f64 * 64.0);
    let half_fan = 12f64.to_radians();
    let emitter_z_m = 3.0 * 1024.0 * sample_pitch_m / (2.0 * half_fan.tan());
    let mut geometry = Geometry::centred(
        440,
        emitters,
        segment_centre_views(96, half_fan),
        0.060 / 440.0,
        width_m / emitters as f64,
        emitter_z_m,
        0.600,
        mono_channel(),
    );
    // Emitter e is centred on sample 64e + 1536 of the 24576-sample hololine,
    // which is centred on x = 0: the grid sits half a slot left of symmetric.
    geometry.emitter_left_x_m = (1536.0 - 12288.0) * sample_pitch_m;
    // Six channels in signal order (zone1.cos, zone1.sin, zone2.cos, …):
    // "Head 1 RG channels produce the sine/cosine pair of zone 1. Head 1 B
    // channel produces the sine of zone 2. Head 2 RG channels produce the
    // sine/cosine pair of zone 3. Head 2 B channel produces cosine of zone 2."
    let slot = |image, component| ChannelSlot { image, component };
    let channels = vec![slot(0, 1), slot(0, 0), slot(1, 2), slot(0, 2), slot(1, 1), slot(1, 0)];
    let fringe = Fringe {
        sample_pitch_m,
        samples_per_hololine: 24576,
        basis: Basis::Chirp {
            chirp_samples: 1024,
            slot_samples: 64,
            zones: 3,
            views_per_zone: 32,
            segment_taper_samples: 0,
            // The ends of every zone piece cross-fade over two segments (the
            // chirp's own ends rise over one): the zones' band edges then fold
            // no light past half the sampling rate (spec/layouts.md §4.2, §4.7).
            piece_taper_samples: 64,
        },
        signal: SignalKind::Iq,
        carrier_cycles_per_sample: Vec::new(),
        colours: ColourSignals::Separate,
        emitter_phases: EmitterPhases::Zero,
        blanking_gains: Some(mark3_blanking_gains()),
        max_folded_energy: None,
        frame_buffer: FrameBuffer {
            image_names: vec!["head1".into(), "head2".into()],
            width: 4080,
            height: 3386,
            components: 3,
            line_samples: 4096,
            rows_per_hololine: 6,
            // Assumption: hololines from the top row; the 746 rows below
            // them fall in the vertical mirror's flyback (80% duty cycle).
            first_row: 0,
            gap_rows: 0,
            channels,
            reverse_odd_lines: false,
        },
        // Assumption: a signed signal centred on code 128.
        quantization: Quantization { bits: 8, offset: 128.0, gain: 127.0 },
    };
    Layout {
        name: "mark3".into(),
        description: "MIT Mark III (Smithwick et al. 2009): 336 emitters × 440 hololines × 96 views, 80 × 60 mm, 24°"
            .into(),
        geometry,
        fringe: Some(fringe),
    }
}

/// Mark III's blanking gains (spec/layouts.md §5.5): tables found
/// numerically (`docs/seams/`) for the basis above, hard segments and every
/// emitter at phase 0, one for every picture and one for flat fields.
fn mark3_blanking_gains() -> BlankingGains {
    use super::mark3_blanking::*;
    BlankingGains {
        samples_each_side: SAMPLES_EACH_SIDE,
        zones: GAINS.iter().map(|z| z.to_vec()).collect(),
        flat_field: Some(FlatFieldGains {
            max_spread: FLAT_FIELD_MAX_SPREAD,
            samples_each_side: FLAT_FIELD_SAMPLES_EACH_SIDE,
            zones: FLAT_FIELD_GAINS.iter().map(|z| z.to_vec()).collect(),
        }),
    }
}

/// Mark I: samples per hololine (Nelson 1993 §1.1.2: "32 kilopixels").
const MARK1_SAMPLES: usize = 32768;
/// Mark I: sample pitch, metres (*assumption*, see [`mark1`]).
const MARK1_PITCH_M: f64 = 0.6e-6;

/// Mark I's frame buffer: three colour layers of 2048 × 1024 8-bit samples,
/// a hololine as 16 rows of 2048.
fn mark1_frame_buffer() -> FrameBuffer {
    FrameBuffer {
        image_names: vec!["red".into(), "green".into(), "blue".into()],
        width: 2048,
        height: 1024,
        components: 1,
        line_samples: 2048,
        rows_per_hololine: 16,
        first_row: 0,
        gap_rows: 0,
        // Signal order per hololine is R, G, B: each colour to its layer.
        channels: (0..3).map(|image| ChannelSlot { image, component: 0 }).collect(),
        reverse_odd_lines: false,
    }
}

/// MIT Mark I in colour (Nelson 1993 §1.1.2), with the focusing-chirp
/// basis the seed's renderer uses (each point's elemental fringe carries a
/// separate amplitude per view zone).
///
/// Stated: 64 RGB hololines of 32K samples, three colour layers of 2
/// megasamples, one view zone of about 16°, viewed at about 600 mm, five view
/// directions for occlusion and specular (Nelson 1993 ch. 2, 4), 8-bit samples.
/// Assumptions: sample pitch 0.6 µm, so that blue (445 nm) keeps the 16° band
/// inside a real signal's 0 to 0.5 cycles per sample around a carrier of 0.25
/// (0.062 to 0.438); a hololine is then 19.7 mm long; wavelengths 633 / 532 /
/// 445 nm; chirps of 5 × 384 samples, one every 128 samples (15 overlapping),
/// which puts the emitter plane at 1920 · 0.6 µm / (2 tan 8°) = 4.10 mm and
/// fits 242 emitters (76.8 µm apart); hololines 0.3 mm apart (a 19.2 mm tall,
/// nearly square image); each layer a 2048 × 1024 frame buffer, 16 rows per
/// hololine (2 megasamples = 2048 × 1024).
pub fn mark1() -> Layout {
    let (chirp, slot) = (1920, 128);
    let half_fan = 8f64.to_radians();
    let emitters = (MARK1_SAMPLES - chirp) / slot + 1;
    let geometry = Geometry::centred(
        64,
        emitters,
        segment_centre_views(5, half_fan),
        0.3e-3,
        slot as f64 * MARK1_PITCH_M,
        chirp as f64 * MARK1_PITCH_M / (2.0 * half_fan.tan()),
        0.600,
        rgb_channels(),
    );
    Layout {
        name: "mark1".into(),
        description: "MIT Mark I colour (Nelson 1993): 242 emitters × 64 hololines × 5 views, RGB, 16° zone, \
                      focusing chirps"
            .into(),
        geometry,
        fringe: Some(mark1_fringe(Basis::Chirp {
            chirp_samples: chirp,
            slot_samples: slot,
            zones: 1,
            views_per_zone: 5,
            segment_taper_samples: 0,
            piece_taper_samples: 0,
        })),
    }
}

/// Mark I's signal side with either basis: a real signal on a quarter-rate
/// carrier, one signal per colour, 8 bits around code 128.
fn mark1_fringe(basis: Basis) -> Fringe {
    Fringe {
        sample_pitch_m: MARK1_PITCH_M,
        samples_per_hololine: MARK1_SAMPLES,
        basis,
        signal: SignalKind::Real,
        carrier_cycles_per_sample: vec![0.25],
        colours: ColourSignals::Separate,
        emitter_phases: EmitterPhases::Zero,
        blanking_gains: None,
        max_folded_energy: None,
        frame_buffer: mark1_frame_buffer(),
        quantization: Quantization { bits: 8, offset: 128.0, gain: 127.0 },
    }
}

/// Mark I with Lucente's hogel basis (abutting hogels of gratings, which ran
/// on Mark I and II): the same display as [`mark1`], with emitters on the
/// hologram plane, one per 128-sample hogel (256 of them, 76.8 µm apart).
pub fn mark1_hogel() -> Layout {
    let hogel = 128;
    let emitters = MARK1_SAMPLES / hogel;
    let geometry = Geometry::centred(
        64,
        emitters,
        segment_centre_views(5, 8f64.to_radians()),
        0.3e-3,
        hogel as f64 * MARK1_PITCH_M,
        0.0,
        0.600,
        rgb_channels(),
    );
    Layout {
        name: "mark1-hogel".into(),
        description: "MIT Mark I colour with hogels (Lucente): 256 emitters × 64 hololines × 5 views, RGB, 16° zone"
            .into(),
        geometry,
        fringe: Some(mark1_fringe(Basis::Hogel { hogel_samples: hogel })),
    }
}

/// MIT Mark II (St.-Hilaire et al.; frame buffer as the public MIT code
/// `itsermo/holovideo-algorithms` lays it, `render_algorithms/ripgen-fbo`
/// RIP.cpp/RIP.h and `holodepth/src/JHolovideoDisplay.cpp`).
///
/// Stated by that code: 144 hololines of 262144 samples, each 128 rows of
/// 2048 clocks; 18 channels = 3 cards × 2 heads × RGB; hololine `i` on card
/// `i mod 3`, colour byte `⌊i/3⌋ mod 3`, head `⌊i/9⌋ mod 2`, sweep `⌊i/18⌋`;
/// 2045 of 2048 clocks and 1757 of 1760 rows shown; 204 blank rows, then per
/// sweep 128 rows of hololine and 48 blank rows; odd sweeps sent backwards
/// (the whole sample sequence reversed); sample pitch from TeO2's 617 m/s at
/// 108.134 MHz, demagnified 275/2830: 0.5545 µm (a 145.35 mm hololine);
/// 633 nm; viewer at 0.5 m; 55 mm tall; emitters 4 mm in front of the
/// hologram, about 7 overlapping chirps per sample (RIP's projector fringes).
/// Assumptions: a ±14° view zone (RIP's 14° + 15° made symmetric) in 28
/// views of 128 samples, a chirp of 3584 samples (emitter plane 3.99 mm):
/// RIP's 103 views of 35 samples each spread by diffraction over about eight
/// views (a segment of `s` samples resolves `λ / (s · pitch)`), so a view is
/// made as wide as its segment's diffraction allows; an
/// emitter every 512 samples (holodepth's 512 per hololine), 506 of which
/// have their whole chirp on the hololine; a real signal with its carrier at
/// 0.25 cycles per sample (band 0.038 to 0.462; RIP's −15° reference put it at
/// 0 to 0.45); a signed signal on code 128, where RIP adds non-negative
/// fringes into a saturating buffer.
pub fn mark2() -> Layout {
    let samples = 262144;
    let pitch_m = 617.0 / 108.134e6 * 275.0 / 2830.0;
    let (chirp, slot, views) = (3584, 512, 28);
    let half_fan = 14f64.to_radians();
    let emitters = (samples - chirp) / slot + 1;
    let geometry = Geometry::centred(
        144,
        emitters,
        segment_centre_views(views, half_fan),
        0.055 / 144.0,
        slot as f64 * pitch_m,
        chirp as f64 * pitch_m / (2.0 * half_fan.tan()),
        0.5,
        mono_channel(),
    );
    // Channel a (= hololine mod 18) of card a mod 3, colour (a/3) mod 3, head
    // (a/9) mod 2; image 2·card + head.
    let channels = (0..18).map(|a| ChannelSlot { image: 2 * (a % 3) + (a / 9) % 2, component: (a / 3) % 3 }).collect();
    Layout {
        name: "mark2".into(),
        description: "MIT Mark II: 506 emitters × 144 hololines × 28 views, 145 × 55 mm, 28°, 18 channels on 3 cards"
            .into(),
        geometry,
        fringe: Some(Fringe {
            sample_pitch_m: pitch_m,
            samples_per_hololine: samples,
            basis: Basis::Chirp {
                chirp_samples: chirp,
                slot_samples: slot,
                zones: 1,
                views_per_zone: views,
                segment_taper_samples: 0,
                piece_taper_samples: 0,
            },
            signal: SignalKind::Real,
            carrier_cycles_per_sample: vec![0.25],
            colours: ColourSignals::Separate,
            emitter_phases: EmitterPhases::Zero,
            blanking_gains: None,
            max_folded_energy: None,
            frame_buffer: FrameBuffer {
                image_names: (0..3).flat_map(|card| (0..2).map(move |head| format!("card{card}-head{head}"))).collect(),
                width: 2045,
                height: 1757,
                components: 3,
                line_samples: 2048,
                rows_per_hololine: 128,
                first_row: 204,
                gap_rows: 48,
                channels,
                reverse_odd_lines: true,
            },
            quantization: Quantization { bits: 8, offset: 128.0, gain: 127.0 },
        }),
    }
}

/// MIT Mark IV (frame buffer as the public MIT code lays it:
/// `render_algorithms/dscp4`, dscp4.conf.in and the fringe kernels).
///
/// Stated by that code: 468 hololines of 355200 samples (100 rows of 3552);
/// 600 "wafels" of 592 samples; 16 views; 6 heads of 3552 × 2600 (2476 of
/// them shown), 18 channels, hololine `y` on channel `a = y mod 18` as its
/// line `⌊y/18⌋`, head `⌊a/3⌋`, byte `a mod 3` (R, G, B); red, green and blue
/// (633, 532, 445 nm) summed into every channel at per-colour carriers, red
/// lowest (225 / 290 / 350 MHz); a hololine 0.15 m wide (0.4223 µm pitch);
/// viewer at 0.5 m.
/// Assumptions: the wafels are hogels (emitters on the hologram plane; the
/// code's per-view depth has no place in a modulation texture); a ±5° view
/// zone, the widest for which the three colours' bands fit side by side in
/// one real signal at this pitch (the code's 30° would need 2.6 times the
/// band its 400 MHz clock has), with carriers 0.085 / 0.225 / 0.39 cycles per
/// sample (bands 0.027–0.143, 0.156–0.294, 0.307–0.473); square pixels
/// (hololines 0.25 mm apart, a 117 mm tall image); gain 73 ≈ 127/√3, as three
/// colours add.
pub fn mark4() -> Layout {
    let samples = 355200;
    let hogel = 592;
    let emitters = samples / hogel;
    let pitch_m = 0.15 / samples as f64;
    let geometry = Geometry::centred(
        468,
        emitters,
        segment_centre_views(16, 5f64.to_radians()),
        hogel as f64 * pitch_m,
        hogel as f64 * pitch_m,
        0.0,
        0.5,
        rgb_channels(),
    );
    Layout {
        name: "mark4".into(),
        description: "MIT Mark IV: 600 emitters × 468 hololines × 16 views, RGB summed per channel, 150 × 117 mm, 10°"
            .into(),
        geometry,
        fringe: Some(Fringe {
            sample_pitch_m: pitch_m,
            samples_per_hololine: samples,
            basis: Basis::Hogel { hogel_samples: hogel },
            signal: SignalKind::Real,
            carrier_cycles_per_sample: vec![0.085, 0.225, 0.39],
            colours: ColourSignals::Summed,
            emitter_phases: EmitterPhases::Zero,
            blanking_gains: None,
            max_folded_energy: None,
            frame_buffer: FrameBuffer {
                image_names: (1..=6).map(|h| format!("head{h}")).collect(),
                width: 3552,
                height: 2600,
                components: 3,
                line_samples: 3552,
                rows_per_hololine: 100,
                first_row: 0,
                gap_rows: 0,
                channels: (0..18).map(|a| ChannelSlot { image: a / 3, component: a % 3 }).collect(),
                reverse_odd_lines: false,
            },
            quantization: Quantization { bits: 8, offset: 128.0, gain: 73.0 },
        }),
    }
}

/// A phase-only LCoS modulator used as a full-parallax hogel display: the
/// holographic stereogram as the field computes it for such modulators
/// (each hogel the 2-D Fourier transform of its directional picture), on
/// HOLOEYE's PLUTO-2.
///
/// Stated (HOLOEYE PLUTO-2 datasheet): 1920 × 1080 pixels at 8.0 µm
/// (15.36 mm × 8.64 mm).
/// Derived: a hogel of `N × N` pixels sends `N` plane waves along each axis,
/// one per frequency of its transform, `λ / (N p)` apart in `sin θ`; centred
/// on the axis (half a step off the transform's own grid, a linear phase
/// across the hogel), the outermost at `±(N − 1) λ / (2 N p)`, inside the
/// modulator's limit `λ / 2p`. With `N = 16` at 532 nm: 120 × 67 hogels of
/// 128 µm (the 1072 middle rows of pixels), 16 × 16 views, ±1.79°.
/// Assumptions: 16-pixel hogels (a square picture per hogel; the trade
/// between hogel size and view count is the user's); one channel at 532 nm
/// (a green DPSS laser, the usual source for such a modulator); hogels on
/// the modulator (`z = 0`); a viewer at 300 mm.
pub fn pluto2_hogels() -> Layout {
    let (pixels_across, pixels_down, pixel_pitch_m) = (1920usize, 1080usize, 8.0e-6);
    let hogel_pixels = 16usize;
    let wavelength_m = 532e-9;
    let step = wavelength_m / (hogel_pixels as f64 * pixel_pitch_m);
    let outermost = 0.5 * (hogel_pixels as f64 - 1.0) * step;
    let views = Views {
        count: hogel_pixels,
        first_theta_rad: (-outermost).asin(),
        last_theta_rad: outermost.asin(),
        spacing: ViewSpacing::Sin,
    };
    let hogel_m = hogel_pixels as f64 * pixel_pitch_m;
    let geometry = Geometry::centred(
        pixels_down / hogel_pixels,
        pixels_across / hogel_pixels,
        views.clone(),
        hogel_m,
        hogel_m,
        0.0,
        0.300,
        vec![ColourChannel::new("Y", wavelength_m)],
    )
    .with_vertical_views(views);
    Layout {
        name: "pluto2-hogels".into(),
        description: "HOLOEYE PLUTO-2 phase modulator (1920 × 1080 at 8 µm, datasheet) as a hogel display: \
                      120 × 67 hogels of 16 × 16 pixels, 16 × 16 views over ±1.79° at 532 nm; full parallax, \
                      geometry only"
            .into(),
        geometry,
        fringe: None,
    }
}

/// A holographic stereogram printer: CHIMERA (Gentet, Gentet and Lee,
/// "CHIMERA, a new holoprinter technology combining low-power continuous
/// lasers and fast printing", Applied Optics 58(34), G226–G230, 2019).
///
/// Stated (the publisher's announcement of the paper, Optica, November
/// 2019): full-parallax hogels printed one after another with red, green
/// and blue low-power continuous lasers; a field of view of 120°; a
/// 30 × 40 cm hologram in about 11 hours.
/// Assumptions: hogels 250 µm square (the announcement gives no size; at
/// 250 µm that print is 1.92 million hogels, 48 a second over 11 hours);
/// one 100 mm × 100 mm tile of 400 × 400 hogels
/// (a larger print is more hogels of the same profile: `holo layout chimera`
/// prints one to edit); 32 × 32 views, the centres of equal segments of
/// `tan θ` over ±60° in both axes (a perspective camera at each hogel, as
/// printers' directional pictures are rendered); hogels on the plate
/// (`z = 0`), a viewer at 500 mm; the colours at holo's red, green and blue
/// wavelengths (a printer's views are set by its optics, not by diffraction
/// at the hogel, so they only name the colours).
pub fn chimera() -> Layout {
    let hogel_m = 250e-6;
    let views = segment_centre_views(32, 60f64.to_radians());
    let geometry = Geometry::centred(400, 400, views.clone(), hogel_m, hogel_m, 0.0, 0.500, rgb_channels())
        .with_vertical_views(views);
    Layout {
        name: "chimera".into(),
        description: "CHIMERA holoprinter (Gentet et al. 2019): full parallax over a 120° field of view; a 100 mm \
                      tile of 400 × 400 hogels of 250 µm (assumed), 32 × 32 views, RGB; geometry only"
            .into(),
        geometry,
        fringe: None,
    }
}
