//! From EXR headers to [`FileInfo`]: every header rule of the spec checked,
//! every problem collected (so `validate` can list them all), nothing
//! allocated from a declared size before it is checked against the limits.

use std::path::{Path, PathBuf};

use exr::meta::attribute::SampleType as ExrSampleType;
use exr::meta::header::Header;
use exr::meta::{BlockDescription, MetaData};
use serde::Serialize;

use super::attributes::{name, Attributes, Radiometry, VERSION};
use super::channels::{parse_channel_name, view_digits};
use super::digest::is_well_formed;
use super::header_digest;
use super::record::ConversionRecord;
use super::{Compression, SampleType, Window, MAX_CHANNELS, MAX_FRAMES, MAX_SAMPLES_PER_FRAME, MAX_SIDE};
use crate::error::Error;
use crate::geometry::{Geometry, CHANNEL_NAMES};
use crate::signature::{self, FileKind};

/// One frame of a file: one EXR part, or for full parallax one part per
/// view (spec §8).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameInfo {
    /// Frame number (`holo.frame`).
    pub number: i64,
    /// `sha256:…` digest of the samples, when the file has one (full
    /// parallax: none for the frame, one for each of its [`FrameInfo::views`]).
    pub digest: Option<String>,
    /// The region that holds samples; outside it every sample is zero (full
    /// parallax: the union of its views').
    pub data_window: Window,
    /// EXR part index (full parallax: of its first view).
    pub part: usize,
    /// Full parallax: each view's part, in the order of
    /// [`Geometry::view_index`]; empty for horizontal parallax.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub views: Vec<ViewPart>,
}

/// The part of one view of a full-parallax frame (spec §8).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ViewPart {
    /// EXR part index.
    pub part: usize,
    /// `sha256:…` digest of the view's samples.
    pub digest: Option<String>,
    /// The region of the view that holds samples.
    pub data_window: Window,
}

/// Everything the headers of a `.holo` file say.
#[derive(Clone, Debug, Serialize)]
pub struct FileInfo {
    /// The file.
    pub path: PathBuf,
    /// Format version (major, minor).
    pub version: (i32, i32),
    /// OpenEXR's `pixelAspectRatio`: a pixel's width over its height as
    /// viewers show it (spec §3.1; 1 in version 1.0).
    pub pixel_aspect: f32,
    /// The geometry shared by all frames.
    pub geometry: Geometry,
    /// Stored sample type.
    pub sample_type: SampleType,
    /// Compression of the pixel data.
    pub compression: Compression,
    /// How samples map to radiance.
    pub radiometry: Radiometry,
    /// `software` attribute: what wrote the file.
    pub software: Option<String>,
    /// `holo.source`: what the content was made from, and how.
    pub source: Option<String>,
    /// `holo.placement`: input coordinates to display metres (row-major,
    /// points as columns), when the writer recorded it.
    pub placement: Option<[[f64; 4]; 4]>,
    /// Frame rate (`framesPerSecond`), as numerator / denominator.
    pub frames_per_second: Option<(i32, u32)>,
    /// Frames, in part order.
    pub frames: Vec<FrameInfo>,
    /// File size on disk.
    pub file_bytes: u64,
    /// `holo.*` attributes this version does not define (ignored).
    pub unknown_attributes: Vec<String>,
    /// `holo.convert.*`: the conversion record as stored (`conversion()`,
    /// in the provenance module, reads it as a converter's options).
    #[serde(rename = "conversion", serialize_with = "super::record::serialize")]
    pub conversion_record: Option<ConversionRecord>,
}

impl FileInfo {
    /// Bytes the samples would take uncompressed, all frames.
    pub fn raw_bytes(&self) -> u64 {
        self.geometry.samples_per_frame() * self.sample_type.bytes() as u64 * self.frames.len() as u64
    }
}

/// What parsing the headers found.
pub(crate) struct Parsed {
    pub info: Option<FileInfo>,
    pub problems: Vec<String>,
    pub warnings: Vec<String>,
}

/// Read only the headers of a file, as an exr [`MetaData`]. A file whose
/// headers OpenEXR cannot parse but which carries header digests is said to
/// be damaged when a digest does not match (a flipped bit in an attribute's
/// size or type breaks the parse before any rule can be checked).
pub(crate) fn read_meta(path: &Path) -> crate::error::Result<(MetaData, u64)> {
    read_meta_and_end(path).map(|(meta, file_bytes, _)| (meta, file_bytes))
}

