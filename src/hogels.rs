//! Hogels as pictures, for holographic-stereogram printers: one PNG per
//! emitter (a *hogel*), its pixels that emitter's views, and back
//! (`spec/hogels.md`). A printer exposes hogels one at a time in raster
//! order; the files are named so that sorting their names gives that order:
//! `hogel_RRR_CCC.png`, row `R` from the top, column `C` from the left,
//! each padded as channel names are (spec §3.2: at least three digits).
//!
//! **A hogel's picture** is `V` pixels wide and `W` tall (`W = 1` for
//! horizontal parallax: a one-pixel strip of the views toward the viewer
//! line). Pixel `(x, y)`, `y` from the top, is horizontal view `h = x` and
//! vertical view `k = W − 1 − y`: the directions are laid out as a viewer
//! facing the display sees them, toward `+x` (right) to the right and toward
//! `+y` (up) at the top, so a viewer above and to the right of the hogel sees
//! its top-right pixel (vertical views count upward, spec §8, pixel rows
//! downward: hence the flip). A printer whose optics mirror the picture
//! (a camera at the hogel looking out, the pseudoscopic convention) flips it.
//!
//! The tone mapping is every picture's ([`crate::picture`]): 16-bit PNGs of
//! a white level at or above every sample come back within half a code step,
//! and exactly for a sample that is itself a code's value. The manifest
//! `holo-hogels.json` records the geometry, the tone mapping, the
//! orientation and every PNG with its size and SHA-256; the PNGs and the
//! manifest are one set ([`crate::output::FileSet`]), written last, and an
//! import refuses a folder whose PNGs disagree with it.
//!
//! A frame is read band by band ([`HoloFile::read_frame_in_bands`], its
//! digests checked before the set is put in place) and imported band by
//! band, so neither needs memory for the frame (`--white auto` aside, which
//! ranks every sample).

use std::ops::Range;
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::format::{view_digits, HoloFile};
use crate::geometry::Geometry;
use crate::modulation::{Band, Modulation};
use crate::output::{check_set_output, verify_set, FileSet, SetFile};
use crate::picture::{encode_png, Tone, White};
use crate::pipeline::{Source, Warnings};
use crate::progress::Progress;
use crate::views::{
    band_rows, check_frame_and_white, folder_manifest, import_tone, malformed, read_manifest, white_of_frame, Picture,
    PictureChannels, ToneMapping,
};

/// Name of the manifest written next to the PNGs.
pub const MANIFEST: &str = "holo-hogels.json";

/// How a hogel's picture holds its views, as the manifest says it: pixel
/// column `x` is horizontal view `h`, pixel row `y` (from the top) vertical
/// view `W − 1 − y`.
pub const ORIENTATION: &str = "x = h, y = W - 1 - k";

/// What to do about a set of hogels that cannot be read as one.
const REMEDY: &str = "export the hogels again";

/// The manifest: what `export-hogels` wrote, for `import-hogels`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HogelManifest {
    /// The geometry of the frame.
    pub geometry: Geometry,
    /// The tone mapping used.
    pub tone: ToneMapping,
    /// How a picture holds its views ([`ORIENTATION`]).
    pub orientation: String,
    /// Every PNG with its size and SHA-256, in raster order.
    #[serde(default)]
    pub files: Vec<SetFile>,
}

/// File name of the hogel in emitter row `row` (from the top), column
/// `column` (from the left) of geometry `g`.
pub fn hogel_file_name(g: &Geometry, row: usize, column: usize) -> String {
    let (dr, dc) = (view_digits(g.hololines), view_digits(g.emitters));
    format!("hogel_{row:0dr$}_{column:0dc$}.png")
}

/// Every hogel's file name, in raster order (row by row from the top, each
/// row from the left): the order a printer exposes them in, and their
/// names' sorted order.
pub fn hogel_file_names(g: &Geometry) -> Vec<String> {
    (0..g.hololines).flat_map(|j| (0..g.emitters).map(move |e| hogel_file_name(g, j, e))).collect()
}

/// The view index ([`Geometry::view_index`]) at pixel `(x, y)` of a hogel's picture.
fn view_at(g: &Geometry, x: usize, y: usize) -> usize {
    g.view_index(x, g.vertical_view_count() - 1 - y)
}

/// The hogels of a frame being written as one set.
struct HogelWriter<'a> {
    g: &'a Geometry,
    set: FileSet,
    tone: Tone,
    channels: PictureChannels,
}

