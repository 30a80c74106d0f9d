//! The arguments module: every value on the command line is parsed, checked
//! and converted here, once, into what the library takes (millimetres
//! typed, metres stored; a choice typed, the library's enum stored), so a
//! command receives values it can hand on as they are.
//!
//! A value that breaks its rule is a usage error (exit 2) whose message says
//! what the value means: `--fps must be positive, not -30`. Every argument
//! that takes a value accepts a negative number ([`negative_numbers`]), so a
//! negative value reaches its check instead of clap's `-- -30` tip; lists of
//! numbers (`--translate -1,0,0`) also allow a leading hyphen.

use std::ffi::OsStr;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use clap::builder::{PossibleValue, TypedValueParser};
use clap::error::ErrorKind;
use clap::{Arg, Args, Command, ValueEnum};
use holo::cameras::quilt::{QuiltSpec, PRESETS};
use holo::cameras::resample::{Blend, Framing, Parallax};
use holo::format::{Compression, SampleType, WriteOptions};
use holo::frame_rate::FrameRate;
use holo::layout::{Layout, BUILTIN};
use holo::mesh::shade::SpecularModel;
use holo::pattern::PatternKind;
use holo::picture::White;
use holo::Geometry;

use crate::failure::Failure;

/// `command` with every argument that takes a value accepting negative
/// numbers, in every subcommand.
pub fn negative_numbers(command: Command) -> Command {
    command
        .mut_args(|a| if a.get_action().takes_values() { a.allow_negative_numbers(true) } else { a })
        .mut_subcommands(negative_numbers)
}

/// A value parser from a function that says what is wrong with a value (a
/// phrase such as `must be positive`); the error names the flag and the value.
#[derive(Clone)]
pub struct Checked<T>(Arc<Parse<T>>);

/// A value's text to the value, or the phrase saying what is wrong with it.
type Parse<T> = dyn Fn(&str) -> Result<T, String> + Send + Sync;

impl<T> Checked<T> {
    fn new(parse: impl Fn(&str) -> Result<T, String> + Send + Sync + 'static) -> Self {
        Checked(Arc::new(parse))
    }
}

impl<T: Clone + Send + Sync + 'static> TypedValueParser for Checked<T> {
    type Value = T;

    fn parse_ref(&self, cmd: &Command, arg: Option<&Arg>, value: &OsStr) -> Result<T, clap::Error> {
        let text = value.to_string_lossy();
        (self.0)(&text).map_err(|why| {
            let flag = match arg {
                Some(a) => a.get_long().map_or_else(|| a.get_id().to_string(), |l| format!("--{l}")),
                None => "a value".to_string(),
            };
            cmd.clone().error(ErrorKind::ValueValidation, format!("{flag} {why}, not {text}"))
        })
    }
}

/// A finite number that passes `ok`, times `to_library` (the factor from the
/// unit typed to the library's).
fn number(ok: fn(f64) -> bool, rule: &'static str, to_library: f64) -> Checked<f64> {
    Checked::new(move |s| match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && ok(x) => Ok(x * to_library),
        _ => Err(rule.to_string()),
    })
}

/// A frame rate, frames a second: a positive number (`30`, `12.5`), or an
/// exact fraction (`24000/1001`, which files then store as such).
pub fn frame_rate() -> Checked<f64> {
    let number = positive().0;
    Checked::new(move |s| match s.contains('/') {
        true => s
            .parse::<FrameRate>()
            .map(FrameRate::frames_per_second)
            .map_err(|_| "must be a positive number or a fraction of whole numbers such as 24000/1001".to_string()),
        false => number(s),
    })
}

/// A positive number.
pub fn positive() -> Checked<f64> {
    number(|x| x > 0.0, "must be positive", 1.0)
}

/// A number that is not negative, as an `f32` (radiance).
pub fn non_negative_f32() -> Checked<f32> {
    let parse = number(|x| x >= 0.0, "must be 0 or more", 1.0).0;
    Checked::new(move |s| parse(s).map(|x| x as f32))
}

/// A positive length typed in millimetres, in metres.
pub fn positive_millimetres() -> Checked<f64> {
    number(|x| x > 0.0, "must be positive (millimetres)", 1e-3)
}

