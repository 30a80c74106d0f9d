//! Exact provenance: which converter made a `.holo` file, from which input,
//! with every option it was given, recorded as the typed `holo.convert.*`
//! attributes (spec/holo-format.md §4.4) so that the same conversion can be
//! made again from the file alone.
//!
//! `holo.source` says the same for people, its numbers rounded; the record
//! is exact (every `f64` a `double`, every choice its command-line name).
//! Each converter's options write and read their own record, beside the
//! options (`ConvertOptions::record`, `CameraConvertOptions::record`,
//! `HoloFlickConvertOptions::record`); the file keeps it raw
//! ([`crate::format::ConversionRecord`]). Here the three meet:
//! [`FileInfo::conversion`] reads a file's record back as its converter's
//! options, complete with the file's own sample type, compression, version
//! and radiometry, ready to hand to the converter with the file's geometry
//! (and, for a scene, `holo.placement` as its matrix if wanted).

use std::ops::Range;
use std::path::Path;

use crate::cameras::convert::CameraConvertOptions;
use crate::error::Result;
use crate::format::{Checked, ConversionRecord, FileInfo, FormatVersion, RecordHead, WriteOptions};
use crate::holoflick::convert::HoloFlickConvertOptions;
use crate::mesh::convert::ConvertOptions;

/// A conversion as a file records it.
#[derive(Clone, Debug, PartialEq)]
pub struct Conversion {
    /// The input as the converter was given it, without the folders above
    /// it: a scene or HoloFlick file, a rig file, a capture's folder.
    pub input: String,
    /// `sha256:` and the 64 lower-case hex digits of the SHA-256 of the
    /// input's bytes, when the input is a file: that file only, not the
    /// files it names (a glTF's buffers, an OBJ's materials, a rig's
    /// pictures).
    pub input_sha256: Option<String>,
    /// The converter, with every option it was given.
    pub options: ConverterOptions,
}

/// Which converter, with its options.
#[derive(Clone, Debug, PartialEq)]
pub enum ConverterOptions {
    /// A scene ([`crate::mesh::convert::convert_mesh`]).
    Mesh(ConvertOptions),
    /// A camera capture ([`crate::cameras::convert::convert_camera_files`]);
    /// what is recorded are the options that make the samples: not the
    /// unseen-ray picture or mask asked for beside them.
    Cameras(CameraConvertOptions),
    /// A HoloFlick ([`crate::holoflick::convert::convert_holoflick`]); of
    /// its render options only the supersampling and the engine, the only
    /// ones that converter uses (the lights come from the HoloFlick).
    HoloFlick(HoloFlickConvertOptions),
}

impl ConverterOptions {
    /// The converter's name, as `holo.convert.kind` stores it.
    pub fn kind(&self) -> &'static str {
        match self {
            ConverterOptions::Mesh(_) => ConvertOptions::KIND,
            ConverterOptions::Cameras(_) => CameraConvertOptions::KIND,
            ConverterOptions::HoloFlick(_) => HoloFlickConvertOptions::KIND,
        }
    }
}

impl Conversion {
    /// The conversion of `input` with `options`: its name, and its SHA-256
    /// when it is a file (read once more; cheap beside any conversion).
    pub fn of_input(input: &Path, options: ConverterOptions) -> Result<Conversion> {
        let RecordHead { input, input_sha256, .. } = RecordHead::of_input(options.kind(), input)?;
        Ok(Conversion { input, input_sha256, options })
    }

    /// The same conversion of other frames (`None`: all): what a part of a
    /// movie made alone records, and what joining the parts records.
    pub fn with_frames(&self, frames: Option<Range<usize>>) -> Conversion {
        let mut c = self.clone();
        match &mut c.options {
            ConverterOptions::Mesh(o) => o.scene.frames = frames,
            ConverterOptions::HoloFlick(o) => o.frames = frames,
            ConverterOptions::Cameras(_) => {}
        }
        c
    }

    /// The `holo.convert.*` attributes that record it, for
    /// [`WriteOptions::conversion`].
    pub fn record(&self) -> ConversionRecord {
        let head = RecordHead {
            kind: self.options.kind().to_string(),
            input: self.input.clone(),
            input_sha256: self.input_sha256.clone(),
        };
        match &self.options {
            ConverterOptions::Mesh(o) => o.record(&head),
            ConverterOptions::Cameras(o) => o.record(&head),
            ConverterOptions::HoloFlick(o) => o.record(&head),
        }
    }

    /// The conversion `record` holds; `None` when it holds none. The
    /// options' write part is `write` (what the file says of itself). An
    /// attribute of the wrong type or with a value its converter would
    /// refuse is a sentence naming it.
    pub fn from_record(record: &ConversionRecord, write: WriteOptions) -> Checked<Option<Conversion>> {
        let Some(RecordHead { kind, input, input_sha256 }) = record.head()? else {
            return Ok(None);
        };
        let r = record.reader();
        let options = match kind.as_str() {
            ConvertOptions::KIND => ConverterOptions::Mesh(ConvertOptions::from_record(&r, write)?),
            CameraConvertOptions::KIND => ConverterOptions::Cameras(CameraConvertOptions::from_record(&r, write)?),
            HoloFlickConvertOptions::KIND => {
                ConverterOptions::HoloFlick(HoloFlickConvertOptions::from_record(&r, write)?)
            }
            other => {
                return Err(format!(
                    "attribute {} is {other:?}; it must be \"{}\", \"{}\" or \"{}\"",
                    crate::format::attribute::convert::KIND,
                    ConvertOptions::KIND,
                    CameraConvertOptions::KIND,
                    HoloFlickConvertOptions::KIND
                ))
            }
        };
        Ok(Some(Conversion { input, input_sha256, options }))
    }
}

impl FileInfo {
    /// The conversion that made the file (`holo.convert.*`, spec §4.4),
    /// its options completed with the file's sample type, compression,
    /// version and radiometry: the same conversion is the same converter,
    /// on the same input, with these options and the file's geometry.
    /// `None` when the file records none; an error naming the attribute
    /// when the record cannot be read (the file's samples are still good).
    pub fn conversion(&self) -> Result<Option<Conversion>> {
        let Some(record) = &self.conversion_record else {
            return Ok(None);
        };
        // The options' write part is what the file says of itself.
        let written = WriteOptions {
            sample_type: self.sample_type,
            compression: self.compression,
            radiometry: self.radiometry.clone(),
            version: FormatVersion::for_number(self.version),
            ..WriteOptions::default()
        };
        Conversion::from_record(record, written).map_err(|problem| crate::error::Error::invalid(&self.path, problem))
    }
}
