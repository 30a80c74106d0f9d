//! `holo check` and `holo view` on files: a `.holo` frame assembled in
//! memory as the display would receive it (8-bit, the layout's
//! quantization), or fringes already written by `holo assemble`.

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::check::{check, view, CheckReport, FrameRef};
use super::picture::Picture;
use super::viewer::Eye;
use crate::assemble::output::{read_frame_images, read_sidecar, StoredImages, FRINGE_SIDECAR};
use crate::assemble::Assembler;
use crate::error::{Error, Result};
use crate::format::HoloFile;
use crate::layout::Layout;
use crate::progress::Progress;

/// A frame's fringes: assembled from a `.holo` frame, or read from a
/// directory `holo assemble` wrote.
struct Fringes {
    assembler: Assembler,
    images: StoredImages,
    /// The source frame's digest, when known.
    digest: Option<String>,
}

impl Fringes {
    fn frame(&self) -> FrameRef<'_> {
        match &self.images {
            StoredImages::Bytes(i) => FrameRef::Bytes(i),
            StoredImages::Floats(i) => FrameRef::Floats(i),
        }
    }
}

/// Whether `path` is a directory of fringes: it holds `holo-fringes.json`,
/// or held a set whose replacement was interrupted (which its reader then
/// says).
pub fn is_fringe_dir(path: &Path) -> bool {
    path.join(FRINGE_SIDECAR).is_file() || crate::output::check_set_complete(path, FRINGE_SIDECAR, "").is_err()
}

/// Frame `frame` (its index in the source file) of the fringes in `dir`; the
/// layout, if given, must be the one they were assembled for.
fn read_fringes(dir: &Path, layout: Option<&Layout>, frame: usize) -> Result<Fringes> {
    let sidecar = read_sidecar(dir)?;
    if let Some(l) = layout {
        if *l != sidecar.layout {
            return Err(Error::argument(
                "layout",
                format!(
                    "{}: the fringes were assembled for layout {}, not {}",
                    dir.display(),
                    sidecar.layout.name,
                    l.name
                ),
            ));
        }
    }
    let Some(position) = sidecar.frames.iter().position(|f| f.index == frame) else {
        let have: Vec<String> = sidecar.frames.iter().map(|f| f.index.to_string()).collect();
        return Err(Error::argument(
            "frame",
            format!(
                "{}: holds frame(s) {} of {}; frame {frame} asked for",
                dir.display(),
                have.join(", "),
                sidecar.source
            ),
        ));
    };
    let images = read_frame_images(dir, &sidecar, position)?;
    Ok(Fringes {
        assembler: Assembler::new(&sidecar.layout)?,
        images,
        digest: sidecar.frames[position].source_digest.clone(),
    })
}

/// Frame `frame` of a `.holo` file assembled in memory for `layout`, 8-bit.
fn assemble_frame(
    file: &HoloFile,
    path: &Path,
    layout: &Layout,
    frame: usize,
) -> Result<(Fringes, crate::modulation::Modulation)> {
    let frames = file.info().frames.len();
    if frame >= frames {
        return Err(Error::no_frame(path, frame, frames));
    }
    let m = file.read_frame(frame)?;
    let assembler = Assembler::new(layout)?;
    let (images, _) = assembler.assemble::<u8>(&m).map_err(|e| with_path(e, path, frame))?;
    let digest = file.info().frames[frame].digest.clone();
    Ok((Fringes { assembler, images: StoredImages::Bytes(images), digest }, m))
}

fn with_path(e: Error, path: &Path, frame: usize) -> Error {
    match e.in_frame_of(path, frame) {
        e @ Error::Argument { .. } => e.naming(path),
        other => other,
    }
}

/// What `holo check` was asked.
#[derive(Clone, Debug, Default)]
pub struct CheckOptions {
    /// Frame index in the `.holo` file.
    pub frame: usize,
    /// Check the fringes in this directory instead of assembling them.
    pub fringes: Option<PathBuf>,
    /// Hololines to check (all when `None`).
    pub hololines: Option<std::ops::Range<usize>>,
}

/// `holo check`'s result: what was checked, and the report.
#[derive(Clone, Debug, Serialize)]
pub struct FileCheck {
    /// The `.holo` file.
    pub file: PathBuf,
    /// Its frame.
    pub frame: usize,
    /// Where the fringes came from: `assembled in memory` or a directory.
    pub fringes: String,
    /// The errors.
    #[serde(flatten)]
    pub report: CheckReport,
}

/// Recover frame `options.frame` of `holo_path` from its fringes (assembled
/// for `layout`, or read from `options.fringes`, whose sidecar names the
/// layout) and compare it with the stored modulation; `progress` counts the
/// hololines checked.
pub fn check_file(
    holo_path: &Path,
    layout: Option<&Layout>,
    options: &CheckOptions,
    progress: &dyn Progress,
) -> Result<FileCheck> {
    let file = HoloFile::open(holo_path)?;
    let (fringes, m, source) = match &options.fringes {
        Some(dir) => {
            let fringes = read_fringes(dir, layout, options.frame)?;
            let frames = file.info().frames.len();
            if options.frame >= frames {
                return Err(Error::no_frame(holo_path, options.frame, frames));
            }
            let m = file.read_frame(options.frame)?;
            if let (Some(a), Some(b)) = (&fringes.digest, &file.info().frames[options.frame].digest) {
                if a != b {
                    return Err(Error::argument(
                        "fringes",
                        format!(
                            "{}: its frame {} is not the one the fringes in {} were assembled from ({a}, not {b})",
                            holo_path.display(),
                            options.frame,
                            dir.display()
                        ),
                    ));
                }
            }
            (fringes, m, dir.display().to_string())
        }
        None => {
            let layout = layout.ok_or_else(|| Error::argument("layout", "checking a .holo file needs a layout"))?;
            let (fringes, m) = assemble_frame(&file, holo_path, layout, options.frame)?;
            (fringes, m, "assembled in memory (8-bit)".into())
        }
    };
    fringes.assembler.check_geometry(&m).map_err(|e| with_path(e, holo_path, options.frame))?;
    let hololines = options.hololines.clone().unwrap_or(0..m.geometry().hololines);
    let report = check(&fringes.assembler, &m, fringes.frame(), hololines, progress)?;
    Ok(FileCheck { file: holo_path.to_path_buf(), frame: options.frame, fringes: source, report })
}