impl<'a> HogelWriter<'a> {
    fn new(g: &'a Geometry, dir: &Path, tone: &ToneMapping) -> Result<Self> {
        let png_tone = tone.tone().map_err(|e| e.naming(dir))?;
        let set = FileSet::create(dir, MANIFEST)?;
        Ok(HogelWriter { g, set, tone: png_tone, channels: PictureChannels::new(g) })
    }

    /// The hogels of emitter rows `rows`, whose samples `band` holds (its
    /// row 0 is `rows.start`): encoded in parallel, written in raster order.
    fn band(&mut self, rows: Range<usize>, band: &Modulation) -> Result<()> {
        let g = self.g;
        let (width, height) = (g.views.count, g.vertical_view_count());
        let (tone, channels, folder) = (&self.tone, &self.channels, self.set.folder());
        let top = rows.start;
        let hogels: Vec<(usize, usize)> = rows.flat_map(|j| (0..g.emitters).map(move |e| (j, e))).collect();
        let pngs: Vec<(String, Vec<u8>)> = hogels
            .par_iter()
            .map(|&(j, e)| {
                let name = hogel_file_name(g, j, e);
                // No physical pixel size: a hogel's pixels are directions.
                let png = encode_png(width, height, channels.colour(), tone, None, |x, y| {
                    channels.pixel(|c| band.get(c, j - top, e, view_at(g, x, y)))
                })
                .map_err(|err| err.naming(&folder.join(&name)))?;
                Ok((name, png))
            })
            // Every item, then the first failure in order: rayon's own collect
            // into a Result returns whichever fails first in time, and an
            // error should name the same file every run.
            .collect::<Vec<Result<_>>>()
            .into_iter()
            .collect::<Result<_>>()?;
        for (name, png) in pngs {
            self.set.add_bytes(&name, &png)?;
        }
        Ok(())
    }

    /// Put the set in place with its manifest; every file written, the manifest last.
    fn commit(self, tone: &ToneMapping, overwrite: bool) -> Result<Vec<PathBuf>> {
        let (g, folder) = (self.g, self.set.folder().to_path_buf());
        self.set.commit(overwrite, |files| {
            let manifest = HogelManifest {
                geometry: g.clone(),
                tone: tone.clone(),
                orientation: ORIENTATION.to_string(),
                files: files.to_vec(),
            };
            serde_json::to_string_pretty(&manifest)
                .map(String::into_bytes)
                .map_err(|e| Error::encode(folder.join(MANIFEST), "JSON", e))
        })
    }
}

/// Write every hogel of `m` as a PNG into `dir` (created if needed), plus
/// the manifest, as one set: nothing is in place until every PNG is
/// complete. Refuses to replace an existing set or file unless `overwrite`;
/// returns every file written, the manifest last.
pub fn export_hogels(m: &Modulation, dir: &Path, tone: &ToneMapping, overwrite: bool) -> Result<Vec<PathBuf>> {
    let g = m.geometry();
    tone.tone().map_err(|e| e.naming(dir))?;
    let _claim = check_set_output(dir, MANIFEST, &hogel_file_names(g), &[], overwrite)?;
    let mut writer = HogelWriter::new(g, dir, tone)?;
    writer.band(0..g.hololines, m)?;
    writer.commit(tone, overwrite)
}

/// What [`export_hogels_file`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct HogelExport {
    /// Every file written, the manifest last.
    pub written: Vec<PathBuf>,
    /// The tone mapping, its white level resolved to the number used.
    pub tone: ToneMapping,
}

/// Write every hogel of frame `frame` of the `.holo` file `holo_path` into
/// `dir` (`holo export-hogels`), reading the frame band by band: white
/// level `white` (chosen among every sample of the frame), `bits` per
/// component. The frame and the tone are checked and the output refused
/// (existing, unless `overwrite`; the input itself; being written by
/// another process) before any work; the set is put in place only once the
/// frame's digests have been checked.
pub fn export_hogels_file(
    holo_path: &Path,
    frame: usize,
    dir: &Path,
    white: White,
    bits: u8,
    overwrite: bool,
) -> Result<HogelExport> {
    let file = HoloFile::open(holo_path)?;
    check_frame_and_white(&file, holo_path, frame, white, dir)?;
    let g = file.geometry();
    // Checked with a stand-in white, before the frame is read for its level.
    ToneMapping { white: 1.0, bits }.tone().map_err(|e| e.naming(dir))?;
    let _claim = check_set_output(dir, MANIFEST, &hogel_file_names(g), &[holo_path], overwrite)?;
    let tone = ToneMapping { white: white_of_frame(&file, frame, white)?, bits };
    let mut writer = HogelWriter::new(g, dir, &tone)?;
    file.read_frame_in_bands(frame, band_rows(g), |rows, band| writer.band(rows, &band))?;
    let written = writer.commit(&tone, overwrite)?;
    Ok(HogelExport { written, tone })
}

