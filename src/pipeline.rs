//! One path for everything that makes frames: `convert mesh`, `convert
//! cameras`, `convert holoflick`, `pattern`, `import-views` (frames of a
//! `.holo` file) and `holoflick encode` / `pack` (frames of a HoloFlick).
//!
//! A [`Source`] says what it can make (how many frames, from which files,
//! with what provenance), decides once where its content goes
//! ([`Source::place`]) and renders one frame at a time into a buffer the
//! output hands it ([`Source::render`]). A [`Sink`] is where the frames go
//! (a `.holo` file, [`HoloSink`]; a HoloFlick, `holoflick::HoloFlickSink`)
//! and owns how they are written. [`run`] joins them and owns, once, what
//! every command used to repeat:
//!
//! - the checks that can fail before any work: an existing output without
//!   permission to replace it, a missing output folder, an output that is one
//!   of the inputs (by path or by device and inode, even when replacing is
//!   allowed);
//! - the frame range: all of the source's frames by default; a range asked
//!   for must be non-empty and inside them;
//! - provenance (what the frames were made from, in words and as the exact
//!   conversion record, written into the output unless the caller gave its
//!   own), the first frame's number and the frame rate of a movie;
//! - warnings, each said once with how often it came up ([`Warnings`]);
//! - progress (a movie counts frames; a single frame reports the source's own
//!   phases) and cancellation ([`Progress::cancelled`], checked before every
//!   frame and band; the output is then not written and nothing is left
//!   behind).
//!
//! A new kind of input is a new `Source`, not a new command body.

use std::borrow::Cow;
use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::format::{write_frame_in_bands, write_frames, ConversionRecord, WriteOptions, WriteReport};
use crate::geometry::Geometry;
use crate::math::Mat4;
use crate::modulation::Band;
use crate::progress::{Progress, Steps, Timings};

/// Something frames are made from.
pub trait Source {
    /// The buffer a frame is rendered into: a [`Band`] of a `.holo` frame
    /// (the whole frame unless [`Source::band_hololines`] asks for bands),
    /// or a HoloFlick frame.
    type Frame;

    /// The files the frames are read from: the output may be none of them.
    fn inputs(&self) -> Vec<PathBuf>;

    /// The input as a user names it, for messages: its files by default.
    fn name(&self) -> String {
        self.inputs().iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(" ")
    }

    /// How many frames there are: frame numbers run `0..frame_count()`.
    fn frame_count(&self) -> usize;

    /// The frame rate as a fraction (numerator, denominator), when the
    /// frames are a movie with one.
    fn frames_per_second(&self) -> Option<(u32, u32)> {
        None
    }

    /// Decide, once and before any frame is rendered, where the content
    /// goes; `frames` are the frames that will be rendered (placement is
    /// usually decided on the first).
    fn place(&mut self, frames: &Range<usize>, warnings: &mut Warnings) -> Result<()> {
        let _ = (frames, warnings);
        Ok(())
    }

    /// What the frames are made from and how, in a line (written into the
    /// output as its provenance; called after [`Source::place`]).
    fn provenance(&self) -> String;

    /// The transform from the input's coordinates to display metres
    /// (row-major, points as columns) that [`Source::place`] chose, written
    /// exactly as `holo.placement`; `None` when the source places nothing.
    fn placement(&self) -> Option<crate::math::Mat4> {
        None
    }

    /// Which converter made the frames, from which input, with every
    /// option (written as `holo.convert.*`; called after
    /// [`Source::place`]); `None` when the frames are not a conversion.
    fn conversion(&self) -> Result<Option<ConversionRecord>> {
        Ok(None)
    }

    /// Render a single frame a band of this many hololines at a time (memory
    /// is then one band, not the frame); `None` renders whole frames.
    fn band_hololines(&self) -> Option<usize> {
        None
    }

    /// Time spent so far inside [`Source::render`] on stages of its own
    /// (`("decode", …)`: reading and decoding the input), which a run's
    /// [`Timings`] shows apart from the rendering proper.
    fn stage_times(&self) -> Timings {
        Timings::default()
    }

    /// Render frame `number` into `frame` (every sample written), reporting
    /// its own phases to `progress`.
    fn render(
        &mut self,
        number: usize,
        frame: &mut Self::Frame,
        progress: &dyn Progress,
        warnings: &mut Warnings,
    ) -> Result<()>;
}

/// Where frames go and how they are written.
pub trait Sink<F> {
    /// What the writer reports.
    type Written;

    /// The output file.
    fn path(&self) -> &Path;

    /// Whether an existing output may be replaced.
    fn overwrite(&self) -> bool;

