//! The fringe side of a layout: which basis turns modulation into hololine
//! signals, what kind of signal the display takes, and where each signal
//! sample goes in the display's frame buffer. Normative description:
//! spec/layouts.md, "Fringe fields". The physics behind the basis (phases,
//! bands, carriers) is in [`crate::assemble::basis`].

use serde::{Deserialize, Serialize};

use super::Layout;

/// Everything between a modulation and the frame buffer.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Fringe {
    /// Distance between fringe samples on the hologram, metres.
    pub sample_pitch_m: f64,
    /// Fringe samples per hololine and signal.
    pub samples_per_hololine: usize,
    /// How emitters and views become fringe samples.
    pub basis: Basis,
    /// What the display takes: complex I/Q pairs or one real signal per zone.
    pub signal: SignalKind,
    /// For real signals: the signal frequency, in cycles per sample, of
    /// light that leaves the hologram along its normal (the carrier the
    /// reference beam undoes), one value for every colour channel or one per
    /// channel. Empty for I/Q signals.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub carrier_cycles_per_sample: Vec<f64>,
    /// Whether each colour channel has its own signals, or all colours are
    /// summed into one (frequency-division colour: every wavelength reads
    /// its own band, which must not overlap another's).
    #[serde(default, skip_serializing_if = "ColourSignals::is_separate")]
    pub colours: ColourSignals,
    /// The constant phase each emitter's basis starts with.
    #[serde(default, skip_serializing_if = "EmitterPhases::is_zero")]
    pub emitter_phases: EmitterPhases,
    /// Gains on the shown samples beside each run of horizontally blanked
    /// samples, which make up for part of the light the blanked samples do
    /// not send (spec/layouts.md §5.5). None: every sample is sent as the
    /// basis makes it, and a blanked run is a hole in the hologram.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blanking_gains: Option<BlankingGains>,
    /// The largest fraction of an element's energy its samples may fold
    /// past half the sampling rate (light that leaves toward a ghost of its
    /// emitter); a basis that folds more is refused. None: not checked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_folded_energy: Option<f64>,
    /// Where the signals go.
    pub frame_buffer: FrameBuffer,
    /// Float signal to stored integer.
    pub quantization: Quantization,
}

/// How emitters and views become fringe samples.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Basis {
    /// Overlapping focusing chirps (Smithwick et al. 2009 §3; Nelson 1993's elemental
    /// fringes), each cut into `zones` pieces of `chirp_samples` samples
    /// carried by separate signals, each piece into `views_per_zone` equal
    /// view segments. Emitter `e`'s piece of zone `k` starts at sample
    /// `e · slot_samples + k · chirp_samples`.
    Chirp {
        /// Samples of one zone piece of a chirp.
        chirp_samples: usize,
        /// Samples between the starts of adjacent emitters' chirps.
        slot_samples: usize,
        /// Zone pieces per emitter (one signal, or I/Q pair, each).
        zones: usize,
        /// Views per zone piece.
        views_per_zone: usize,
        /// Samples over which adjacent view segments cross-fade (a raised
        /// cosine centred on each boundary, zone boundaries included; the
        /// chirp's two ends fade in over half as many): 0 keeps hard
        /// edges, whose sidelobes fold past half the sampling rate.
        #[serde(default, skip_serializing_if = "is_zero")]
        segment_taper_samples: usize,
        /// Samples over which the ends of every zone piece fade instead:
        /// where two pieces of one chirp meet (a raised cosine centred on
        /// the boundary, each piece's element widened by half of it) and at
        /// the chirp's own two ends (over half as many, inside the segment).
        /// The piece ends are the band edges of the zones' signals, whose
        /// hard edges fold the most (spec/layouts.md §4.2, §4.7); 0 fades
        /// them as `segment_taper_samples` says.
        #[serde(default, skip_serializing_if = "is_zero")]
        piece_taper_samples: usize,
    },
    /// Abutting hogels (Lucente 1994): emitter `e` is the hogel of samples
    /// `e · hogel_samples …`, on the hologram plane; within it every view is a
    /// sum of gratings whose directions fill the view's angular interval,
    /// with pseudo-random phases.
    Hogel {
        /// Samples per hogel (= between emitters).
        hogel_samples: usize,
    },
}

