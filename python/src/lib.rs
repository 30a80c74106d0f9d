//! `holo` from Python: the extension module `holo._holo` (the Python package
//! `holo` re-exports it with its documentation, `python/holo/__init__.py`).
//!
//! A thin layer over the library: every call is one library call, with the
//! GIL released while it works, numpy arrays in and out (samples in the
//! library's own order, `[channel, hololine, emitter, view]`, or for full
//! parallax `[channel, hololine, emitter, vertical view, view]`, so a frame
//! becomes an array without a copy), and the library's errors as Python
//! exceptions carrying the same one-sentence messages.

use std::borrow::Cow;
use std::path::PathBuf;

use numpy::{
    IntoPyArray, PyArray3, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyIterator, PyTuple};

use std::sync::Mutex;

use holo::format::{write_frames, Compression, Region, SampleType, WriteOptions};
use holo::reconstruct::check::FrameRef;

create_exception!(holo, HoloError, PyException, "Anything holo refuses or cannot do.");
create_exception!(
    holo,
    FileError,
    HoloError,
    "The operating system refused a read or write, or a file that must not be replaced exists."
);
create_exception!(
    holo,
    FormatError,
    HoloError,
    "A file that is not a readable .holo file: damaged, truncated, breaking the spec, or of a newer major version."
);
create_exception!(
    holo,
    InputError,
    HoloError,
    "An argument or array that does not fit: a wrong shape, a bad sample, an unknown name."
);

/// The library's error as the matching Python exception, same message.
fn to_py(e: holo::Error) -> PyErr {
    use holo::Error as E;
    let message = e.to_string();
    match e {
        E::Io { .. } | E::Output { .. } => FileError::new_err(message),
        E::Exr { .. }
        | E::Invalid { .. }
        | E::NewerMajorVersion { .. }
        | E::TooLarge { .. }
        | E::DigestMismatch { .. }
        | E::NoFrame { .. } => FormatError::new_err(message),
        _ => InputError::new_err(message),
    }
}

/// The shape of one frame of `g` as an array: `[channel, hololine, emitter,
/// view]`, or for full parallax `[channel, hololine, emitter, vertical view,
/// view]`. Either is the order of a [`holo::Modulation`]'s samples (spec §8,
/// "In memory": an emitter's views run `k · V + h`), so a frame becomes an
/// array, and a C-ordered array a frame, without reordering.
fn frame_shape(g: &holo::Geometry) -> Vec<usize> {
    let mut shape = vec![g.channels.len(), g.hololines, g.emitters];
    if let Some(vertical) = &g.vertical_views {
        shape.push(vertical.count);
    }
    shape.push(g.views.count);
    shape
}

/// The names of [`frame_shape`]'s axes, for messages.
fn frame_axes(g: &holo::Geometry) -> &'static str {
    match g.vertical_views {
        None => "[channel, hololine, emitter, view]",
        Some(_) => "[channel, hololine, emitter, vertical view, view]",
    }
}

/// The geometry of a modulation texture, in physical units (metres,
/// radians): what the display's emitters, hololines and views are.
#[pyclass(module = "holo", frozen)]
#[derive(Clone)]
struct Geometry {
    inner: holo::Geometry,
}