/// Where a viewer is: horizontal position and height on the viewer's side,
/// distance (the layout's viewer distance when `None`) and pupil.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeAt {
    /// Horizontal position, metres.
    pub x_m: f64,
    /// Height, metres.
    pub y_m: f64,
    /// Distance from the hologram plane, metres.
    pub distance_m: Option<f64>,
    /// Pupil diameter, metres.
    pub pupil_m: f64,
    /// Whether the eye adds neighbouring emitters' light as amplitudes
    /// (spec/layouts.md §9.2), not as powers.
    pub coherent: bool,
}

/// The pictures viewers at `eyes` see of frame `frame` of `input`: a `.holo`
/// file (assembled in memory for `layout`) or a directory of fringes;
/// `progress` counts the hololines.
pub fn view_file(
    input: &Path,
    layout: Option<&Layout>,
    frame: usize,
    eyes: &[EyeAt],
    progress: &dyn Progress,
) -> Result<Vec<Picture>> {
    let fringes = if is_fringe_dir(input) {
        read_fringes(input, layout, frame)?
    } else if input.is_dir() {
        return Err(Error::argument(
            "input",
            format!(
                "{}: a directory without {FRINGE_SIDECAR}: give a .holo file or a directory `holo assemble` wrote",
                input.display()
            ),
        ));
    } else {
        let layout = layout.ok_or_else(|| Error::argument("layout", "viewing a .holo file needs a layout"))?;
        assemble_frame(&HoloFile::open(input)?, input, layout, frame)?.0
    };
    let g = &fringes.assembler.layout().geometry;
    let eyes: Vec<Eye> = eyes
        .iter()
        .map(|e| Eye {
            x_m: e.x_m,
            y_m: e.y_m,
            z_m: e.distance_m.unwrap_or(g.viewer_distance_m),
            pupil_m: e.pupil_m,
            coherent: e.coherent,
        })
        .collect();
    view(&fringes.assembler, fringes.frame(), &eyes, progress)
}

impl fmt::Display for FileCheck {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.report;
        writeln!(
            f,
            "{} frame {} on layout {}, hololines {}..{}, fringes {}",
            self.file.display(),
            self.frame,
            r.layout,
            r.hololines.start,
            r.hololines.end,
            self.fringes
        )?;
        let v = &r.verdict;
        let smooth =
            v.bounds.optical_smooth.map(|b| format!("; content smooth across views keeps within {}", percent(b)));
        for (what, e, pass, bound, note) in [
            (
                format!("signal recovery (least squares, {} iterations at most)", r.iterations),
                &r.signal,
                v.signal,
                v.bounds.signal,
                None,
            ),
            (
                "optical recovery (each view's light at the emitter plane)".to_string(),
                &r.optical,
                v.optical,
                v.bounds.optical,
                smooth,
            ),
        ] {
            writeln!(f, "  {what}")?;
            writeln!(
                f,
                "    relative L2 {:.3e}   PSNR {:.1} dB (peak {:.3})   worst emitter: {} hololine {} emitter {}, RMS error {:.3} of the modulation's RMS",
                e.relative_l2, e.psnr_db, e.peak, e.worst.channel, e.worst.hololine, e.worst.emitter, e.worst.relative_rms
            )?;
            match (pass, bound) {
                (Some(pass), Some(bound)) => writeln!(
                    f,
                    "    {}: {} {} the bound {}{}",
                    if pass { "pass" } else { "FAIL" },
                    percent(e.relative_l2),
                    if pass { "is below" } else { "is not below" },
                    percent(bound),
                    note.unwrap_or_default()
                )?,
                _ => writeln!(f, "    no bound stated")?,
            }
        }
        let whose = match v.bounds.stated_for {
            Some(name) => format!("the bounds of spec/layouts.md §9.1 for {name}, 8-bit fringes"),
            None if v.bounds.signal.is_some() => "the bound of spec/layouts.md §9.1 for float fringes".to_string(),
            None => format!(
                "spec/layouts.md §9.1 states bounds for mark3 and mark1 (8-bit fringes) and for float fringes, not for \
                 layout {}: figures only",
                r.layout
            ),
        };
        match v.pass {
            Some(true) => writeln!(f, "  verdict: pass ({whose})"),
            Some(false) => writeln!(f, "  verdict: FAIL ({whose})"),
            None => writeln!(f, "  verdict: none ({whose})"),
        }
    }
}

/// A relative error as a percentage, with the digits it needs.
fn percent(x: f64) -> String {
    let p = 100.0 * x;
    if p >= 1.0 {
        format!("{p:.1}%")
    } else {
        format!("{p:.2e}%")
    }
}
