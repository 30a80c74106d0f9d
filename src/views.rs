//! Views as pictures: one PNG per view (`view_000.png`, …; full parallax
//! `view_000_000.png`, … by horizontal then vertical view), `emitters` wide
//! and `hololines` tall, and back. The tone mapping is [`crate::picture`]'s
//! (docs/commands.md, "Pictures: tone mapping and shape"): `linear = clamp(sample / white, 0, 1)`, encoded
//! with the sRGB transfer function and quantised to 8 or 16 bits; import
//! inverts it. A sidecar `holo-views.json` records the geometry and the tone
//! mapping (the white level as the number used, however it was chosen), so
//! `import-views` can rebuild the file without being told them again. The
//! PNGs and the sidecar are one set ([`crate::output::FileSet`]): the sidecar
//! is written last and lists every PNG with its size and SHA-256, and an
//! import refuses a folder whose PNGs disagree with it.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::format::{view_digits, HoloFile};
use crate::geometry::Geometry;
use crate::modulation::{Band, Modulation};
use crate::output::{check_set_complete, check_set_output, verify_set, FileSet, SetFile};
use crate::picture::decode::{decode_png, DecodeError};
use crate::picture::{encode_png, Bits, Colour, Tone, White};
use crate::pipeline::{Source, Warnings};
use crate::progress::Progress;

/// Name of the sidecar written next to the PNGs.
pub const SIDECAR: &str = "holo-views.json";

/// How samples become pixel values, as the sidecar records it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToneMapping {
    /// The sample value shown as full white (a [`crate::picture::White`]
    /// resolved to its number for the frame exported).
    pub white: f32,
    /// 8 or 16 bits per component.
    pub bits: u8,
}

impl ToneMapping {
    /// The tone of the PNGs; fails on a white level that is not finite and
    /// positive or a depth other than 8 or 16 bits.
    pub fn tone(&self) -> Result<Tone> {
        Tone::new(self.white, Bits::from_count(self.bits)?)
    }
}

impl Default for ToneMapping {
    fn default() -> Self {
        ToneMapping { white: 1.0, bits: 16 }
    }
}

/// The sidecar: what `export-views` wrote, for `import-views`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    /// The geometry of the views.
    pub geometry: Geometry,
    /// The tone mapping used.
    pub tone: ToneMapping,
    /// Every PNG with its size and SHA-256 (empty in sidecars written before
    /// sets listed their files: such a folder is not imported as a set).
    #[serde(default)]
    pub files: Vec<SetFile>,
}

/// File name of view `v` for a geometry with `view_count` views.
pub fn view_file_name(v: usize, view_count: usize) -> String {
    let digits = view_digits(view_count);
    format!("view_{v:0digits$}.png")
}

/// File name of the view with index `view` among an emitter's views of `g`
/// ([`Geometry::view_index`]): `view_HHH.png`, or for full parallax
/// `view_HHH_KKK.png` (horizontal view, vertical view; each padded as channel
/// names are, spec §3.2).
pub fn view_file_name_of(g: &Geometry, view: usize) -> String {
    match g.vertical_views {
        None => view_file_name(view, g.views.count),
        Some(_) => {
            let (h, k) = g.view_of_index(view);
            let (dh, dk) = (view_digits(g.views.count), view_digits(g.vertical_view_count()));
            format!("view_{h:0dh$}_{k:0dk$}.png")
        }
    }
}

