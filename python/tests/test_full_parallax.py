"""Full-parallax frames (spec/holo-format.md §8) from Python: five axes, regions by rows and by views, writing, and
the light-field tools' axis orders (README, "Full parallax"), checked against OpenEXR's own reading of each view.

Every array written here says in each sample where it stands (`encoded`), so a sample put in the wrong place
cannot pass for a right one; none is zero.
"""

import re
import subprocess

import numpy as np
import OpenEXR
import pytest

import holo
from test_holo import FIXTURES, cli

FULL_FIXTURES = sorted((FIXTURES / "v1.3").glob("*.holo"))


def encoded(shape):
    """An array of `shape` (every axis under 10 long) whose sample at index (i0, i1, …) is 1 + the number with
    those digits, i0 first: exact in float32, never zero."""
    digits = np.indices(shape)
    return (1 + sum(d * 10 ** (len(shape) - 1 - a) for a, d in enumerate(digits))).astype(np.float32)


def full_geometry(vertical_views=2):
    """A small RGB full-parallax geometry whose axes all differ in length: 3 channels × 4 hololines × 6 emitters
    × 2 vertical × 5 horizontal views (from the bundled fixture's numbers, which are known good)."""
    d = holo.open(FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo").geometry.to_dict()
    d.update(hololines=4, emitters=6)
    d["views"]["count"] = 5
    return holo.Geometry.from_dict(d).with_vertical_views(vertical_views)


def openexr_views(path):
    """Every view of every frame of a full-parallax file, read by OpenEXR alone: {(frame, h, k): [channel, row,
    column] float32} (spec §8: part (f·W + k)·V + h holds view (h, k) of frame f, its channels the colours, +0.0
    outside its data window)."""
    f = OpenEXR.File(str(path), separate_channels=True)
    views = {}
    for p, part in enumerate(f.parts):
        header = part.header
        v, w = int(header["holo.views"]), int(header["holo.viewsVertical"])
        frame, k, h = p // (v * w), p // v % w, p % v
        assert tuple(int(x) for x in header["holo.view"]) == (h, k), (p, header["holo.view"])
        (x0, y0), (x1, y1) = (tuple(map(int, b)) for b in header["displayWindow"])
        (dx0, dy0), (dx1, dy1) = (tuple(map(int, b)) for b in header["dataWindow"])
        order = [c for c in ["R", "G", "B", "Y"] if c in part.channels]
        out = np.zeros((len(order), y1 - y0 + 1, x1 - x0 + 1), dtype=np.float32)
        for c, colour in enumerate(order):
            out[c, dy0 - y0 : dy1 - y0 + 1, dx0 - x0 : dx1 - x0 + 1] = part.channels[colour].pixels.astype(np.float32)
        views[(frame, h, k)] = out
    return views


def test_a_full_parallax_file_reads_as_five_axes_equal_to_openexrs_views():
    assert FULL_FIXTURES, "the bundled full-parallax fixtures are missing"
    for path in FULL_FIXTURES:
        f = holo.open(path)
        g = f.geometry
        assert g.parallax == "full" and f.info()["version"] == (1, 3)
        assert g.shape == (len(g.channels), g.hololines, g.emitters, g.vertical_views, g.views)
        lossy = f.info()["compression"] in ("b44", "b44a", "dwaa", "dwab", "pxr24")
        for (i, h, k), want in openexr_views(path).items():
            got = f.frame(i)
            assert got.shape == g.shape and got.dtype == np.float32
            # A lossy codec's small negative undershoot reads as +0 (spec §3.4).
            want = np.where(want < 0, np.float32(0), want) if lossy else want
            assert np.array_equal(got[:, :, :, k, h], want), (path, i, h, k)
            halves = f.frame(i, dtype=np.float16)
            assert halves.shape == g.shape and np.array_equal(halves, got.astype(np.float16)), path
    # Horizontal parallax is as it was: four axes, no vertical views.
    hp = holo.open(FIXTURES / "v1.2" / "frames-rgb-f32-zip.holo")
    g = hp.geometry
    assert g.parallax == "horizontal" and g.vertical_views is None and g.vertical_view_angles_rad is None
    assert g.shape == (3, g.hololines, g.emitters, g.views) and hp.frame(0).shape == g.shape


def test_full_parallax_frames_are_written_and_read_back_exactly(tmp_path):
    g = full_geometry()
    assert g.shape == (3, 4, 6, 2, 5)
    frames = [encoded(g.shape) + 100000 * i for i in range(3)]
    # One frame, an array of frames (one more leading axis), a sequence, and a generator.
    for name, given, count in [
        ("one", frames[0], 1),
        ("stacked", np.stack(frames), 3),
        ("list", frames, 3),
        ("generator", (x for x in frames), 3),
    ]:
        path = tmp_path / f"{name}.holo"
        holo.write(path, given, g, frame_count=count, sample_type="f32", compression="zip")
        back = holo.open(path)
        assert back.geometry == g and back.frame_count == count, name
        for i in range(count):
            assert back.frame(i).tobytes() == frames[i].tobytes(), (name, i)
        for (i, h, k), pixels in openexr_views(path).items():
            assert np.array_equal(pixels, frames[i][:, :, :, k, h]), (name, i, h, k)
        assert holo.validate(path)["valid"], name
    run = subprocess.run([cli(), "validate", str(tmp_path / "stacked.holo")], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


def test_a_frame_of_the_wrong_shape_is_refused_naming_both(tmp_path):
    g = full_geometry()
    axes = "[channel, hololine, emitter, vertical view, view]"
    # A horizontal-parallax frame (four axes) for a full-parallax geometry.
    with pytest.raises(holo.InputError, match=re.escape(f"an array of shape [3, 4, 6, 5]; the geometry's frames are [3, 4, 6, 2, 5] {axes}")):
        holo.write(tmp_path / "x.holo", np.ones((3, 4, 6, 5), np.float32), g)
    # Five axes, the views' two swapped.
    with pytest.raises(holo.InputError, match=re.escape(f"frame 0: an array of shape [3, 4, 6, 5, 2]; the geometry's frames are [3, 4, 6, 2, 5] {axes}")):
        holo.write(tmp_path / "x.holo", np.ones((3, 4, 6, 5, 2), np.float32), g)
    bad = encoded(g.shape)
    bad[1, 2, 3, 1, 4] = np.nan
    with pytest.raises(holo.InputError, match="hololine 2"):
        holo.write(tmp_path / "nan.holo", bad, g)
    assert list(tmp_path.iterdir()) == []


def test_regions_read_rows_and_views(tmp_path):
    g = full_geometry()
    path = tmp_path / "full.holo"
    frames = [encoded(g.shape) + 100000 * i for i in range(2)]
    holo.write(path, frames, g, sample_type="f32")
    f = holo.open(path)
    whole = f.frame(1)
    assert np.array_equal(f.region(1, hololines=(1, 3)), whole[:, 1:3])
    part = f.region(1, hololines=(1, 3), emitters=(2, 5), views=(1, 4), vertical_views=(1, 2))
    assert part.shape == (3, 2, 3, 1, 3) and np.array_equal(part, whole[:, 1:3, 2:5, 1:2, 1:4])
    assert np.array_equal(f.region(1, views=(4, 5)), whole[..., 4:5])
    # (Frame 0's samples are small enough for float16.)
    halves = f.region(0, vertical_views=(0, 1), dtype=np.float16)
    assert halves.dtype == np.float16 and np.array_equal(halves, frames[0][:, :, :, 0:1].astype(np.float16))
    with pytest.raises(holo.InputError, match=r"region .*views 0\.\.9"):
        f.region(1, views=(0, 9))
    # Horizontal parallax: views too, and no vertical views.
    hp = holo.open(FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo")
    assert np.array_equal(hp.region(1, hololines=(1, 3), views=(1, 3)), hp.frame(1)[:, 1:3, :, 1:3])
    with pytest.raises(holo.InputError, match="horizontal parallax"):
        hp.region(1, vertical_views=(0, 1))


def test_the_geometry_says_its_parallax_and_a_dict_carries_it():
    g = full_geometry(vertical_views=3)
    assert g.parallax == "full" and g.vertical_views == 3 and g.views == 5
    phi = g.vertical_view_angles_rad
    # Centred on the normal, over the horizontal views' cone, ascending (view 0 looks down the most).
    assert len(phi) == 3 and phi[0] < phi[1] < phi[2] and abs(phi[1]) < 1e-15 and phi[0] == pytest.approx(-phi[2])
    assert phi[2] - phi[0] == pytest.approx(g.view_angles_rad[-1] - g.view_angles_rad[0])
    y = g.hololine_y_m
    assert len(y) == g.hololines and all(a > b for a, b in zip(y, y[1:]))
    d = g.to_dict()
    assert d["parallax"] == "full" and d["vertical_views"]["count"] == 3
    assert holo.Geometry.from_dict(d) == g and "3 vertical views" in repr(g)
    hp = holo.open(FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo").geometry
    assert hp.to_dict()["parallax"] == "horizontal" and "vertical_views" not in hp.to_dict()
    assert "vertical" not in repr(hp)
    with pytest.raises(holo.InputError, match="full parallax needs vertical view directions"):
        holo.Geometry.from_dict(dict(hp.to_dict(), parallax="full"))
    with pytest.raises(holo.InputError, match="vertical view count is zero"):
        hp.with_vertical_views(0)
    assert hp.with_vertical_views(2, cone_rad=0.1).vertical_view_angles_rad == pytest.approx([-0.05, 0.05])


def test_each_axis_order_puts_every_sample_where_its_table_says():
    C, H, E, W, V = shape = full_geometry().shape
    frame = encoded(shape)
    assert set(holo.AXIS_ORDERS) == {"holo", "lftoolbox", "olas"}
    # Light Field Toolbox, LF[t, s, v, u, c]: t the view row, counted downward (against k).
    lf = holo.to_axes(frame, "lftoolbox")
    t, s, v, u, c = np.indices(lf.shape)
    assert lf.shape == (W, V, H, E, C) and np.array_equal(lf, frame[c, v, u, W - 1 - t, s])
    # OLAS, lightField[My, Mx, Ny, Nx, C]: Mx the view column, counted leftward (against h).
    ol = holo.to_axes(frame, "olas")
    my, mx, ny, nx, c = np.indices(ol.shape)
    assert ol.shape == (W, V, H, E, C) and np.array_equal(ol, frame[c, ny, nx, my, V - 1 - mx])
    assert np.array_equal(holo.to_axes(frame, "holo"), frame)
    for order in holo.AXIS_ORDERS:
        # Views of the same samples, and exact both ways.
        there = holo.to_axes(frame, order)
        assert np.shares_memory(there, frame), order
        assert np.array_equal(holo.from_axes(there, order), frame), order
        theirs = encoded(there.shape)
        assert np.array_equal(holo.to_axes(holo.from_axes(theirs, order), order), theirs), order


def test_each_axis_order_points_where_its_table_says():
    # The samples of a frame set to each axis' physical quantity: view directions φ (up) and θ (right), and
    # the emitters' y and x. Along each of an order's axes they must run as the README's table says.
    g = full_geometry(vertical_views=3)
    C, H, E, W, V = g.shape
    quantities = {
        "phi": np.array(g.vertical_view_angles_rad)[None, None, None, :, None],
        "theta": np.array(g.view_angles_rad)[None, None, None, None, :],
        "y": np.array(g.hololine_y_m)[None, :, None, None, None],
        "x": np.array(g.emitter_x_m)[None, None, :, None, None],
    }
    frames = {name: np.broadcast_to(q, g.shape) for name, q in quantities.items()}

    def along(order, name, axis):
        a = np.moveaxis(holo.to_axes(frames[name], order), axis, 0)
        return a.reshape(a.shape[0], -1)[:, 0]

    def rises(x):
        return bool(np.all(np.diff(x) > 0))

    def falls(x):
        return bool(np.all(np.diff(x) < 0))

    # [t, s, v, u, c]: t downward, s rightward, v downward, u rightward.
    assert falls(along("lftoolbox", "phi", 0)) and rises(along("lftoolbox", "theta", 1))
    assert falls(along("lftoolbox", "y", 2)) and rises(along("lftoolbox", "x", 3))
    # [My, Mx, Ny, Nx, C]: My upward, Mx leftward, Ny downward, Nx rightward.
    assert rises(along("olas", "phi", 0)) and falls(along("olas", "theta", 1))
    assert falls(along("olas", "y", 2)) and rises(along("olas", "x", 3))


def test_axis_orders_refuse_what_they_cannot_convert():
    g = full_geometry()
    frame = encoded(g.shape)
    with pytest.raises(holo.InputError, match="'lftoolbox'"):
        holo.to_axes(frame, "tsvuc")
    with pytest.raises(holo.InputError, match="3 axes"):
        holo.to_axes(frame[0, 0], "olas")
    with pytest.raises(holo.InputError, match="not a numpy array"):
        holo.from_axes([[1.0]], "olas")
    # With a geometry, the shape is checked, said in the order's own axes.
    wrong = np.ones((5, 2, 4, 6, 3), np.float32)
    with pytest.raises(holo.InputError, match=re.escape("shape (5, 2, 4, 6, 3) [t, s, v, u, c]; the geometry's frames are (2, 5, 4, 6, 3)")):
        holo.from_axes(wrong, "lftoolbox", g)
    # A horizontal-parallax frame is one row of views, and comes back with its four axes.
    hp = holo.open(FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo")
    f = hp.frame(1)
    lf = holo.to_axes(f, "lftoolbox")
    assert lf.shape == (1, hp.geometry.views, hp.geometry.hololines, hp.geometry.emitters, 3)
    assert np.array_equal(holo.from_axes(lf, "lftoolbox", hp.geometry), f)


@pytest.mark.parametrize("order", ["lftoolbox", "olas"])
def test_a_file_written_from_a_toolbox_ordered_array_reads_back_equal(tmp_path, order):
    g = full_geometry(vertical_views=3)
    C, H, E, W, V = g.shape
    theirs = encoded(holo.to_axes(np.empty(g.shape, np.float32), order).shape)
    path = tmp_path / f"{order}.holo"
    holo.write(path, holo.from_axes(theirs, order, g), g, sample_type="f32")
    assert np.array_equal(holo.to_axes(holo.open(path).frame(0), order), theirs)
    # Each stored view, as OpenEXR reads it, is the toolbox's picture of that view.
    for (_, h, k), pixels in openexr_views(path).items():
        if order == "lftoolbox":
            want = theirs[W - 1 - k, h]
        else:
            want = theirs[k, V - 1 - h]
        assert np.array_equal(pixels, np.moveaxis(want, -1, 0)), (h, k)
