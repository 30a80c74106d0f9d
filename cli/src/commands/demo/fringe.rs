//! The demo's picture of the fringes: a thumbnail of every frame-buffer
//! image beside a zoom into a few hundred samples of one hololine's signal,
//! where the chirps that steer light into the views can be seen.
//!
//! A thumbnail of the codes themselves would be mid-grey (the quantization's
//! offset) wherever there is signal or not, since the fringes average out;
//! each thumbnail pixel shows instead the RMS signal of the block of
//! frame-buffer pixels under it, per component, so the picture shows where
//! the light of the scene is carried.
//!
//! A legend says what it shows: which signal each component carries (so
//! the false colour reads as zones: on Mark III head 1's red and green are
//! zone 1's sine and cosine, together yellow), which views each zone
//! carries, and what the lobes of the hololine's signal are (stretches of
//! emitters the scene lights, each lit emitter's chirp a run of samples).

use std::ops::Range;

use rayon::prelude::*;

use holo::assemble::{Assembler, FrameImages};
use holo::Result;

use super::canvas::{Canvas, LABEL_SCALE, WHITE};
use super::font;

/// Frame-buffer pixels per thumbnail pixel, each way.
pub const THUMBNAIL_SHRINK: usize = 8;
/// Pixels a signal sample takes across in the zoom.
const ZOOM_SAMPLE_WIDTH: usize = 3;
/// Pixels of a plot from its lowest signal (−1) to its highest (+1).
const ZOOM_HEIGHT: usize = 160;
/// Room around the parts and for a label line, pixels.
pub const MARGIN: usize = 12;
/// Marks the zoomed samples in the thumbnail.
const MARK: [f32; 3] = [1.0, 0.1, 0.1];

/// The picture and where its zoom is.
#[derive(Clone, Debug)]
pub struct FringePicture {
    /// The picture.
    pub canvas: Canvas,
    /// The hololine zoomed into.
    pub hololine: usize,
    /// The samples shown.
    pub samples: Range<usize>,
    /// The legend drawn: what the colours, zones and lobes are (what the
    /// tests read of the picture, with the lobes).
    pub legend: Vec<String>,
    /// The emitters of each lobe of the hololine's signal, in order.
    pub lobes: Vec<Range<usize>>,
}

/// Characters a legend line holds at [`LABEL_SCALE`] in the picture's width.
pub fn line_chars(width: usize) -> usize {
    (width - 2 * MARGIN) / (font::ADVANCE * LABEL_SCALE)
}

/// `items` joined by `sep` into lines of at most `chars` characters.
fn wrapped(items: &[String], sep: &str, chars: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for item in items {
        match lines.last_mut() {
            Some(line) if line.chars().count() + sep.chars().count() + item.chars().count() <= chars => {
                line.push_str(sep);
                line.push_str(item);
            }
            _ => lines.push(item.clone()),
        }
    }
    lines
}

/// The name of signal `s` of a hololine (`zone1.cos`, or `R.zone1` with
/// several colours sent separately).
fn signal_name(layout: &holo::layout::Layout, s: usize) -> String {
    let fringe = layout.fringe.as_ref().expect("an assembler's layout has a fringe side");
    let names = fringe.signal_names();
    let channels = &layout.geometry.channels;
    match fringe.colours {
        holo::layout::ColourSignals::Separate if channels.len() > 1 => {
            format!("{}.{}", channels[s / names.len()].name, names[s % names.len()])
        }
        _ => names[s % names.len()].clone(),
    }
}