/// [`read_meta`], with the byte position where the headers end (and the
/// offset tables begin).
pub(crate) fn read_meta_and_end(path: &Path) -> crate::error::Result<(MetaData, u64, u64)> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let file_bytes = file.metadata().map_err(|e| Error::io(path, e))?.len();
    // The bytes the parser takes are counted: it consumes exactly the
    // headers (every list it reads ends with a byte it consumes).
    let mut reader = Positioned::new(file);
    let meta = MetaData::read_from_buffered(&mut reader, false).map_err(|e| {
        if let Some(kind) = other_kind(path) {
            return Error::invalid(path, kind);
        }
        match header_digest::read_stored(path).map(|stored| header_digest::problems(&stored, false)) {
            Ok(damage) if !damage.is_empty() => Error::invalid(path, damage.join("; ")),
            _ => Error::exr(path, e),
        }
    })?;
    Ok((meta, file_bytes, reader.at()))
}

/// A buffered file that knows where it is: what the header parser took,
/// and the reader's seeks from chunk to chunk, which keep the buffer when
/// the next chunk follows.
pub(super) struct Positioned {
    inner: std::io::BufReader<std::fs::File>,
    at: u64,
}

impl Positioned {
    pub(super) fn new(file: std::fs::File) -> Positioned {
        Positioned { inner: std::io::BufReader::new(file), at: 0 }
    }

    /// The byte position of the next read.
    pub(super) fn at(&self) -> u64 {
        self.at
    }

    pub(super) fn seek_to(&mut self, to: u64) -> std::io::Result<()> {
        use std::io::Seek;
        if to != self.at {
            match i64::try_from(to).ok().zip(i64::try_from(self.at).ok()) {
                Some((to, at)) => self.inner.seek_relative(to - at)?,
                None => {
                    self.inner.seek(std::io::SeekFrom::Start(to))?;
                }
            }
            self.at = to;
        }
        Ok(())
    }
}

impl std::io::Read for Positioned {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.at += n as u64;
        Ok(n)
    }
}

/// What a file that is not OpenEXR is instead, for the files holo's users
/// most often hand a `.holo` command by mistake (recognised by their first
/// bytes), with the command that takes it.
fn other_kind(path: &Path) -> Option<&'static str> {
    let mut head = [0u8; 8];
    std::io::Read::read_exact(&mut std::fs::File::open(path).ok()?, &mut head).ok()?;
    match signature::kind_of(&head)? {
        FileKind::HoloFlick => Some(
            "is a HoloFlick (.hflk), not a .holo file: `holo holoflick info` describes it, `holo convert holoflick` renders it into one",
        ),
        FileKind::Png => {
            Some("is a PNG picture, not a .holo file: `holo convert cameras` (or `holo import-views`) makes one from pictures")
        }
        FileKind::Glb => Some("is a glTF scene (.glb), not a .holo file: `holo convert mesh` renders it into one"),
        FileKind::OpenExr => None,
    }
}

/// Open: the headers must have no problem at all, and (when `sealed`) each
/// must match its digest. The writer opens its own file unsealed, before the
/// digests are filled in. With the headers as OpenEXR's meta data, and the
/// byte position where they end.
pub(crate) fn file_info(path: &Path, sealed: bool) -> crate::error::Result<(FileInfo, MetaData, u64)> {
    let (meta, file_bytes, headers_end) = read_meta_and_end(path)?;
    let stored = if sealed { Some(header_digest::read_stored(path)?) } else { None };
    let parsed = parse(path, &meta, file_bytes, stored.as_ref())?;
    match (parsed.info, parsed.problems.first()) {
        (Some(info), None) => Ok((info, meta, headers_end)),
        (_, Some(first)) => {
            let more = parsed.problems.len() - 1;
            let tail =
                if more > 0 { format!(" (and {more} more problem(s); run `holo validate`)") } else { String::new() };
            Err(Error::invalid(path, format!("{first}{tail}")))
        }
        (None, None) => Err(Error::invalid(path, "the headers could not be read")),
    }
}