/// The constant phase each emitter's basis is multiplied by (spec/layouts.md
/// §4.6): where the light of neighbouring emitters meets, in a coherent eye
/// (§9.2), their relative phase decides whether it adds or cancels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EmitterPhases {
    /// Every emitter at phase 0.
    #[default]
    Zero,
    /// Emitter `e` at `2π · splitmix64(e) / 2⁶⁴`, the generator of the hogel
    /// gratings' phases.
    Random,
    /// `0, π/2, 0, π/2, …`: every emitter in quadrature with both
    /// neighbours.
    Quadrature,
    /// Minus each emitter's path to the centre of the viewer line, in
    /// phase: the emitters' light arrives at the viewer distance as from one
    /// flat array, so from every eye position on the line identical
    /// neighbours interfere alike and a uniform hololine looks uniform.
    Viewer,
}

impl EmitterPhases {
    fn is_zero(&self) -> bool {
        *self == EmitterPhases::Zero
    }
}

/// Complex gains on the shown samples beside each run of horizontally
/// blanked samples (spec/layouts.md §5.5): the `K` samples before a run and
/// the `K` after it (in signal order, so on the hologram too) are multiplied,
/// as complex baseband samples `I + iQ`, by the gains of their zone, before
/// quantization. The same gains serve every run: within a hololine the
/// basis crosses every run alike when runs are a whole number of zone pieces
/// apart, as on Mark III.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlankingGains {
    /// Shown samples taken on each side of a blanked run, `K`.
    pub samples_each_side: usize,
    /// Per zone, in signal order: `2K` gains `[re, im]`, first for the `K`
    /// samples before a run, then for the `K` after it.
    pub zones: Vec<Vec<[f64; 2]>>,
    /// Gains for a run whose neighbourhood is evenly lit, used there
    /// instead of `zones`. None: `zones` beside every run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flat_field: Option<FlatFieldGains>,
}

/// Blanking gains for evenly lit neighbourhoods (spec/layouts.md §5.5):
/// beside a run whose elements (of every zone) with segments within
/// `samples_each_side` of it have radiances that differ by at most
/// `max_spread` of the largest, these gains are used instead of the
/// layout's others. Chosen for flat fields (the picture a display is
/// calibrated with, and any evenly lit area), where the interference the
/// gains rely on is known: they bring such a seam back further than gains
/// that must suit every picture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlatFieldGains {
    /// The largest spread of the radiances, `(max − min) / max`, that
    /// counts as evenly lit.
    pub max_spread: f64,
    /// Shown samples taken on each side of a blanked run, `K`.
    pub samples_each_side: usize,
    /// Per zone, in signal order: `2K` gains `[re, im]`, as
    /// [`BlankingGains::zones`].
    pub zones: Vec<Vec<[f64; 2]>>,
}

impl BlankingGains {
    /// The most samples any of the tables takes on one side of a run.
    pub fn reach(&self) -> usize {
        self.flat_field.as_ref().map_or(0, |f| f.samples_each_side).max(self.samples_each_side)
    }
}

/// The kind of signal a display takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SignalKind {
    /// Complex baseband: a cosine (I) and a sine (Q) signal per zone, which
    /// the display's single-sideband up-converter shifts to the zone's band
    /// (Mark III's Weaver modulators, Smithwick et al. 2009 §5.1).
    Iq,
    /// One real signal per zone, driven as it is: the fringe carries its own
    /// carrier and both sidebands (the first order is the one used).
    Real,
}

/// How colour channels share signals.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ColourSignals {
    /// Each colour channel has its own signals (Mark I's colour layers).
    #[default]
    Separate,
    /// The colours' signals are added into one, each colour in its own band
    /// (Mark IV's frequency-division colour).
    Summed,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl ColourSignals {
    fn is_separate(&self) -> bool {
        *self == ColourSignals::Separate
    }
}