/// Write every view of `m` as a PNG into `dir` (created if needed), plus the
/// sidecar, as one set: nothing is in place until every PNG is complete.
/// Refuses to replace an existing set or file unless `overwrite`; returns
/// every file written, the sidecar last.
pub fn export_views(m: &Modulation, dir: &Path, tone: &ToneMapping, overwrite: bool) -> Result<Vec<PathBuf>> {
    let png_tone = tone.tone().map_err(|e| e.naming(dir))?;
    let g = m.geometry();
    let names: Vec<String> = (0..g.views_per_emitter()).map(|v| view_file_name_of(g, v)).collect();
    let _claim = check_set_output(dir, SIDECAR, &names, &[], overwrite)?;
    let mut set = FileSet::create(dir, SIDECAR)?;
    let channels = PictureChannels::new(g);
    for (v, name) in names.iter().enumerate() {
        // One pixel per emitter and hololine, so that import-views takes the
        // pictures back sample for sample; their physical size, in the pHYs
        // chunk, gives viewers that honour it the display's proportions.
        let pixel_size = Some([g.emitter_pitch_m, g.hololine_pitch_m]);
        let png = encode_png(g.emitters, g.hololines, channels.colour(), &png_tone, pixel_size, |e, j| {
            channels.pixel(|c| m.get(c, j, e, v))
        })
        .map_err(|e| e.naming(&dir.join(name)))?;
        set.add_bytes(name, &png)?;
    }
    set.commit(overwrite, |files| {
        let sidecar = Sidecar { geometry: g.clone(), tone: tone.clone(), files: files.to_vec() };
        serde_json::to_string_pretty(&sidecar)
            .map(String::into_bytes)
            .map_err(|e| Error::encode(dir.join(SIDECAR), "JSON", e))
    })
}

/// Read the sidecar of an exported directory.
pub fn read_sidecar(path: &Path) -> Result<Sidecar> {
    read_manifest(path, "holo-views sidecar")
}

/// The sidecar of the folder `dir` when it has one (`None`: pictures made
/// elsewhere, read as they are). A folder whose set's replacement was
/// interrupted is refused first, whatever else it holds.
pub fn folder_sidecar(dir: &Path) -> Result<Option<Sidecar>> {
    folder_manifest(dir, SIDECAR, REMEDY, read_sidecar)
}

/// The JSON manifest of a set of pictures at `path`, a `kind` (for the
/// message when it is not one).
pub(crate) fn read_manifest<T: serde::de::DeserializeOwned>(path: &Path, kind: &str) -> Result<T> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text).map_err(|e| malformed(path, format!("not a {kind}: {e}")))
}

/// The manifest `name` of the folder `dir`, read by `read`, when it has one
/// (`None`: pictures made elsewhere, read as they are). A folder whose
/// set's replacement was interrupted is refused first, whatever else it
/// holds, saying `remedy`.
pub(crate) fn folder_manifest<T>(
    dir: &Path,
    name: &str,
    remedy: &'static str,
    read: impl FnOnce(&Path) -> Result<T>,
) -> Result<Option<T>> {
    check_set_complete(dir, name, remedy)?;
    let path = dir.join(name);
    path.exists().then(|| read(&path)).transpose()
}

/// What to do about a set of views that cannot be read as one.
const REMEDY: &str = "export the views again";

/// Read a geometry from a JSON file: a bare [`Geometry`] or a sidecar.
pub fn read_geometry_json(path: &Path) -> Result<Geometry> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    if let Ok(s) = serde_json::from_str::<Sidecar>(&text) {
        return Ok(s.geometry);
    }
    serde_json::from_str(&text)
        .map_err(|e| Error::layout(path.display().to_string(), format!("not a geometry JSON file: {e}")))
}

/// Build a modulation from the PNGs in `dir` (the inverse of [`export_views`]).
/// A folder with a sidecar is a set: its PNGs are first checked against the
/// sizes and digests the sidecar lists, and a folder that disagrees (or
/// whose sidecar lists none) is refused, naming the file. A folder without
/// a sidecar holds pictures made elsewhere and is read as it is.
pub fn import_views(dir: &Path, geometry: &Geometry, tone: &ToneMapping) -> Result<Modulation> {
    let png_tone = import_tone(dir, tone)?;
    // Even pictures read without their sidecar may not be of a set whose
    // replacement was interrupted: they could be of two sets.
    if let Some(sidecar) = folder_sidecar(dir)? {
        verify_set(dir, SIDECAR, &sidecar.files, REMEDY)?;
    }
    let g = geometry;
    let mut m = Modulation::zeros(g.clone())?;
    for v in 0..g.views_per_emitter() {
        let path = dir.join(view_file_name_of(g, v));
        let picture = Picture::read(&path, (g.emitters, g.hololines), "emitters × hololines")?;
        for (c, ch) in g.channels.iter().enumerate() {
            for j in 0..g.hololines {
                for e in 0..g.emitters {
                    m.set(c, j, e, v, png_tone.sample(picture.code(&ch.name, j * g.emitters + e)));
                }
            }
        }
    }
    Ok(m)
}

