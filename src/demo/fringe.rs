//! The demo's picture of the fringes: a thumbnail of every frame-buffer
//! image beside a zoom into a few hundred samples of one hololine's signal,
//! where the chirps that steer light into the views can be seen.
//!
//! A thumbnail of the codes themselves would be mid-grey (the quantization's
//! offset) wherever there is signal or not, since the fringes average out;
//! each thumbnail pixel shows instead the RMS signal of the block of
//! frame-buffer pixels under it, per component, so the picture shows where
//! the light of the scene is carried.

use std::ops::Range;

use rayon::prelude::*;

use crate::assemble::{Assembler, FrameImages};
use crate::Result;

use super::canvas::{Canvas, WHITE};
use super::font;

/// Frame-buffer pixels per thumbnail pixel, each way.
const THUMBNAIL_SHRINK: usize = 8;
/// Pixels a signal sample takes across in the zoom.
const ZOOM_SAMPLE_WIDTH: usize = 3;
/// Pixels of a plot from its lowest signal (−1) to its highest (+1).
const ZOOM_HEIGHT: usize = 160;
/// Room around the parts and for a label line, pixels.
const MARGIN: usize = 12;
/// Each font pixel is this many pixels.
const LABEL_SCALE: usize = 2;
/// Marks the zoomed samples in the thumbnail.
const MARK: [f32; 3] = [1.0, 0.1, 0.1];

/// The picture and where its zoom is.
#[derive(Clone, Debug)]
pub struct FringePicture {
    /// The picture.
    pub canvas: Canvas,
    /// The hololine zoomed into.
    pub hololine: usize,
    /// Its signal (in the layout's signal order) shown.
    pub signal: usize,
    /// The samples shown.
    pub samples: Range<usize>,
}

fn label_height() -> usize {
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

    let height = MARGIN + 3 * (label_height() + MARGIN) + th + 2 * ZOOM_HEIGHT + MARGIN;
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

    // The whole hololine, then the zoom, each with its label.
    let whole_top = top + th + MARGIN;
    canvas.text(MARGIN, whole_top, LABEL_SCALE, &format!("hololine {hololine}: its {} samples", row.len()), WHITE);
    let whole_plot = whole_top + label_height();
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
    Ok(FringePicture { canvas, hololine, signal: 0, samples })
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
