//! Assembled frames on disk: one image per head (or colour layer) per frame,
//! as 8-bit PNG, 8-bit raw frame-buffer bytes, or float OpenEXR, plus a
//! `holo-fringes.json` sidecar that names the layout (in full, so custom
//! profiles travel with their fringes) and the files.
//!
//! The images and the sidecar are one set ([`crate::output::FileSet`]): all
//! images are written as temporaries, put in place together, and the
//! sidecar, which lists every image with its size and SHA-256, comes last.
//! An existing set is replaced whole, and only when asked; a reader refuses
//! a folder whose sidecar is missing or disagrees with its images.

use std::fs::File;
use std::io::{Read, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{Assembler, FrameImages, FrameStats};
use crate::error::{Error, Result};
use crate::layout::Layout;
use crate::output::{check_set_output, verify_set, AtomicFile, FileSet, SetFile};
use crate::picture::decode::decode_png;
use crate::progress::{Progress, Steps};

/// Name of the sidecar in a fringe directory.
pub const FRINGE_SIDECAR: &str = "holo-fringes.json";

/// How fringe images are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FringeFormat {
    /// 8-bit PNG, quantized with the layout's offset and gain.
    Png,
    /// The same 8-bit pixels as bare bytes, row by row, components interleaved:
    /// what is copied into the frame buffer.
    Raw,
    /// The float signal before quantization, OpenEXR (32-bit float, ZIP).
    Exr,
}

impl FringeFormat {
    /// From a command-line name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "png" => Some(FringeFormat::Png),
            "raw" => Some(FringeFormat::Raw),
            "exr" => Some(FringeFormat::Exr),
            _ => None,
        }
    }
    /// File extension.
    pub fn extension(self) -> &'static str {
        match self {
            FringeFormat::Png => "png",
            FringeFormat::Raw => "raw",
            FringeFormat::Exr => "exr",
        }
    }
}

/// The sidecar of a fringe directory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FringeSidecar {
    /// The layout the fringes were assembled for.
    pub layout: Layout,
    /// The file format of the images.
    pub format: FringeFormat,
    /// Image width, height and components (raw files have no header).
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Components per pixel.
    pub components: usize,
    /// The .holo file assembled.
    pub source: String,
    /// The frames, in order.
    pub frames: Vec<FringeFrame>,
    /// Every image of the set with its size and SHA-256 (empty in sidecars
    /// written before sets listed their files: such a set is refused).
    #[serde(default)]
    pub files: Vec<SetFile>,
}

/// One assembled frame in a sidecar.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FringeFrame {
    /// Frame index in the source file.
    pub index: usize,
    /// The source frame's digest, when it had one.
    pub source_digest: Option<String>,
    /// One file per image, in the layout's image order (names relative to the directory).
    pub files: Vec<String>,
    /// Samples clipped by the quantization.
    pub clipped: u64,
}

/// Options of [`assemble_file`].
#[derive(Clone, Debug)]
pub struct AssembleOptions {
    /// Frames to assemble (indices in file order); all when `None`.
    pub frames: Option<Range<usize>>,
    /// File format.
    pub format: FringeFormat,
    /// Replace existing files.
    pub overwrite: bool,
    /// When the file's geometry is not the layout's, resample every frame
    /// onto the layout by rays ([`super::retarget`]) instead of refusing.
    pub resample: bool,
}

/// What [`assemble_file`] did.
#[derive(Clone, Debug)]
pub struct AssembleReport {
    /// Every file written, sidecar last.
    pub files: Vec<PathBuf>,
    /// Per assembled frame.
    pub frames: Vec<FringeFrame>,
    /// Totals over the frames.
    pub stats: FrameStats,
    /// When the frames were resampled onto the layout: totals over the frames.
    pub resampled: Option<super::retarget::RetargetStats>,
    /// Where the time went: `read` (decoding the frames), `resample`,
    /// `assemble`, `encode` (the images written).
    pub timings: crate::progress::Timings,
}