#[pymethods]
impl Geometry {
    /// Emitters per hololine.
    #[getter]
    fn emitters(&self) -> usize {
        self.inner.emitters
    }
    /// Hololines (rows).
    #[getter]
    fn hololines(&self) -> usize {
        self.inner.hololines
    }
    /// Views per emitter (full parallax: horizontal views, `V`).
    #[getter]
    fn views(&self) -> usize {
        self.inner.views.count
    }
    /// `"horizontal"` (views vary in `θ` only, toward the viewer line) or
    /// `"full"` (a grid of views per emitter, spec §8).
    #[getter]
    fn parallax(&self) -> &'static str {
        match self.inner.parallax {
            holo::geometry::Parallax::Horizontal => "horizontal",
            holo::geometry::Parallax::Full => "full",
        }
    }
    /// Full parallax: vertical views per emitter (`W`); `None` for
    /// horizontal parallax.
    #[getter]
    fn vertical_views(&self) -> Option<usize> {
        self.inner.vertical_views.as_ref().map(|v| v.count)
    }
    /// Colour channel names, in sample order (`R`, `G`, `B` or `Y`).
    #[getter]
    fn channels(&self) -> Vec<String> {
        self.inner.channels.iter().map(|c| c.name.clone()).collect()
    }
    /// Each channel's vacuum wavelength, metres.
    #[getter]
    fn wavelengths_m(&self) -> Vec<f64> {
        self.inner.channels.iter().map(|c| c.wavelength_m).collect()
    }
    /// The shape of one frame's array: `(channels, hololines, emitters,
    /// views)`, or for full parallax `(channels, hololines, emitters,
    /// vertical_views, views)`.
    #[getter]
    fn shape<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        PyTuple::new(py, frame_shape(&self.inner))
    }
    /// Distance between emitters along a hololine, metres.
    #[getter]
    fn emitter_pitch_m(&self) -> f64 {
        self.inner.emitter_pitch_m
    }
    /// Distance between hololines, metres.
    #[getter]
    fn hololine_pitch_m(&self) -> f64 {
        self.inner.hololine_pitch_m
    }
    /// `z` of the emitter plane (positive: in front of the hologram), metres.
    #[getter]
    fn emitter_z_m(&self) -> f64 {
        self.inner.emitter_z_m
    }
    /// Distance of the viewer line from the hologram, metres.
    #[getter]
    fn viewer_distance_m(&self) -> f64 {
        self.inner.viewer_distance_m
    }
    /// Every view's horizontal direction, radians, ascending.
    #[getter]
    fn view_angles_rad(&self) -> Vec<f64> {
        (0..self.inner.views.count).map(|v| self.inner.views.theta_rad(v)).collect()
    }
    /// Full parallax: every vertical view's direction (`φ`, from `+z`
    /// toward `+y`), radians, ascending; `None` for horizontal parallax.
    #[getter]
    fn vertical_view_angles_rad(&self) -> Option<Vec<f64>> {
        self.inner.vertical_views.as_ref().map(|v| (0..v.count).map(|k| v.theta_rad(k)).collect())
    }
    /// `x` of every emitter's centre, metres.
    #[getter]
    fn emitter_x_m(&self) -> Vec<f64> {
        (0..self.inner.emitters).map(|e| self.inner.emitter_x_m(e)).collect()
    }
    /// `y` of every hololine (full parallax: emitter row), metres, from
    /// hololine 0 at the top downward.
    #[getter]
    fn hololine_y_m(&self) -> Vec<f64> {
        (0..self.inner.hololines).map(|j| self.inner.hololine_y_m(j)).collect()
    }
    /// This geometry made full parallax (spec §8) with `count` vertical
    /// views, tan-spaced and centred on the display's normal over `cone_rad`
    /// from the lowest to the highest (by default the horizontal views' own
    /// cone), as `holo convert cameras --vertical-views N` makes it; checked
    /// as `from_dict` is.
    #[pyo3(signature = (count, cone_rad=None))]
    fn with_vertical_views(&self, count: usize, cone_rad: Option<f64>) -> PyResult<Geometry> {
        checked(self.inner.clone().with_centred_vertical_views(count, cone_rad))
    }
    /// Every field, as the `.holo` spec names them (a dict of plain values;
    /// `Geometry.from_dict` takes it back).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.inner).map_err(|e| HoloError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }
    /// The geometry a dict from `to_dict` describes (checked as a file's is).
    #[staticmethod]
    fn from_dict(py: Python<'_>, fields: &Bound<'_, PyDict>) -> PyResult<Geometry> {
        let text: String = py.import("json")?.call_method1("dumps", (fields,))?.extract()?;
        let inner: holo::Geometry =
            serde_json::from_str(&text).map_err(|e| InputError::new_err(format!("the dict is not a geometry: {e}")))?;
        checked(inner)
    }
    fn __eq__(&self, other: &Geometry) -> bool {
        self.inner == other.inner
    }
    fn __repr__(&self) -> String {
        let g = &self.inner;
        let vertical = match &g.vertical_views {
            Some(v) => format!(" × {} vertical views", v.count),
            None => String::new(),
        };
        format!(
            "Geometry({} emitters × {} hololines × {} views{vertical}, channels {:?})",
            g.emitters,
            g.hololines,
            g.views.count,
            self.channels()
        )
    }
}

/// `inner` for Python if it is valid and a frame of it fits a `.holo` frame
/// (checked without making one: a huge geometry is refused, not allocated).
fn checked(inner: holo::Geometry) -> PyResult<Geometry> {
    let problems = inner.frame_problems();
    if !problems.is_empty() {
        return Err(InputError::new_err(format!("invalid geometry: {}", problems.join("; "))));
    }
    Ok(Geometry { inner })
}

/// A `.holo` file opened for reading: its header is read and checked, its
/// frames are read when asked for.
#[pyclass(module = "holo", frozen)]
struct HoloFile {
    inner: holo::format::HoloFile,
}

/// The name `write` takes for a sample type.
fn sample_type_name(t: SampleType) -> &'static str {
    match t {
        SampleType::F16 => "f16",
        SampleType::F32 => "f32",
    }
}

/// Samples of a frame of `g` (or of a region, `g` its part) as a numpy
/// array of [`frame_shape`], without a copy.
fn samples_array<'py, T: numpy::Element>(
    py: Python<'py>,
    g: &holo::Geometry,
    samples: Vec<T>,
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    samples.into_pyarray(py).reshape(frame_shape(g))
}

