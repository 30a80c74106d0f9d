//! Views as pictures: one PNG per view (`view_000.png`, …), `emitters` wide
//! and `hololines` tall, and back. The tone mapping (README, "Views as
//! PNG") is: `linear = sample / white`, clamped to [0, 1], encoded with the
//! sRGB transfer function and quantised to 8 or 16 bits; import inverts it.
//! A sidecar `holo-views.json` records the geometry and the tone mapping, so
//! `import-views` can rebuild the file without being told them again. The
//! PNGs and the sidecar are one set ([`crate::output::FileSet`]): the sidecar
//! is written last and lists every PNG with its size and SHA-256, and an
//! import refuses a folder whose PNGs disagree with it.

use std::path::{Path, PathBuf};

use image::{ImageBuffer, ImageFormat, Luma, Rgb};
use serde::{Deserialize, Serialize};

use crate::format::{view_digits, WriteOptions, WriteReport};
use crate::output::{check_set_complete, check_set_output, verify_set, FileSet, SetFile};
use crate::pipeline::{HoloSink, Run, Source, Warnings};
use crate::progress::Progress;
use crate::{Band, Error, Geometry, Modulation, Result};

/// Name of the sidecar written next to the PNGs.
pub const SIDECAR: &str = "holo-views.json";

/// How samples become pixel values.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ToneMapping {
    /// The sample value shown as full white.
    pub white: f32,
    /// 8 or 16 bits per component.
    pub bits: u8,
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

/// sRGB encoding of a linear value in [0, 1] (IEC 61966-2-1).
pub fn srgb_encode(linear: f64) -> f64 {
    let x = linear.clamp(0.0, 1.0);
    if x <= 0.003_130_8 {
        12.92 * x
    } else {
        1.055 * x.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB decoding to a linear value in [0, 1].
pub fn srgb_decode(encoded: f64) -> f64 {
    let x = encoded.clamp(0.0, 1.0);
    if x <= 0.040_45 {
        x / 12.92
    } else {
        ((x + 0.055) / 1.055).powf(2.4)
    }
}

/// File name of view `v` for a geometry with `view_count` views.
pub fn view_file_name(v: usize, view_count: usize) -> String {
    let digits = view_digits(view_count);
    format!("view_{v:0digits$}.png")
}

fn check_tone(tone: &ToneMapping) -> Result<()> {
    if !(tone.white.is_finite() && tone.white > 0.0) {
        return Err(Error::Usage(format!("white level {} must be finite and positive", tone.white)));
    }
    if tone.bits != 8 && tone.bits != 16 {
        return Err(Error::Usage(format!("{} bits per component: choose 8 or 16", tone.bits)));
    }
    Ok(())
}

/// Write every view of `m` as a PNG into `dir` (created if needed), plus the
/// sidecar, as one set: nothing is in place until every PNG is complete.
/// Refuses to replace an existing set or file unless `overwrite`; returns
/// every file written, the sidecar last.
pub fn export_views(m: &Modulation, dir: &Path, tone: &ToneMapping, overwrite: bool) -> Result<Vec<PathBuf>> {
    check_tone(tone)?;
    let g = m.geometry();
    let names: Vec<String> = (0..g.views.count).map(|v| view_file_name(v, g.views.count)).collect();
    check_set_output(dir, SIDECAR, &names, &[], overwrite)?;
    let mut set = FileSet::create(dir, SIDECAR)?;
    let colour_slot = |name: &str| match name {
        "R" => 0,
        "G" => 1,
        _ => 2,
    };
    let mono = g.channel_index("Y");
    let quantise = |x: f32| -> f64 {
        let max = if tone.bits == 8 { 255.0 } else { 65535.0 };
        (srgb_encode(f64::from(x) / f64::from(tone.white)) * max).round()
    };
    let (w, h) = (g.emitters as u32, g.hololines as u32);
    for (v, name) in names.iter().enumerate() {
        let path = dir.join(name);
        set.add(name, |out| {
            let save = |result: image::ImageResult<()>| {
                result.map_err(|e| Error::Usage(format!("{}: cannot write PNG: {e}", path.display())))
            };
            match (mono, tone.bits) {
                (Some(c), 8) => save(
                    ImageBuffer::from_fn(w, h, |x, y| Luma([quantise(m.get(c, y as usize, x as usize, v)) as u8]))
                        .write_to(out, ImageFormat::Png),
                ),
                (Some(c), _) => save(
                    ImageBuffer::from_fn(w, h, |x, y| Luma([quantise(m.get(c, y as usize, x as usize, v)) as u16]))
                        .write_to(out, ImageFormat::Png),
                ),
                (None, bits) => {
                    let mut rgb = vec![[0f64; 3]; (w * h) as usize];
                    for (c, ch) in g.channels.iter().enumerate() {
                        for j in 0..g.hololines {
                            for e in 0..g.emitters {
                                rgb[j * g.emitters + e][colour_slot(&ch.name)] = quantise(m.get(c, j, e, v));
                            }
                        }
                    }
                    let px = |x: u32, y: u32| rgb[(y * w + x) as usize];
                    if bits == 8 {
                        save(
                            ImageBuffer::from_fn(w, h, |x, y| Rgb(px(x, y).map(|c| c as u8)))
                                .write_to(out, ImageFormat::Png),
                        )
                    } else {
                        save(
                            ImageBuffer::from_fn(w, h, |x, y| Rgb(px(x, y).map(|c| c as u16)))
                                .write_to(out, ImageFormat::Png),
                        )
                    }
                }
            }
        })?;
    }
    set.commit(overwrite, |files| {
        let sidecar = Sidecar { geometry: g.clone(), tone: tone.clone(), files: files.to_vec() };
        serde_json::to_string_pretty(&sidecar).map(String::into_bytes).map_err(|e| Error::Usage(e.to_string()))
    })
}

/// Read the sidecar of an exported directory.
pub fn read_sidecar(path: &Path) -> Result<Sidecar> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    serde_json::from_str(&text).map_err(|e| Error::invalid(path, format!("not a holo-views sidecar: {e}")))
}

/// Read a geometry from a JSON file: a bare [`Geometry`] or a sidecar.
pub fn read_geometry_json(path: &Path) -> Result<Geometry> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    if let Ok(s) = serde_json::from_str::<Sidecar>(&text) {
        return Ok(s.geometry);
    }
    serde_json::from_str(&text).map_err(|e| Error::invalid(path, format!("not a geometry JSON file: {e}")))
}