/// What each image's false colour shows: its components' signals, grouped
/// by the zone they carry, each group named by the colour its components
/// make together.
fn colour_legend(layout: &holo::layout::Layout) -> Vec<String> {
    let fringe = layout.fringe.as_ref().expect("an assembler's layout has a fringe side");
    let fb = &fringe.frame_buffer;
    let signals = layout.signals_per_hololine();
    // The signals each channel carries, over as many hololines as it takes to repeat.
    let mut carried: Vec<Vec<usize>> = vec![Vec::new(); fb.channels.len()];
    for k in 0..signals * fb.channels.len() {
        let (channel, s) = (k % fb.channels.len(), k % signals);
        if !carried[channel].contains(&s) {
            carried[channel].push(s);
        }
    }
    const COMPONENTS: [&str; 4] = ["red", "green", "blue", "alpha"];
    let mut lines = Vec::new();
    for (image, name) in fb.image_names.iter().enumerate() {
        // (group, its components, each with what of the group it carries)
        let mut groups: Vec<(String, Vec<(usize, String)>)> = Vec::new();
        for (channel, slot) in fb.channels.iter().enumerate().filter(|(_, s)| s.image == image) {
            let names: Vec<String> = carried[channel].iter().map(|&s| signal_name(layout, s)).collect();
            let (group, part) = match names.as_slice() {
                [one] => match one.rsplit_once('.') {
                    Some((g, p)) if p == "cos" || p == "sin" => (g.to_string(), p.to_string()),
                    _ => (one.clone(), String::new()),
                },
                many => (many.join("/"), String::new()),
            };
            match groups.iter_mut().find(|(g, _)| *g == group) {
                Some((_, parts)) => parts.push((slot.component, part)),
                None => groups.push((group, vec![(slot.component, part)])),
            }
        }
        // Each group's components in order, the groups by their first (red first).
        groups.iter_mut().for_each(|(_, parts)| parts.sort());
        groups.sort_by_key(|(_, parts)| parts[0].0);
        let said: Vec<String> = groups
            .iter()
            .map(|(group, parts)| {
                if fb.components == 1 {
                    return format!("brightness = {group}");
                }
                let mask = parts.iter().fold(0, |m, (c, _)| m | 1 << c);
                let colour = match mask & 7 {
                    1 => "red",
                    2 => "green",
                    4 => "blue",
                    3 => "yellow",
                    5 => "magenta",
                    6 => "cyan",
                    7 => "white",
                    _ => "alpha",
                };
                let what: Vec<String> = parts
                    .iter()
                    .map(|(c, p)| {
                        let c = COMPONENTS[(*c).min(3)];
                        if p.is_empty() {
                            c.to_string()
                        } else {
                            format!("{c} {p}")
                        }
                    })
                    .collect();
                format!("{colour} = {group} ({})", what.join(", "))
            })
            .collect();
        lines.push(format!("{name}: {}", said.join(", ")));
    }
    lines
}

/// The views each zone of colour 0 carries, as `zone1: +4.1 to +11.9 deg`.
fn zone_legend(a: &Assembler) -> Vec<String> {
    let layout = a.layout();
    let basis = a.plan(0).basis();
    let views = &layout.geometry.views;
    let e = basis.emitters / 2;
    (0..basis.zones())
        .filter_map(|zone| {
            let degrees: Vec<f64> = (0..views.count)
                .filter(|&v| basis.segment(e, v).zone == zone)
                .map(|v| views.theta_rad(v).to_degrees())
                .collect();
            let lo = degrees.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = degrees.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (!degrees.is_empty()).then(|| format!("zone{}: views {lo:+.1} to {hi:+.1} deg", zone + 1))
        })
        .collect()
}

/// The share of the envelope's peak above which a stretch of the signal is
/// a lobe: below it, the dimmer stretches between bright ones (the demo's
/// hololine reads as two lobes, its dip between them at about a seventh of
/// the peak).
const LOBE_SHARE: f64 = 0.3;