/// A frame's samples as a numpy array, without a copy.
fn frame_array(py: Python<'_>, m: holo::Modulation) -> PyResult<Bound<'_, PyArrayDyn<f32>>> {
    let g = m.geometry().clone();
    samples_array(py, &g, m.into_samples())
}

/// The element type a read hands back: float32 unless `dtype` (anything
/// `numpy.dtype` takes) is float16; any other is an error naming both.
fn read_dtype_is_f16(py: Python<'_>, dtype: Option<&Bound<'_, PyAny>>) -> PyResult<bool> {
    let Some(dtype) = dtype.filter(|d| !d.is_none()) else { return Ok(false) };
    let descr = py.import("numpy")?.getattr("dtype")?.call1((dtype,))?;
    let descr = descr.downcast::<numpy::PyArrayDescr>()?;
    if descr.is_equiv_to(&numpy::dtype::<half::f16>(py)) {
        Ok(true)
    } else if descr.is_equiv_to(&numpy::dtype::<f32>(py)) {
        Ok(false)
    } else {
        Err(InputError::new_err(format!("dtype {descr}: frames are read as float32 or float16")))
    }
}

#[pymethods]
impl HoloFile {
    /// The file's path.
    #[getter]
    fn path(&self) -> PathBuf {
        self.inner.path().clone()
    }
    /// The geometry.
    #[getter]
    fn geometry(&self) -> Geometry {
        Geometry { inner: self.inner.geometry().clone() }
    }
    /// Frames in the file.
    #[getter]
    fn frame_count(&self) -> usize {
        self.inner.info().frames.len()
    }
    fn __len__(&self) -> usize {
        self.frame_count()
    }
    /// What the header says: format version, sample type, compression,
    /// frame rate, provenance, radiometry, size (a dict).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let info = self.inner.info();
        let d = PyDict::new(py);
        d.set_item("version", info.version)?;
        d.set_item("sample_type", sample_type_name(info.sample_type))?;
        d.set_item("compression", info.compression.name())?;
        d.set_item("frames", info.frames.len())?;
        d.set_item("frames_per_second", info.frames_per_second.map(|(n, den)| f64::from(n) / f64::from(den)))?;
        d.set_item("source", info.source.clone())?;
        d.set_item("software", info.software.clone())?;
        d.set_item("scale", info.radiometry.scale)?;
        d.set_item("unit", info.radiometry.unit.clone())?;
        d.set_item("file_bytes", info.file_bytes)?;
        d.set_item("placement", info.placement.map(|m| m.to_vec()))?;
        Ok(d)
    }
    /// Frame `index` as an array of shape `geometry.shape`, axes `[channel,
    /// hololine, emitter, view]` (full parallax: `[channel, hololine,
    /// emitter, vertical view, view]`); its digest is checked. float32 by default;
    /// `dtype=numpy.float16` hands back an f16 file's samples as stored,
    /// without a float32 pass (an f32 file's are rounded; one too large for
    /// float16 is an error).
    #[pyo3(signature = (index, dtype=None))]
    fn frame<'py>(
        &self,
        py: Python<'py>,
        index: usize,
        dtype: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = self.inner.geometry();
        if read_dtype_is_f16(py, dtype)? {
            let samples = py.allow_threads(|| self.inner.read_frame_samples::<half::f16>(index)).map_err(to_py)?;
            Ok(samples_array(py, g, samples)?.into_any())
        } else {
            let samples = py.allow_threads(|| self.inner.read_frame_samples::<f32>(index)).map_err(to_py)?;
            Ok(samples_array(py, g, samples)?.into_any())
        }
    }
    /// Part of frame `index`: hololines `hololines = (first, end)`,
    /// emitters `emitters = (first, end)`, (horizontal) views `views =
    /// (first, end)` and, full parallax only, vertical views `vertical_views
    /// = (first, end)` (each by default all), every channel; an array of
    /// that part with `frame`'s axes, float32 or (`dtype=numpy.float16`)
    /// float16 as `frame` says. Only the chunks holding those hololines are
    /// decoded, and of a full-parallax file only those views' parts.
    #[pyo3(signature = (index, hololines=None, emitters=None, dtype=None, *, views=None, vertical_views=None))]
    #[allow(clippy::too_many_arguments)]
    fn region<'py>(
        &self,
        py: Python<'py>,
        index: usize,
        hololines: Option<(usize, usize)>,
        emitters: Option<(usize, usize)>,
        dtype: Option<&Bound<'py, PyAny>>,
        views: Option<(usize, usize)>,
        vertical_views: Option<(usize, usize)>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let g = self.inner.geometry();
        if g.vertical_views.is_none() && vertical_views.is_some() {
            return Err(InputError::new_err(format!(
                "{}: vertical_views given, but the file is horizontal parallax: it has no vertical views",
                self.inner.path().display()
            )));
        }
        let all = Region::all(g);
        let range =
            |given: Option<(usize, usize)>, all: &std::ops::Range<usize>| given.map_or(all.clone(), |(a, b)| a..b);
        let region = Region {
            hololines: range(hololines, &all.hololines),
            emitters: range(emitters, &all.emitters),
            views: range(views, &all.views),
            vertical_views: range(vertical_views, &all.vertical_views),
        };
        // The part's own shape, for the array.
        let mut part = g.clone();
        (part.hololines, part.emitters, part.views.count) =
            (region.hololines.len(), region.emitters.len(), region.views.len());
        if let Some(vertical) = &mut part.vertical_views {
            vertical.count = region.vertical_views.len();
        }
        if read_dtype_is_f16(py, dtype)? {
            let samples =
                py.allow_threads(|| self.inner.read_region_samples::<half::f16>(index, &region)).map_err(to_py)?;
            Ok(samples_array(py, &part, samples)?.into_any())
        } else {
            let samples = py.allow_threads(|| self.inner.read_region_samples::<f32>(index, &region)).map_err(to_py)?;
            Ok(samples_array(py, &part, samples)?.into_any())
        }
    }
    fn __repr__(&self) -> String {
        format!("HoloFile({:?}, {} frame(s))", self.inner.path(), self.frame_count())
    }
}

/// Open a `.holo` file (`str` or `pathlib.Path`): the header is read and
/// checked now, frames when asked for.
#[pyfunction]
fn open(py: Python<'_>, path: PathBuf) -> PyResult<HoloFile> {
    let inner = py.allow_threads(|| holo::format::HoloFile::open(&path)).map_err(to_py)?;
    Ok(HoloFile { inner })
}

/// `array` as float32 samples: a float32 numpy array as it is, any other
/// real floating-point one (float16, float64, long double; any memory
/// order) converted, as numpy 2 makes `frame * k` float64 for a float64 `k`;
/// anything else refused, naming `what`.
fn float32_array<'py>(array: &Bound<'py, PyAny>, what: &str) -> PyResult<PyReadonlyArrayDyn<'py, f32>> {
    if let Ok(samples) = array.extract::<PyReadonlyArrayDyn<'py, f32>>() {
        return Ok(samples);
    }
    let dtype = array.getattr("dtype").ok();
    let kind = dtype.as_ref().and_then(|d| d.getattr("kind").ok()).and_then(|k| k.extract::<String>().ok());
    match kind.as_deref() {
        Some("f") => array.call_method1("astype", ("float32",))?.extract(),
        Some(_) => Err(InputError::new_err(format!(
            "{what}: a numpy array of {} samples; give real floating-point ones (float16, float32 or float64)",
            dtype.map_or_else(|| "other".to_string(), |d| d.to_string())
        ))),
        None => Err(InputError::new_err(format!(
            "{what}: not a numpy array; give one of real floating-point samples (float16, float32 or float64)"
        ))),
    }
}