    /// The most frames the output holds, and what it is (`a .holo file`),
    /// for the message when more are asked.
    fn max_frames(&self) -> (u64, &'static str) {
        (u64::MAX, "the output")
    }

    /// Write the frames of `job`, asking `render(number, buffer)` for each
    /// (for a banded `.holo` frame: for each band, in order).
    fn write(self, job: &Job, render: &mut dyn FnMut(usize, &mut F) -> Result<()>) -> Result<Self::Written>;
}

/// What [`run`] decided, for the sink.
#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    /// The frames to write, by the source's numbering.
    pub frames: Range<usize>,
    /// The source's provenance.
    pub provenance: String,
    /// The source's placement ([`Source::placement`]).
    pub placement: Option<crate::math::Mat4>,
    /// The source's conversion ([`Source::conversion`]).
    pub conversion: Option<ConversionRecord>,
    /// The source's frame rate.
    pub frames_per_second: Option<(u32, u32)>,
    /// Bands of a single frame (see [`Source::band_hololines`]).
    pub band_hololines: Option<usize>,
}

/// What a run did.
#[derive(Clone, Debug)]
pub struct Run<W> {
    /// The frames written, by the source's numbering.
    pub frames: Range<usize>,
    /// Warnings, each once, with how often it came up.
    pub warnings: Vec<String>,
    /// The sink's report.
    pub written: W,
    /// Where the time went: the source's own stages, `render`, `write`.
    pub timings: Timings,
}

/// Make `frames` (all by default) of `source` and write them to `sink`; see
/// the [module documentation](self) for what a run checks and reports.
pub fn run<S, K>(
    source: &mut S,
    sink: K,
    frames: Option<Range<usize>>,
    progress: &dyn Progress,
) -> Result<Run<K::Written>>
where
    S: Source,
    K: Sink<S::Frame>,
{
    let inputs = source.inputs();
    let read: Vec<&Path> = inputs.iter().map(PathBuf::as_path).collect();
    // Held until the output is in place.
    let _claim = crate::output::check_output(sink.path(), &read, sink.overwrite())?;
    let frames = frame_range(&source.name(), frames, source.frame_count())?;
    let (most, output) = sink.max_frames();
    if frames.len() as u64 > most {
        let rate = match source.frames_per_second() {
            Some((n, d)) => format!(" at {} frames per second", rate_text(f64::from(n) / f64::from(d))),
            None => String::new(),
        };
        return Err(Error::argument(
            "frame rate",
            format!(
                "{}: {} frames{rate} asked for; {output} holds at most {most}: lower the frame rate, or ask for fewer frames",
                source.name(),
                frames.len(),
            ),
        ));
    }
    cancelled(progress)?;
    let mut warnings = Warnings::default();
    let mut timings = Timings::default();
    timings.time("place", || source.place(&frames, &mut warnings))?;
    let job = Job {
        frames: frames.clone(),
        provenance: source.provenance(),
        placement: source.placement(),
        conversion: source.conversion()?,
        frames_per_second: source.frames_per_second(),
        band_hololines: if frames.len() == 1 { source.band_hololines() } else { None },
    };
    // A movie counts its frames; a single frame shows the source's phases.
    let movie = (frames.len() > 1).then(|| Steps::begin(progress, "frames", frames.len()));
    let quiet = Cancellable(progress);
    let inner: &dyn Progress = if movie.is_some() { &quiet } else { progress };
    let mut rendering = std::time::Duration::ZERO;
    let started = std::time::Instant::now();
    let written = sink.write(&job, &mut |number, frame| {
        cancelled(progress)?;
        let t = std::time::Instant::now();
        source.render(number, frame, inner, &mut warnings)?;
        rendering += t.elapsed();
        cancelled(progress)?;
        if let Some(m) = &movie {
            m.step();
        }
        Ok(())
    })?;
    // The sink's time is writing, less the rendering it asked for; the
    // source's own stages are part of its rendering.
    let writing = started.elapsed().saturating_sub(rendering);
    let own = source.stage_times();
    timings.merge(&own);
    let own: std::time::Duration = own.stages().iter().map(|(_, t)| *t).sum();
    timings.add("render", rendering.saturating_sub(own));
    timings.add("write", writing);
    Ok(Run { frames, warnings: warnings.lines(), written, timings })
}