/// The lobes of a signal of zone `zone` of colour 0 (`row`): stretches of
/// samples whose RMS over an emitter's step is above [`LOBE_SHARE`] of the
/// largest, as the emitters whose pieces of that zone lie within each.
fn lobes(a: &Assembler, row: &[f32], zone: usize) -> Vec<Range<usize>> {
    let basis = a.plan(0).basis();
    let step = basis.step.max(1);
    let windows: Vec<f64> = row
        .chunks(step)
        .map(|w| (w.iter().map(|v| f64::from(*v).powi(2)).sum::<f64>() / w.len() as f64).sqrt())
        .collect();
    let peak = windows.iter().copied().fold(0.0, f64::max);
    if peak == 0.0 {
        return Vec::new();
    }
    // Runs of lit windows; a gap of one window is the chirps' own ripple.
    let mut runs: Vec<Range<usize>> = Vec::new();
    for (k, _) in windows.iter().enumerate().filter(|(_, &w)| w > LOBE_SHARE * peak) {
        match runs.last_mut() {
            Some(run) if k <= run.end + 1 => run.end = k + 1,
            _ => runs.push(k..k + 1),
        }
    }
    // Each emitter's extent in this zone's signal.
    let extent = |e: usize| {
        let pieces = (0..basis.views).map(|v| basis.segment(e, v)).filter(|s| s.zone == zone);
        pieces.fold((usize::MAX, 0), |(lo, hi), s| (lo.min(s.start), hi.max(s.start + s.len)))
    };
    runs.iter()
        .filter(|run| run.len() > 1)
        .filter_map(|run| {
            let (n0, n1) = (run.start * step, run.end * step);
            let inside: Vec<usize> = (0..basis.emitters)
                .filter(|&e| {
                    let (lo, hi) = extent(e);
                    lo >= n0 && hi <= n1
                })
                .collect();
            Some(*inside.first()?..*inside.last()? + 1)
        })
        .collect()
}

pub fn label_height() -> usize {
    font::GLYPH_SIZE.1 * LABEL_SCALE + MARGIN / 2
}

