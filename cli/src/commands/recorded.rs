//! A conversion as a `.holo` file records it (`holo.convert.*`): the
//! command line that makes it again, for `holo info`, and `holo convert
//! like`, which makes it again from the file alone.
//!
//! The flags and their units are those of `convert.rs`; the names of the
//! choices are the library's own (`args.rs`).

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use clap::Args;
use holo::cameras::convert::{convert_camera_files, CameraConvertOptions};
use holo::cameras::read::OpenOptions;
use holo::format::{Compression, FileInfo, SampleType};
use holo::holoflick::convert::{convert_holoflick, HoloFlickConvertOptions};
use holo::mesh::convert::{convert_mesh, ConvertOptions};
use holo::mesh::place::display_volume;
use holo::mesh::render::{Engine, RenderOptions, Supersample};
use holo::mesh::shade::parse_light;
use holo::mesh::Light;
use holo::provenance::{Conversion, ConverterOptions};

use super::{check_output, Failure, Outcome};
use crate::out::{say, warn};
use crate::progress::Reporter;

/// A conversion as a command line, and what of it the command line cannot
/// give exactly.
pub struct CommandLine {
    /// `holo convert …`, each argument shell-quoted where it needs to be.
    pub line: String,
    /// Options the flags cannot give exactly, in words.
    pub unsaid: Vec<String>,
}

/// The command line that makes `c` again for the display of `info`
/// (`--layout` a built-in layout when one has that geometry), writing `OUT.holo`.
pub fn command_line(c: &Conversion, info: &FileInfo) -> CommandLine {
    let mut a = Line::default();
    // A full-parallax file: a layout's horizontal geometry with vertical views.
    let horizontal = holo::Geometry {
        vertical_views: None,
        parallax: holo::geometry::Parallax::Horizontal,
        ..info.geometry.clone()
    };
    let builtin_of = |g: &holo::Geometry| {
        holo::layout::BUILTIN.into_iter().find(|name| holo::layout::builtin(name).is_some_and(|l| l.geometry == *g))
    };
    // A full-parallax built-in is named as it is; any other full-parallax
    // geometry as a horizontal one with vertical views.
    let full_builtin = builtin_of(&info.geometry).filter(|_| info.geometry.vertical_views.is_some());
    let layout = full_builtin.or_else(|| builtin_of(&horizontal)).unwrap_or_else(|| {
        a.unsaid.push("the layout, which no built-in one is: LAYOUT stands for it".into());
        "LAYOUT"
    });
    a.push(["--layout", layout, "-o", "OUT.holo"]);
    if let (Some(vertical), None) = (&info.geometry.vertical_views, full_builtin) {
        let cone_deg = (vertical.last_theta_rad - vertical.first_theta_rad).to_degrees();
        a.flag("--vertical-views", vertical.count);
        a.flag("--vertical-cone", cone_deg);
        let made = horizontal.with_centred_vertical_views(vertical.count, Some(cone_deg.to_radians()));
        if made != info.geometry {
            a.unsaid.push("the vertical views, which --vertical-cone gives only centred and tan-spaced".into());
        }
    }
    let kind = c.options.kind();
    match &c.options {
        ConverterOptions::Mesh(o) => mesh(&mut a, o, info),
        ConverterOptions::Cameras(o) => cameras(&mut a, o),
        ConverterOptions::HoloFlick(o) => holoflick(&mut a, o),
    }
    let write = match &c.options {
        ConverterOptions::Mesh(o) => &o.write,
        ConverterOptions::Cameras(o) => &o.write,
        ConverterOptions::HoloFlick(o) => &o.write,
    };
    if write.sample_type == SampleType::F32 {
        a.push(["--f32"]);
    }
    if write.compression != Compression::Zip {
        a.push(["--compression", write.compression.name()]);
    }
    let line = ["holo", "convert", kind, &c.input].into_iter().chain(a.args.iter().map(String::as_str)).map(quoted);
    CommandLine { line: line.collect::<Vec<_>>().join(" "), unsaid: a.unsaid }
}