/// An angle typed in degrees between 0 and 180 (a field of view or a view
/// cone), in degrees as the library takes them.
pub fn angle_below_180_degrees() -> Checked<f64> {
    number(|x| x > 0.0 && x < 180.0, "must be between 0 and 180 (degrees)", 1.0)
}

/// An angle from 0 to 180 degrees, both included.
pub fn degrees_0_to_180() -> Checked<f64> {
    number(|x| (0.0..=180.0).contains(&x), "must be from 0 to 180 (degrees)", 1.0)
}

/// A whole number from `min` up to `max`.
pub fn whole(min: usize, max: usize) -> Checked<usize> {
    let rule = if max == usize::MAX {
        format!("must be a whole number, {min} or more")
    } else {
        format!("must be {min} to {max}")
    };
    Checked::new(move |s| {
        s.trim().parse::<usize>().ok().filter(|n| (min..=max).contains(n)).ok_or_else(|| rule.clone())
    })
}

/// A whole number, `min` or more.
pub fn at_least(min: usize) -> Checked<usize> {
    whole(min, usize::MAX)
}

/// `n` comma-separated finite numbers, each times `to_library`.
fn numbers<const N: usize>(what: &'static str, to_library: f64) -> Checked<[f64; N]> {
    Checked::new(move |s| {
        let v: Option<Vec<f64>> =
            s.split(',').map(|t| t.trim().parse::<f64>().ok().filter(|x| x.is_finite())).collect();
        v.and_then(|v| <[f64; N]>::try_from(v).ok())
            .map(|a| a.map(|x| x * to_library))
            .ok_or_else(|| format!("must be {N} comma-separated numbers ({what})"))
    })
}

/// Three numbers, `X,Y,Z`, in the unit typed.
pub fn triple(what: &'static str) -> Checked<[f64; 3]> {
    numbers(what, 1.0)
}

/// Three lengths typed in millimetres, `X,Y,Z`, in metres.
pub fn millimetre_triple() -> Checked<[f64; 3]> {
    numbers("X,Y,Z in millimetres", 1e-3)
}

/// A row-major 4×4 matrix: 16 numbers.
pub fn matrix() -> Checked<[[f64; 4]; 4]> {
    let parse = numbers::<16>("a row-major 4x4 matrix", 1.0).0;
    Checked::new(move |s| {
        let v = parse(s)?;
        Ok(std::array::from_fn(|i| std::array::from_fn(|k| v[4 * i + k])))
    })
}

/// The viewer's couch of a HoloFlick: `XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX` in
/// metres, each minimum at most its maximum.
pub fn couch() -> Checked<holo::holoflick::container::ViewerCouch> {
    let six = numbers::<6>("XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX in metres", 1.0).0;
    Checked::new(move |s| {
        let v = six(s)?;
        if (0..3).any(|k| v[k] > v[k + 3]) {
            return Err("must have each minimum at most its maximum (XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX)".into());
        }
        Ok(holo::holoflick::container::ViewerCouch { min_m: [v[0], v[1], v[2]], max_m: [v[3], v[4], v[5]] })
    })
}

/// A horizontal eye position `X[,Y]` typed in millimetres, in metres.
pub fn eye_millimetres() -> Checked<(f64, f64)> {
    let pair = numbers::<2>("X,Y in millimetres", 1e-3).0;
    let one = numbers::<1>("X or X,Y in millimetres", 1e-3).0;
    Checked::new(move |s| if s.contains(',') { pair(s).map(|[x, y]| (x, y)) } else { one(s).map(|[x]| (x, 0.0)) })
}

/// Frames or hololines: `N`, `A..B` (B excluded) or `A..=B`, not empty.
pub fn range() -> Checked<Range<usize>> {
    Checked::new(|s| {
        let bad = || "must be N, A..B (B excluded) or A..=B, not empty".to_string();
        let number = |t: &str| t.trim().parse::<usize>().map_err(|_| bad());
        let range = if let Some((a, b)) = s.split_once("..=") {
            number(a)?..number(b)? + 1
        } else if let Some((a, b)) = s.split_once("..") {
            number(a)?..number(b)?
        } else {
            let n = number(s)?;
            n..n + 1
        };
        if range.is_empty() {
            return Err(bad());
        }
        Ok(range)
    })
}