/// A real floating-point array ([`float32_array`]) of exactly `g`'s frame
/// shape ([`frame_shape`]) as a modulation (copied).
fn modulation_of(g: &holo::Geometry, array: &Bound<'_, PyAny>, index: usize) -> PyResult<holo::Modulation> {
    let array = float32_array(array, &format!("frame {index}"))?;
    let want = frame_shape(g);
    if array.shape() != want {
        return Err(InputError::new_err(format!(
            "frame {index}: an array of shape {:?}; the geometry's frames are {:?} {}",
            array.shape(),
            want,
            frame_axes(g)
        )));
    }
    // A contiguous slice is in memory order, which for a Fortran-ordered
    // array is not the frame's axis order: only a C-ordered one is copied as
    // it lies.
    let samples = match array.as_slice() {
        Ok(s) if array.is_c_contiguous() => s.to_vec(),
        _ => array.as_array().iter().copied().collect(),
    };
    holo::Modulation::from_samples(g.clone(), samples).map_err(to_py)
}

/// Write frames to a new `.holo` file. `frames` is one frame (an array of
/// `geometry.shape`, float32 or any other real floating-point type, converted;
/// five axes for a full-parallax geometry), an array of frames (one more leading axis),
/// a sequence of frames, or an iterator or generator of frames (give
/// `frame_count`: the file's headers say how many frames follow). Frames from
/// an iterator are taken one at a time, so a long movie is never in memory.
#[pyfunction]
#[pyo3(signature = (path, frames, geometry, *, frame_count=None, sample_type="f16", compression="zip", source="", frames_per_second=None, overwrite=false))]
#[allow(clippy::too_many_arguments)]
fn write(
    py: Python<'_>,
    path: PathBuf,
    frames: &Bound<'_, PyAny>,
    geometry: &Geometry,
    frame_count: Option<usize>,
    sample_type: &str,
    compression: &str,
    source: &str,
    frames_per_second: Option<f64>,
    overwrite: bool,
) -> PyResult<()> {
    let g = &geometry.inner;
    let sample_type = match sample_type {
        "f16" => SampleType::F16,
        "f32" => SampleType::F32,
        other => return Err(InputError::new_err(format!("sample_type {other:?}: give \"f16\" or \"f32\""))),
    };
    let compression = Compression::from_name(compression).ok_or_else(|| {
        let names: Vec<&str> = Compression::ALL.iter().map(|c| c.name()).collect();
        InputError::new_err(format!("compression {compression:?}: give one of {}", names.join(", ")))
    })?;
    let frames_per_second = match frames_per_second {
        None => None,
        Some(fps) if fps.is_finite() && fps > 0.0 => Some(((fps * 1000.0).round() as i32, 1000)),
        Some(fps) => return Err(InputError::new_err(format!("frames_per_second {fps} must be positive"))),
    };
    let options = WriteOptions {
        sample_type,
        compression,
        source: source.to_string(),
        frames_per_second,
        overwrite,
        ..WriteOptions::default()
    };
    // One frame, an array of frames, a sequence, or an iterator.
    let ndim = frames.getattr("ndim").ok().and_then(|n| n.extract::<usize>().ok());
    let items: Vec<Bound<'_, PyAny>>;
    let mut iterator: Option<Bound<'_, PyIterator>> = None;
    let frame_ndim = frame_shape(g).len();
    let count = match ndim {
        Some(n) if n == frame_ndim => {
            items = vec![frames.clone()];
            1
        }
        // Fewer axes than a frame: neither a frame nor frames (a
        // horizontal-parallax frame given for a full-parallax geometry).
        Some(n) if n < frame_ndim => {
            let shape: Vec<usize> = frames.getattr("shape")?.extract()?;
            return Err(InputError::new_err(format!(
                "frames: an array of shape {shape:?}; the geometry's frames are {:?} {}: give one, or an array of them (one more leading axis)",
                frame_shape(g),
                frame_axes(g)
            )));
        }
        Some(_) => {
            items = frames.try_iter()?.collect::<PyResult<_>>()?;
            items.len()
        }
        None if frames.hasattr("__len__")? => {
            items = frames.try_iter()?.collect::<PyResult<_>>()?;
            items.len()
        }
        None => {
            items = Vec::new();
            iterator = Some(frames.try_iter()?);
            frame_count.ok_or_else(|| {
                InputError::new_err("frames come from an iterator: give frame_count, the number it yields")
            })?
        }
    };
    if let Some(n) = frame_count {
        if n != count {
            return Err(InputError::new_err(format!("frame_count {n}, but {count} frames were given")));
        }
    }
    // The Python error that stopped the writer (a bad frame, or the
    // iterator's own exception), raised as it is once the writer has
    // removed its partial file.
    let failure: Mutex<Option<PyErr>> = Mutex::new(None);
    let iterator = iterator.map(|it| it.unbind());
    let items: Vec<Py<PyAny>> = items.into_iter().map(|x| x.unbind()).collect();
    let next = |i: usize| -> holo::Result<Cow<'static, holo::Modulation>> {
        Python::with_gil(|py| {
            let frame = match &iterator {
                Some(it) => it.bind(py).clone().next(),
                None => Some(Ok(items[i].bind(py).clone())),
            };
            let converted = match frame {
                Some(Ok(f)) => modulation_of(g, &f, i),
                Some(Err(e)) => Err(e),
                None => Err(InputError::new_err(format!("the iterator ended after {i} of {count} frames"))),
            };
            converted.map(Cow::Owned).map_err(|e| {
                *failure.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
                holo::Error::Cancelled
            })
        })
    };
    let written = py.allow_threads(|| write_frames(&path, g, count, &options, next));
    match (written, failure.into_inner().unwrap_or_else(|p| p.into_inner())) {
        (Ok(_), _) => Ok(()),
        (Err(_), Some(e)) => Err(e),
        (Err(e), None) => Err(to_py(e)),
    }
}

