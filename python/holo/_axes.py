"""Full-parallax frames in the axis orders of the light-field tools, and back (README, "Full parallax").

holo's frame is ``[channel, hololine, emitter, vertical view, view]`` = ``[c, j, e, k, h]``: hololine ``j`` from the
top down, emitter ``e`` from the left, horizontal view ``h`` toward ``+x`` (rightward), vertical view ``k`` toward
``+y`` (upward; spec/holo-format.md §8). An order is those five axes permuted, some of them reversed; the
conversions are numpy views of the same memory, exact both ways.
"""

from typing import Any, Optional

import numpy as np

from ._holo import InputError

# holo's axes, by position in its frame.
_C, _J, _E, _K, _H = range(5)

# Each order: its axes' names, the holo axis at each of its positions, and the holo axes it runs the other way.
_ORDERS = {
    # holo's own frame.
    "holo": ("[channel, hololine, emitter, vertical view, view]", (_C, _J, _E, _K, _H), ()),
    # Dansereau's Light Field Toolbox for MATLAB: LF(t, s, v, u, c), indexed as an image is, I(y, x, c): t and v
    # grow downward as image rows do, s and u rightward. A view's row t grows as the camera goes down, so it sees
    # rays heading down: t runs against k.
    "lftoolbox": ("[t, s, v, u, c]", (_K, _H, _J, _E, _C), (_K,)),
    # OLAS (Padmanaban, Peng and Wetzstein 2019), the array its holographic_stereogram_* functions take:
    # lightField [My, Mx, Ny, Nx, C], My x Mx angular samples (views), Ny x Nx spatial (rows down, columns right).
    # Its demo loads camera rows top first and columns left first, then flips both view axes
    # (load_unity_light_field(..., flipLFOutput=true)), so My grows upward (with k) and Mx leftward (against h).
    "olas": ("[My, Mx, Ny, Nx, C]", (_K, _H, _J, _E, _C), (_H,)),
}

AXIS_ORDERS = {name: axes for name, (axes, _, _) in _ORDERS.items()}
"""Every order ``to_axes`` and ``from_axes`` know, with its axes' names."""


def _order(order: str):
    try:
        return _ORDERS[order]
    except KeyError:
        raise InputError(f"axis order {order!r}: give one of {', '.join(map(repr, _ORDERS))}") from None


def _array(array: Any, what: str) -> np.ndarray:
    if not hasattr(array, "shape"):
        raise InputError(f"{what}: not a numpy array; give one of five axes")
    return np.asarray(array)


def to_axes(frame: Any, order: str) -> np.ndarray:
    """``frame`` (``[channel, hololine, emitter, vertical view, view]``, as ``HoloFile.frame`` reads a full-parallax
    one; a horizontal-parallax frame's four axes are taken as one vertical view) with its axes in ``order``, one
    of ``AXIS_ORDERS``: a view of the same samples (``numpy.ascontiguousarray`` makes a copy)."""
    _, positions, reversed_axes = _order(order)
    frame = _array(frame, "frame")
    if frame.ndim == 4:
        frame = frame[:, :, :, np.newaxis, :]
    if frame.ndim != 5:
        raise InputError(
            f"frame: an array of {frame.ndim} axes; give a frame of 5, [channel, hololine, emitter, vertical view, "
            "view] (or 4, horizontal parallax)"
        )
    return np.flip(frame, reversed_axes).transpose(positions)


def from_axes(array: Any, order: str, geometry: Optional[Any] = None) -> np.ndarray:
    """``array``, five axes in ``order`` (one of ``AXIS_ORDERS``), as holo's frame ``[channel, hololine, emitter,
    vertical view, view]``: a view of the same samples, which ``write`` takes. With ``geometry``, its shape must
    be that geometry's frames', and a horizontal-parallax geometry's frame comes back with its four axes."""
    names, positions, reversed_axes = _order(order)
    array = _array(array, "array")
    if array.ndim != 5:
        raise InputError(f"array: an array of {array.ndim} axes; an array in order {order!r} has 5, {names}")
    frame = np.flip(array.transpose(np.argsort(positions)), reversed_axes)
    if geometry is None:
        return frame
    want = tuple(geometry.shape)
    want5 = want if len(want) == 5 else want[:3] + (1,) + want[3:]
    if frame.shape != want5:
        expected = tuple(want5[p] for p in positions)
        raise InputError(
            f"array: shape {array.shape} {names}; the geometry's frames are {expected} in that order"
        )
    return frame[:, :, :, 0, :] if len(want) == 4 else frame
