"""holo: the .holo modulation-texture file of holographic stereogram displays, from Python.

A ``.holo`` file (an OpenEXR file, ``spec/holo-format.md``) stores what every emitter of every hololine of a
display sends in every view direction. This package reads and writes them as numpy arrays with the axes
``[channel, hololine, emitter, view]``, in physical units (metres, radians)::

    import holo
    f = holo.open("scene.holo")
    f.geometry.shape            # (channels, hololines, emitters, views)
    frame = f.frame(0)          # numpy float32 array of that shape
    holo.write("copy.holo", frame, f.geometry)  # any real float array: float64 (numpy 2's frame * k) is converted
    mark3 = holo.Layout.load("mark3")
    images = holo.assemble(frame, mark3)      # the display's frame-buffer images, uint8
    seen = holo.view(frame, mark3, [0.0])     # what an eye at x = 0 sees, [hololine, emitter, channel]

A full-parallax file's frames have five axes, ``[channel, hololine, emitter, vertical view, view]``;
``to_axes(frame, "lftoolbox")`` and ``from_axes(array, "lftoolbox")`` convert them to and from the light-field
tools' orders (``AXIS_ORDERS``: the Light Field Toolbox's ``[t, s, v, u, c]``, OLAS's ``[My, Mx, Ny, Nx, C]``).

Heavy calls release the GIL, so other Python threads run meanwhile. Errors are ``holo.HoloError`` or one of
its kinds: ``FileError`` (the operating system refused), ``FormatError`` (not a readable .holo file) and
``InputError`` (an argument or array that does not fit); each message is one sentence naming the file.
"""

from ._axes import AXIS_ORDERS, from_axes, to_axes
from ._holo import (
    FileError,
    FormatError,
    Geometry,
    HoloError,
    HoloFile,
    InputError,
    Layout,
    assemble,
    check,
    convert_mesh,
    open,
    render_mesh,
    resample_cameras,
    validate,
    view,
    write,
)

__all__ = [
    "AXIS_ORDERS",
    "FileError",
    "FormatError",
    "Geometry",
    "HoloError",
    "HoloFile",
    "InputError",
    "Layout",
    "assemble",
    "check",
    "convert_mesh",
    "from_axes",
    "open",
    "render_mesh",
    "resample_cameras",
    "to_axes",
    "validate",
    "view",
    "write",
]