/// File name of image `image` of frame `index`.
pub fn image_file_name(index: usize, image_name: &str, format: FringeFormat) -> String {
    format!("frame{index:04}-{image_name}.{}", format.extension())
}

/// Assemble frames of `input` for `layout` into `out_dir`; `progress`
/// counts the frames.
pub fn assemble_file(
    input: &Path,
    layout: &Layout,
    out_dir: &Path,
    options: &AssembleOptions,
    progress: &dyn Progress,
) -> Result<AssembleReport> {
    let assembler = Assembler::new(layout)?;
    let file = crate::format::Frames::open(input)?;
    let range = options.frames.clone().unwrap_or_else(|| file.all());
    file.check_range(&range)?;
    let fb = &layout.fringe.as_ref().expect("Assembler::new checked").frame_buffer;
    let names = |index: usize| -> Vec<String> {
        fb.image_names.iter().map(|n| image_file_name(index, n, options.format)).collect()
    };
    let all_names: Vec<String> = range.clone().flat_map(names).collect();
    let _claim = check_set_output(out_dir, FRINGE_SIDECAR, &all_names, &[input], options.overwrite)?;
    // Check the geometry before any work, with the file named.
    let fits = assembler.check_fits(file.geometry());
    if file.geometry().vertical_views.is_some() {
        // No resampling takes full parallax to a layout yet.
        fits.as_ref().map_err(|e| Error::argument("modulation", format!("{}: {e}", input.display())))?;
    }
    let mut resampled = match (fits, options.resample) {
        (Ok(()), _) => None,
        (Err(_), true) => Some(super::retarget::RetargetStats::default()),
        (Err(e), false) => {
            return Err(Error::argument(
                "modulation",
                format!("{}: {e}, or assemble with resampling on", input.display()),
            ));
        }
    };

    // The folder is made only now that the input is open and fits.
    let mut set = FileSet::create(out_dir, FRINGE_SIDECAR)?;
    let mut bytes: FrameImages<u8> = FrameImages { width: 0, height: 0, components: 0, images: vec![] };
    let mut floats: FrameImages<f32> = FrameImages { width: 0, height: 0, components: 0, images: vec![] };
    let mut frames = Vec::new();
    let mut total = FrameStats::default();
    let steps = Steps::begin(progress, "frames", range.len());
    let mut timings = crate::progress::Timings::default();
    for index in range.clone() {
        let mut m = timings.time("read", || file.read_frame(index))?;
        if let Some(total) = resampled.as_mut() {
            let (r, stats) = timings.time("resample", || super::retarget::retarget(&m, &layout.geometry))?;
            total.outside += stats.outside;
            total.total += stats.total;
            m = r;
        }
        let stats = timings
            .time("assemble", || match options.format {
                FringeFormat::Exr => assembler.assemble_into(&m, &mut floats),
                _ => assembler.assemble_into(&m, &mut bytes),
            })
            .map_err(|e| e.in_frame_of(input, index))?;
        let files = names(index);
        let encoding = std::time::Instant::now();
        for (image, name) in files.iter().enumerate() {
            set.add(name, |out| match options.format {
                FringeFormat::Png => write_png(out, &bytes, image),
                FringeFormat::Raw => out.write_all(&bytes.images[image]).map_err(|e| Error::io(out.destination(), e)),
                FringeFormat::Exr => write_exr(out, &floats, image),
            })?;
        }
        timings.add("encode", encoding.elapsed());
        total.clipped += stats.clipped;
        total.dark_hololines += stats.dark_hololines;
        frames.push(FringeFrame { index, source_digest: file.digest(index), files, clipped: stats.clipped });
        steps.step();
    }
    let mut sidecar = FringeSidecar {
        layout: layout.clone(),
        format: options.format,
        width: fb.width,
        height: fb.height,
        components: fb.components,
        source: input.display().to_string(),
        frames: frames.clone(),
        files: vec![],
    };
    let committing = std::time::Instant::now();
    let files = set.commit(options.overwrite, |listed| {
        sidecar.files = listed.to_vec();
        Ok(serde_json::to_string_pretty(&sidecar).expect("plain data").into_bytes())
    })?;
    timings.add("encode", committing.elapsed());
    Ok(AssembleReport { files, frames, stats: total, resampled, timings })
}