/// Two whole numbers `AxB`, each from 1 to `max` (`N` alone is `NxN` when
/// `square` allows it).
pub fn by(max: usize, square: bool) -> Checked<(usize, usize)> {
    Checked::new(move |s| {
        let n = |t: &str| t.trim().parse::<usize>().ok().filter(|n| (1..=max).contains(n));
        let limit = if max == usize::MAX { "1 or more".to_string() } else { format!("from 1 to {max}") };
        let rule = || format!("must be {}AxB with whole numbers {limit}", if square { "N or " } else { "" });
        match s.split_once(['x', 'X']) {
            Some((a, b)) => n(a).zip(n(b)).ok_or_else(rule),
            None if square => n(s).map(|k| (k, k)).ok_or_else(rule),
            None => Err(rule()),
        }
    })
}

/// `--white`: the sample value shown as full white, `max` or `auto` (one
/// meaning everywhere: [`White`]).
pub fn white() -> Checked<White> {
    Checked::new(|s| s.parse::<White>().map_err(|_| "must be auto, max or a finite positive number".to_string()))
}

/// `import-views --white`: the number the views were exported with (the
/// sidecar records it), as `auto` and `max` cannot be undone.
pub fn white_number() -> Checked<f32> {
    Checked::new(|s| match s.parse::<White>() {
        Ok(White::Value(white)) => Ok(white),
        Ok(_) => Err("must be a number: give the white level the views were exported with".to_string()),
        Err(_) => Err("must be a finite positive number (the white level the views were exported with)".to_string()),
    })
}

/// The help of every `--white` that chooses a white level, then what the
/// command's samples are.
macro_rules! white_help {
    ($samples:literal) => {
        concat!(
            "Sample value shown as full white: a positive number, `max` (the largest sample: nothing clips) or ",
            "`auto` (the 99.9th percentile of the samples, so a few specular glints do not darken the rest); ",
            $samples
        )
    };
}

pub(crate) use white_help;

/// The help of a `--layout` argument: the built-in layouts, from the library.
pub fn layout_help(default: &str) -> String {
    let (full, horizontal): (Vec<&str>, Vec<&str>) = BUILTIN
        .into_iter()
        .partition(|name| holo::layout::builtin(name).is_some_and(|l| l.geometry.vertical_views.is_some()));
    format!(
        "Display layout: {} (built in; full parallax: {}; `holo layout --list`), or a .toml/.json profile{default}",
        horizontal.join(", "),
        full.join(", ")
    )
}

/// Load a layout ready to assemble: a built-in name or a profile file; a
/// file name that names no file says so.
pub fn load_layout(name: &str) -> Result<Layout, Failure> {
    missing_file(name)?;
    Ok(holo::assemble::load_layout(name)?)
}

/// Whether to keep the layout's blanking gains (spec/layouts.md §5.5).
#[derive(Args, Clone, Copy, Debug, Default)]
pub struct BlankingArg {
    /// Send the samples beside the horizontal blanking as the basis makes
    /// them, without the layout's blanking gains: the display's raw
    /// behaviour, where each blanked run leaves a dark emitter column
    /// (spec/layouts.md §5.5).
    #[arg(long)]
    pub raw_blanking: bool,
}

impl BlankingArg {
    /// `layout`, without its blanking gains if asked.
    pub fn apply(self, mut layout: Layout) -> Layout {
        if let Some(f) = layout.fringe.as_mut() {
            if self.raw_blanking {
                f.blanking_gains = None;
            } else if let Some(caveat) = f.blanking_gains_caveat() {
                crate::out::warn(format_args!("layout {}: {caveat}; --raw-blanking drops them", layout.name));
            }
        }
        layout
    }
}

/// The geometry of a layout, or of a geometry JSON file (`holo-views.json`).
pub fn layout_geometry(name: &str) -> Result<Geometry, Failure> {
    missing_file(name)?;
    let path = Path::new(name);
    if path.extension().is_some_and(|e| e == "json") {
        if let Ok(g) = holo::views::read_geometry_json(path) {
            return Ok(g);
        }
    }
    Ok(holo::assemble::load_layout(name)?.geometry)
}