impl Fringe {
    /// Zones: separately carried pieces of every emitter's fan.
    pub fn zones(&self) -> usize {
        match self.basis {
            Basis::Chirp { zones, .. } => zones,
            Basis::Hogel { .. } => 1,
        }
    }
    /// Signals per hololine and colour channel.
    pub fn signals_per_colour(&self) -> usize {
        match self.signal {
            SignalKind::Iq => 2 * self.zones(),
            SignalKind::Real => self.zones(),
        }
    }
    /// Names of the signals of one colour channel, in order
    /// (`zone1.cos`, `zone1.sin`, …, or `zone1`, …).
    pub fn signal_names(&self) -> Vec<String> {
        (1..=self.zones())
            .flat_map(|k| match self.signal {
                SignalKind::Iq => vec![format!("zone{k}.cos"), format!("zone{k}.sin")],
                SignalKind::Real => vec![format!("zone{k}")],
            })
            .collect()
    }
    /// Samples between adjacent emitters.
    pub fn emitter_step_samples(&self) -> usize {
        match self.basis {
            Basis::Chirp { slot_samples, .. } => slot_samples,
            Basis::Hogel { hogel_samples } => hogel_samples,
        }
    }
    /// Samples one emitter's basis spans (all zones).
    pub fn emitter_span_samples(&self) -> usize {
        match self.basis {
            Basis::Chirp { chirp_samples, zones, .. } => chirp_samples * zones,
            Basis::Hogel { hogel_samples } => hogel_samples,
        }
    }
    /// The most emitters whose whole basis fits in a hololine.
    pub fn max_emitters(&self) -> usize {
        let (span, step) = (self.emitter_span_samples(), self.emitter_step_samples());
        if span > self.samples_per_hololine || step == 0 {
            0
        } else {
            (self.samples_per_hololine - span) / step + 1
        }
    }
    /// `x` of emitter `e`, metres: the centre of its basis, on a hololine
    /// centred on `x = 0` (sample `n` centred at `(n + ½ − N/2) · pitch`).
    pub fn emitter_x_m(&self, e: usize) -> f64 {
        let centre = (e * self.emitter_step_samples()) as f64 + self.emitter_span_samples() as f64 / 2.0;
        (centre - self.samples_per_hololine as f64 / 2.0) * self.sample_pitch_m
    }
    /// Problems with the blanking gains: they need I/Q signals of their own
    /// per colour, one list of
    /// `2K` finite, non-zero gains per zone, and blanked runs far enough
    /// apart that no sample is taken twice or lies in another run.
    pub fn blanking_gains_problems(&self) -> Vec<String> {
        let Some(g) = &self.blanking_gains else { return Vec::new() };
        let mut p = Vec::new();
        let k = g.samples_each_side;
        if self.signal != SignalKind::Iq {
            p.push("blanking gains are complex: they need I/Q signals".into());
        }
        if self.colours == ColourSignals::Summed {
            p.push("blanking gains are for colours with signals of their own, not summed".into());
        }
        let mut table = |what: &str, k: usize, zones: &[Vec<[f64; 2]>]| {
            if k == 0 {
                p.push(format!("{what} need samples_each_side ≥ 1"));
            }
            // A table longer than the hololine reaches nothing more (and 2K
            // must not overflow below).
            if k > self.samples_per_hololine {
                p.push(format!(
                    "{what}: samples_each_side = {k} is more than a hololine's {} samples",
                    self.samples_per_hololine
                ));
                return;
            }
            if zones.len() != self.zones() {
                p.push(format!("{what} for {} zones; the basis has {}", zones.len(), self.zones()));
            }
            for (z, gains) in zones.iter().enumerate() {
                if gains.len() != 2 * k {
                    p.push(format!(
                        "{what} of zone {}: {} gains, not 2 · samples_each_side = {}",
                        z + 1,
                        gains.len(),
                        2 * k
                    ));
                }
                if let Some([re, im]) =
                    gains.iter().find(|[re, im]| !(re.is_finite() && im.is_finite()) || re.hypot(*im) < 1e-6)
                {
                    p.push(format!("{what} of zone {}: gain {re} + {im}i must be finite and not zero", z + 1));
                }
            }
        };
        table("blanking gains", k, &g.zones);
        if let Some(f) = &g.flat_field {
            table("flat-field blanking gains", f.samples_each_side, &f.zones);
            if !(0.0..1.0).contains(&f.max_spread) {
                p.push(format!(
                    "flat-field blanking gains: max_spread {} must be at least 0 and below 1",
                    f.max_spread
                ));
            }
        }
        let k = g.reach();
        if k > self.samples_per_hololine {
            return p; // named above
        }
        let fb = &self.frame_buffer;
        for reversed in [false, true] {
            let runs = fb.blanked_runs(self.samples_per_hololine, reversed);
            if let Some(pair) = runs.windows(2).find(|r| r[1].start - r[0].end < 2 * k) {
                p.push(format!(
                    "blanked runs at samples {}..{} and {}..{} are closer than 2 · samples_each_side = {}",
                    pair[0].start,
                    pair[0].end,
                    pair[1].start,
                    pair[1].end,
                    2 * k
                ));
                break;
            }
        }
        p
    }
    /// Why this fringe's blanking gains do not suit it, when they do not:
    /// gains are found for one set of emitter phases, and the built-in
    /// tables for every emitter at phase 0 (spec/layouts.md §7.1), so
    /// gains kept beside `emitter_phases` other than `zero` are named. Not
    /// an error: the layout is valid, its seams only worse than it could be.
    pub fn blanking_gains_caveat(&self) -> Option<String> {
        (self.blanking_gains.is_some() && self.emitter_phases != EmitterPhases::Zero).then(|| {
            format!(
                "its blanking gains were found for every emitter at phase 0, and it sets emitter_phases = \"{}\": \
                 they lift its dark columns less and leave bright ones (Mark III with viewer phases, evenly lit: \
                 0.38–4.2 of the neighbours, 0.53–1.15 without gains; spec/layouts.md §7.1)",
                format!("{:?}", self.emitter_phases).to_lowercase()
            )
        })
    }
    /// [`Layout::blanking_gains_reference`] for one lane of zone `zone`'s
    /// pair of a hololine, `lane` 0 (I) or 1 (Q), on a line sent backwards if
    /// `reversed`: `sent` is that lane with its gains, from the pair's
    /// samples before any gain (`re` = I, `im` = Q).
    #[allow(clippy::too_many_arguments)]
    fn lane_blanking_gains_reference(
        &self,
        reversed: bool,
        zone: usize,
        lane: usize,
        re: &[f64],
        im: &[f64],
        sent: &mut [f64],
        radiance_range: &dyn Fn(std::ops::Range<usize>) -> (f64, f64),
    ) {
        let Some(general) = &self.blanking_gains else { return };
        let fb = &self.frame_buffer;
        let samples = re.len();
        let blanked = |n: usize| (if reversed { samples - 1 - n } else { n }) % fb.line_samples >= fb.width;
        // Each maximal run [a, b) of blanked samples of this lane's line, in
        // signal order n: a − K + i takes gain i, b + i gain K + i (the
        // lower-n side takes the table's first half however the line is
        // sent), of the flat-field table when the elements (of every zone)
        // within its K of the run are evenly lit, else of the general one.
        let mut n = 0;
        while n < samples {
            if !blanked(n) {
                n += 1;
                continue;
            }
            let a = n;
            while n < samples && blanked(n) {
                n += 1;
            }
            let (k, gains) = match &general.flat_field {
                Some(f)
                    if {
                        let k = f.samples_each_side;
                        let (lo, hi) = radiance_range(a.saturating_sub(k)..(n + k).min(samples));
                        hi > 0.0 && hi - lo <= f.max_spread * hi
                    } =>
                {
                    (f.samples_each_side, &f.zones[zone])
                }
                _ => (general.samples_each_side, &general.zones[zone]),
            };
            // I' = Re(g s), Q' = Im(g s), s = I + iQ.
            let mut gain = |at: usize, i: usize| {
                let [gr, gi] = gains[i];
                sent[at] = if lane == 0 { gr * re[at] - gi * im[at] } else { gr * im[at] + gi * re[at] };
            };
            for i in 0..k {
                if a + i >= k {
                    gain(a + i - k, i);
                }
                if n + i < samples {
                    gain(n + i, k + i);
                }
            }
        }
    }
    /// The in-signal carrier of colour channel `c` (zero for I/Q signals).
    pub fn carrier(&self, c: usize) -> f64 {
        match self.carrier_cycles_per_sample.as_slice() {
            [] => 0.0,
            [one] => *one,
            many => many.get(c).copied().unwrap_or(f64::NAN),
        }
    }
}