/// Check every header rule, and with the headers as `stored`, their digests
/// (spec §7.2; a damaged header is the first problem, since it explains any
/// other). Errors only for a newer major version (which a reader must refuse
/// before looking further, spec §9) in a header that is not damaged.
pub(crate) fn parse(
    path: &Path,
    meta: &MetaData,
    file_bytes: u64,
    stored: Option<&header_digest::StoredHeaders>,
) -> crate::error::Result<Parsed> {
    let mut problems = Vec::new();
    let mut warnings = Vec::new();
    let headers = &meta.headers;
    let Some(first) = headers.first() else {
        return Ok(Parsed { info: None, problems: vec!["the file has no parts".into()], warnings });
    };
    let attrs = Attributes::new(&[&first.shared_attributes.other, &first.own_attributes.other]);
    if attrs.holo_names().is_empty() {
        problems.push("this is an OpenEXR file but not a .holo file: it has no holo.* attributes".into());
        return Ok(Parsed { info: None, problems, warnings });
    }
    let version = attrs.v2i(name::VERSION);
    // From 1.2 every part is sealed; in any version a seal present is checked.
    let sealed_version = version.as_ref().is_ok_and(|v| *v >= (1, 2));
    if let Some(stored) = stored {
        problems.extend(header_digest::problems(stored, sealed_version));
    }
    let version = match version {
        Ok(v) => v,
        Err(e) => {
            problems.push(e);
            return Ok(Parsed { info: None, problems, warnings });
        }
    };
    if version.0 > VERSION.0 && problems.is_empty() {
        return Err(Error::NewerMajorVersion {
            path: path.into(),
            major: version.0,
            minor: version.1,
            supported: VERSION.0,
        });
    }
    if version.0 < 1 || version.1 < 0 {
        problems.push(format!("{} is {}.{}; the first version is 1.0", name::VERSION, version.0, version.1));
    }
    if version.1 > VERSION.1 {
        warnings.push(format!(
            "written with format version {}.{}, newer than this reader's {}.{}; attributes it does not know are ignored",
            version.0, version.1, VERSION.0, VERSION.1
        ));
    }
    if headers.len() as u64 > MAX_FRAMES {
        problems.push(format!("the file has {} parts, more than the limit of {MAX_FRAMES}", headers.len()));
        return Ok(Parsed { info: None, problems, warnings });
    }

    // Full parallax (spec §8) names each part's channels by colour alone.
    let full = attrs.string(name::PARALLAX).is_ok_and(|p| p == "full");
    if full && version < (1, 3) {
        problems.push(format!(
            "{} is \"full\" but {} is {}.{}: full parallax needs format version 1.3",
            name::PARALLAX,
            name::VERSION,
            version.0,
            version.1
        ));
    }
    // Channel list of the first part: colours, views, sample type.
    let (colours, sample_type) = match channel_list(first, full) {
        Ok(x) => x,
        Err(e) => {
            problems.push(e);
            return Ok(Parsed { info: None, problems, warnings });
        }
    };
    let geometry = match attrs.geometry(&colours) {
        Ok(g) => g,
        Err(e) => {
            problems.push(e);
            return Ok(Parsed { info: None, problems, warnings });
        }
    };
    // Limits before anything is sized from the geometry.
    for (what, n, limit) in [
        ("hololine count", geometry.hololines as u64, MAX_SIDE),
        ("emitter count", geometry.emitters as u64, MAX_SIDE),
        ("channel count (views × colours)", channels_per_part(&geometry), MAX_CHANNELS),
        ("views per frame", geometry.views_per_emitter() as u64, MAX_FRAMES),
        // A full-parallax frame is read band by band (spec §10).
        ("samples per frame", if full { 0 } else { geometry.samples_per_frame() }, MAX_SAMPLES_PER_FRAME),
    ] {
        if n > limit {
            return Err(Error::TooLarge { path: path.into(), what, value: n, limit });
        }
    }
    problems.extend(geometry.problems());
    if !full {
        check_channels(first, &geometry, &mut problems);
    }
    check_pixel_aspect(first.shared_attributes.pixel_aspect, version, &geometry, &mut problems, &mut warnings);

    let radiometry = attrs.radiometry().unwrap_or_else(|e| {
        problems.push(e);
        Radiometry::default()
    });
    let compression = Compression::from_exr(first.compression).unwrap_or_else(|| {
        problems.push(format!("compression {} is not one the spec allows", first.compression));
        Compression::None
    });
    if !compression.is_lossless_for(sample_type) {
        warnings.push(format!("compression {} is lossy for {:?} samples", compression.name(), sample_type));
    }

    let mut parts = Vec::new();
    let mut chunk_total: u64 = 0;
    let part_zero = PartZero { colours: &colours, sample_type, geometry: &geometry, compression };
    let views = if full { geometry.views_per_emitter().max(1) } else { 1 };
    let frame_count = headers.len() / views;
    if headers.len() % views != 0 {
        problems.push(format!(
            "the file has {} parts, not a whole number of frames of {views} views (one part per view)",
            headers.len()
        ));
    }
    for (part, header) in headers.iter().enumerate() {
        chunk_total += header.chunk_count as u64;
        let view = full.then(|| geometry.view_of_index(part % views));
        parts.push(check_part(part, header, frame_count, view, &part_zero, &mut problems));
    }
    let frames = if full { frames_of_views(parts, views, &geometry, &mut problems) } else { parts };
    if frames.windows(2).any(|w| w[1].number <= w[0].number) {
        problems.push("frame numbers (holo.frame) are not strictly increasing from frame to frame".into());
    }
    // The offset tables hold one u64 per chunk; a file smaller than that is
    // damaged, and its tables must not be allocated.
    if chunk_total.saturating_mul(8) > file_bytes {
        problems.push(format!("the headers declare {chunk_total} chunks, more than a {file_bytes}-byte file can hold"));
    }

    for n in attrs.holo_names() {
        if !super::attributes::is_known(n) {
            warnings.push(format!("unknown attribute {n} ignored"));
        }
    }
    let unknown_attributes =
        attrs.holo_names().into_iter().filter(|n| !super::attributes::is_known(n)).map(String::from).collect();
    let text =
        |t: &Option<exr::meta::attribute::Text>| t.as_ref().map(|t| String::from_utf8_lossy(t.as_slice()).into_owned());
    let conversion_record = ConversionRecord::from_attributes(&attrs);
    let info = FileInfo {
        path: path.into(),
        version,
        pixel_aspect: first.shared_attributes.pixel_aspect,
        geometry,
        sample_type,
        compression,
        radiometry,
        software: text(&first.own_attributes.software_name),
        source: attrs.optional(name::SOURCE, Attributes::string).unwrap_or_else(|e| {
            problems.push(e);
            None
        }),
        placement: attrs
            .optional(name::PLACEMENT, Attributes::m44d)
            .unwrap_or_else(|e| {
                problems.push(e);
                None
            })
            .map(|m| super::attributes::matrix_from_m44d(&m)),
        frames_per_second: first.own_attributes.frames_per_second.map(|r| (r.0, r.1)),
        frames,
        file_bytes,
        unknown_attributes,
        conversion_record,
    };
    Ok(Parsed { info: Some(info), problems, warnings })
}