/// Read a fringe directory's sidecar, once the images it lists are checked
/// against their sizes and digests: a folder without a sidecar, or whose
/// images are missing, mixed with others or damaged, is refused, naming the
/// file.
pub fn read_sidecar(dir: &Path) -> Result<FringeSidecar> {
    // An interrupted replacement first: its sidecar is gone, which would
    // otherwise be all a reader says.
    crate::output::check_set_complete(dir, FRINGE_SIDECAR, REMEDY)?;
    let path = crate::output::require_manifest(dir, FRINGE_SIDECAR)?;
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let sidecar: FringeSidecar =
        serde_json::from_str(&text).map_err(|e| malformed(&path, format!("not a fringe sidecar: {e}")))?;
    let problems = super::problems(&sidecar.layout);
    if !problems.is_empty() {
        return Err(malformed(&path, format!("inconsistent layout: {}", problems.join("; "))));
    }
    verify_set(dir, FRINGE_SIDECAR, &sidecar.files, REMEDY)?;
    if let Some(name) =
        sidecar.frames.iter().flat_map(|f| &f.files).find(|n| !sidecar.files.iter().any(|f| &f.name == *n))
    {
        return Err(malformed(&path, format!("frame image {name} is not among the files it lists")));
    }
    Ok(sidecar)
}

/// What to do about a fringe set that cannot be read as one.
const REMEDY: &str = "assemble the fringes again";

/// Fringe images read back, in their stored type.
#[derive(Clone, Debug)]
pub enum StoredImages {
    /// PNG or raw.
    Bytes(FrameImages<u8>),
    /// EXR.
    Floats(FrameImages<f32>),
}

/// Read frame `frame` (position in the sidecar's list) of a fringe directory.
pub fn read_frame_images(dir: &Path, sidecar: &FringeSidecar, frame: usize) -> Result<StoredImages> {
    let entry = sidecar.frames.get(frame).ok_or_else(|| Error::no_frame(dir, frame, sidecar.frames.len()))?;
    let (w, h, c) = (sidecar.width, sidecar.height, sidecar.components);
    let len = w * h * c;
    match sidecar.format {
        FringeFormat::Exr => {
            let images = entry.files.iter().map(|f| read_exr(&dir.join(f), w, h, c)).collect::<Result<Vec<_>>>()?;
            Ok(StoredImages::Floats(FrameImages { width: w, height: h, components: c, images }))
        }
        format => {
            let mut images = Vec::new();
            for f in &entry.files {
                let path = dir.join(f);
                let data = if format == FringeFormat::Png {
                    read_png(&path, w, h, c)?
                } else {
                    let mut data = Vec::new();
                    File::open(&path).and_then(|mut f| f.read_to_end(&mut data)).map_err(|e| Error::io(&path, e))?;
                    data
                };
                if data.len() != len {
                    return Err(malformed(
                        &path,
                        format!("holds {} bytes; a {w} × {h} × {c} image has {len}", data.len()),
                    ));
                }
                images.push(data);
            }
            Ok(StoredImages::Bytes(FrameImages { width: w, height: h, components: c, images }))
        }
    }
}

impl StoredImages {
    /// [`Assembler::unpack`] whichever the type.
    pub fn unpack(&self, assembler: &Assembler, hololines: usize) -> Result<Vec<super::Signals>> {
        match self {
            StoredImages::Bytes(i) => assembler.unpack(i, hololines),
            StoredImages::Floats(i) => assembler.unpack(i, hololines),
        }
    }
}

fn colour_type(path: &Path, components: usize) -> Result<png::ColorType> {
    match components {
        1 => Ok(png::ColorType::Grayscale),
        3 => Ok(png::ColorType::Rgb),
        4 => Ok(png::ColorType::Rgba),
        c => Err(Error::unsupported(path, format!("PNG cannot hold {c} components per pixel; use raw or exr"))),
    }
}