/// The fringe picture of one assembled frame (`images`, 8-bit, as the frame
/// buffer holds them) for `a`'s layout: the thumbnails; under them the
/// whole signal of the hololine that carries the most, at one column per
/// few dozen samples (the scene's extent along it shows); and under that
/// a zoom where its light begins, the first emitters' chirps one by one
/// before many overlap.
pub fn fringe_picture(a: &Assembler, images: &FrameImages<u8>) -> Result<FringePicture> {
    let layout = a.layout();
    let fringe = layout.fringe.as_ref().expect("an assembler's layout has a fringe side");
    let q = &fringe.quantization;
    let (tw, th) = (images.width / THUMBNAIL_SHRINK, images.height / THUMBNAIL_SHRINK);
    let thumbnails: Vec<Canvas> =
        images.images.iter().map(|image| thumbnail(images, image, q.offset, q.gain)).collect();
    // Normalised together, so the images compare.
    let peak = thumbnails.iter().flat_map(|t| t.rgb.iter().flatten()).fold(0f32, |m, &v| m.max(v));

    let hololines = layout.geometry.hololines;
    let unpacked = a.unpack(images, hololines)?;
    let signals = &unpacked[0];
    let energy = |row: &[f32]| row.iter().map(|v| f64::from(v * v)).sum::<f64>();
    let hololine =
        (0..hololines).max_by(|&x, &y| energy(signals.row(0, x)).total_cmp(&energy(signals.row(0, y)))).unwrap_or(0);
    let row = signals.row(0, hololine);
    let plot_width = images.images.len() * (tw + MARGIN) - MARGIN;
    let width = plot_width + 2 * MARGIN;
    let count = (plot_width / ZOOM_SAMPLE_WIDTH).min(row.len());
    // From a few samples before the first that carries a tenth of the
    // hololine's peak (a dark hololine: from its start).
    let row_peak = row.iter().fold(0f32, |m, v| m.max(v.abs()));
    let first = row.iter().position(|v| v.abs() > 0.1 * row_peak && row_peak > 0.0).unwrap_or(0);
    let start = first.saturating_sub(count / 16).min(row.len() - count);
    let samples = start..start + count;

    // The legend: under the thumbnails what their colours are; under the
    // whole hololine's label what its lobes are.
    let chars = line_chars(width);
    let mut colours = vec![format!(
        "colour: rms signal of {THUMBNAIL_SHRINK} x {THUMBNAIL_SHRINK} frame-buffer pixels, per component"
    )];
    colours.extend(colour_legend(layout));
    colours.extend(wrapped(&zone_legend(a), ", ", chars));
    let zone = 0;
    let lobes = lobes(a, row, zone);
    let lobe_words: Vec<String> = lobes
        .iter()
        .map(|r| {
            let g = &layout.geometry;
            // Whole millimetres, without a "-0".
            let mm = |x_m: f64| (x_m * 1e3).round() + 0.0;
            let (x0, x1) = (mm(g.emitter_x_m(r.start)), mm(g.emitter_x_m(r.end - 1)));
            format!("emitters {}-{} (x {x0:+.0} to {x1:+.0} mm)", r.start, r.end - 1)
        })
        .collect();
    let mut about_lobes =
        vec![format!("envelope: the light of the scene along the hololine in zone{} views", zone + 1)];
    if lobe_words.is_empty() {
        about_lobes.push("lobes: none, the hololine is dark".to_string());
    } else {
        about_lobes.push(format!("lobes: the bright stretches (above {LOBE_SHARE} of the peak), darker between:"));
        about_lobes.extend(wrapped(&lobe_words, ", ", chars));
    }
    let legend_lines = colours.len() + about_lobes.len();

    let height =
        MARGIN + 3 * (label_height() + MARGIN) + legend_lines * label_height() + MARGIN + th + 2 * ZOOM_HEIGHT + MARGIN;
    let mut canvas = Canvas::new(width, height, true);
    let top = MARGIN + label_height();
    for (k, (t, name)) in thumbnails.iter().zip(&fringe.frame_buffer.image_names).enumerate() {
        let x = MARGIN + k * (tw + MARGIN);
        canvas.text(x, MARGIN, LABEL_SCALE, &format!("{name}: signal amplitude"), WHITE);
        let mut t = t.clone();
        t.rgb.iter_mut().for_each(|p| *p = p.map(|v| v / peak.max(f32::MIN_POSITIVE)));
        canvas.paste(x, top, &t);
    }
    // Where the zoomed samples are in the frame buffer: a box round them.
    let fb = &fringe.frame_buffer;
    let per_hololine = layout.signals_per_hololine();
    let placed: Vec<_> =
        samples.clone().filter_map(|n| fb.place(hololine, 0, n, per_hololine, fringe.samples_per_hololine)).collect();
    if let (Some(first), Some(last)) = (placed.first(), placed.last()) {
        let x0 = MARGIN + first.image * (tw + MARGIN);
        let (c0, c1) = (first.column.min(last.column), first.column.max(last.column));
        let (r0, r1) = (first.row.min(last.row), first.row.max(last.row));
        let [c0, c1, r0, r1] = [c0, c1, r0, r1].map(|p| p / THUMBNAIL_SHRINK);
        outline(&mut canvas, (x0 + c0).saturating_sub(3), (top + r0).saturating_sub(3), c1 - c0 + 7, r1 - r0 + 7);
    }

    let mut y = top + th + MARGIN;
    for line in &colours {
        canvas.text(MARGIN, y, LABEL_SCALE, line, WHITE);
        y += label_height();
    }

    // The whole hololine, then the zoom, each with its label.
    let whole_top = y + MARGIN;
    let signal_name = signal_name(layout, 0);
    canvas.text(
        MARGIN,
        whole_top,
        LABEL_SCALE,
        &format!("hololine {hololine}, signal {signal_name}: its {} samples", row.len()),
        WHITE,
    );
    let mut y = whole_top + label_height();
    for line in &about_lobes {
        canvas.text(MARGIN, y, LABEL_SCALE, line, WHITE);
        y += label_height();
    }
    let whole_plot = y;
    plot(&mut canvas, (MARGIN, whole_plot), plot_width, row, row_peak.max(f32::MIN_POSITIVE));
    let per_column = row.len() as f64 / plot_width as f64;
    let (z0, z1) = ((samples.start as f64 / per_column) as usize, (samples.end as f64 / per_column).ceil() as usize);
    outline(&mut canvas, MARGIN + z0, whole_plot, (z1 - z0).max(1) + 1, ZOOM_HEIGHT);
    let zoom_top = whole_plot + ZOOM_HEIGHT + MARGIN;
    canvas.text(
        MARGIN,
        zoom_top,
        LABEL_SCALE,
        &format!("samples {} to {}: the chirps begin", samples.start, samples.end),
        MARK,
    );
    plot(
        &mut canvas,
        (MARGIN, zoom_top + label_height()),
        plot_width,
        &row[samples.clone()],
        row_peak.max(f32::MIN_POSITIVE),
    );
    let legend = colours.into_iter().chain(about_lobes).collect();
    Ok(FringePicture { canvas, hololine, samples, legend, lobes })
}