/// A layout argument that looks like a file (it has an extension or a
/// folder) but names none.
fn missing_file(name: &str) -> Result<(), Failure> {
    let path = Path::new(name);
    let file_like = path.extension().is_some() || path.components().count() > 1;
    if holo::layout::builtin(name).is_none() && file_like && !path.exists() {
        return Err(Failure(format!(
            "{name}: no such file (a layout is {} or a .toml/.json profile)",
            BUILTIN.join(", ")
        )));
    }
    Ok(())
}

/// Vertical views added to a horizontal-parallax layout (`convert mesh`,
/// `convert cameras`): the file made full parallax (spec §8).
#[derive(Args, Clone, Debug, Default)]
pub struct VerticalViewsArgs {
    /// Full parallax: this many vertical views per emitter besides the horizontal ones (spec §8);
    /// 2 to 64.
    #[arg(long = "vertical-views", value_name = "N", value_parser = whole(2, 64))]
    pub vertical_views: Option<usize>,
    /// Full parallax: degrees from the lowest vertical view to the highest, centred on the
    /// display's normal (default: the horizontal views' cone).
    #[arg(long = "vertical-cone", value_name = "DEG", requires = "vertical_views", value_parser = angle_below_180_degrees())]
    pub vertical_cone_deg: Option<f64>,
}

impl VerticalViewsArgs {
    /// The geometry of layout `name` (as [`layout_geometry`]) with these
    /// vertical views; a full-parallax layout is refused when some are asked for.
    pub fn geometry(&self, name: &str) -> Result<Geometry, Failure> {
        let g = layout_geometry(name)?;
        let Some(count) = self.vertical_views else { return Ok(g) };
        if let Some(vertical) = &g.vertical_views {
            return Err(Failure(format!(
                "layout {name} is full parallax already ({} vertical views); --vertical-views makes a horizontal-parallax layout full parallax",
                vertical.count
            )));
        }
        Ok(g.with_centred_vertical_views(count, self.vertical_cone_deg.map(f64::to_radians)))
    }
}

/// Where a scene goes in the display (`convert mesh`, `holoflick encode`):
/// fitted into the display's volume unless a scale or a matrix is given
/// (`holo::mesh::place`).
#[derive(Args, Clone, Debug, Default)]
pub struct PlacementArgs {
    /// Rotation before fitting, degrees about x, then y, then z: RX,RY,RZ.
    #[arg(long = "rotate", value_name = "RX,RY,RZ", value_parser = triple("RX,RY,RZ in degrees"), allow_hyphen_values = true)]
    pub rotate_deg: Option<[f64; 3]>,
    /// Display millimetres per scene unit, instead of fitting the scene to the display (a scene that then
    /// leaves the display's volume is said).
    #[arg(long = "scale", value_name = "MM", value_parser = positive_millimetres())]
    pub scale_m: Option<f64>,
    /// Offset after centring, millimetres: X,Y,Z (x right, y up, z toward the viewer).
    #[arg(long = "translate", value_name = "X,Y,Z", value_parser = millimetre_triple(), allow_hyphen_values = true)]
    pub translate_m: Option<[f64; 3]>,
    /// A row-major 4x4 matrix (16 numbers, scene units to display metres) instead of fitting; the other
    /// placement options are then not used.
    #[arg(long, value_name = "16 NUMBERS", value_parser = matrix(), allow_hyphen_values = true)]
    pub matrix: Option<[[f64; 4]; 4]>,
}

impl PlacementArgs {
    /// The library's placement.
    pub fn placement(&self) -> holo::mesh::place::Placement {
        holo::mesh::place::Placement {
            rotate_deg: self.rotate_deg.unwrap_or([0.0; 3]),
            scale: self.scale_m,
            translate_m: self.translate_m.unwrap_or([0.0; 3]),
            matrix: self.matrix,
        }
    }
}

/// The output of a command writing one `.holo` file, and how it is written.
#[derive(Args)]
pub struct WriteArgs {
    /// Output .holo file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Store f32 samples instead of f16.
    #[arg(long)]
    pub f32: bool,
    /// Compression of the samples.
    #[arg(long, value_enum, default_value = "zip")]
    pub compression: CompressionChoice,
    /// Replace an existing output file.
    #[arg(long)]
    pub force: bool,
    /// Format version to write: 1.2 (each header sealed by its digest; a full-parallax file is written as
    /// 1.3, which it needs), 1.3 (the same), 1.1 (for readers of 1.1: the same without the seal) or 1.0
    /// (square pixels, for readers of version 1.0).
    #[arg(long = "format-version", value_enum, default_value = "1.2")]
    pub format_version: FormatVersionChoice,
}

