"""The holo Python package against OpenEXR's own Python bindings and the holo command line.

Run by .ci/python.sh in a fresh virtual environment: `pip install ./python pytest OpenEXR`, then
`HOLO_CLI=target/debug/holo pytest python/tests`. HOLO_CLI must name the command-line tool: the tests that run
it fail, not skip, without it.
"""

import subprocess
import threading
import time

import numpy as np
import OpenEXR
import pytest

import holo
from clitool import FIXTURES, cli


def openexr_frames(path):
    """Every part of a .holo file as [channel, hololine, emitter, view] float32, read by OpenEXR alone
    (spec/holo-format.md: channels `v{view}.{colour}`, pixel (x, y) = emitter x on hololine y, one part per
    frame, +0.0 outside a part's data window)."""
    f = OpenEXR.File(str(path), separate_channels=True)
    frames = []
    for part in f.parts:
        h = part.header
        (x0, y0), (x1, y1) = (tuple(map(int, b)) for b in h["displayWindow"])
        (dx0, dy0), (dx1, dy1) = (tuple(map(int, b)) for b in h["dataWindow"])
        colours = sorted({name.split(".")[1] for name in part.channels})
        order = [c for c in ["R", "G", "B", "Y"] if c in colours]
        views = int(h["holo.views"])
        digits = max(3, len(str(views - 1)))
        out = np.zeros((len(order), y1 - y0 + 1, x1 - x0 + 1, views), dtype=np.float32)
        for c, colour in enumerate(order):
            for v in range(views):
                pixels = part.channels[f"v{v:0{digits}d}.{colour}"].pixels.astype(np.float32)
                out[c, dy0 - y0 : dy1 - y0 + 1, dx0 - x0 : dx1 - x0 + 1, v] = pixels
        frames.append(out)
    return frames