/// What every later part must share with part 0.
struct PartZero<'a> {
    colours: &'a [String],
    sample_type: SampleType,
    geometry: &'a Geometry,
    compression: Compression,
}

/// The rules of one part (one frame): the same channels, geometry and
/// compression as part 0, flat single-level data, the windows, the frame
/// number and the digest. Problems are collected; the frame's facts returned.
fn check_part(
    part: usize,
    header: &Header,
    frame_count: usize,
    view: Option<(usize, usize)>,
    zero: &PartZero,
    problems: &mut Vec<String>,
) -> FrameInfo {
    let part_count = frame_count * view.map_or(1, |_| zero.geometry.views_per_emitter());
    let here = Attributes::new(&[&header.shared_attributes.other, &header.own_attributes.other]);
    let prefix = if part_count > 1 { format!("part {part}: ") } else { String::new() };
    if part > 0 {
        let same = channel_list(header, view.is_some()).ok() == Some((zero.colours.to_vec(), zero.sample_type))
            && here.geometry(zero.colours).ok().as_ref() == Some(zero.geometry);
        if !same {
            problems.push(format!("{prefix}geometry or channels differ from part 0; every frame must share them"));
        }
        if Compression::from_exr(header.compression) != Some(zero.compression) {
            problems.push(format!("{prefix}compression differs from part 0"));
        }
    }
    if header.deep {
        problems.push(format!("{prefix}deep data is not allowed"));
    }
    if let BlockDescription::Tiles(t) = header.blocks {
        if t.level_mode != exr::meta::attribute::LevelMode::Singular {
            problems.push(format!("{prefix}mip or rip levels are not allowed"));
        }
    }
    let display = header.shared_attributes.display_window;
    if display.position.0 != 0
        || display.position.1 != 0
        || display.size.0 != zero.geometry.emitters
        || display.size.1 != zero.geometry.hololines
    {
        problems.push(format!(
            "{prefix}display window is {}×{} at ({}, {}); it must be emitters × hololines = {}×{} at (0, 0)",
            display.size.0,
            display.size.1,
            display.position.0,
            display.position.1,
            zero.geometry.emitters,
            zero.geometry.hololines
        ));
    }
    let (dx, dy) = (header.own_attributes.layer_position.0, header.own_attributes.layer_position.1);
    let (dw, dh) = (header.layer_size.0, header.layer_size.1);
    let inside =
        dx >= 0 && dy >= 0 && dx as usize + dw <= zero.geometry.emitters && dy as usize + dh <= zero.geometry.hololines;
    if !inside {
        problems.push(format!("{prefix}data window {dw}×{dh} at ({dx}, {dy}) is not inside the display window"));
    }
    let number = match here.optional(name::FRAME, Attributes::int) {
        Ok(n) => i64::from(n.unwrap_or(part as i32)),
        Err(e) => {
            problems.push(format!("{prefix}{e}"));
            part as i64
        }
    };
    match here.optional(name::FRAME_COUNT, Attributes::int) {
        Ok(Some(n)) if n as usize != frame_count => problems.push(match view {
            None => format!("{prefix}{} is {n} but the file has {} part(s)", name::FRAME_COUNT, part_count),
            Some(_) => format!(
                "{prefix}{} is {n} but the file's {part_count} parts are {frame_count} frame(s)",
                name::FRAME_COUNT
            ),
        }),
        Ok(_) => {}
        Err(e) => problems.push(format!("{prefix}{e}")),
    }
    let digest = match here.optional(name::DIGEST, Attributes::string) {
        Ok(Some(d)) if is_well_formed(&d) => Some(d),
        Ok(Some(d)) => {
            problems.push(format!("{prefix}{} {d:?} is not `sha256:` and 64 hex digits", name::DIGEST));
            None
        }
        Ok(None) => {
            problems.push(format!("{prefix}required attribute {} is missing", name::DIGEST));
            None
        }
        Err(e) => {
            problems.push(format!("{prefix}{e}"));
            None
        }
    };
    if let Some((h, k)) = view {
        match here.v2i(name::VIEW) {
            Ok(stored) if stored == (h as i32, k as i32) => {}
            Ok((sh, sk)) => problems.push(format!(
                "{prefix}{} is ({sh} {sk}) but part {part} holds view ({h} {k}) (parts go frame by frame, vertical view by vertical view, then horizontal)",
                name::VIEW
            )),
            Err(e) => problems.push(format!("{prefix}{e}")),
        }
    } else if here.has(name::VIEW) {
        problems.push(format!("{prefix}attribute {} is for full parallax; this file's is horizontal", name::VIEW));
    }
    FrameInfo {
        number,
        digest,
        data_window: Window { x: dx.max(0) as usize, y: dy.max(0) as usize, width: dw, height: dh },
        part,
        views: Vec::new(),
    }
}