/// Build a modulation from the PNGs in `dir` (the inverse of [`export_views`]).
/// A folder with a sidecar is a set: its PNGs are first checked against the
/// sizes and digests the sidecar lists, and a folder that disagrees (or
/// whose sidecar lists none) is refused, naming the file. A folder without
/// a sidecar holds pictures made elsewhere and is read as it is.
pub fn import_views(dir: &Path, geometry: &Geometry, tone: &ToneMapping) -> Result<Modulation> {
    check_tone(tone)?;
    // Even pictures read without their sidecar may not be of a set whose
    // replacement was interrupted: they could be of two sets.
    check_set_complete(dir, SIDECAR, "export the views again")?;
    let sidecar_path = dir.join(SIDECAR);
    if sidecar_path.exists() {
        let sidecar = read_sidecar(&sidecar_path)?;
        verify_set(dir, SIDECAR, &sidecar.files, "export the views again")?;
    }
    let g = geometry;
    let mut m = Modulation::zeros(g.clone())?;
    for v in 0..g.views.count {
        let path = dir.join(view_file_name(v, g.views.count));
        let img = image::open(&path).map_err(|e| match e {
            image::ImageError::IoError(io) => Error::io(&path, io),
            other => Error::invalid(&path, format!("not a readable PNG: {other}")),
        })?;
        if (img.width() as usize, img.height() as usize) != (g.emitters, g.hololines) {
            return Err(Error::invalid(
                &path,
                format!(
                    "is {}×{} pixels; the geometry needs emitters × hololines = {}×{}",
                    img.width(),
                    img.height(),
                    g.emitters,
                    g.hololines
                ),
            ));
        }
        let rgb = img.to_rgb16();
        let luma = img.to_luma16();
        for (c, ch) in g.channels.iter().enumerate() {
            for j in 0..g.hololines {
                for e in 0..g.emitters {
                    let q = match ch.name.as_str() {
                        "R" => rgb.get_pixel(e as u32, j as u32)[0],
                        "G" => rgb.get_pixel(e as u32, j as u32)[1],
                        "B" => rgb.get_pixel(e as u32, j as u32)[2],
                        _ => luma.get_pixel(e as u32, j as u32)[0],
                    };
                    let value = srgb_decode(f64::from(q) / 65535.0) * f64::from(tone.white);
                    m.set(c, j, e, v, value as f32);
                }
            }
        }
    }
    Ok(m)
}

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
        let n = geometry.views.count;
        let mut inputs = vec![dir.to_path_buf(), dir.join(SIDECAR)];
        inputs.extend((0..n).map(|v| dir.join(view_file_name(v, n))));
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

/// Import the pictures in `dir` for `geometry` into the `.holo` file
/// `output` (`holo import-views`).
pub fn import_views_file(
    dir: &Path,
    geometry: &Geometry,
    tone: &ToneMapping,
    output: &Path,
    options: WriteOptions,
    progress: &dyn Progress,
) -> Result<Run<WriteReport>> {
    let mut source = ViewsSource::new(dir, geometry, tone);
    crate::pipeline::run(&mut source, HoloSink::new(output, geometry, options), None, progress)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips() {
        for i in 0..=1000 {
            let x = i as f64 / 1000.0;
            assert!((srgb_decode(srgb_encode(x)) - x).abs() < 1e-12);
        }
        assert!((srgb_encode(1.0) - 1.0).abs() < 1e-15);
        assert_eq!(srgb_encode(0.0), 0.0);
    }
}
