//! Sets of pictures of a frame, as folders hold them: one picture per view
//! ([`crate::views`], `export-views`) or per hogel ([`crate::hogels`],
//! `export-hogels`), each set with its manifest; and the import of either
//! into a `.holo` file (`holo import-views`, `holo import-hogels`).

use std::path::Path;

use crate::error::Result;
use crate::format::WriteOptions;
use crate::format::WriteReport;
use crate::geometry::Geometry;
use crate::hogels::{folder_hogel_manifest, HogelsSource, MANIFEST};
use crate::pipeline::{HoloSink, Run};
use crate::progress::Progress;
use crate::views::{folder_sidecar, ToneMapping, ViewsSource, SIDECAR};

/// The kind of set of pictures a folder holds, each with its manifest.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureSet {
    /// One picture per view (`export-views`, [`SIDECAR`]).
    Views,
    /// One picture per hogel (`export-hogels`, [`MANIFEST`]).
    Hogels,
}

impl PictureSet {
    /// The name of its manifest.
    pub fn manifest(self) -> &'static str {
        match self {
            PictureSet::Views => SIDECAR,
            PictureSet::Hogels => MANIFEST,
        }
    }

    /// The geometry and tone mapping the manifest in `dir` records, when
    /// there is one (`None`: pictures made elsewhere). A folder whose set's
    /// replacement was interrupted, or whose manifest is not one, is refused.
    pub fn folder_manifest(self, dir: &Path) -> Result<Option<(Geometry, ToneMapping)>> {
        Ok(match self {
            PictureSet::Views => folder_sidecar(dir)?.map(|s| (s.geometry, s.tone)),
            PictureSet::Hogels => folder_hogel_manifest(dir)?.map(|m| (m.geometry, m.tone)),
        })
    }
}

/// Import the pictures of kind `set` in `dir` for `geometry` into the
/// `.holo` file `output` (`holo import-views`, `holo import-hogels`; the
/// hogels band by band).
pub fn import_pictures_file(
    set: PictureSet,
    dir: &Path,
    geometry: &Geometry,
    tone: &ToneMapping,
    output: &Path,
    options: WriteOptions,
    progress: &dyn Progress,
) -> Result<Run<WriteReport>> {
    let sink = HoloSink::new(output, geometry, options);
    match set {
        PictureSet::Views => crate::pipeline::run(&mut ViewsSource::new(dir, geometry, tone), sink, None, progress),
        PictureSet::Hogels => crate::pipeline::run(&mut HogelsSource::new(dir, geometry, tone)?, sink, None, progress),
    }
}