/// The whole-movie decisions a run of `source` over `frames` would make,
/// without making a frame: the frames (all when `None`, checked against the
/// source's count) and the placement, decided on the run's first frame.
/// A farm decides once with this, then hands every chunk the same placement
/// so each frames the scene as one run of the whole movie would.
pub fn decide<S: Source>(source: &mut S, frames: Option<Range<usize>>) -> Result<(Range<usize>, Option<Mat4>)> {
    let frames = frame_range(&source.name(), frames, source.frame_count())?;
    source.place(&frames, &mut Warnings::default())?;
    Ok((frames, source.placement()))
}

/// [`run`] for a source read from the file `input`: the output is refused
/// (exists, folder missing, is the input) before `open` reads the input,
/// which can take a while. Returns the source, with what it counted, and
/// the run.
pub fn open_and_run<S, K>(
    input: &Path,
    open: impl FnOnce(&Path) -> Result<S>,
    sink: K,
    frames: Option<Range<usize>>,
    progress: &dyn Progress,
) -> Result<(S, Run<K::Written>)>
where
    S: Source,
    K: Sink<S::Frame>,
{
    let _claim = crate::output::check_output(sink.path(), &[input], sink.overwrite())?;
    let started = std::time::Instant::now();
    let mut source = open(input)?;
    let opening = started.elapsed();
    let mut run = run(&mut source, sink, frames, progress)?;
    let mut timings = Timings::default();
    timings.add("open", opening);
    timings.merge(&run.timings);
    run.timings = timings;
    Ok((source, run))
}

/// [`open_and_run`] into the `.holo` file `output` for `geometry`, written
/// as `write` says: what every converter of one input file into a `.holo`
/// file does.
pub fn open_and_write<S: Source<Frame = Band>>(
    input: &Path,
    open: impl FnOnce(&Path) -> Result<S>,
    (output, geometry, write): (&Path, &Geometry, &WriteOptions),
    frames: Option<Range<usize>>,
    progress: &dyn Progress,
) -> Result<(S, Run<WriteReport>)> {
    open_and_run(input, open, HoloSink::new(output, geometry, write.clone()), frames, progress)
}

/// The lowest frame rate of a movie, frames per second (one frame in a
/// thousand seconds: rates are written as fractions whose denominators go
/// up to 1000).
pub const MIN_FRAMES_PER_SECOND: f64 = 1e-3;

/// The highest frame rate of a movie, frames per second: far past any
/// display's (holographic video runs at tens of frames a second), short of
/// rates whose frame counts no file holds.
pub const MAX_FRAMES_PER_SECOND: f64 = 1e6;

/// The most frames one source may make: as many as the largest output
/// holds (a HoloFlick, whose container checks that the two agree).
pub const MAX_SOURCE_FRAMES: u64 = 1 << 20;

/// A frame rate as text: plain, or in scientific notation when far from 1.
fn rate_text(frames_per_second: f64) -> String {
    if (1e-3..1e7).contains(&frames_per_second.abs()) {
        format!("{frames_per_second}")
    } else {
        format!("{frames_per_second:e}")
    }
}

/// Refuse a frame rate (frames per second) outside
/// [`MIN_FRAMES_PER_SECOND`] ..= [`MAX_FRAMES_PER_SECOND`]: what every
/// command that samples an animation checks before any work.
pub fn check_frame_rate(frames_per_second: f64) -> Result<()> {
    if (MIN_FRAMES_PER_SECOND..=MAX_FRAMES_PER_SECOND).contains(&frames_per_second) {
        return Ok(());
    }
    Err(Error::argument(
        "frame rate",
        format!(
            "the frame rate must be from {} to {} frames per second, not {}",
            rate_text(MIN_FRAMES_PER_SECOND),
            rate_text(MAX_FRAMES_PER_SECOND),
            rate_text(frames_per_second)
        ),
    ))
}

/// The frames of `name`'s animation of `duration_s` seconds sampled at
/// `frames_per_second` (checked, [`check_frame_rate`]): its first and last
/// pose included, `floor(duration × rate) + 1`, refused past
/// [`MAX_SOURCE_FRAMES`] with a message about the rate, before anything is
/// made for them.
pub fn animation_frames(name: &Path, duration_s: f64, frames_per_second: f64) -> Result<usize> {
    check_frame_rate(frames_per_second)?;
    let count = (duration_s.max(0.0) * frames_per_second).floor() + 1.0;
    if count.is_nan() || count > MAX_SOURCE_FRAMES as f64 {
        return Err(Error::argument(
            "frame rate",
            format!(
                "{}: its animation of {duration_s:.3} s at {} frames per second is {count:.0} frames, more than \
                 the {MAX_SOURCE_FRAMES} a movie may have: lower the frame rate",
                name.display(),
                rate_text(frames_per_second)
            ),
        ));
    }
    Ok(count as usize)
}