/// Arguments, and what they cannot say.
#[derive(Default)]
struct Line {
    args: Vec<String>,
    unsaid: Vec<String>,
}

impl Line {
    fn push<const N: usize>(&mut self, args: [&str; N]) {
        self.args.extend(args.iter().map(|s| s.to_string()));
    }
    fn flag(&mut self, flag: &str, value: impl std::fmt::Display) {
        self.push([flag, &value.to_string()]);
    }
    /// A flag taking millimetres for `metres`, or several comma-separated.
    fn millimetres(&mut self, flag: &str, metres: &[f64]) {
        let typed: Vec<String> = metres
            .iter()
            .map(|&m| {
                millimetres(m).unwrap_or_else(|| {
                    self.unsaid.push(format!("{flag} exactly ({m} m)"));
                    (m * 1e3).to_string()
                })
            })
            .collect();
        self.flag(flag, typed.join(","));
    }
    fn frames(&mut self, frames: &Option<std::ops::Range<usize>>) {
        if let Some(f) = frames {
            self.flag("--frames", format!("{}..{}", f.start, f.end));
        }
    }
    fn supersample(&mut self, s: Supersample) {
        self.flag("--supersample", format!("{}x{}", s.emitter, s.view));
        self.flag("--hololine-supersample", s.hololine);
    }
}

/// The millimetres a flag takes (it multiplies what is typed by 1e-3) for
/// exactly `metres`: the shortest decimal near `metres · 1e3` that gives it
/// back, `None` when no decimal does.
fn millimetres(metres: f64) -> Option<String> {
    let near = metres * 1e3;
    // The value typed for `metres` is within a few units in the last place
    // of `metres · 1e3`; nearest first.
    let candidates = (0..=8i64).map(|k| if k % 2 == 0 { k / 2 } else { -(k + 1) / 2 });
    candidates
        .map(|k| f64::from_bits(near.to_bits().wrapping_add_signed(k)))
        .find(|x| x.is_finite() && *x * 1e-3 == metres)
        .map(|x| x.to_string())
}

/// `s` as a shell reads it back: single-quoted unless plain.
fn quoted(s: &str) -> String {
    let plain = !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || "_-.,/:=+@%".contains(c));
    if plain {
        s.to_string()
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

fn mesh(a: &mut Line, o: &ConvertOptions, info: &FileInfo) {
    let (s, r) = (&o.scene, &o.render);
    a.frames(&s.frames);
    a.flag("--fps", s.frames_per_second);
    a.supersample(r.supersample);
    a.flag("--specular", r.lighting.model.name());
    if !r.scene_lights {
        a.push(["--no-scene-lights"]);
    }
    if !r.default_lights {
        a.unsaid.push("no default lights for a scene without lights".into());
    }
    // Point lights are typed relative to the middle of the display volume.
    let (lo, hi) = display_volume(&info.geometry);
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), info.geometry.emitter_z_m];
    for (i, light) in r.lighting.lights.iter().enumerate() {
        let (spec, exact) = light_spec(light, centre);
        if !exact {
            a.unsaid.push(format!("light {i} exactly ({spec} is near it)"));
        }
        a.flag("--light", spec);
    }
    let p = &s.placement;
    match &p.matrix {
        Some(m) => a.flag("--matrix", m.iter().flatten().map(f64::to_string).collect::<Vec<_>>().join(",")),
        None => {
            if p.rotate_deg != [0.0; 3] {
                a.flag("--rotate", p.rotate_deg.map(|x| x.to_string()).join(","));
            }
            if let Some(scale) = p.scale {
                a.millimetres("--scale", &[scale]);
            }
            if p.translate_m != [0.0; 3] {
                a.millimetres("--translate", &p.translate_m);
            }
        }
    }
    if r.engine == Engine::Reference {
        a.push(["--reference"]);
    }
    if let Some(deg) = s.smooth_normals_deg {
        a.flag("--smooth-normals", deg);
    }
}

