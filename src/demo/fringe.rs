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
/// Pixels of the zoom's plot from its lowest signal (−1) to its highest (+1).
const ZOOM_HEIGHT: usize = 220;
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
/// buffer holds them) for `a`'s layout.
pub fn fringe_picture(a: &Assembler, images: &FrameImages<u8>) -> Result<FringePicture> {
    let layout = a.layout();
    let fringe = layout.fringe.as_ref().expect("an assembler's layout has a fringe side");
    let q = &fringe.quantization;
    let (tw, th) = (images.width / THUMBNAIL_SHRINK, images.height / THUMBNAIL_SHRINK);
    let thumbnails: Vec<Canvas> =
        images.images.iter().map(|image| thumbnail(images, image, q.offset, q.gain)).collect();
    // Normalised together, so the images compare.
    let peak = thumbnails.iter().flat_map(|t| t.rgb.iter().flatten()).fold(0f32, |m, &v| m.max(v));

    // The zoom: the strongest window of the strongest hololine's first signal.
    let hololines = layout.geometry.hololines;
    let unpacked = a.unpack(images, hololines)?;
    let signals = &unpacked[0];
    let energy = |row: &[f32]| row.iter().map(|v| f64::from(v * v)).sum::<f64>();
    let hololine =
        (0..hololines).max_by(|&x, &y| energy(signals.row(0, x)).total_cmp(&energy(signals.row(0, y)))).unwrap_or(0);
    let row = signals.row(0, hololine);
    let width = images.images.len() * (tw + MARGIN) + MARGIN;
    let count = ((width - 2 * MARGIN) / ZOOM_SAMPLE_WIDTH).min(row.len());
    let step = (count / 4).max(1);
    let start = (0..=row.len() - count)
        .step_by(step)
        .max_by(|&x, &y| energy(&row[x..x + count]).total_cmp(&energy(&row[y..y + count])))
        .unwrap_or(0);
    let samples = start..start + count;

    let height = MARGIN + label_height() + th + MARGIN + label_height() + ZOOM_HEIGHT + MARGIN;
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
        let (c0, c1) =
            (first.column.min(last.column) / THUMBNAIL_SHRINK, first.column.max(last.column) / THUMBNAIL_SHRINK);
        let (r0, r1) = (first.row.min(last.row) / THUMBNAIL_SHRINK, first.row.max(last.row) / THUMBNAIL_SHRINK);
        let (left, right, up, down) =
            (x0 + c0.saturating_sub(3), x0 + c1 + 3, top + r0.saturating_sub(3), top + r1 + 3);
        canvas.fill(left, up, right - left + 1, 1, MARK);
        canvas.fill(left, down, right - left + 1, 1, MARK);
        canvas.fill(left, up, 1, down - up + 1, MARK);
        canvas.fill(right, up, 1, down - up + 1, MARK);
    }

    let zoom_top = top + th + MARGIN;
    canvas.text(
        MARGIN,
        zoom_top,
        LABEL_SCALE,
        &format!("hololine {hololine}, samples {} to {} of {}: chirps", samples.start, samples.end, row.len()),
        MARK,
    );
    let plot_top = zoom_top + label_height();
    let y_of = |v: f32| {
        let t = (1.0 - f64::from(v.clamp(-1.0, 1.0))) / 2.0;
        plot_top + (t * (ZOOM_HEIGHT - 1) as f64).round() as usize
    };
    // The zero line, then the signal as a line from sample to sample.
    canvas.fill(MARGIN, y_of(0.0), count * ZOOM_SAMPLE_WIDTH, 1, [0.05; 3]);
    for (i, &v) in row[samples.clone()].iter().enumerate() {
        let next = row.get(samples.start + i + 1).copied().unwrap_or(v);
        let (a, b) = (y_of(v).min(y_of(next)), y_of(v).max(y_of(next)));
        let x = MARGIN + i * ZOOM_SAMPLE_WIDTH;
        canvas.fill(x, y_of(v), ZOOM_SAMPLE_WIDTH, 1, WHITE);
        canvas.fill(x + ZOOM_SAMPLE_WIDTH - 1, a, 1, b - a + 1, WHITE);
    }
    Ok(FringePicture { canvas, hololine, signal: 0, samples })
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