/// `asked` (all of `count` frames by default), checked against them.
pub fn frame_range(name: &str, asked: Option<Range<usize>>, count: usize) -> Result<Range<usize>> {
    let frames = asked.unwrap_or(0..count);
    if frames.start >= frames.end || frames.end > count {
        return Err(Error::NoFrame { path: name.into(), asked: frames, frames: count });
    }
    Ok(frames)
}

fn cancelled(progress: &dyn Progress) -> Result<()> {
    if progress.cancelled() {
        Err(Error::Cancelled)
    } else {
        Ok(())
    }
}

/// Reports nothing but passes cancellation on: the source's own phases while
/// a movie counts frames.
struct Cancellable<'a>(&'a dyn Progress);

impl Progress for Cancellable<'_> {
    fn phase(&self, _name: &str, _total: u64) {}
    fn advance(&self, _done: u64) {}
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// Warnings of a run, each kept once with how often it came up: the same
/// zero-area-triangle warning for forty instances of a mesh is one line.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Warnings {
    /// (message, count) in the order first seen.
    seen: Vec<(String, usize)>,
}

impl Warnings {
    /// One more occurrence of `message`.
    pub fn add(&mut self, message: impl Into<String>) {
        let message = message.into();
        match self.seen.iter_mut().find(|(m, _)| *m == message) {
            Some((_, n)) => *n += 1,
            None => self.seen.push((message, 1)),
        }
    }

    /// The warnings of one frame of several: a warning every frame repeats
    /// (a scene's, loaded again for each frame) counts as often as a single
    /// frame has it, not once per frame.
    pub fn merge_frame<'a>(&mut self, messages: impl IntoIterator<Item = &'a String>) {
        let mut frame = Warnings::default();
        for m in messages {
            frame.add(m.as_str());
        }
        for (message, count) in frame.seen {
            match self.seen.iter_mut().find(|(m, _)| *m == message) {
                Some((_, n)) => *n = (*n).max(count),
                None => self.seen.push((message, count)),
            }
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.seen.is_empty()
    }

    /// One line each: the message, and how often it came up when more than once.
    pub fn lines(&self) -> Vec<String> {
        self.seen.iter().map(|(m, n)| if *n > 1 { format!("{m} ({n} times)") } else { m.clone() }).collect()
    }
}

/// A `.holo` file as the output of a run.
#[derive(Clone, Debug)]
pub struct HoloSink<'a> {
    path: &'a Path,
    geometry: &'a Geometry,
    options: WriteOptions,
}

impl<'a> HoloSink<'a> {
    /// Write `path` for `geometry` with `options`: an empty
    /// [`WriteOptions::source`] is filled with the source's provenance (and
    /// absent [`WriteOptions::placement`] and [`WriteOptions::conversion`]
    /// with the source's), a movie without [`WriteOptions::frames_per_second`] gets the source's
    /// rate, and [`WriteOptions::first_frame_number`] is the first frame's.
    pub fn new(path: &'a Path, geometry: &'a Geometry, options: WriteOptions) -> Self {
        HoloSink { path, geometry, options }
    }
}

