//! The options of `convert cameras` as a file records them (spec §4.4):
//! what makes the samples (not the unseen-ray picture or mask asked for
//! beside them), written beside what it means and read back checked
//! against what the converter accepts.

use crate::format::attribute::convert as n;
use crate::format::{Checked, ConversionRecord, RecordHead, RecordReader, RecordWriter, WriteOptions};
use crate::mesh::render::Engine;

use super::convert::CameraConvertOptions;
use super::read::{CameraHints, OpenOptions};
use super::resample::{Blend, CameraOptions, Framing, Parallax, PlacementRequest, MAX_EMITTER_TAPS};

impl CameraConvertOptions {
    /// `holo.convert.kind` of a capture's conversion.
    pub const KIND: &'static str = "cameras";

    /// The record of this conversion of the capture `head` names.
    pub fn record(&self, head: &RecordHead) -> ConversionRecord {
        let mut r = RecordWriter::new(head);
        let resample = &self.resample;
        let p = &resample.placement;
        r.text(n::BLEND, resample.blend.name());
        r.text(n::ENGINE, if resample.reference { Engine::Reference } else { Engine::Fast }.name());
        r.flag(n::DEPTH_MAPS, resample.use_depth);
        r.optional_double(n::FOCUS, p.focus);
        r.optional_double(n::SCALE, p.scale);
        if let Some(c) = p.centre {
            r.v3d(n::CENTRE, c);
        }
        r.text(n::FRAMING, p.framing.name());
        r.text(n::PARALLAX, p.parallax.name());
        if let Some(taps) = resample.emitter_taps {
            r.int(n::EMITTER_TAPS, taps);
        }
        let open = &self.open;
        r.optional_double(n::FOLDER_BASELINE, open.folder.baseline);
        write_hints(&mut r, [n::FOLDER_FOCAL_PX, n::FOLDER_H_FOV_DEG, n::FOLDER_FOCUS], &open.folder.camera);
        r.double(n::FOLDER_M_PER_UNIT, open.folder.metres_per_unit);
        write_hints(&mut r, [n::STANFORD_FOCAL_PX, n::STANFORD_H_FOV_DEG, n::STANFORD_FOCUS], &open.stanford.camera);
        r.double(n::STANFORD_M_PER_UNIT, open.stanford.metres_per_unit);
        r.double(n::QUILT_VIEW_CONE_DEG, open.quilt.view_cone_deg);
        r.double(n::QUILT_V_FOV_DEG, open.quilt.vertical_fov_deg);
        r.finish()
    }

    /// The options a record holds, with `write` as their write part.
    pub fn from_record(r: &RecordReader, write: WriteOptions) -> Checked<CameraConvertOptions> {
        let a = r.attributes();
        let hints = |[focal_px, fov_deg, focus]: [&str; 3]| -> Checked<CameraHints> {
            Ok(CameraHints {
                focal_length_px: r.optional_positive(focal_px)?,
                horizontal_fov_deg: r.optional_double(fov_deg, below_180_degrees, BELOW_180_DEGREES)?,
                focus_distance: r.optional_positive(focus)?,
            })
        };
        let resample = CameraOptions {
            blend: r.choice(n::BLEND, &Blend::ALL, Blend::name)?,
            placement: PlacementRequest {
                scale: r.optional_positive(n::SCALE)?,
                centre: a.optional(n::CENTRE, |a, k| a.v3d(k))?,
                focus: r.optional_positive(n::FOCUS)?,
                framing: r.choice(n::FRAMING, &Framing::ALL, Framing::name)?,
                parallax: r.choice(n::PARALLAX, &Parallax::ALL, Parallax::name)?,
            },
            use_depth: r.flag(n::DEPTH_MAPS)?,
            want_mask: false,
            reference: r.choice(n::ENGINE, &Engine::ALL, Engine::name)? == Engine::Reference,
            emitter_taps: a.optional(n::EMITTER_TAPS, |_, k| r.whole(k, 1, MAX_EMITTER_TAPS))?,
        };
        let mut open = OpenOptions::default();
        open.folder.baseline = r.optional_positive(n::FOLDER_BASELINE)?;
        open.folder.camera = hints([n::FOLDER_FOCAL_PX, n::FOLDER_H_FOV_DEG, n::FOLDER_FOCUS])?;
        open.folder.metres_per_unit = r.positive(n::FOLDER_M_PER_UNIT)?;
        open.stanford.camera = hints([n::STANFORD_FOCAL_PX, n::STANFORD_H_FOV_DEG, n::STANFORD_FOCUS])?;
        open.stanford.metres_per_unit = r.positive(n::STANFORD_M_PER_UNIT)?;
        open.quilt.view_cone_deg = r.double(n::QUILT_VIEW_CONE_DEG, below_180_degrees, BELOW_180_DEGREES)?;
        open.quilt.vertical_fov_deg = r.double(n::QUILT_V_FOV_DEG, below_180_degrees, BELOW_180_DEGREES)?;
        Ok(CameraConvertOptions { resample, open, unseen_png: None, write })
    }
}

/// A capture's camera hints under the names `[focal length, field of view,
/// focus distance]`.
fn write_hints(r: &mut RecordWriter, [focal_px, fov_deg, focus]: [&str; 3], h: &CameraHints) {
    r.optional_double(focal_px, h.focal_length_px);
    r.optional_double(fov_deg, h.horizontal_fov_deg);
    r.optional_double(focus, h.focus_distance);
}

/// Fields of view and view cones: an angle strictly between 0 and 180
/// degrees (what a camera's picture can span).
fn below_180_degrees(x: f64) -> bool {
    x > 0.0 && x < 180.0
}

const BELOW_180_DEGREES: &str = "between 0 and 180 (degrees)";