impl Layout {
    /// spec/layouts.md §5.5 read straight, in f64: the signals of hololine
    /// `j` of colour channel `colour` (`signals[s][n]`, in the layout's signal
    /// order, I/Q pairs per zone) with the shown samples before and after
    /// every blanked run multiplied, as `I + iQ`, by their zone's gains.
    /// `radiance_range(samples)` is the least and the largest radiance
    /// (negative ones taken as 0) of the hololine's elements (of every zone)
    /// whose segments overlap `samples`: it decides where the flat-field
    /// gains apply. The reference the frame assembler's gains are tested
    /// against; does nothing without gains (which need I/Q signals and
    /// separate colours).
    pub fn blanking_gains_reference(
        &self,
        j: usize,
        colour: usize,
        signals: &mut [Vec<f64>],
        radiance_range: &dyn Fn(std::ops::Range<usize>) -> (f64, f64),
    ) {
        let Some(f) = &self.fringe else { return };
        if f.blanking_gains.is_none() {
            return;
        }
        let per_colour = signals.len();
        for zone in 0..per_colour / 2 {
            // Each lane goes out on its own line, which may be sent the other
            // way from its partner's (a pair split across two lines): each
            // takes the runs of its own line.
            let reversed = |lane: usize| {
                let s = colour * per_colour + 2 * zone + lane;
                let (_, line) = f.frame_buffer.channel_and_line(j, s, self.signals_per_hololine());
                f.frame_buffer.line_reversed(line)
            };
            let (re, im) = (signals[2 * zone].clone(), signals[2 * zone + 1].clone());
            for lane in 0..2 {
                f.lane_blanking_gains_reference(
                    reversed(lane),
                    zone,
                    lane,
                    &re,
                    &im,
                    &mut signals[2 * zone + lane],
                    radiance_range,
                );
            }
        }
    }
}

