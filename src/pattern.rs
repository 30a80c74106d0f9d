//! Display-engineering test patterns: the inputs people calibrate a display
//! with, and inputs with known answers for every later stage.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::format::{WriteOptions, WriteReport};
use crate::geometry::Geometry;
use crate::modulation::{Band, Modulation};
use crate::pipeline::{HoloSink, Run, Source, Warnings};
use crate::progress::Progress;

/// Which pattern.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatternKind {
    /// One emitter (column) lit in every view on every hololine.
    SingleEmitter,
    /// One view lit for every emitter.
    SingleView,
    /// Every n-th emitter lit in every view (a comb: emitter pitch, focus).
    EveryNthEmitter,
    /// Brightness rising linearly from view 0 (dark) to the last view (full).
    ViewRamp,
    /// Full parallax: brightness rising linearly from the lowest vertical
    /// view (dark) to the highest (full).
    VerticalViewRamp,
    /// Eight vertical bars: white, yellow, cyan, green, magenta, red, blue,
    /// black (grey levels for one channel), the same in every view.
    ColourBars,
    /// Squares of `cell` hololines × `cell` emitters alternating dark and full.
    Checkerboard,
}

impl PatternKind {
    /// Every kind with its command-line name.
    pub const ALL: [(PatternKind, &'static str); 7] = [
        (PatternKind::SingleEmitter, "single-emitter"),
        (PatternKind::SingleView, "single-view"),
        (PatternKind::EveryNthEmitter, "every-nth-emitter"),
        (PatternKind::ViewRamp, "view-ramp"),
        (PatternKind::VerticalViewRamp, "vertical-view-ramp"),
        (PatternKind::ColourBars, "colour-bars"),
        (PatternKind::Checkerboard, "checkerboard"),
    ];

    /// Parse a command-line name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(k, _)| *k)
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(k, _)| *k == self).map(|(_, n)| *n).unwrap_or("?")
    }
}

/// A pattern and its parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Pattern {
    /// Which pattern.
    pub kind: PatternKind,
    /// Emitter of `single-emitter` (default: the centre one).
    pub emitter: Option<usize>,
    /// View of `single-view` (default: the centre one).
    pub view: Option<usize>,
    /// Full parallax: vertical view of `single-view` (default: the centre one).
    pub vertical_view: Option<usize>,
    /// Spacing of `every-nth-emitter` (default 8).
    pub every: usize,
    /// Cell size of `checkerboard` in hololines and emitters (default 8).
    pub cell: usize,
    /// Value of a fully lit sample (linear radiance, default 1).
    pub level: f32,
}

impl Pattern {
    /// A pattern with default parameters.
    pub fn new(kind: PatternKind) -> Self {
        Pattern { kind, emitter: None, view: None, vertical_view: None, every: 8, cell: 8, level: 1.0 }
    }

    /// One-line description for provenance (`holo.source`); a vertical
    /// view is said only when one is given, so horizontal-parallax patterns
    /// say what they always said.
    pub fn describe(&self) -> String {
        let vertical = self.vertical_view.map(|k| format!(" vertical_view={k}")).unwrap_or_default();
        format!(
            "holo pattern kind={} emitter={:?} view={:?}{vertical} every={} cell={} level={}",
            self.kind.name(),
            self.emitter,
            self.view,
            self.every,
            self.cell,
            self.level
        )
    }