/// A full-parallax file's parts (one per view, spec §8) as its frames: the
/// `views` parts of a frame must share `holo.frame`.
fn frames_of_views(parts: Vec<FrameInfo>, views: usize, g: &Geometry, problems: &mut Vec<String>) -> Vec<FrameInfo> {
    parts
        .chunks_exact(views)
        .map(|frame| {
            let first = &frame[0];
            if let Some(other) = frame.iter().find(|p| p.number != first.number) {
                let (h, k) = g.view_of_index(other.part - first.part);
                problems.push(format!(
                    "part {} (view ({h} {k})): {} is {} but the frame's first view says {}: a frame's views share it",
                    other.part,
                    name::FRAME,
                    other.number,
                    first.number
                ));
            }
            let (mut x0, mut y0, mut x1, mut y1) = (usize::MAX, usize::MAX, 0, 0);
            for p in frame.iter().filter(|p| p.data_window.width > 0 && p.data_window.height > 0) {
                let w = p.data_window;
                (x0, y0, x1, y1) = (x0.min(w.x), y0.min(w.y), x1.max(w.x + w.width), y1.max(w.y + w.height));
            }
            let data_window = if x0 == usize::MAX {
                Window { x: 0, y: 0, width: 1, height: 1 }
            } else {
                Window { x: x0, y: y0, width: x1 - x0, height: y1 - y0 }
            };
            FrameInfo {
                number: first.number,
                digest: None,
                data_window,
                part: first.part,
                views: frame
                    .iter()
                    .map(|p| ViewPart { part: p.part, digest: p.digest.clone(), data_window: p.data_window })
                    .collect(),
            }
        })
        .collect()
}