/// A `--light` spec for `light` and whether it gives exactly that light
/// back (its name aside): its own name when that is such a spec (as for
/// every light given on the command line), else one made from its values.
fn light_spec(light: &Light, centre: [f64; 3]) -> (String, bool) {
    let gives = |spec: &str| parse_light(spec, centre).is_ok_and(|l| same_but_name(&l, light));
    if let Light::Point { name, .. } | Light::Directional { name, .. } = light {
        if gives(name) {
            return (name.clone(), true);
        }
    }
    let list = |v: &[f64]| v.iter().map(f64::to_string).collect::<Vec<_>>().join(",");
    // Brightness is stored as `f32`: its shortest decimal, read back as a
    // double and narrowed, is the same `f32`.
    let brightness = |v: &[f32; 3]| v.map(|x| x.to_string()).join(",");
    let spec = match light {
        Light::Directional { direction, irradiance, .. } => {
            format!("dir:{}:{}", list(direction), brightness(irradiance))
        }
        Light::Point { position, intensity, .. } => {
            // The spec gives the irradiance at the centre; the light keeps
            // the intensity, irradiance times distance squared.
            let d2: f64 = (0..3).map(|k| (position[k] - centre[k]).powi(2)).sum();
            let mm = position.map(|m| millimetres(m).unwrap_or_else(|| (m * 1e3).to_string()));
            format!("point:{}:{}", mm.join(","), list(&intensity.map(|i| f64::from(i) / d2)))
        }
        Light::Ambient { radiance } => format!("ambient:{}", brightness(radiance)),
    };
    let exact = gives(&spec);
    (spec, exact)
}

fn same_but_name(a: &Light, b: &Light) -> bool {
    match (a, b) {
        (
            Light::Directional { direction: d, irradiance: e, .. },
            Light::Directional { direction: d2, irradiance: e2, .. },
        ) => d == d2 && e == e2,
        (Light::Point { position: p, intensity: i, .. }, Light::Point { position: p2, intensity: i2, .. }) => {
            p == p2 && i == i2
        }
        (Light::Ambient { radiance: r }, Light::Ambient { radiance: r2 }) => r == r2,
        _ => false,
    }
}

fn cameras(a: &mut Line, o: &CameraConvertOptions) {
    let (r, open) = (&o.resample, &o.open);
    let p = &r.placement;
    a.flag("--blend", r.blend.name());
    // One set of flags gives the capture's hints to every reader and the
    // focus to the placement as well.
    let hints = &open.folder.camera;
    if let Some(f) = p.focus.or(hints.focus_distance) {
        a.flag("--focus", f);
    }
    if let Some(scale) = p.scale {
        a.millimetres("--scale", &[scale]);
    }
    if let Some(c) = p.centre {
        a.flag("--center", c.map(|x| x.to_string()).join(","));
    }
    a.flag("--framing", p.framing.name());
    a.flag("--parallax", p.parallax.name());
    if !r.use_depth {
        a.push(["--no-depth"]);
    }
    if let Some(taps) = r.emitter_taps {
        a.flag("--taps", taps);
    }
    if let Some(b) = open.folder.baseline {
        a.flag("--baseline", b);
    }
    if let Some(f) = hints.focal_length_px {
        a.flag("--focal-px", f);
    }
    if let Some(f) = hints.horizontal_fov_deg {
        a.flag("--fov", f);
    }
    a.flag("--view-cone", open.quilt.view_cone_deg);
    a.flag("--quilt-fov", open.quilt.vertical_fov_deg);
    if r.reference {
        a.push(["--reference"]);
    }
    let defaults = OpenOptions::default();
    if open.stanford.camera != *hints || hints.focus_distance != p.focus {
        a.unsaid.push("different focus or camera hints for each kind of capture".into());
    }
    if open.folder.metres_per_unit != defaults.folder.metres_per_unit
        || open.stanford.metres_per_unit != defaults.stanford.metres_per_unit
    {
        a.unsaid.push("metres per capture unit".into());
    }
}