/// The tone that takes a set's codes back to samples: `tone`'s white at 16
/// bits, as every PNG is read at 16 bits (an 8-bit code `q` becomes
/// `257·q`, the same fraction of full white); `tone` is refused, naming
/// `dir`, if its white or depth is not one a picture can have.
pub(crate) fn import_tone(dir: &Path, tone: &ToneMapping) -> Result<Tone> {
    Bits::from_count(tone.bits).map_err(|e| e.naming(dir))?;
    Tone::new(tone.white, Bits::Sixteen).map_err(|e| e.naming(dir))
}

/// How a geometry's colour channels fill a picture's pixels, and back: `R`,
/// `G` and `B` their own component (a colour the file lacks is black), a
/// one-wavelength (`Y`) file grey.
#[derive(Clone, Debug)]
pub(crate) struct PictureChannels {
    /// Each channel and the RGB component it fills.
    slots: Vec<(usize, usize)>,
    /// The channel of a one-wavelength file.
    mono: Option<usize>,
}

impl PictureChannels {
    pub(crate) fn new(g: &Geometry) -> Self {
        let slots = g
            .channels
            .iter()
            .enumerate()
            .map(|(c, ch)| match ch.name.as_str() {
                "R" => (c, 0),
                "G" => (c, 1),
                _ => (c, 2),
            })
            .collect();
        PictureChannels { slots, mono: g.channel_index("Y") }
    }

    /// Grey for a one-wavelength file, else RGB.
    pub(crate) fn colour(&self) -> Colour {
        if self.mono.is_some() {
            Colour::Grey
        } else {
            Colour::Rgb
        }
    }

    /// The linear RGB of a pixel whose channel `c` is `sample(c)` (grey in
    /// all three components, so an RGB picture of a mono file is grey too).
    pub(crate) fn pixel(&self, sample: impl Fn(usize) -> f32) -> [f32; 3] {
        match self.mono {
            Some(c) => [sample(c); 3],
            None => {
                let mut rgb = [0.0; 3];
                for &(c, slot) in &self.slots {
                    rgb[slot] = sample(c);
                }
                rgb
            }
        }
    }
}

/// A PNG of a set read back: its codes at 16 bits, as RGB and as grey.
pub(crate) struct Picture {
    rgb: Vec<u16>,
    grey: Vec<u16>,
}

impl Picture {
    /// The PNG at `path`, which must be `size` (width, height) pixels: the
    /// geometry's `what` (`emitters × hololines`), said when it is not.
    pub(crate) fn read(path: &Path, size: (usize, usize), what: &str) -> Result<Picture> {
        let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
        let img = decode_png(std::io::BufReader::new(file)).map_err(|e| match e {
            DecodeError::Io(io) => Error::io(path, io),
            other => malformed(path, format!("not a readable PNG: {other}")),
        })?;
        if (img.width, img.height) != size {
            return Err(malformed(
                path,
                format!("is {}×{} pixels; the geometry needs {what} = {}×{}", img.width, img.height, size.0, size.1),
            ));
        }
        Ok(Picture { rgb: img.rgb16(), grey: img.grey16() })
    }

    /// The code of channel `name` at pixel `at` (row-major from the top
    /// left): red, green or blue its component, any other channel the
    /// picture read as grey.
    pub(crate) fn code(&self, name: &str, at: usize) -> u16 {
        match name {
            "R" => self.rgb[3 * at],
            "G" => self.rgb[3 * at + 1],
            "B" => self.rgb[3 * at + 2],
            _ => self.grey[at],
        }
    }
}