impl Sink<Band> for HoloSink<'_> {
    type Written = WriteReport;

    fn path(&self) -> &Path {
        self.path
    }

    fn overwrite(&self) -> bool {
        self.options.overwrite
    }

    fn max_frames(&self) -> (u64, &'static str) {
        (crate::format::MAX_FRAMES, "a .holo file")
    }

    fn write(self, job: &Job, render: &mut dyn FnMut(usize, &mut Band) -> Result<()>) -> Result<WriteReport> {
        let (g, mut options) = (self.geometry, self.options);
        if options.source.is_empty() {
            options.source = job.provenance.clone();
        }
        if options.placement.is_none() {
            options.placement = job.placement;
        }
        if options.conversion.is_none() {
            options.conversion = job.conversion.clone();
        }
        if options.frames_per_second.is_none() && job.frames.len() > 1 {
            options.frames_per_second = job.frames_per_second.and_then(|(n, d)| Some((i32::try_from(n).ok()?, d)));
        }
        options.first_frame_number = i32::try_from(job.frames.start).map_err(|_| {
            Error::argument(
                "frame number",
                format!("{}: frame number {} is too large", self.path.display(), job.frames.start),
            )
        })?;
        let start = job.frames.start;
        match job.band_hololines {
            Some(lines) => write_frame_in_bands(self.path, g, lines, &options, |band| render(start, band)),
            None => write_frames(self.path, g, job.frames.len(), &options, |i| {
                let mut frame = Band::zeros(g.clone(), 0..g.hololines)?;
                render(start + i, &mut frame)?;
                Ok(Cow::Owned(frame.into_modulation()?))
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Geometry;
    use crate::progress::Silent;
    use std::sync::atomic::{AtomicBool, Ordering};

    /// Frame `n` is `n + 1` everywhere; frame 2 warns twice.
    struct Count {
        frames: usize,
        rendered: Vec<usize>,
    }

    impl Source for Count {
        type Frame = Band;
        fn name(&self) -> String {
            "count".into()
        }
        fn inputs(&self) -> Vec<PathBuf> {
            Vec::new()
        }
        fn frame_count(&self) -> usize {
            self.frames
        }
        fn frames_per_second(&self) -> Option<(u32, u32)> {
            Some((24, 1))
        }
        fn provenance(&self) -> String {
            "counting".into()
        }
        fn render(&mut self, n: usize, frame: &mut Band, _: &dyn Progress, warnings: &mut Warnings) -> Result<()> {
            frame.samples_mut().fill(n as f32 + 1.0);
            self.rendered.push(n);
            warnings.merge_frame(&vec!["same".to_string(); if n == 2 { 2 } else { 1 }]);
            Ok(())
        }
    }

    /// Run a `Count` of `frames` frames for `asked` into a small `.holo`
    /// file in a new folder: (the folder, the frames rendered, the outcome).
    fn run_count(
        frames: usize,
        asked: Option<Range<usize>>,
        progress: &dyn Progress,
    ) -> (tempfile::TempDir, Vec<usize>, Result<Run<WriteReport>>) {
        use crate::geometry::{mono_channel, Views};
        let g = Geometry::centred(4, 6, Views::tan_spaced(3, -0.2, 0.2), 1.3e-4, 2.4e-4, 0.027, 0.6, mono_channel());
        let dir = tempfile::tempdir().unwrap();
        let mut source = Count { frames, rendered: Vec::new() };
        let path = dir.path().join("count.holo");
        let sink = HoloSink::new(&path, &g, WriteOptions::default());
        let outcome = run(&mut source, sink, asked, progress);
        (dir, source.rendered, outcome)
    }

    #[test]
    fn a_run_writes_the_frames_asked_for_with_provenance_and_counted_warnings() {
        let (dir, rendered, run) = run_count(5, Some(1..4), &Silent);
        let run = run.unwrap();
        assert_eq!(rendered, [1, 2, 3]);
        assert_eq!(run.frames, 1..4);
        assert_eq!(run.warnings, ["same (2 times)"]);
        let file = crate::format::HoloFile::open(dir.path().join("count.holo")).unwrap();
        assert_eq!(file.info().frames.len(), 3);
        assert_eq!(file.info().source.as_deref(), Some("counting"));
        assert_eq!(file.info().frames_per_second, Some((24, 1)));
        assert_eq!(file.read_frame(0).unwrap().get(0, 0, 0, 0), 2.0);
    }

    #[test]
    fn a_range_outside_the_source_is_refused_before_any_work() {
        let (dir, rendered, run) = run_count(1, Some(0..3), &Silent);
        let e = run.unwrap_err();
        assert_eq!(e.to_string(), "count: frames 0..3 asked for; it has frames 0..1");
        assert!(rendered.is_empty() && std::fs::read_dir(dir.path()).unwrap().count() == 0);
    }

    #[test]
    fn a_cancelled_run_leaves_nothing() {
        struct CancelAfterFirst(AtomicBool);
        impl Progress for CancelAfterFirst {
            fn phase(&self, _: &str, _: u64) {}
            fn advance(&self, done: u64) {
                if done >= 1 {
                    self.0.store(true, Ordering::Relaxed);
                }
            }
            fn cancelled(&self) -> bool {
                self.0.load(Ordering::Relaxed)
            }
        }
        let (dir, rendered, run) = run_count(4, None, &CancelAfterFirst(AtomicBool::new(false)));
        let e = run.unwrap_err();
        assert!(matches!(e, Error::Cancelled), "{e}");
        assert_eq!(rendered, [0]);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing left behind");
    }

    #[test]
    fn warnings_count_repeats_within_a_frame_not_across_frames() {
        let mut w = Warnings::default();
        let frame = vec!["a".to_string(), "b".to_string(), "a".to_string()];
        w.merge_frame(&frame);
        w.merge_frame(&frame);
        w.add("c");
        w.add("c");
        assert_eq!(w.lines(), ["a (2 times)", "b", "c (2 times)"]);
    }
}