/// A `width × height` outline in [`MARK`] with its top left at `(x, y)`.
fn outline(canvas: &mut Canvas, x: usize, y: usize, width: usize, height: usize) {
    canvas.fill(x, y, width, 1, MARK);
    canvas.fill(x, y + height - 1, width, 1, MARK);
    canvas.fill(x, y, 1, height, MARK);
    canvas.fill(x + width - 1, y, 1, height, MARK);
}

/// `signal` (`−peak` to `peak`) plotted `width` pixels wide and
/// [`ZOOM_HEIGHT`] tall from `(x, y)`: each column spans the samples under it from their least
/// to their greatest, and joins its neighbours, so a few samples a column
/// show as a line and many as their envelope.
fn plot(canvas: &mut Canvas, (x, y): (usize, usize), width: usize, signal: &[f32], peak: f32) {
    let y_of = |v: f32| {
        let t = (1.0 - f64::from((v / peak).clamp(-1.0, 1.0))) / 2.0;
        y + (t * (ZOOM_HEIGHT - 1) as f64).round() as usize
    };
    canvas.fill(x, y_of(0.0), width, 1, [0.05; 3]);
    let n = signal.len();
    let mut previous: Option<f32> = None;
    for column in 0..width {
        let (a, b) = (column * n / width, ((column + 1) * n / width).max(column * n / width + 1).min(n));
        let samples = &signal[a.min(n - 1)..b.max(a.min(n - 1) + 1)];
        let (lo, hi) = samples.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        // Join the previous column's last sample to this one's range.
        let (lo, hi) = previous.map_or((lo, hi), |p| (lo.min(p), hi.max(p)));
        previous = samples.last().copied();
        let (top, bottom) = (y_of(hi), y_of(lo));
        canvas.fill(x + column, top, 1, bottom - top + 1, WHITE);
    }
}

/// Image `image`'s RMS signal per block of `THUMBNAIL_SHRINK` pixels a
/// side, per component (a grey image in all three colours).
fn thumbnail(images: &FrameImages<u8>, image: &[u8], offset: f64, gain: f64) -> Canvas {
    let (tw, th) = (images.width / THUMBNAIL_SHRINK, images.height / THUMBNAIL_SHRINK);
    let c = images.components;
    let mut t = Canvas::new(tw, th, c == 1);
    let n = (THUMBNAIL_SHRINK * THUMBNAIL_SHRINK) as f64;
    t.rgb.par_chunks_mut(tw).enumerate().for_each(|(y, out)| {
        for (x, out) in out.iter_mut().enumerate() {
            let mut sum = [0f64; 3];
            for row in y * THUMBNAIL_SHRINK..(y + 1) * THUMBNAIL_SHRINK {
                let start = (row * images.width + x * THUMBNAIL_SHRINK) * c;
                for pixel in image[start..start + THUMBNAIL_SHRINK * c].chunks_exact(c) {
                    for (k, s) in sum.iter_mut().enumerate() {
                        let v = (f64::from(pixel[k.min(c - 1)]) - offset) / gain;
                        *s += v * v;
                    }
                }
            }
            *out = sum.map(|s| (s / n).sqrt() as f32);
        }
    });
    t
}
