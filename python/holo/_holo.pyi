"""Type stubs of the extension module (python/src/lib.rs); the package re-exports every name."""

import os
import pathlib
from typing import Any, Callable, Iterable, Iterator, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, "os.PathLike[str]"]
Frame = npt.NDArray[np.float32]
# Frames, colours and pictures given to holo: float32, or any real floating-point array (converted).
Floats = npt.NDArray[np.floating[Any]]

class HoloError(Exception):
    """Anything holo refuses or cannot do."""

class FileError(HoloError):
    """The operating system refused a read or write, or a file that must not be replaced exists."""

class FormatError(HoloError):
    """A file that is not a readable .holo file: damaged, truncated, breaking the spec, or of a newer major version."""

class InputError(HoloError):
    """An argument or array that does not fit: a wrong shape, a bad sample, an unknown name."""

class Geometry:
    """The geometry of a modulation texture, in physical units (metres, radians)."""

    @property
    def emitters(self) -> int:
        """Emitters per hololine."""
    @property
    def hololines(self) -> int:
        """Hololines (rows)."""
    @property
    def views(self) -> int:
        """Views per emitter (full parallax: horizontal views, V)."""
    @property
    def parallax(self) -> str:
        """"horizontal" (views vary in θ only, toward the viewer line) or "full" (a grid of views, spec §8)."""
    @property
    def vertical_views(self) -> Optional[int]:
        """Full parallax: vertical views per emitter (W); None for horizontal parallax."""
    @property
    def channels(self) -> list[str]:
        """Colour channel names in sample order ("R", "G", "B" or "Y")."""
    @property
    def wavelengths_m(self) -> list[float]:
        """Each channel's vacuum wavelength, metres."""
    @property
    def shape(self) -> Tuple[int, ...]:
        """The shape of one frame's array: (channels, hololines, emitters, views), or for full parallax
        (channels, hololines, emitters, vertical_views, views)."""
    @property
    def emitter_pitch_m(self) -> float:
        """Distance between emitters along a hololine, metres."""
    @property
    def hololine_pitch_m(self) -> float:
        """Distance between hololines, metres."""
    @property
    def emitter_z_m(self) -> float:
        """z of the emitter plane (positive: in front of the hologram), metres."""
    @property
    def viewer_distance_m(self) -> float:
        """Distance of the viewer line from the hologram, metres."""
    @property
    def view_angles_rad(self) -> list[float]:
        """Every view's horizontal direction, radians, ascending."""
    @property
    def vertical_view_angles_rad(self) -> Optional[list[float]]:
        """Full parallax: every vertical view's direction (φ, from +z toward +y), radians, ascending; None for
        horizontal parallax."""
    @property
    def emitter_x_m(self) -> list[float]:
        """x of every emitter's centre, metres."""
    @property
    def hololine_y_m(self) -> list[float]:
        """y of every hololine (full parallax: emitter row), metres, from hololine 0 at the top downward."""
    def with_vertical_views(self, count: int, cone_rad: Optional[float] = None) -> "Geometry":
        """This geometry made full parallax with `count` vertical views, tan-spaced and centred on the normal over
        cone_rad (default: the horizontal views' cone), as `holo convert cameras --vertical-views N` makes it."""
    def to_dict(self) -> dict[str, Any]:
        """Every field, as the .holo spec names them; Geometry.from_dict takes it back."""
    @staticmethod
    def from_dict(fields: dict[str, Any]) -> "Geometry":
        """The geometry a dict from to_dict describes (checked as a file's is)."""

class HoloFile:
    """A .holo file opened for reading: its header is read and checked, its frames are read when asked for."""

    @property
    def path(self) -> pathlib.Path:
        """The file's path."""
    @property
    def geometry(self) -> Geometry:
        """The geometry."""
    @property
    def frame_count(self) -> int:
        """Frames in the file."""
    def __len__(self) -> int: ...
    def info(self) -> dict[str, Any]:
        """What the header says: version, sample_type, compression, frames, frames_per_second, source,
        software, scale, unit, file_bytes, placement."""
    def frame(self, index: int, dtype: Any = None) -> Frame:
        """Frame `index` as an array [channel, hololine, emitter, view] (full parallax: [channel, hololine,
        emitter, vertical view, view]); its digest is checked. float32 by default; dtype=numpy.float16 hands back
        an f16 file's samples as stored, without a float32 pass."""
    def region(
        self,
        index: int,
        hololines: Optional[Tuple[int, int]] = None,
        emitters: Optional[Tuple[int, int]] = None,
        dtype: Any = None,
        *,
        views: Optional[Tuple[int, int]] = None,
        vertical_views: Optional[Tuple[int, int]] = None,
    ) -> Frame:
        """Hololines, emitters, views and (full parallax) vertical views, each (first, end), default all, of frame
        `index`, with frame()'s axes; float32, or float16 with dtype=numpy.float16. Only the chunks holding those
        hololines are decoded, and of a full-parallax file only those views' parts."""