/// The sample value `white` chooses among every sample of frame `frame`
/// of `file` (as [`White::level`] does, and as `export-views` chooses it
/// among the frame in memory), read band by band: a number or `max` needs
/// memory for a band only, `auto` (a percentile) for the frame's samples.
pub fn white_of_frame(file: &HoloFile, frame: usize, white: White) -> Result<f32> {
    let g = file.geometry();
    let band_rows = band_rows(g);
    match white {
        White::Value(_) => Ok(white.level([])),
        White::Max => {
            // The largest finite sample of each band (0 if none is positive),
            // then the rule's own choice among them.
            let mut largest = Vec::new();
            file.read_frame_in_bands(frame, band_rows, |_, band| {
                largest.push(band.samples().iter().filter(|x| x.is_finite()).fold(0.0, |a: f32, &b| a.max(b)));
                Ok(())
            })?;
            Ok(White::Max.level(largest))
        }
        White::Auto => {
            let mut samples = Vec::new();
            file.read_frame_in_bands(frame, band_rows, |_, band| {
                samples.extend_from_slice(band.samples());
                Ok(())
            })?;
            Ok(White::Auto.level(samples))
        }
    }
}

/// Emitter rows an export reads at a time: as many as fit in
/// [`BAND_BYTES`] of f32 samples, at least one.
pub(crate) fn band_rows(g: &Geometry) -> usize {
    let row_bytes = (g.emitters * g.views_per_emitter() * g.channels.len() * 4).max(1);
    (BAND_BYTES / row_bytes).clamp(1, g.hololines.max(1))
}

/// The samples an export holds at a time (a band of a frame), bytes.
const BAND_BYTES: usize = 64 << 20;

/// A folder of view pictures as a [`Source`] of one `.holo` frame (the
/// inverse of [`export_views`], read by [`import_views`]).
#[derive(Clone, Debug)]
pub struct ViewsSource<'a> {
    dir: &'a Path,
    tone: &'a ToneMapping,
    /// The pictures and the sidecar: the output may be none of them.
    inputs: Vec<PathBuf>,
}

impl<'a> ViewsSource<'a> {
    /// The pictures in `dir` for `geometry`, decoded with `tone`.
    pub fn new(dir: &'a Path, geometry: &Geometry, tone: &'a ToneMapping) -> Self {
        let mut inputs = vec![dir.to_path_buf(), dir.join(SIDECAR)];
        inputs.extend((0..geometry.views_per_emitter()).map(|v| dir.join(view_file_name_of(geometry, v))));
        ViewsSource { dir, tone, inputs }
    }
}

impl Source for ViewsSource<'_> {
    type Frame = Band;

    fn name(&self) -> String {
        self.dir.display().to_string()
    }

    fn inputs(&self) -> Vec<PathBuf> {
        self.inputs.clone()
    }

    fn frame_count(&self) -> usize {
        1
    }

    fn provenance(&self) -> String {
        format!("holo import-views from {}", self.dir.display())
    }

    fn render(&mut self, _number: usize, frame: &mut Band, _: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let read = import_views(self.dir, frame.geometry(), self.tone)?;
        frame.samples_mut().copy_from_slice(read.samples());
        Ok(())
    }
}

/// Refuse, naming `path`, a frame the file does not have, and, naming the
/// output `dir`, a white level no picture can have: what every export of
/// a file's frame checks before its output.
pub(crate) fn check_frame_and_white(
    file: &HoloFile,
    path: &Path,
    frame: usize,
    white: White,
    dir: &Path,
) -> Result<()> {
    let frames = file.info().frames.len();
    if frame >= frames {
        return Err(Error::no_frame(path, frame, frames));
    }
    if let Some(problem) = white.problem() {
        return Err(Error::argument("white level", format!("{}: {problem}", dir.display())));
    }
    Ok(())
}

/// A file of a set of pictures that is not what it should be.
pub(crate) fn malformed(path: &Path, problem: String) -> Error {
    Error::Set { path: path.to_path_buf(), problem: crate::error::SetProblem::Malformed(problem) }
}