fn write_png(out: &mut AtomicFile, images: &FrameImages<u8>, image: usize) -> Result<()> {
    let path = out.destination().to_path_buf();
    let colour = colour_type(&path, images.components)?;
    let failed = |e: png::EncodingError| Error::encode(&path, "PNG", e);
    let mut encoder = png::Encoder::new(out, images.width as u32, images.height as u32);
    encoder.set_color(colour);
    encoder.set_depth(png::BitDepth::Eight);
    // Fast deflate after the Sub filter: blank and dark areas become zero
    // runs, which it packs well; fringes themselves are noise-like. (Fast
    // alone would choose the filter; Sub is set after it.) No other chunk
    // than IHDR, IDAT and IEND: the bytes depend on the samples only.
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::Filter::Sub);
    let mut writer = encoder.write_header().map_err(failed)?;
    writer.write_image_data(&images.images[image]).map_err(failed)?;
    writer.finish().map_err(failed)
}

fn read_png(path: &Path, w: usize, h: usize, c: usize) -> Result<Vec<u8>> {
    let file = File::open(path).map_err(|e| Error::io(path, e))?;
    let img =
        decode_png(std::io::BufReader::new(file)).map_err(|e| malformed(path, format!("not a readable PNG: {e}")))?;
    if (img.width, img.height) != (w, h) {
        return Err(malformed(path, format!("is {} × {}; the sidecar says {w} × {h}", img.width, img.height)));
    }
    Ok(match c {
        1 => img.grey8(),
        3 => img.rgb8(),
        _ => img.rgba8(),
    })
}

const COMPONENT_NAMES: [&str; 4] = ["R", "G", "B", "A"];

fn write_exr(out: &mut AtomicFile, images: &FrameImages<f32>, image: usize) -> crate::error::Result<()> {
    use exr::prelude::*;
    let path = out.destination().to_path_buf();
    let (w, h, c) = (images.width, images.height, images.components);
    if c > COMPONENT_NAMES.len() {
        return Err(crate::error::Error::unsupported(
            &path,
            format!("{c} components per pixel; EXR output takes up to 4"),
        ));
    }
    let data = &images.images[image];
    let channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = (0..c)
        .map(|k| {
            let samples: Vec<f32> = data.iter().skip(k).step_by(c).copied().collect();
            AnyChannel::new(COMPONENT_NAMES[k], FlatSamples::F32(samples))
        })
        .collect();
    let layer = Layer::new(
        (w, h),
        LayerAttributes::named("fringe"),
        // Tiles stored in increasing y (then x), whatever order the
        // compressing threads finish in: the same frame gives the same bytes
        // at any thread count.
        Encoding {
            compression: exr::compression::Compression::ZIP16,
            line_order: LineOrder::Increasing,
            ..Encoding::default()
        },
        AnyChannels::sort(channels),
    );
    Image::from_layer(layer).write().to_buffered(out).map_err(|e| crate::error::Error::exr(&path, e))
}

fn read_exr(path: &Path, w: usize, h: usize, c: usize) -> crate::error::Result<Vec<f32>> {
    use exr::prelude::*;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| crate::error::Error::exr(path, e))?;
    let size = image.layer_data.size;
    if (size.width(), size.height()) != (w, h) {
        return Err(malformed(path, format!("is {} × {}; the sidecar says {w} × {h}", size.width(), size.height())));
    }
    let mut out = vec![0f32; w * h * c];
    for (k, name) in COMPONENT_NAMES.iter().take(c).enumerate() {
        let channel = image.layer_data.channel_data.list.iter().find(|ch| ch.name == **name);
        let Some(channel) = channel else {
            return Err(malformed(path, format!("has no channel {name}")));
        };
        for (i, v) in channel.sample_data.values_as_f32().enumerate() {
            out[i * c + k] = v;
        }
    }
    Ok(out)
}

/// A file of a fringe set that is not what its manifest says it is.
fn malformed(path: &Path, problem: String) -> Error {
    Error::Set { path: path.to_path_buf(), problem: crate::error::SetProblem::Malformed(problem) }
}