/// Check a `.holo` file against the spec, reading every frame and its
/// digest: a dict with `valid`, the rules broken (`problems`, empty when
/// valid), `warnings` and the number of `frames`.
#[pyfunction]
fn validate<'py>(py: Python<'py>, path: PathBuf) -> PyResult<Bound<'py, PyDict>> {
    let v = py.allow_threads(|| holo::validate(&path)).map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("valid", v.is_valid())?;
    d.set_item("problems", v.violations.clone())?;
    d.set_item("warnings", v.warnings.clone())?;
    d.set_item("frames", v.info.as_ref().map(|i| i.frames.len()))?;
    Ok(d)
}

/// A display layout: the modulation geometry a display expects and how a
/// modulation becomes its frame buffer (spec/layouts.md). Checked when made,
/// its assembler (the tabulated basis) built once.
#[pyclass(module = "holo", frozen)]
struct Layout {
    assembler: holo::assemble::Assembler,
}

impl Layout {
    fn new(layout: holo::layout::Layout) -> PyResult<Layout> {
        let problems = holo::assemble::problems(&layout);
        if !problems.is_empty() {
            return Err(InputError::new_err(format!("layout {}: {}", layout.name, problems.join("; "))));
        }
        let assembler = holo::assemble::Assembler::new(&layout).map_err(to_py)?;
        Ok(Layout { assembler })
    }
    fn layout(&self) -> &holo::layout::Layout {
        self.assembler.layout()
    }
}

#[pymethods]
impl Layout {
    /// A built-in layout (`mark3`, `mark1`, `mark1-hogel`, `mark2`, `mark4`)
    /// or a profile file (`.toml` or `.json`, `str` or `pathlib.Path`).
    #[staticmethod]
    fn load(py: Python<'_>, name_or_path: PathBuf) -> PyResult<Layout> {
        let text = name_or_path.to_string_lossy().into_owned();
        let layout = py.allow_threads(|| holo::assemble::load_layout(&text)).map_err(to_py)?;
        py.allow_threads(|| Layout::new(layout))
    }
    /// The layout a dict from `to_dict` describes, checked as a profile is.
    #[staticmethod]
    fn from_dict(py: Python<'_>, fields: &Bound<'_, PyDict>) -> PyResult<Layout> {
        let text: String = py.import("json")?.call_method1("dumps", (fields,))?.extract()?;
        let layout: holo::layout::Layout = serde_json::from_str(&text)
            .map_err(|e| InputError::new_err(format!("the dict is not a layout profile: {e}")))?;
        py.allow_threads(|| Layout::new(layout))
    }
    /// Every field, as a profile file has them.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(self.layout()).map_err(|e| HoloError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }
    /// The layout's name.
    #[getter]
    fn name(&self) -> String {
        self.layout().name.clone()
    }
    /// The modulation geometry the display expects.
    #[getter]
    fn geometry(&self) -> Geometry {
        Geometry { inner: self.layout().geometry.clone() }
    }
    /// The frame buffer's image names, in the order `assemble` returns them.
    #[getter]
    fn image_names(&self) -> Vec<String> {
        self.layout().fringe.as_ref().map(|f| f.frame_buffer.image_names.clone()).unwrap_or_default()
    }
    fn __repr__(&self) -> String {
        format!("Layout({:?})", self.layout().name)
    }
}

/// A frame from an array (real floating-point, the layout's geometry's shape).
fn frame_for(layout: &Layout, frame: &Bound<'_, PyAny>) -> PyResult<holo::Modulation> {
    modulation_of(&layout.layout().geometry, frame, 0)
}

/// Assemble one frame (a float array of `layout.geometry.shape`) into the
/// layout's frame buffer: one array per image (`layout.image_names`),
/// `[row, column, component]`, uint8 codes as the display takes them, or
/// with `samples="f32"` the float signals before quantization (0 where no
/// signal lands). The same bytes as `holo assemble`.
#[pyfunction]
#[pyo3(signature = (frame, layout, *, samples="u8"))]
fn assemble<'py>(
    py: Python<'py>,
    frame: &Bound<'py, PyAny>,
    layout: &Layout,
    samples: &str,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let m = frame_for(layout, frame)?;
    let a = &layout.assembler;
    fn arrays<'py, T: numpy::Element + holo::assemble::FringeSample>(
        py: Python<'py>,
        images: holo::assemble::FrameImages<T>,
    ) -> PyResult<Vec<Bound<'py, PyAny>>> {
        let shape = [images.height, images.width, images.components];
        images.images.into_iter().map(|i| Ok(i.into_pyarray(py).reshape(shape)?.into_any())).collect()
    }
    match samples {
        "u8" => arrays(py, py.allow_threads(|| a.assemble::<u8>(&m)).map_err(to_py)?.0),
        "f32" => arrays(py, py.allow_threads(|| a.assemble::<f32>(&m)).map_err(to_py)?.0),
        other => Err(InputError::new_err(format!("samples {other:?}: give \"u8\" or \"f32\""))),
    }
}