/// Read the manifest of an exported folder.
pub fn read_hogel_manifest(path: &Path) -> Result<HogelManifest> {
    let manifest: HogelManifest = read_manifest(path, "holo-hogels manifest")?;
    if manifest.orientation != ORIENTATION {
        return Err(malformed(
            path,
            format!(
                "lays its pictures out as {:?}; holo reads {ORIENTATION:?} (pixel column = horizontal view, \
                 top row = the highest vertical view)",
                manifest.orientation
            ),
        ));
    }
    Ok(manifest)
}

/// The manifest of the folder `dir` when it has one (`None`: hogels made
/// elsewhere, read as they are). A folder whose set's replacement was
/// interrupted is refused first, whatever else it holds.
pub fn folder_hogel_manifest(dir: &Path) -> Result<Option<HogelManifest>> {
    folder_manifest(dir, MANIFEST, REMEDY, read_hogel_manifest)
}

/// The hogel pictures in a folder, read into bands of a frame of one geometry.
struct HogelReader<'a> {
    dir: &'a Path,
    g: &'a Geometry,
    tone: Tone,
    /// Whether the folder's set has been checked against its manifest.
    verified: bool,
}

impl<'a> HogelReader<'a> {
    fn new(dir: &'a Path, g: &'a Geometry, tone: &ToneMapping) -> Result<Self> {
        Ok(HogelReader { dir, g, tone: import_tone(dir, tone)?, verified: false })
    }

    /// Fill `samples`, laid out as a [`Band`] of emitter rows `rows`, from their hogels.
    fn band(&mut self, rows: Range<usize>, samples: &mut [f32]) -> Result<()> {
        if !self.verified {
            // Even pictures read without their manifest may not be of a set
            // whose replacement was interrupted: they could be of two sets.
            if let Some(manifest) = folder_hogel_manifest(self.dir)? {
                verify_set(self.dir, MANIFEST, &manifest.files, REMEDY)?;
            }
            self.verified = true;
        }
        let g = self.g;
        let (width, height, views) = (g.views.count, g.vertical_view_count(), g.views_per_emitter());
        let lines = rows.len();
        let hogels: Vec<(usize, usize)> = rows.clone().flat_map(|j| (0..g.emitters).map(move |e| (j, e))).collect();
        let read: Vec<Vec<f32>> = hogels
            .par_iter()
            .map(|&(j, e)| {
                let path = self.dir.join(hogel_file_name(g, j, e));
                let picture = Picture::read(&path, (width, height), "horizontal × vertical views")?;
                // This hogel's views, channel by channel.
                let mut out = vec![0.0; g.channels.len() * views];
                for (c, channel) in g.channels.iter().enumerate() {
                    for y in 0..height {
                        for x in 0..width {
                            let code = picture.code(&channel.name, y * width + x);
                            out[c * views + view_at(g, x, y)] = self.tone.sample(code);
                        }
                    }
                }
                Ok(out)
            })
            // Every item, then the first failure in order: rayon's own collect
            // into a Result returns whichever fails first in time, and an
            // error should name the same file every run.
            .collect::<Vec<Result<_>>>()
            .into_iter()
            .collect::<Result<_>>()?;
        for ((j, e), hogel) in hogels.into_iter().zip(read) {
            for c in 0..g.channels.len() {
                let at = ((c * lines + j - rows.start) * g.emitters + e) * views;
                samples[at..at + views].copy_from_slice(&hogel[c * views..(c + 1) * views]);
            }
        }
        Ok(())
    }
}

/// Build a frame from the hogel PNGs in `dir` (the inverse of
/// [`export_hogels`]). A folder with a manifest is a set: its PNGs are first
/// checked against the sizes and digests it lists, and a folder that
/// disagrees (or whose manifest lists none) is refused, naming the file. A
/// folder without one holds hogels made elsewhere, read as they are.
pub fn import_hogels(dir: &Path, geometry: &Geometry, tone: &ToneMapping) -> Result<Modulation> {
    let mut m = Modulation::zeros(geometry.clone())?;
    HogelReader::new(dir, geometry, tone)?.band(0..geometry.hololines, m.samples_mut())?;
    Ok(m)
}