    /// Render the pattern for a geometry.
    pub fn render(&self, geometry: &Geometry) -> Result<Modulation> {
        let g = geometry;
        let level = self.level;
        if !(level.is_finite() && level >= 0.0) {
            return Err(Error::argument(
                "pattern level",
                format!("pattern level {level} must be finite and not negative"),
            ));
        }
        let pick = |what: &str, i: Option<usize>, n: usize| -> Result<usize> {
            let i = i.unwrap_or(n / 2);
            if i < n {
                Ok(i)
            } else {
                Err(Error::argument("pattern", format!("{what} {i} is out of range: the layout has {n}")))
            }
        };
        let emitter = pick("emitter", self.emitter, g.emitters)?;
        let view = pick("view", self.view, g.views.count)?;
        let full_parallax_only = match self.kind {
            PatternKind::VerticalViewRamp => Some("the vertical-view-ramp pattern"),
            _ => self.vertical_view.map(|_| "a vertical view"),
        };
        if let (Some(what), None) = (full_parallax_only, &g.vertical_views) {
            return Err(Error::argument(
                "pattern",
                format!("{what} needs a full-parallax layout: this one has horizontal parallax only"),
            ));
        }
        let vertical_view = pick("vertical view", self.vertical_view, g.vertical_view_count())?;
        let vertical_views = g.vertical_view_count();
        if self.every == 0 || self.cell == 0 {
            return Err(Error::argument("pattern", "the emitter spacing and checker cell must each be at least 1"));
        }
        let views = g.views.count;
        let names: Vec<String> = g.channels.iter().map(|c| c.name.clone()).collect();
        // Bars: white, yellow, cyan, green, magenta, red, blue, black as (R, G, B).
        const BARS: [[f32; 3]; 8] = [
            [1., 1., 1.],
            [1., 1., 0.],
            [0., 1., 1.],
            [0., 1., 0.],
            [1., 0., 1.],
            [1., 0., 0.],
            [0., 0., 1.],
            [0., 0., 0.],
        ];
        Modulation::from_fn(g.clone(), |c, j, e, index| {
            // Horizontal and vertical view (the vertical one 0 for horizontal parallax).
            let (v, k) = g.view_of_index(index);
            let lit = match self.kind {
                PatternKind::SingleEmitter => f32::from(e == emitter),
                PatternKind::SingleView => f32::from(v == view && k == vertical_view),
                PatternKind::EveryNthEmitter => f32::from(e % self.every == 0),
                PatternKind::ViewRamp => {
                    if views > 1 {
                        v as f32 / (views - 1) as f32
                    } else {
                        1.0
                    }
                }
                PatternKind::VerticalViewRamp => {
                    if vertical_views > 1 {
                        k as f32 / (vertical_views - 1) as f32
                    } else {
                        1.0
                    }
                }
                PatternKind::ColourBars => {
                    let bar = BARS[(e * 8 / g.emitters).min(7)];
                    match names[c].as_str() {
                        "R" => bar[0],
                        "G" => bar[1],
                        "B" => bar[2],
                        // Rec. 709 luminance of the bar.
                        _ => 0.2126 * bar[0] + 0.7152 * bar[1] + 0.0722 * bar[2],
                    }
                }
                PatternKind::Checkerboard => f32::from((j / self.cell + e / self.cell) % 2 == 0),
            };
            lit * level
        })
    }
}

/// A test pattern as a [`Source`] of one `.holo` frame.
#[derive(Clone, Debug)]
pub struct PatternSource<'a> {
    pattern: &'a Pattern,
}

impl<'a> PatternSource<'a> {
    /// The frame `pattern` draws.
    pub fn new(pattern: &'a Pattern) -> Self {
        PatternSource { pattern }
    }
}

impl Source for PatternSource<'_> {
    type Frame = Band;

    fn name(&self) -> String {
        self.pattern.describe()
    }

    fn inputs(&self) -> Vec<PathBuf> {
        Vec::new()
    }

    fn frame_count(&self) -> usize {
        1
    }

    fn provenance(&self) -> String {
        self.pattern.describe()
    }

    fn render(&mut self, _number: usize, frame: &mut Band, _: &dyn Progress, _: &mut Warnings) -> Result<()> {
        let drawn = self.pattern.render(frame.geometry())?;
        frame.samples_mut().copy_from_slice(drawn.samples());
        Ok(())
    }
}

/// Write `pattern` for `geometry` into the `.holo` file `output`
/// (`holo pattern`).
pub fn write_pattern(
    pattern: &Pattern,
    geometry: &Geometry,
    output: &Path,
    options: WriteOptions,
    progress: &dyn Progress,
) -> Result<Run<WriteReport>> {
    crate::pipeline::run(&mut PatternSource::new(pattern), HoloSink::new(output, geometry, options), None, progress)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::mark3;

    #[test]
    fn patterns_light_what_they_say() {
        let g = mark3().geometry;
        let m = Pattern { emitter: Some(17), ..Pattern::new(PatternKind::SingleEmitter) }.render(&g).unwrap();
        assert_eq!(m.get(0, 5, 17, 3), 1.0);
        assert_eq!(m.get(0, 5, 18, 3), 0.0);
        let m = Pattern::new(PatternKind::ViewRamp).render(&g).unwrap();
        assert_eq!(m.get(0, 0, 0, 95), 1.0);
        assert_eq!(m.get(0, 0, 0, 0), 0.0);
        let m = Pattern::new(PatternKind::Checkerboard).render(&g).unwrap();
        assert_eq!((m.get(0, 0, 0, 0), m.get(0, 8, 0, 0), m.get(0, 8, 8, 0)), (1.0, 0.0, 1.0));
        let bad = Pattern { view: Some(96), ..Pattern::new(PatternKind::SingleView) }.render(&g);
        assert!(bad.is_err());
    }
}