/// What eyes see of one frame on the display, by scalar diffraction
/// (spec/layouts.md §9): one float32 array `[hololine, emitter, channel]` per
/// eye, 1 for a fully lit emitter. `eyes_x_m`: horizontal eye positions on
/// the viewer line, metres; `distance_m`: the layout's viewer distance when
/// None; `coherent`: the eye images the emitter plane, neighbours interfere
/// (§9.2).
#[pyfunction]
#[pyo3(signature = (frame, layout, eyes_x_m, *, distance_m=None, pupil_m=4e-3, coherent=false))]
fn view<'py>(
    py: Python<'py>,
    frame: &Bound<'py, PyAny>,
    layout: &Layout,
    eyes_x_m: Vec<f64>,
    distance_m: Option<f64>,
    pupil_m: f64,
    coherent: bool,
) -> PyResult<Vec<Bound<'py, PyArray3<f32>>>> {
    let m = frame_for(layout, frame)?;
    let a = &layout.assembler;
    let g = &layout.layout().geometry;
    let eyes: Vec<holo::reconstruct::viewer::Eye> = eyes_x_m
        .iter()
        .map(|&x_m| holo::reconstruct::viewer::Eye {
            x_m,
            y_m: g.viewer_height_m,
            z_m: distance_m.unwrap_or(g.viewer_distance_m),
            pupil_m,
            coherent,
        })
        .collect();
    let pictures = py
        .allow_threads(|| {
            let (images, _) = a.assemble::<u8>(&m)?;
            holo::reconstruct::check::view(a, FrameRef::Bytes(&images), &eyes, &holo::progress::Silent)
        })
        .map_err(to_py)?;
    pictures
        .into_iter()
        .map(|p| {
            let shape = [p.hololines, p.emitters, p.channels.len()];
            p.data.into_pyarray(py).reshape(shape)
        })
        .collect()
}