/// `--format-version`: which version of the .holo format to write.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatVersionChoice {
    /// Version 1.3 (full parallax; horizontal parallax is written as 1.2).
    #[value(name = "1.3")]
    V1_3,
    /// Version 1.2.
    #[value(name = "1.2")]
    V1_2,
    /// Version 1.1.
    #[value(name = "1.1")]
    V1_1,
    /// Version 1.0.
    #[value(name = "1.0")]
    V1_0,
}

impl WriteArgs {
    /// The write options these arguments ask for, with provenance `source`
    /// (empty: the converter writes its own).
    pub fn options(&self, source: String) -> WriteOptions {
        WriteOptions {
            sample_type: if self.f32 { SampleType::F32 } else { SampleType::F16 },
            compression: self.compression.0,
            source,
            overwrite: self.force,
            version: match self.format_version {
                FormatVersionChoice::V1_3 => holo::format::FormatVersion::V1_3,
                FormatVersionChoice::V1_2 => holo::format::FormatVersion::V1_2,
                FormatVersionChoice::V1_1 => holo::format::FormatVersion::V1_1,
                FormatVersionChoice::V1_0 => holo::format::FormatVersion::V1_0,
            },
            ..WriteOptions::default()
        }
    }
}

/// A library enum offered as a clap [`ValueEnum`]: its values, names and
/// help come from the library's own list, so `--help` lists them all.
macro_rules! library_choice {
    ($(#[$doc:meta])* $name:ident($library:ty) = $all:expr, $value:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug)]
        pub struct $name(pub $library);

        impl ValueEnum for $name {
            fn value_variants<'a>() -> &'a [Self] {
                static ALL: OnceLock<Vec<$name>> = OnceLock::new();
                ALL.get_or_init(|| $all.into_iter().map($name).collect())
            }

            fn to_possible_value(&self) -> Option<PossibleValue> {
                let value: fn($library) -> PossibleValue = $value;
                Some(value(self.0))
            }
        }
    };
}

library_choice!(
    /// `--compression`: every compression a `.holo` file may use.
    CompressionChoice(Compression) = Compression::ALL,
    |c| {
        let help = match (c.is_lossless_for(SampleType::F16), c.is_lossless_for(SampleType::F32)) {
            (true, true) => "lossless",
            (true, false) => "lossless for f16, lossy for f32",
            _ => "lossy",
        };
        PossibleValue::new(c.name()).help(help)
    }
);

library_choice!(
    /// `pattern --kind`: every test pattern.
    PatternChoice(PatternKind) = PatternKind::ALL.map(|(kind, _)| kind),
    |k| PossibleValue::new(k.name())
);

library_choice!(
    /// `export-quilt --preset`: the Looking Glass quilt settings.
    PresetChoice(&'static str) = PRESETS,
    |name| {
        let value = PossibleValue::new(name);
        let value = if name == "standard" { value.alias("4k") } else { value };
        match QuiltSpec::preset(name) {
            Some(s) => value.help(format!(
                "{}x{} tiles of {}x{}, aspect {}",
                s.columns, s.rows, s.tile_width, s.tile_height, s.aspect
            )),
            None => value,
        }
    }
);

impl PresetChoice {
    /// The quilt settings of this preset.
    pub fn spec(self) -> Result<QuiltSpec, Failure> {
        QuiltSpec::preset(self.0).ok_or_else(|| Failure(format!("no quilt preset {:?}", self.0)))
    }
}

library_choice!(
    /// `--specular`: the specular lobe.
    SpecularChoice(SpecularModel) = SpecularModel::ALL,
    |m| PossibleValue::new(m.name()).help(match m {
        SpecularModel::Blinn => "(N·H)^n, Blinn 1977",
        SpecularModel::Phong => "(R·V)^n, Phong 1975",
    })
);

library_choice!(
    /// `--blend`: how the cameras around a ray are weighted.
    BlendChoice(Blend) = Blend::ALL,
    |b| {
        let value = PossibleValue::new(b.name());
        match b {
            Blend::Nearest => value.help("The nearest camera"),
            Blend::Linear => {
                value.alias("barycentric").help("Linear along a rail, barycentric in the cameras' Delaunay triangle")
            }
            Blend::NaturalNeighbour => value
                .aliases(["natural-neighbour", "natural-neighbor"])
                .help("Sibson's natural-neighbour coordinates"),
        }
    }
);

library_choice!(
    /// `convert cameras --framing`: how big the capture is shown.
    FramingChoice(Framing) = Framing::ALL,
    |f| PossibleValue::new(f.name()).help(match f {
        Framing::Fit => "The middle camera's view at the focus fits the emitter plane, its shape kept",
        Framing::Fill => "The middle camera's view at the focus covers the emitter plane, its overflowing edges cut",
        Framing::FillWidth => "The middle camera's view at the focus fills the display's width",
        Framing::CamerasAtViewer => "The cameras as far from the focus as the viewer is from the display",
    })
);

library_choice!(
    /// `convert cameras --parallax`: how the capture's directions meet the display's views.
    ParallaxChoice(Parallax) = Parallax::ALL,
    |p| PossibleValue::new(p.name()).help(match p {
        Parallax::Fit => "The cameras' span spread across the eye positions that see the display",
        Parallax::True => "The display's ray directions as they are: where no camera looked, rays stay black",
    })
);

/// `assemble --format`: how fringe images are stored.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FringeFormatChoice {
    /// 8-bit PNG with the layout's offset and gain.
    Png,
    /// The same 8-bit pixels as bare bytes, as the frame buffer takes them.
    Raw,
    /// The float signal before quantization (OpenEXR).
    Exr,
}

impl From<FringeFormatChoice> for holo::assemble::output::FringeFormat {
    fn from(c: FringeFormatChoice) -> Self {
        match c {
            FringeFormatChoice::Png => Self::Png,
            FringeFormatChoice::Raw => Self::Raw,
            FringeFormatChoice::Exr => Self::Exr,
        }
    }
}

/// What `export-views` and `export-hogels` take besides the file and the
/// folder: the frame, how its samples become PNG codes, and whether to
/// replace a set.
#[derive(Args)]
pub struct PictureExportArgs {
    /// Frame (0-based, in file order).
    #[arg(long, default_value = "0", value_parser = at_least(0))]
    pub frame: usize,
    /// Bits per component.
    #[arg(long, value_enum, default_value = "16")]
    pub bits: PngBits,
    #[arg(long, default_value = "1", value_parser = white(), help = white_help!("the samples are every view of the frame"))]
    pub white: White,
    /// Replace existing PNGs.
    #[arg(long)]
    pub force: bool,
}

/// What `import-views` and `import-hogels` take besides the folder: the
/// geometry and white level, when the folder's manifest is not to say
/// them, and the `.holo` file written.
#[derive(Args)]
pub struct PictureImportArgs {
    /// Geometry: a layout name, a layout profile or a geometry .json (default: the folder's manifest).
    #[arg(long)]
    pub geometry: Option<String>,
    /// Sample value of full white, a positive number (default: the manifest's, else 1).
    #[arg(long, value_parser = white_number())]
    pub white: Option<f32>,
    #[command(flatten)]
    pub write: WriteArgs,
}

/// `export-views --bits`: bits per PNG component.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum PngBits {
    /// 8-bit PNGs.
    #[value(name = "8")]
    Eight,
    /// 16-bit PNGs.
    #[value(name = "16")]
    Sixteen,
}

impl PngBits {
    /// Bits per component.
    pub fn bits(self) -> u8 {
        match self {
            PngBits::Eight => 8,
            PngBits::Sixteen => 16,
        }
    }
}

/// `pattern --channels`: colour channels instead of the layout's own.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ChannelsChoice {
    /// Red, green and blue.
    Rgb,
    /// One luminance channel.
    Y,
}

impl ChannelsChoice {
    /// The channels.
    pub fn channels(self) -> Vec<holo::geometry::ColourChannel> {
        match self {
            ChannelsChoice::Rgb => holo::geometry::rgb_channels(),
            ChannelsChoice::Y => holo::geometry::mono_channel(),
        }
    }
}