fn holoflick(a: &mut Line, o: &HoloFlickConvertOptions) {
    a.frames(&o.frames);
    a.supersample(o.render.supersample);
    if o.fit {
        a.push(["--fit"]);
    }
    if let Some(m) = &o.matrix {
        a.flag("--matrix", m.iter().flatten().map(f64::to_string).collect::<Vec<_>>().join(","));
    }
    if o.render.engine == Engine::Reference {
        a.unsaid.push("the reference engine".into());
    }
    if o.render != (RenderOptions { supersample: o.render.supersample, engine: o.render.engine, ..Default::default() })
    {
        a.unsaid.push("render options other than supersampling".into());
    }
}

/// Make a conversion again as a .holo file records it: the same converter,
/// options and display, from the same input (its SHA-256 checked).
#[derive(Args)]
pub struct LikeArgs {
    /// The .holo file whose conversion is made again.
    #[arg(value_name = "FILE")]
    like: PathBuf,
    /// The input, when it is not the file named in the record in the current folder.
    #[arg(long)]
    input: Option<PathBuf>,
    /// Output .holo file.
    #[arg(short, long)]
    output: PathBuf,
    /// Replace an existing output file.
    #[arg(long)]
    force: bool,
}

pub fn like(a: LikeArgs) -> Outcome {
    let file = holo::HoloFile::open(&a.like)?;
    let info = file.info();
    let Some(recorded) = info.conversion()? else {
        return Err(Failure(format!(
            "{}: the file does not record the conversion that made it (holo.convert.*)",
            a.like.display()
        )));
    };
    let input = a.input.clone().unwrap_or_else(|| PathBuf::from(&recorded.input));
    if !input.exists() {
        return Err(Failure(format!(
            "{}: no such file or folder; {} was made from {}: give where it is with --input",
            input.display(),
            a.like.display(),
            recorded.input
        )));
    }
    let _claim = check_output(&a.output, &[&input, &a.like], a.force)?;
    if let Some(recorded_digest) = &recorded.input_sha256 {
        let now = Conversion::of_input(&input, recorded.options.clone())?;
        if now.input_sha256.as_ref() != Some(recorded_digest) {
            warn(format_args!(
                "{}: not the input {} was made from (its SHA-256 differs): the result will differ",
                input.display(),
                a.like.display()
            ));
        }
    }
    let g = &info.geometry;
    let (out, progress, started) = (a.output.as_path(), Reporter::on_stderr(), Instant::now());
    let written = match recorded.options.clone() {
        ConverterOptions::Mesh(mut o) => {
            o.write.overwrite = a.force;
            convert_mesh(&input, g, out, &o, &progress)?.written
        }
        ConverterOptions::Cameras(mut o) => {
            o.write.overwrite = a.force;
            convert_camera_files(&input, g, out, &o, &progress)?.written
        }
        ConverterOptions::HoloFlick(mut o) => {
            o.write.overwrite = a.force;
            convert_holoflick(&input, g, out, &o, &progress)?.written
        }
    };
    say!(
        "converted {} again as {} records it, into {} in {:.2} s",
        input.display(),
        a.like.display(),
        written.path.display(),
        started.elapsed().as_secs_f64()
    );
    // As `holo info A B` judges it (a full-parallax frame has a digest per view).
    let same =
        holo::report::same_content(&holo::report::info(&a.like, false)?, &holo::report::info(&written.path, false)?);
    say!("same content as {}: {}", a.like.display(), if same { "yes" } else { "no" });
    Ok(ExitCode::SUCCESS)
}