class Layout:
    """A display layout (spec/layouts.md): the geometry the display expects and its frame buffer; checked when made."""

    @staticmethod
    def load(name_or_path: PathLike) -> "Layout":
        """A built-in layout (mark3, mark1, mark1-hogel, mark2, mark4) or a .toml/.json profile."""
    @staticmethod
    def from_dict(fields: dict[str, Any]) -> "Layout":
        """The layout a dict from to_dict describes, checked as a profile is."""
    def to_dict(self) -> dict[str, Any]:
        """Every field, as a profile file has them."""
    @property
    def name(self) -> str:
        """The layout's name."""
    @property
    def geometry(self) -> Geometry:
        """The modulation geometry the display expects."""
    @property
    def image_names(self) -> list[str]:
        """The frame buffer's image names, in the order assemble returns them."""

def assemble(frame: Floats, layout: Layout, *, samples: str = "u8") -> list[np.ndarray]:
    """One frame into the layout's frame buffer: one array [row, column, component] per image, uint8 codes
    ("u8") or the float signals before quantization ("f32"); the same bytes as `holo assemble`."""

def view(
    frame: Floats,
    layout: Layout,
    eyes_x_m: Sequence[float],
    *,
    distance_m: Optional[float] = None,
    pupil_m: float = 4e-3,
    coherent: bool = False,
) -> list[npt.NDArray[np.float32]]:
    """What eyes at these positions see of the frame on the display: one [hololine, emitter, channel] array
    per eye, 1 for a fully lit emitter; coherent=True lets neighbouring emitters interfere."""

def check(frame: Floats, layout: Layout) -> dict[str, Any]:
    """The frame assembled to 8 bits and recovered two ways: {signal, optical} with relative_l2, psnr_db,
    peak and the worst emitter, and the verdict against spec/layouts.md §9.1's bounds (verdict: bounds,
    signal, optical, pass; None where no bound is stated)."""

Progress = Callable[[str, int, int], Optional[bool]]

def convert_mesh(
    input: PathLike, layout: Layout, output: PathLike, *, overwrite: bool = False, progress: Optional[Progress] = None
) -> dict[str, Any]:
    """A mesh file (glTF, OBJ, PLY) into a new .holo file for the layout's display, with `holo convert mesh`'s
    defaults: {path, frames, triangles, warnings}. progress(phase, done, total) is called as steps finish;
    returning False (or raising) stops the work and leaves no file."""

def render_mesh(
    vertices: npt.NDArray[np.float64],
    faces: npt.ArrayLike,
    layout: Layout,
    *,
    colours: Optional[Floats] = None,
    progress: Optional[Progress] = None,
) -> Frame:
    """A mesh given as arrays (vertices (n, 3), faces (m, 3), optional per-vertex linear RGB(A) colours),
    fitted to the layout's display and rendered with the default lights: one frame for write()."""

def resample_cameras(
    pictures: Sequence[Floats],
    intrinsics: Sequence[npt.ArrayLike],
    poses: Sequence[npt.ArrayLike],
    layout: Layout,
    *,
    metres_per_unit: float = 1.0,
    focus_distance: Optional[float] = None,
    progress: Optional[Progress] = None,
) -> Tuple[Frame, dict[str, Any]]:
    """Pictures of a calibrated rig (linear RGB (height, width, 3) each, 3x3 intrinsics K, 3x4 or 4x4
    world-to-camera [R | t] in OpenCV's convention) resampled into one frame for the layout's display, as
    `holo convert cameras` does: (frame, {placement, surface, rays, unseen, unseen_outside_frame, warnings})."""

def open(path: PathLike) -> HoloFile:
    """Open a .holo file: the header is read and checked now, frames when asked for."""

def write(
    path: PathLike,
    frames: Union[Floats, Sequence[Floats], Iterable[Floats], Iterator[Floats]],
    geometry: Geometry,
    *,
    frame_count: Optional[int] = None,
    sample_type: str = "f16",
    compression: str = "zip",
    source: str = "",
    frames_per_second: Optional[float] = None,
    overwrite: bool = False,
) -> None:
    """Write frames to a new .holo file: one frame (geometry.shape: five axes for full parallax), an array of
    frames, a sequence, or an iterator (give frame_count); frames from an iterator are taken one at a time."""

def validate(path: PathLike) -> dict[str, Any]:
    """Check a .holo file against the spec, every frame and digest: {valid, problems, warnings, frames}."""