/// Assemble one frame to the layout's 8-bit frame buffer and recover the
/// modulation from it two ways (spec/layouts.md §9): a dict with `signal`
/// (least squares) and `optical` (each view's light), each with
/// `relative_l2`, `psnr_db`, `peak` and the `worst` emitter.
#[pyfunction]
fn check<'py>(py: Python<'py>, frame: &Bound<'py, PyAny>, layout: &Layout) -> PyResult<Bound<'py, PyAny>> {
    let m = frame_for(layout, frame)?;
    let a = &layout.assembler;
    let hololines = 0..m.geometry().hololines;
    let report = py
        .allow_threads(|| {
            let (images, _) = a.assemble::<u8>(&m)?;
            holo::reconstruct::check::check(a, &m, FrameRef::Bytes(&images), hololines, &holo::progress::Silent)
        })
        .map_err(to_py)?;
    let text = serde_json::to_string(&report).map_err(|e| HoloError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// Convert a mesh file (glTF, OBJ, PLY) into a new `.holo` file for
/// `layout`'s display, with the command line's defaults (`holo convert
/// mesh`): the scene fitted to the display, every frame of an animation.
/// Returns a dict: the output path, frames, triangles and warnings.
/// `progress(phase, done, total)` is called as steps finish; returning
/// `False` stops the work and leaves no file.
#[pyfunction]
#[pyo3(signature = (input, layout, output, *, overwrite=false, progress=None))]
fn convert_mesh<'py>(
    py: Python<'py>,
    input: PathBuf,
    layout: &Layout,
    output: PathBuf,
    overwrite: bool,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut options = holo::mesh::convert::ConvertOptions::default();
    options.write.overwrite = overwrite;
    let g = &layout.layout().geometry;
    let progress = PyProgress::new(progress);
    let converted = py.allow_threads(|| holo::mesh::convert::convert_mesh(&input, g, &output, &options, &progress));
    let report = progress.result(converted)?;
    let d = PyDict::new(py);
    d.set_item("path", report.path)?;
    d.set_item("frames", (report.frames.start, report.frames.end))?;
    d.set_item("triangles", report.triangles)?;
    d.set_item("warnings", report.warnings)?;
    Ok(d)
}

/// Progress for the library from a Python callable `progress(phase, done,
/// total)`, called with the GIL as steps finish. The work stops, leaving
/// nothing behind, when the callable returns `False` or raises, and on
/// Ctrl-C (a signal Python has pending); the exception then comes through.
struct PyProgress {
    callback: Option<Py<PyAny>>,
    /// The current phase, its total, and the steps last reported: the
    /// library's threads finish steps in any order, the callback sees the
    /// count rise.
    phase: Mutex<(String, u64, Option<u64>)>,
    stop: Mutex<Option<PyErr>>,
    stopped: std::sync::atomic::AtomicBool,
}

impl PyProgress {
    fn new(callback: Option<Py<PyAny>>) -> PyProgress {
        PyProgress {
            callback,
            phase: Mutex::new((String::new(), 0, None)),
            stop: Mutex::new(None),
            stopped: std::sync::atomic::AtomicBool::new(false),
        }
    }
    fn halt(&self, e: PyErr) {
        *self.stop.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
        self.stopped.store(true, std::sync::atomic::Ordering::Relaxed);
    }
    /// The library's result, or the Python exception that stopped it.
    fn result<T>(self, r: holo::Result<T>) -> PyResult<T> {
        match (r, self.stop.into_inner().unwrap_or_else(|p| p.into_inner())) {
            (Ok(x), _) => Ok(x),
            (Err(_), Some(e)) => Err(e),
            (Err(e), None) => Err(to_py(e)),
        }
    }
}

impl holo::progress::Progress for PyProgress {
    fn phase(&self, name: &str, total: u64) {
        *self.phase.lock().unwrap_or_else(|p| p.into_inner()) = (name.to_string(), total, None);
        self.advance(0);
    }
    fn advance(&self, done: u64) {
        if self.stopped.load(std::sync::atomic::Ordering::Relaxed) {
            return;
        }
        Python::with_gil(|py| {
            if let Err(e) = py.check_signals() {
                return self.halt(e);
            }
            let Some(callback) = &self.callback else { return };
            let (name, total) = {
                // Under the GIL, so reports cannot overtake one another.
                let mut phase = self.phase.lock().unwrap_or_else(|p| p.into_inner());
                if phase.2.is_some_and(|last| done <= last) {
                    return;
                }
                phase.2 = Some(done);
                (phase.0.clone(), phase.1)
            };
            match callback.call1(py, (name, done, total)) {
                Ok(answer) if answer.bind(py).is(&*pyo3::types::PyBool::new(py, false)) => self.halt(holo_cancelled()),
                Ok(_) => {}
                Err(e) => self.halt(e),
            }
        })
    }
    fn cancelled(&self) -> bool {
        self.stopped.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// What a progress callback that returned `False` gets.
fn holo_cancelled() -> PyErr {
    HoloError::new_err("cancelled by the progress callback; nothing was written")
}

/// Render a mesh given as arrays into one frame for `layout`'s display, as
/// `convert_mesh` renders a file: `vertices` (n, 3) float64 in any units
/// (the scene is fitted to the display), `faces` (m, 3) integer indices,
/// optional `colours` (n, 3) or (n, 4) float linear RGB(A) per vertex (else
/// white); lit by the default lights. Returns the frame (float32 array of
/// `layout.geometry.shape`) for `write`.
#[pyfunction]
#[pyo3(signature = (vertices, faces, layout, *, colours=None, progress=None))]
fn render_mesh<'py>(
    py: Python<'py>,
    vertices: PyReadonlyArrayDyn<'py, f64>,
    faces: &Bound<'py, PyAny>,
    layout: &Layout,
    colours: Option<Bound<'py, PyAny>>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyArrayDyn<f32>>> {
    let shape = vertices.shape().to_vec();
    if shape.len() != 2 || shape[1] != 3 {
        return Err(InputError::new_err(format!("vertices: an array of shape {shape:?}; give (n, 3)")));
    }
    let v = vertices.as_array();
    let positions: Vec<[f64; 3]> = (0..shape[0]).map(|i| [v[[i, 0]], v[[i, 1]], v[[i, 2]]]).collect();
    let faces: PyReadonlyArrayDyn<'py, i64> = faces
        .call_method1("astype", ("int64",))?
        .extract()
        .map_err(|_| InputError::new_err("faces: give an integer array of shape (m, 3)"))?;
    let fshape = faces.shape().to_vec();
    if fshape.len() != 2 || fshape[1] != 3 {
        return Err(InputError::new_err(format!("faces: an array of shape {fshape:?}; give (m, 3)")));
    }
    let f = faces.as_array();
    let mut triangles = Vec::with_capacity(fshape[0]);
    for t in 0..fshape[0] {
        let mut tri = [0u32; 3];
        for k in 0..3 {
            let i = f[[t, k]];
            if i < 0 || i as usize >= positions.len() {
                return Err(InputError::new_err(format!(
                    "faces: triangle {t} names vertex {i}; there are {} vertices",
                    positions.len()
                )));
            }
            tri[k] = i as u32;
        }
        triangles.push(tri);
    }
    let colours = match colours {
        None => Vec::new(),
        Some(c) => {
            let c = float32_array(&c, "colours")?;
            let cs = c.shape().to_vec();
            if cs.len() != 2 || cs[0] != positions.len() || !(cs[1] == 3 || cs[1] == 4) {
                return Err(InputError::new_err(format!(
                    "colours: an array of shape {cs:?}; give ({}, 3) or ({}, 4), one per vertex",
                    positions.len(),
                    positions.len()
                )));
            }
            let a = c.as_array();
            (0..cs[0]).map(|i| [a[[i, 0]], a[[i, 1]], a[[i, 2]], if cs[1] == 4 { a[[i, 3]] } else { 1.0 }]).collect()
        }
    };
    let object = holo::mesh::Object { name: "arrays".into(), positions, triangles, colours, ..Default::default() };
    let mut scene = holo::mesh::Scene { source: "arrays".into(), objects: vec![object], ..Default::default() };
    let g = &layout.layout().geometry;
    let options = holo::mesh::render::RenderOptions::default();
    let progress = PyProgress::new(progress);
    let rendered = py.allow_threads(|| {
        holo::mesh::place::place(&mut scene, g, &holo::mesh::place::Placement::default())?;
        holo::mesh::render::render(&scene, g, &options, &progress)
    });
    let (m, _) = progress.result(rendered)?;
    frame_array(py, m)
}

/// One float64 matrix of `rows × 3` or `rows × 4` from an array-like.
fn matrix(m: &Bound<'_, PyAny>, what: &str, rows: usize) -> PyResult<Vec<Vec<f64>>> {
    let a: PyReadonlyArrayDyn<'_, f64> = m
        .call_method0("__array__")
        .and_then(|x| x.call_method1("astype", ("float64",)))
        .and_then(|x| x.extract())
        .map_err(|_| InputError::new_err(format!("{what}: give a {rows}×3 or {rows}×4 array")))?;
    let shape = a.shape().to_vec();
    if shape.len() != 2 || shape[0] < rows || !(shape[1] == 3 || shape[1] == 4) {
        return Err(InputError::new_err(format!("{what}: an array of shape {shape:?}; give {rows}×3 or {rows}×4")));
    }
    let v = a.as_array();
    Ok((0..shape[0]).map(|i| (0..shape[1]).map(|j| v[[i, j]]).collect()).collect())
}

/// Resample pictures from a calibrated camera rig into one frame for
/// `layout`'s display, as `holo convert cameras` does a rig file: one
/// float array `(height, width, 3)` of linear RGB per camera, its 3×3
/// intrinsic matrix `K` (pixels; pixel centres at integers, `(0, 0)` top left)
/// and its 3×4 or 4×4 world-to-camera extrinsics `[R | t]` (OpenCV's
/// convention: `x_camera = R x_world + t`, camera `x` right, `y` down, `z`
/// forward), in world units of `metres_per_unit` metres. The default
/// placement fits the middle camera's view at the focus (`focus_distance`
/// world units, else the cameras' convergence) to the display. Returns the
/// frame and a dict of what was done (placement, rays, unseen rays).
#[pyfunction]
#[pyo3(signature = (pictures, intrinsics, poses, layout, *, metres_per_unit=1.0, focus_distance=None, progress=None))]
#[allow(clippy::too_many_arguments)]
fn resample_cameras<'py>(
    py: Python<'py>,
    pictures: Vec<Bound<'py, PyAny>>,
    intrinsics: Vec<Bound<'py, PyAny>>,
    poses: Vec<Bound<'py, PyAny>>,
    layout: &Layout,
    metres_per_unit: f64,
    focus_distance: Option<f64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<(Bound<'py, PyArrayDyn<f32>>, Bound<'py, PyDict>)> {
    use holo::cameras::{Camera, ImageSource, Intrinsics, Pose, Rig};
    if pictures.len() != intrinsics.len() || pictures.len() != poses.len() || pictures.is_empty() {
        return Err(InputError::new_err(format!(
            "{} pictures, {} intrinsic matrices and {} poses: give one of each per camera",
            pictures.len(),
            intrinsics.len(),
            poses.len()
        )));
    }
    let mut cameras = Vec::new();
    let mut views = Vec::new();
    for (k, ((picture, kk), pose)) in pictures.iter().zip(&intrinsics).zip(&poses).enumerate() {
        let picture = float32_array(picture, &format!("picture {k}"))?;
        let shape = picture.shape().to_vec();
        if shape.len() != 3 || shape[2] != 3 {
            return Err(InputError::new_err(format!(
                "picture {k}: an array of shape {shape:?}; give (height, width, 3)"
            )));
        }
        let (height, width) = (shape[0], shape[1]);
        let a = picture.as_array();
        let rgb: Vec<[f32; 3]> = (0..height * width)
            .map(|i| [a[[i / width, i % width, 0]], a[[i / width, i % width, 1]], a[[i / width, i % width, 2]]])
            .collect();
        let kk = matrix(kk, &format!("intrinsics {k}"), 3)?;
        let rt = matrix(pose, &format!("pose {k}"), 3)?;
        if rt[0].len() != 4 {
            return Err(InputError::new_err(format!("pose {k}: give the 3×4 or 4×4 matrix [R | t]")));
        }
        let rotation = [[rt[0][0], rt[0][1], rt[0][2]], [rt[1][0], rt[1][1], rt[1][2]], [rt[2][0], rt[2][1], rt[2][2]]];
        let t = [rt[0][3], rt[1][3], rt[2][3]];
        // The centre of projection: −Rᵀ t.
        let centre = [0, 1, 2].map(|j| -(rotation[0][j] * t[0] + rotation[1][j] * t[1] + rotation[2][j] * t[2]));
        cameras.push(Camera {
            name: format!("camera {k}"),
            image: ImageSource::File(format!("picture {k}").into()),
            width,
            height,
            intrinsics: Intrinsics { fx: kk[0][0], fy: kk[1][1], cx: kk[0][2], cy: kk[1][2] },
            pose: Pose { rotation, centre },
            depth: None,
        });
        views.push(holo::cameras::resample::CameraView {
            picture: holo::cameras::image::Picture { width, height, rgb },
            depth_z: None,
        });
    }
    let rig = Rig { source: "arrays".into(), cameras, metres_per_unit, focus_distance, linear: true };
    let g = &layout.layout().geometry;
    let options = holo::cameras::resample::CameraOptions::default();
    let progress = PyProgress::new(progress);
    let resampled = py.allow_threads(|| holo::cameras::resample::resample_rig(&rig, &views, g, &options, &progress));
    let (m, report) = progress.result(resampled)?;
    let d = PyDict::new(py);
    d.set_item("placement", report.placement)?;
    d.set_item("surface", report.surface)?;
    d.set_item("rays", report.rays)?;
    d.set_item("unseen", report.unseen)?;
    d.set_item("unseen_outside_frame", report.unseen_outside_frame)?;
    d.set_item("warnings", report.warnings)?;
    Ok((frame_array(py, m)?, d))
}

/// The extension module.
#[pymodule]
fn _holo(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("HoloError", py.get_type::<HoloError>())?;
    m.add("FileError", py.get_type::<FileError>())?;
    m.add("FormatError", py.get_type::<FormatError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add_class::<Geometry>()?;
    m.add_class::<HoloFile>()?;
    m.add_class::<Layout>()?;
    m.add_function(wrap_pyfunction!(assemble, m)?)?;
    m.add_function(wrap_pyfunction!(view, m)?)?;
    m.add_function(wrap_pyfunction!(check, m)?)?;
    m.add_function(wrap_pyfunction!(convert_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(render_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(resample_cameras, m)?)?;
    m.add_function(wrap_pyfunction!(open, m)?)?;
    m.add_function(wrap_pyfunction!(write, m)?)?;
    m.add_function(wrap_pyfunction!(validate, m)?)?;
    Ok(())
}