/// One frame-buffer channel: an image and a component of its pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelSlot {
    /// Image (head, or colour layer), 0-based.
    pub image: usize,
    /// Component of the pixel (0 = R, 1 = G, 2 = B, 3 = A).
    pub component: usize,
}

/// The frame buffer: `images` images of `width × height` pixels of
/// `components` components, fed by channels that take hololine signals in turn.
///
/// Signal `s` of hololine `j` is item `k = j · S + s` (`S` signals per
/// hololine); it goes to channel `k mod C` as that channel's line `ℓ = k div C`,
/// which occupies rows `first_row + ℓ · (rows_per_hololine + gap_rows)` on.
/// Sample `n` goes to row `n div line_samples` of that block, column
/// `n mod line_samples`; samples at columns `≥ width` fall in the horizontal
/// blanking and are not shown. With `reverse_odd_lines`, odd lines are sent
/// from their last sample to their first (scan direction alternates).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameBuffer {
    /// Names of the images, used in file names (`head1`, …).
    pub image_names: Vec<String>,
    /// Visible columns.
    pub width: usize,
    /// Visible rows.
    pub height: usize,
    /// Components per pixel.
    pub components: usize,
    /// Samples per video line, visible plus horizontal blanking.
    pub line_samples: usize,
    /// Video lines per hololine.
    pub rows_per_hololine: usize,
    /// Rows before the first hololine.
    pub first_row: usize,
    /// Blank rows after each hololine's block.
    pub gap_rows: usize,
    /// The channels in the order hololine signals are dealt to them.
    pub channels: Vec<ChannelSlot>,
    /// Odd lines run backwards.
    pub reverse_odd_lines: bool,
}

/// Where one fringe sample lands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pixel {
    /// Image.
    pub image: usize,
    /// Row.
    pub row: usize,
    /// Column.
    pub column: usize,
    /// Component.
    pub component: usize,
}

