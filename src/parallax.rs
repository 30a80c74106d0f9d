//! Between full and horizontal parallax (`holo resample`): a `.holo` file's
//! frames made again with the other kind of parallax, read and written band
//! by band of emitter rows.
//!
//! Full → horizontal keeps what a viewer on the viewer line sees: each row's
//! views in the vertical direction toward the viewer line
//! ([`crate::modulation::full_to_horizontal`]). Horizontal → full cannot make
//! up vertical parallax the file does not hold: every vertical view of an
//! emitter is a copy of its horizontal-parallax views, and the run says so.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::format::{HoloFile, Region, WriteOptions, WriteReport};
use crate::geometry::{Geometry, Parallax};
use crate::modulation::{full_to_horizontal, rows_beyond_vertical_views, Band};
use crate::pipeline::{HoloSink, Run, Source, Warnings};
use crate::progress::Progress;

/// The geometry a horizontal-parallax file gets when made full parallax
/// with `vertical` views, or a full-parallax one made horizontal (`None`).
pub fn resampled_geometry(g: &Geometry, vertical: Option<crate::geometry::Views>) -> Result<Geometry> {
    match (vertical, &g.vertical_views) {
        (None, Some(_)) => Ok(Geometry { parallax: Parallax::Horizontal, vertical_views: None, ..g.clone() }),
        (Some(views), None) => Ok(g.clone().with_vertical_views(views)),
        (None, None) => Err(Error::argument("parallax", "the file has horizontal parallax already")),
        (Some(_), Some(old)) => Err(Error::argument(
            "parallax",
            format!("the file is full parallax already ({} vertical views)", old.count),
        )),
    }
}

/// The frames of a `.holo` file with the other parallax, as a [`Source`].
pub struct ParallaxSource {
    path: PathBuf,
    file: HoloFile,
    target: Geometry,
}

impl ParallaxSource {
    /// The frames of `path` resampled to `target` (from
    /// [`resampled_geometry`]; the emitter grid, views and colours must be
    /// the file's).
    pub fn open(path: &Path, target: Geometry) -> Result<ParallaxSource> {
        let file = HoloFile::open(path)?;
        let g = file.geometry();
        let same_grid = Geometry { parallax: g.parallax, vertical_views: g.vertical_views.clone(), ..target.clone() };
        if same_grid != *g || target.vertical_views.is_some() == g.vertical_views.is_some() {
            return Err(Error::argument(
                "geometry",
                format!("{}: the target geometry is not this file's with the other parallax", path.display()),
            ));
        }
        Ok(ParallaxSource { path: path.to_path_buf(), file, target })
    }
}

impl Source for ParallaxSource {
    type Frame = Band;

    fn inputs(&self) -> Vec<PathBuf> {
        vec![self.path.clone()]
    }

    fn frame_count(&self) -> usize {
        self.file.info().frames.len()
    }

    fn frames_per_second(&self) -> Option<(u32, u32)> {
        self.file.info().frames_per_second.and_then(|(n, d)| u32::try_from(n).ok().map(|n| (n, d)))
    }

    fn place(&mut self, _frames: &std::ops::Range<usize>, warnings: &mut Warnings) -> Result<()> {
        match &self.target.vertical_views {
            Some(vertical) => warnings.add(format!(
                "{}: horizontal parallax holds no vertical parallax: each emitter's {} vertical views are copies of its views",
                self.path.display(),
                vertical.count
            )),
            None => {
                let beyond = rows_beyond_vertical_views(self.file.geometry());
                if let (Some(first), Some(last)) = (beyond.first(), beyond.last()) {
                    warnings.add(format!(
                        "{}: {} emitter rows ({first} to {last}) have no vertical view toward the viewer line: they are black",
                        self.path.display(),
                        beyond.len()
                    ));
                }
            }
        }
        Ok(())
    }

    fn provenance(&self) -> String {
        let to = if self.target.vertical_views.is_some() { "full" } else { "horizontal" };
        format!("holo resample {} to {to} parallax", self.path.display())
    }

    fn band_hololines(&self) -> Option<usize> {
        Some(crate::views::band_rows(self.file.geometry()).min(crate::views::band_rows(&self.target)))
    }

    fn render(&mut self, number: usize, band: &mut Band, _: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let g = self.file.geometry();
        let rows = band.hololines();
        let region = Region {
            hololines: rows.clone(),
            emitters: 0..g.emitters,
            views: 0..g.views.count,
            vertical_views: 0..g.vertical_view_count(),
        };
        let read = self.file.read_region(number, &region)?;
        match &self.target.vertical_views {
            None => band.samples_mut().copy_from_slice(full_to_horizontal(&read)?.samples()),
            Some(vertical) => {
                // Each emitter's run of V views, copied into each of its W vertical views.
                let v = g.views.count;
                let out = band.samples_mut().chunks_exact_mut(v * vertical.count);
                for (to, from) in out.zip(read.samples().chunks_exact(v)) {
                    to.chunks_exact_mut(v).for_each(|w| w.copy_from_slice(from));
                }
            }
        }
        Ok(())
    }
}

/// Write the frames of `input` with the other parallax into `output`
/// (`holo resample`): `vertical` views make a horizontal-parallax file full
/// parallax, `None` makes a full-parallax one horizontal.
pub fn resample_parallax(
    input: &Path,
    vertical: Option<crate::geometry::Views>,
    output: &Path,
    options: WriteOptions,
    progress: &dyn Progress,
) -> Result<Run<WriteReport>> {
    let file = HoloFile::open(input)?;
    let target = resampled_geometry(file.geometry(), vertical).map_err(|e| e.naming(input))?;
    drop(file);
    let mut source = ParallaxSource::open(input, target.clone())?;
    crate::pipeline::run(&mut source, HoloSink::new(output, &target, options), None, progress)
}