/// A folder of hogel pictures as a [`Source`] of one `.holo` frame, read
/// band by band (the inverse of [`export_hogels_file`];
/// [`crate::pictures::import_pictures_file`] writes it into a `.holo` file).
pub struct HogelsSource<'a> {
    reader: HogelReader<'a>,
    /// The folder, its manifest and the pictures: the output may be none of them.
    inputs: Vec<PathBuf>,
}

impl<'a> HogelsSource<'a> {
    /// The hogels in `dir` for `geometry`, decoded with `tone`.
    pub fn new(dir: &'a Path, geometry: &'a Geometry, tone: &ToneMapping) -> Result<Self> {
        let mut inputs = vec![dir.to_path_buf(), dir.join(MANIFEST)];
        inputs.extend(hogel_file_names(geometry).into_iter().map(|name| dir.join(name)));
        Ok(HogelsSource { reader: HogelReader::new(dir, geometry, tone)?, inputs })
    }
}

impl Source for HogelsSource<'_> {
    type Frame = Band;

    fn name(&self) -> String {
        self.reader.dir.display().to_string()
    }

    fn inputs(&self) -> Vec<PathBuf> {
        self.inputs.clone()
    }

    fn frame_count(&self) -> usize {
        1
    }

    fn provenance(&self) -> String {
        format!("holo import-hogels from {}", self.reader.dir.display())
    }

    fn band_hololines(&self) -> Option<usize> {
        Some(band_rows(self.reader.g))
    }

    fn render(&mut self, _number: usize, band: &mut Band, _: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let rows = band.hololines();
        self.reader.band(rows, band.samples_mut())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{rgb_channels, Views};

    #[test]
    fn hogels_written_and_read_in_bands_are_those_of_the_whole_frame() {
        let g = Geometry::centred(5, 3, Views::tan_spaced(2, -0.1, 0.1), 1e-3, 1e-3, 0.0, 0.5, rgb_channels())
            .with_vertical_views(Views::tan_spaced(3, -0.1, 0.1));
        let m = Modulation::from_fn(g.clone(), |c, j, e, v| 0.01 * (1 + c + 3 * j + 11 * e + 37 * v) as f32).unwrap();
        let tone = ToneMapping { white: 4.0, bits: 16 };
        let dir = tempfile::tempdir().unwrap();
        let whole = dir.path().join("whole");
        export_hogels(&m, &whole, &tone, false).unwrap();
        // Bands of two rows (the last of one), each cut from the frame as a region read gives it.
        let banded = dir.path().join("banded");
        let mut writer = HogelWriter::new(&g, &banded, &tone).unwrap();
        for top in (0..g.hololines).step_by(2) {
            let rows = top..(top + 2).min(g.hololines);
            let mut band = Band::zeros(g.clone(), rows.clone()).unwrap();
            band.copy_rows_from(&m);
            let mut sub = g.clone();
            sub.hololines = rows.len();
            sub.hololine_top_y_m = g.hololine_y_m(rows.start);
            writer.band(rows, &Modulation::from_samples(sub, band.samples().to_vec()).unwrap()).unwrap();
        }
        writer.commit(&tone, false).unwrap();
        let manifest = |dir: &Path| read_hogel_manifest(&dir.join(MANIFEST)).unwrap().files;
        assert_eq!(manifest(&whole), manifest(&banded));
        // Read back in bands of two rows.
        let mut reader = HogelReader::new(&banded, &g, &tone).unwrap();
        let mut back = Modulation::zeros(g.clone()).unwrap();
        for top in (0..g.hololines).step_by(2) {
            let rows = top..(top + 2).min(g.hololines);
            let mut band = Band::zeros(g.clone(), rows.clone()).unwrap();
            reader.band(rows.clone(), band.samples_mut()).unwrap();
            for c in 0..g.channels.len() {
                for j in rows.clone() {
                    let at = back.index(c, j, 0, 0);
                    let line = band.hololine(c, j);
                    back.samples_mut()[at..at + line.len()].copy_from_slice(line);
                }
            }
        }
        assert_eq!(back, import_hogels(&whole, &g, &tone).unwrap());
        let worst = back.samples().iter().zip(m.samples()).map(|(a, b)| (a - b).abs()).fold(0f32, f32::max);
        assert!(worst < 4.0 * 1e-4, "{worst}");
    }
}