impl FrameBuffer {
    /// Channel and line of signal `s` of hololine `j`, with `signals` per hololine.
    pub fn channel_and_line(&self, j: usize, s: usize, signals: usize) -> (usize, usize) {
        let k = j * signals + s;
        (k % self.channels.len(), k / self.channels.len())
    }
    /// First row of line `line`.
    pub fn line_first_row(&self, line: usize) -> usize {
        self.first_row + line * (self.rows_per_hololine + self.gap_rows)
    }
    /// Lines a channel needs for `hololines` hololines of `signals` signals.
    pub fn lines(&self, hololines: usize, signals: usize) -> usize {
        (hololines * signals).div_ceil(self.channels.len())
    }
    /// Where sample `n` of signal `s` of hololine `j` goes, or `None` when it
    /// falls in the horizontal blanking.
    pub fn place(&self, j: usize, s: usize, n: usize, signals: usize, samples: usize) -> Option<Pixel> {
        let (channel, line) = self.channel_and_line(j, s, signals);
        let sent = if self.line_reversed(line) { samples - 1 - n } else { n };
        let column = sent % self.line_samples;
        (column < self.width).then(|| {
            let slot = self.channels[channel];
            Pixel {
                image: slot.image,
                row: self.line_first_row(line) + sent / self.line_samples,
                column,
                component: slot.component,
            }
        })
    }
    /// Whether a channel's line `line` is sent from its last sample to its first.
    pub fn line_reversed(&self, line: usize) -> bool {
        self.reverse_odd_lines && line % 2 == 1
    }
    /// The runs of samples (in signal order) of a `samples`-sample hololine
    /// sent forwards or, `reversed`, backwards that fall in the horizontal
    /// blanking, in increasing order.
    pub fn blanked_runs(&self, samples: usize, reversed: bool) -> Vec<std::ops::Range<usize>> {
        let blanked = |n: usize| {
            let sent = if reversed { samples - 1 - n } else { n };
            self.line_samples > 0 && sent % self.line_samples >= self.width
        };
        let mut runs: Vec<std::ops::Range<usize>> = Vec::new();
        for n in (0..samples).filter(|&n| blanked(n)) {
            match runs.last_mut() {
                Some(run) if run.end == n => run.end = n + 1,
                _ => runs.push(n..n + 1),
            }
        }
        runs
    }
    /// Everything that makes this frame buffer unusable for `hololines`
    /// hololines of `signals` signals of `samples` samples.
    pub fn problems(&self, hololines: usize, signals: usize, samples: usize) -> Vec<String> {
        let mut p = Vec::new();
        if self.image_names.is_empty() || self.width == 0 || self.height == 0 || self.components == 0 {
            p.push("the frame buffer needs at least one image of at least one pixel".into());
        }
        if self.line_samples < self.width {
            p.push(format!("line_samples {} is less than the visible width {}", self.line_samples, self.width));
        } else if self.width > 0 && self.line_samples - self.width > self.line_samples / 2 {
            // Displays blank a few samples of each line (Mark III 16 of 4096,
            // analogue video about a fifth); most of every line unseen is a
            // mistyped width, not a display.
            p.push(format!(
                "width {} of line_samples {}: {} of every {} samples would fall in the horizontal blanking and never be \
                 shown (at most half may)",
                self.width,
                self.line_samples,
                self.line_samples - self.width,
                self.line_samples
            ));
        }
        if self.line_samples == 0 || self.rows_per_hololine * self.line_samples != samples {
            p.push(format!(
                "{} rows of {} samples do not hold a hololine of {samples} samples",
                self.rows_per_hololine, self.line_samples
            ));
        }
        if self.channels.is_empty() {
            p.push("the frame buffer has no channels".into());
        }
        for (i, c) in self.channels.iter().enumerate() {
            if c.image >= self.image_names.len() || c.component >= self.components {
                p.push(format!("channel {i} names image {} component {}, which do not exist", c.image, c.component));
            }
            if self.channels[..i].contains(c) {
                p.push(format!("channel {i} repeats image {} component {}", c.image, c.component));
            }
        }
        if !self.channels.is_empty() && self.lines(hololines, signals) > 0 {
            let last_row = self.line_first_row(self.lines(hololines, signals) - 1) + self.rows_per_hololine;
            if last_row > self.height {
                p.push(format!(
                    "{hololines} hololines of {signals} signal(s) need {last_row} rows; the images have {}",
                    self.height
                ));
            }
        }
        p
    }
}

/// Float signal to stored integer: `clamp(round(offset + gain · x), 0, 2^bits − 1)`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quantization {
    /// Bits per stored sample (8 for the video frame buffers here).
    pub bits: u8,
    /// Stored value of a zero signal.
    pub offset: f64,
    /// Stored steps per unit of signal.
    pub gain: f64,
}

impl Quantization {
    /// The largest stored value.
    pub fn max_code(&self) -> f64 {
        ((1u64 << self.bits) - 1) as f64
    }
    /// Problems with these numbers.
    pub fn problems(&self) -> Vec<String> {
        let mut p = Vec::new();
        if self.bits != 8 {
            p.push(format!("{}-bit samples: only 8-bit frame buffers are supported", self.bits));
        }
        if !(self.offset.is_finite() && self.gain.is_finite() && self.gain > 0.0) {
            p.push(format!("quantization offset {} and gain {} must be finite, gain > 0", self.offset, self.gain));
        } else if self.offset < 0.0 || self.offset > self.max_code() {
            p.push(format!("quantization offset {} is outside 0..={}", self.offset, self.max_code()));
        }
        p
    }
}