def random_geometry():
    """A small RGB geometry: the bundled fixture's, whose numbers are known good."""
    return holo.open(FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo").geometry


@pytest.mark.parametrize("sample_type", ["f16", "f32"])
@pytest.mark.parametrize("compression", ["none", "zip", "piz"])
def test_a_written_file_reads_back_bit_exact_through_openexr_and_validates(tmp_path, sample_type, compression):
    g = random_geometry()
    rng = np.random.default_rng(7)
    frames = [rng.uniform(0.0, 2.0, size=g.shape).astype(np.float32) for _ in range(3)]
    if sample_type == "f16":
        frames = [f.astype(np.float16).astype(np.float32) for f in frames]
    path = tmp_path / "written.holo"
    holo.write(path, frames, g, sample_type=sample_type, compression=compression, frames_per_second=24)
    for want, got in zip(frames, openexr_frames(path)):
        assert got.tobytes() == want.tobytes()
    back = holo.open(path)
    assert back.frame_count == 3 and back.info()["compression"] == compression
    for i, want in enumerate(frames):
        assert back.frame(i).tobytes() == want.tobytes()
    assert holo.validate(path)["valid"]
    run = subprocess.run([cli(), "validate", str(path)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr


def test_a_frame_read_by_the_package_equals_openexrs_samples():
    paths = [p for v in ("v1.2", "v1.1", "v1.0") for p in sorted((FIXTURES / v).glob("*.holo"))]
    assert paths, "the bundled .holo fixtures are missing"
    for path in paths:
        f = holo.open(path)
        theirs = openexr_frames(path)
        assert f.frame_count == len(theirs)
        for i, want in enumerate(theirs):
            got = f.frame(i)
            assert got.shape == f.geometry.shape and got.dtype == np.float32
            # A lossy codec's small negative undershoot reads as +0 (spec §3.4).
            want = np.where(want < 0, np.float32(0), want) if f.info()["compression"] in ("b44", "b44a", "dwaa", "dwab", "pxr24") else want
            assert np.array_equal(got, want), path


def test_float16_frames_are_the_stored_samples_without_a_float32_pass(tmp_path):
    # An f16 file: float16 arrays equal OpenEXR's own float16 channels, bit for bit, whole and in part.
    g = random_geometry()
    rng = np.random.default_rng(11)
    want = rng.uniform(0.0, 3.0, size=g.shape).astype(np.float16)
    path = tmp_path / "halves.holo"
    holo.write(path, want.astype(np.float32), g, sample_type="f16", compression="zip")
    f = holo.open(path)
    for dtype in (np.float16, "float16", "f2", np.dtype("<f2")):
        got = f.frame(0, dtype=dtype)
        assert got.dtype == np.float16 and got.shape == g.shape
        assert got.tobytes() == want.tobytes()
    theirs = OpenEXR.File(str(path), separate_channels=True).parts[0].channels
    assert theirs["v000.R"].pixels.dtype == np.float16
    assert np.array_equal(got[0, :, :, 0], theirs["v000.R"].pixels)
    part = f.region(0, hololines=(1, 3), emitters=(2, 5), dtype=np.float16)
    assert part.dtype == np.float16 and np.array_equal(part, want[:, 1:3, 2:5, :])
    assert f.frame(0, dtype=np.float32).dtype == np.float32 and f.frame(0).dtype == np.float32
    # An f32 file read as float16 is rounded; a sample float16 cannot hold is an error, not infinity.
    g32 = holo.open(FIXTURES / "v1.2" / "frames-rgb-f32-zip.holo")
    assert np.array_equal(g32.frame(1, dtype=np.float16), g32.frame(1).astype(np.float16))
    big = np.full(g.shape, 1.0, dtype=np.float32)
    big[0, 1, 2, 0] = 1e6
    holo.write(tmp_path / "big.holo", big, g, sample_type="f32")
    with pytest.raises(holo.InputError, match="too large for f16"):
        holo.open(tmp_path / "big.holo").frame(0, dtype=np.float16)
    with pytest.raises(holo.InputError, match="float32 or float16"):
        f.frame(0, dtype=np.int32)
    # A damaged f16 file is refused in float16 too: the digest is checked.
    data = bytearray(path.read_bytes())
    data[-3] ^= 0x01
    (tmp_path / "damaged.holo").write_bytes(bytes(data))
    with pytest.raises(holo.FormatError):
        holo.open(tmp_path / "damaged.holo").frame(0, dtype=np.float16)


def test_a_region_is_that_part_of_the_frame():
    f = holo.open(FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo")
    whole = f.frame(1)
    part = f.region(1, hololines=(1, 3), emitters=(2, 5))
    assert np.array_equal(part, whole[:, 1:3, 2:5, :])


def test_frames_stream_from_a_generator_one_at_a_time(tmp_path):
    g = random_geometry()
    made = []

    def frames():
        for i in range(4):
            made.append(i)
            yield np.full(g.shape, i / 4, dtype=np.float32)

    path = tmp_path / "stream.holo"
    holo.write(str(path), frames(), g, frame_count=4)
    f = holo.open(path)
    assert made == [0, 1, 2, 3] and f.frame_count == 4
    assert all(float(f.frame(i)[0, 0, 0, 0]) == i / 4 for i in range(4))


def test_any_real_float_array_is_taken_converted_to_float32(tmp_path):
    g = random_geometry()
    frame = np.random.default_rng(3).uniform(0.0, 2.0, size=g.shape)
    # float64 (numpy 2 makes `frame * k` so for a float64 k), float16, and float arrays in any memory order.
    wide = np.concatenate([frame, frame], axis=3)
    for name, array in {
        "f64": frame,
        "f16": frame.astype(np.float16),
        "fortran": np.asfortranarray(frame.astype(np.float32)),
        "strided": wide[..., : g.shape[3]],
        "reversed": frame[:, ::-1].copy()[:, ::-1],
        "longdouble": frame.astype(np.longdouble),
    }.items():
        path = tmp_path / f"{name}.holo"
        holo.write(path, array, g, sample_type="f32")
        assert np.array_equal(holo.open(path).frame(0), array.astype(np.float32)), name
    # The README's example: frames streamed from a generator of float64 products.
    f32 = frame.astype(np.float32)
    path = tmp_path / "scaled.holo"
    holo.write(path, (f32 * k for k in np.linspace(0, 1, 3)), g, frame_count=3, sample_type="f32")
    back = holo.open(path)
    for i, k in enumerate(np.linspace(0, 1, 3)):
        assert np.array_equal(back.frame(i), (f32 * k).astype(np.float32)), i
    # The calls that take a frame, colours or pictures take them too.
    layout = holo.Layout.load("mark1")
    ramp = np.linspace(0.0, 1.0, int(np.prod(layout.geometry.shape))).reshape(layout.geometry.shape)
    for a, b in zip(holo.assemble(ramp, layout), holo.assemble(ramp.astype(np.float32), layout)):
        assert np.array_equal(a, b)
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    red = np.tile([[1.0, 0.0, 0.0]], (4, 1))
    assert np.array_equal(
        holo.render_mesh(vertices, faces, layout, colours=red),
        holo.render_mesh(vertices, faces, layout, colours=red.astype(np.float32)),
    )


def test_geometry_round_trips_through_a_dict():
    g = random_geometry()
    d = g.to_dict()
    assert d["emitters"] == g.emitters and d["hololines"] == g.hololines
    assert holo.Geometry.from_dict(d) == g
    # Checked without making a frame of it: a geometry far too large is refused, not allocated.
    huge = dict(d, emitters=10**9, hololines=10**9)
    with pytest.raises(holo.InputError, match="geometry"):
        holo.Geometry.from_dict(huge)
    assert len(g.view_angles_rad) == g.views and len(g.emitter_x_m) == g.emitters
    assert g.emitter_pitch_m > 0 and g.viewer_distance_m > 0 and all(w > 0 for w in g.wavelengths_m)


def test_bad_input_raises_the_documented_exception_naming_the_file(tmp_path):
    missing = tmp_path / "missing.holo"
    with pytest.raises(holo.FileError, match="missing.holo"):
        holo.open(missing)
    garbage = tmp_path / "garbage.holo"
    garbage.write_bytes(b"not an EXR file at all" * 10)
    with pytest.raises(holo.FormatError, match="garbage.holo"):
        holo.open(garbage)
    truncated = tmp_path / "truncated.holo"
    whole = (FIXTURES / "v1.1" / "frames-rgb-f32-zip.holo").read_bytes()
    truncated.write_bytes(whole[: len(whole) // 2])
    with pytest.raises(holo.HoloError, match="truncated.holo"):
        holo.open(truncated).frame(1)
    g = random_geometry()
    with pytest.raises(holo.InputError, match="shape"):
        holo.write(tmp_path / "x.holo", np.zeros((1, 2, 3, 4), np.float32), g)
    with pytest.raises(holo.InputError, match="int32 samples; give real floating-point ones"):
        holo.write(tmp_path / "x.holo", np.zeros(g.shape, np.int32), g)
    with pytest.raises(holo.InputError, match="frame 0: not a numpy array"):
        holo.write(tmp_path / "x.holo", [[1.0]], g)
    with pytest.raises(holo.InputError, match="compression"):
        holo.write(tmp_path / "x.holo", np.zeros(g.shape, np.float32), g, compression="gzip")
    bad = np.zeros(g.shape, np.float32)
    bad[0, 1, 2, 0] = np.nan
    with pytest.raises(holo.InputError, match="hololine 1"):
        holo.write(tmp_path / "nan.holo", bad, g)
    assert not (tmp_path / "nan.holo").exists() and not (tmp_path / "x.holo").exists()
    # A file that exists is not replaced unless asked.
    kept = tmp_path / "kept.holo"
    kept.write_bytes(b"mine")
    with pytest.raises(holo.FileError, match="kept.holo"):
        holo.write(kept, np.zeros(g.shape, np.float32), g)
    assert kept.read_bytes() == b"mine"
    # Every kind is a HoloError.
    assert issubclass(holo.FileError, holo.HoloError) and issubclass(holo.InputError, holo.HoloError)


def test_an_iterators_own_exception_comes_through_and_nothing_is_left(tmp_path):
    g = random_geometry()

    def frames():
        yield np.zeros(g.shape, np.float32)
        raise KeyError("the renderer stopped")

    path = tmp_path / "partial.holo"
    with pytest.raises(KeyError, match="renderer stopped"):
        holo.write(path, frames(), g, frame_count=3)
    assert list(tmp_path.iterdir()) == []


def ticks_beside(work):
    """Run `work` in a thread while this one ticks every millisecond: (ticks, seconds the work took)."""
    ticks = []
    done = threading.Event()

    def run():
        try:
            work()
        finally:
            done.set()

    t = threading.Thread(target=run)
    started = time.perf_counter()
    t.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    t.join()
    return ticks, time.perf_counter() - started


def test_heavy_work_leaves_other_python_threads_running(tmp_path):
    # A large frame written with zip (seconds of work in the library): while it
    # runs, another Python thread must get the interpreter.
    g0 = random_geometry().to_dict()
    g0.update(emitters=600, hololines=400)
    g0["views"]["count"] = 32
    g = holo.Geometry.from_dict(g0)
    frame = np.random.default_rng(1).uniform(0, 1, size=g.shape).astype(np.float32)
    ticks, elapsed = ticks_beside(lambda: holo.write(tmp_path / "big.holo", frame, g, sample_type="f32", compression="zip"))
    assert elapsed > 0.2, f"the write took only {elapsed:.3f} s: too short to tell"
    # With the GIL held for the whole write, the loop above would have run once or twice.
    assert len(ticks) > 0.3 * elapsed / 0.001 * 0.5, f"{len(ticks)} ticks in {elapsed:.2f} s"


def test_conversion_and_assembly_give_the_clis_bytes_on_the_bundled_spot(tmp_path):
    spot = FIXTURES / "mesh" / "spot" / "spot.obj"
    layout = holo.Layout.load("mark1")
    report = holo.convert_mesh(spot, layout, tmp_path / "package.holo")
    assert report["triangles"] > 100 and report["frames"] == (0, 1)
    run = subprocess.run(
        [cli(), "convert", "mesh", str(spot), "--layout", "mark1", "-o", str(tmp_path / "cli.holo")],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    ours, theirs = holo.open(tmp_path / "package.holo"), holo.open(tmp_path / "cli.holo")
    assert np.array_equal(ours.frame(0), theirs.frame(0))
    assert (tmp_path / "package.holo").read_bytes() == (tmp_path / "cli.holo").read_bytes()
    run = subprocess.run(
        [cli(), "assemble", str(tmp_path / "cli.holo"), "--layout", "mark1", "--format", "raw", "-o", str(tmp_path / "fringes")],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    images = holo.assemble(ours.frame(0), layout)
    assert len(images) == len(layout.image_names) == 3
    for name, image in zip(layout.image_names, images):
        raw = (tmp_path / "fringes" / f"frame0000-{name}.raw").read_bytes()
        assert image.dtype == np.uint8 and image.tobytes() == raw, name


def test_layouts_view_and_check_from_python():
    layout = holo.Layout.load("mark1")
    d = layout.to_dict()
    assert d["name"] == "mark1" and holo.Layout.from_dict(d).geometry == layout.geometry
    g = layout.geometry
    frame = np.full(g.shape, 0.5, dtype=np.float32)
    seen = holo.view(frame, layout, [0.0, 0.02])
    assert len(seen) == 2 and seen[0].shape == (g.hololines, g.emitters, len(g.channels))
    middle = seen[0][:, g.emitters // 4 : 3 * g.emitters // 4, :]
    assert abs(float(middle.mean()) - 0.5) < 0.1
    report = holo.check(frame, layout)
    assert report["signal"]["relative_l2"] < 0.012 and report["optical"]["relative_l2"] < 0.06
    with pytest.raises(holo.InputError, match="layout"):
        bad = layout.to_dict()
        bad["geometry"]["emitters"] = 10**6
        holo.Layout.from_dict(bad)
    with pytest.raises(holo.HoloError, match="nosuchlayout"):
        holo.Layout.load("nosuchlayout")


def test_assembly_in_a_thread_does_not_block_another_python_thread():
    layout = holo.Layout.load("mark3")
    frame = np.random.default_rng(3).uniform(0, 1, size=layout.geometry.shape).astype(np.float32)
    ticks, elapsed = ticks_beside(lambda: [holo.assemble(frame, layout) for _ in range(5)])
    assert elapsed > 0.05, f"assembly took only {elapsed:.3f} s: too short to tell"
    assert len(ticks) > 0.15 * elapsed / 0.001, f"{len(ticks)} ticks in {elapsed:.2f} s"


def test_a_mesh_from_arrays_renders_and_progress_can_stop_the_work(tmp_path):
    layout = holo.Layout.load("mark1")
    # A tetrahedron, red.
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    colours = np.tile(np.array([[1.0, 0.0, 0.0]], dtype=np.float32), (4, 1))
    seen = []
    frame = holo.render_mesh(vertices, faces, layout, colours=colours, progress=lambda p, d, t: seen.append((p, d, t)))
    assert frame.shape == layout.geometry.shape and frame.dtype == np.float32
    r, g, b = (float(frame[c].sum()) for c in range(3))
    # Red but for the default material's white specular highlights.
    assert r > 0 and g < 1e-3 * r and b < 1e-3 * r, (r, g, b)
    assert seen and seen[-1][1] == seen[-1][2], seen[-3:]
    # The library's threads finish steps in any order; the callback sees the count rise within a phase.
    for (p0, d0, _), (p1, d1, _) in zip(seen, seen[1:]):
        assert p0 != p1 or d1 > d0, seen
    with pytest.raises(holo.InputError, match="vertex 9"):
        holo.render_mesh(vertices, np.array([[0, 1, 9]]), layout)
    # Stopped by the callback: nothing is written.
    out = tmp_path / "stopped.holo"
    with pytest.raises(holo.HoloError, match="cancelled"):
        holo.convert_mesh(FIXTURES / "mesh" / "spot" / "spot.obj", layout, out, progress=lambda p, d, t: d < 3)
    assert not out.exists() and list(tmp_path.iterdir()) == []


def wall_rig(colour_at, n=9, width=128, height=128, focal=100.0):
    """Cameras along x at z = 1 looking down −z at a painted wall z = 0 (OpenCV convention: x right, y down,
    z forward), each picture rendered here by tracing its pixels to the wall."""
    R = np.array([[1.0, 0, 0], [0, -1.0, 0], [0, 0, -1.0]])
    K = np.array([[focal, 0, (width - 1) / 2], [0, focal, (height - 1) / 2], [0, 0, 1.0]])
    pictures, intrinsics, poses = [], [], []
    v, u = np.mgrid[0:height, 0:width]
    rays_camera = np.stack([(u - K[0, 2]) / focal, (v - K[1, 2]) / focal, np.ones_like(u, dtype=float)], axis=-1)
    for k in range(n):
        centre = np.array([0.04 * (k - (n - 1) / 2), 0.0, 1.0])
        t = -R @ centre
        rays = rays_camera @ R  # world directions: Rᵀ d for each pixel
        s = -centre[2] / rays[..., 2]
        x, y = centre[0] + s * rays[..., 0], centre[1] + s * rays[..., 1]
        pictures.append(colour_at(x, y).astype(np.float32))
        intrinsics.append(K)
        poses.append(np.hstack([R, t[:, None]]))
    return pictures, intrinsics, poses


def test_a_camera_rig_from_arrays_resamples_into_a_frame():
    layout = holo.Layout.load("mark1")
    colour = np.array([0.3, 0.5, 0.7], dtype=np.float32)
    pictures, intrinsics, poses = wall_rig(lambda x, y: np.broadcast_to(colour, x.shape + (3,)))
    frame, report = holo.resample_cameras(pictures, intrinsics, poses, layout, focus_distance=1.0)
    assert frame.shape == layout.geometry.shape
    # Wide cameras (65°) see the whole focus plane from every eye position.
    assert report["rays"] > 0 and report["unseen"] < 0.1 * report["rays"], report
    # A wall of one colour is that colour wherever a camera sees it.
    for c in range(3):
        seen = frame[c][frame[c] > 0]
        assert seen.size > 0.9 * frame[c].size and np.allclose(seen, colour[c], rtol=1e-5), (c, seen.min(), seen.max())
    with pytest.raises(holo.InputError, match="one of each per camera"):
        holo.resample_cameras(pictures, intrinsics[:2], poses, layout)
    with pytest.raises(holo.InputError, match="picture 0"):
        holo.resample_cameras([p[..., :2].copy() for p in pictures], intrinsics, poses, layout)
    # Pictures in float64 (as `image / 255.0` makes them) are taken, converted.
    again, _ = holo.resample_cameras([p.astype(np.float64) for p in pictures], intrinsics, poses, layout, focus_distance=1.0)
    assert np.array_equal(again, frame)