/// EXR channels in each part: views × colours, or for full parallax the colours.
fn channels_per_part(g: &Geometry) -> u64 {
    match g.vertical_views {
        None => (g.views.count as u64).saturating_mul(g.channels.len() as u64),
        Some(_) => g.channels.len() as u64,
    }
}

/// The colour suffixes (in R, G, B, Y order) and the sample type of a part.
/// The pixel aspect ratio (shared by every part): fixed at 1 in version 1.0;
/// from 1.1 the emitter grid's proportions, any positive value read (spec
/// §3.1). It never changes what a sample means.
fn check_pixel_aspect(
    aspect: f32,
    version: (i32, i32),
    g: &Geometry,
    problems: &mut Vec<String>,
    warnings: &mut Vec<String>,
) {
    let physical = (g.emitter_pitch_m / g.hololine_pitch_m) as f32;
    if version < (1, 1) {
        if aspect != 1.0 {
            problems.push(format!("pixel aspect ratio is {aspect}; version 1.0 requires 1"));
        }
    } else if !(aspect.is_finite() && aspect > 0.0) {
        problems.push(format!("pixel aspect ratio is {aspect}; it must be a positive number"));
    } else if (aspect / physical - 1.0).abs() > 1e-6 {
        warnings.push(format!(
            "pixel aspect ratio is {aspect}, not the emitter grid's {physical} (emitter pitch over hololine pitch): viewers show the picture out of proportion"
        ));
    }
}

/// (For full parallax, `full`, each channel is named by its colour alone.)
fn channel_list(header: &Header, full: bool) -> Result<(Vec<String>, SampleType), String> {
    let list = &header.channels.list;
    if list.is_empty() {
        return Err("the part has no channels".into());
    }
    if list.len() as u64 > MAX_CHANNELS {
        return Err(format!("{} channels, more than the limit of {MAX_CHANNELS}", list.len()));
    }
    let sample_type = match list[0].sample_type {
        ExrSampleType::F16 => SampleType::F16,
        ExrSampleType::F32 => SampleType::F32,
        ExrSampleType::U32 => return Err("channels hold UINT samples; the spec allows HALF or FLOAT".into()),
    };
    let mut colours = Vec::new();
    for ch in list {
        let n = String::from_utf8_lossy(ch.name.as_slice());
        let colour = if full {
            n.as_ref()
        } else {
            let Some((_, colour, _)) = parse_channel_name(&n) else {
                return Err(format!("channel {n:?} is not named v<view>.<colour> (such as v000.R)"));
            };
            colour
        };
        if !CHANNEL_NAMES.contains(&colour) {
            return Err(format!("channel {n:?} has colour {colour:?}; allowed are R, G, B and Y"));
        }
        if !colours.iter().any(|c: &String| c == colour) {
            colours.push(colour.to_string());
        }
        if ch.sample_type != list[0].sample_type {
            return Err("channels do not all have the same sample type".into());
        }
        if ch.sampling.0 != 1 || ch.sampling.1 != 1 {
            return Err(format!("channel {n:?} is subsampled; every channel must have sampling 1×1"));
        }
    }
    colours.sort_by_key(|c| CHANNEL_NAMES.iter().position(|n| n == c));
    Ok((colours, sample_type))
}

/// The channel list must be exactly views × colours, equal-width view numbers.
fn check_channels(header: &Header, g: &Geometry, problems: &mut Vec<String>) {
    let digits = view_digits(g.views.count);
    let mut seen = vec![false; g.views.count * g.channels.len()];
    for ch in &header.channels.list {
        let n = String::from_utf8_lossy(ch.name.as_slice());
        let Some((v, colour, width)) = parse_channel_name(&n) else {
            continue;
        };
        if width != digits {
            problems.push(format!("channel {n:?}: view numbers must have exactly {digits} digits"));
            return;
        }
        if v >= g.views.count {
            problems.push(format!("channel {n:?} names view {v} but {} is {}", name::VIEWS, g.views.count));
            return;
        }
        if let Some(c) = g.channel_index(colour) {
            seen[v * g.channels.len() + c] = true;
        }
    }
    if let Some(i) = seen.iter().position(|s| !s) {
        let (v, c) = (i / g.channels.len(), i % g.channels.len());
        problems.push(format!(
            "channel {} is missing: {} views × {} colour(s) need {} channels",
            super::channels::channel_name(v, &g.channels[c].name, digits),
            g.views.count,
            g.channels.len(),
            seen.len()
        ));
    }
}
