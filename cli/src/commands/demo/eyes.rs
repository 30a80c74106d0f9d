//! The eyes the demo shows: their pupil, and what they see as labelled
//! tiles on a contact sheet.

use holo::reconstruct::picture::Picture;

use super::canvas::{Canvas, LABEL_SCALE, WHITE};
use super::font;

/// An eye's pupil, metres.
pub const PUPIL_M: f64 = 4e-3;

/// Room round tiles and labels, pixels.
const GAP: usize = 8;

/// The outline drawn round each picture of the display: the edge of its
/// emitter plane, so the scene's size and place on it show (and, the
/// display's width and height being known, its proportions can be
/// measured). Blue, a colour no grey scene has.
pub const DISPLAY_EDGE: [f32; 3] = [0.0, 0.02, 0.3];

/// `picture` shrunk `shrink` times, outlined by [`DISPLAY_EDGE`] one pixel
/// outside it, with `label` under it.
pub fn labelled(picture: &Picture, shrink: usize, label: &str) -> Canvas {
    let tile = Canvas::from_picture(picture, shrink);
    let label_height = font::GLYPH_SIZE.1 * LABEL_SCALE + 2 * GAP;
    let (w, h) = (tile.width + 2, tile.height + 2);
    let mut c = Canvas::new(w, h + label_height, tile.grey);
    c.fill(0, 0, w, h, DISPLAY_EDGE);
    c.paste(1, 1, &tile);
    let x = w.saturating_sub(font::width(label) * LABEL_SCALE) / 2;
    c.text(x, h + GAP, LABEL_SCALE, label, WHITE);
    c
}

/// Labelled tiles of `pictures`, `columns` a row, each shrunk `shrink`
/// times, on black with a gap between them.
pub fn contact_sheet(pictures: &[(String, &Picture)], columns: usize, shrink: usize) -> Canvas {
    let tiles: Vec<Canvas> = pictures.iter().map(|(label, p)| labelled(p, shrink, label)).collect();
    let (w, h) = tiles.first().map_or((0, 0), |t| (t.width, t.height));
    let columns = columns.clamp(1, tiles.len().max(1));
    let rows = tiles.len().div_ceil(columns);
    let mut sheet = Canvas::new(columns * (w + GAP) + GAP, rows * (h + GAP) + GAP, tiles.iter().all(|t| t.grey));
    for (k, t) in tiles.iter().enumerate() {
        sheet.paste(GAP + (k % columns) * (w + GAP), GAP + (k / columns) * (h + GAP), t);
    }
    sheet
}
