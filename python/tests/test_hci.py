"""`holo export-hci` read as the 4D Light Field Benchmark's python-tools read a scene folder.

Their `file_io.read_parameters` reads `parameters.cfg` with configparser, section by section, and
`read_lightfield` lists the files whose names start with `input_` and end with `.png`, sorted, and puts picture
`idx` at camera row `idx // num_cams_x`, column `idx % num_cams_y`. The same is done here, and each picture
compared with the view `holo export-views` writes: camera row 0 must be the highest vertical view (the benchmark's
rows step down, holo's vertical views up), column 0 the leftmost horizontal view.

Only the standard library and the command line (HOLO_CLI, clitool.py): the CI environment has no image
package, so the PNGs are decoded here (8-bit grey or RGB, the five filters of the PNG specification).
"""

import configparser
import os
import pathlib
import struct
import subprocess
import zlib

from clitool import FIXTURES, cli


def run(*args):
    done = subprocess.run([cli(), *map(str, args)], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return done.stdout


def read_png(path):
    """(width, height, components, rows): an 8-bit, non-interlaced grey or RGB PNG, rows of bytes."""
    data = pathlib.Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    at, idat = 8, b""
    while at < len(data):
        (length,) = struct.unpack(">I", data[at : at + 4])
        kind, body = data[at + 4 : at + 8], data[at + 8 : at + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour in (0, 2) and interlace == 0, (path, depth, colour, interlace)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    components = 3 if colour == 2 else 1
    stride = width * components
    raw = zlib.decompress(idat)
    rows, previous = [], bytearray(stride)
    for y in range(height):
        line = raw[y * (stride + 1) : (y + 1) * (stride + 1)]
        kind, row = line[0], bytearray(line[1:])
        for i in range(stride):
            left = row[i - components] if i >= components else 0
            up, up_left = previous[i], previous[i - components] if i >= components else 0
            if kind == 1:
                row[i] = (row[i] + left) & 255
            elif kind == 2:
                row[i] = (row[i] + up) & 255
            elif kind == 3:
                row[i] = (row[i] + (left + up) // 2) & 255
            elif kind == 4:
                p = left + up - up_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - up_left)
                row[i] = (row[i] + (left if pa <= pb and pa <= pc else up if pb <= pc else up_left)) & 255
        rows.append(bytes(row))
        previous = row
    return width, height, components, rows


def read_parameters(folder):
    parser = configparser.ConfigParser()
    parser.read(folder / "parameters.cfg")
    params = {
        "width": int(parser.get("intrinsics", "image_resolution_x_px")),
        "height": int(parser.get("intrinsics", "image_resolution_y_px")),
        "num_cams_x": int(parser.get("extrinsics", "num_cams_x")),
        "num_cams_y": int(parser.get("extrinsics", "num_cams_y")),
    }
    for section, keys in {
        "intrinsics": ["focal_length_mm", "sensor_size_mm", "fstop"],
        "extrinsics": ["baseline_mm", "focus_distance_m"]
        + [f"center_cam_{a}" for a in ("x_m", "y_m", "z_m", "rx_rad", "ry_rad", "rz_rad")],
        "meta": ["disp_min", "disp_max", "frustum_disp_min", "frustum_disp_max", "depth_map_scale"],
    }.items():
        for key in keys:
            params[key] = float(parser.get(section, key))
    for key in ["scene", "category", "date", "version", "authors", "contact"]:
        params[key] = parser.get("meta", key)
    return params


def read_lightfield(folder):
    params = read_parameters(folder)
    views = sorted(f for f in os.listdir(folder) if f.startswith("input_") and f.endswith(".png"))
    field = {}
    for idx, view in enumerate(views):
        width, height, components, rows = read_png(folder / view)
        assert (width, height, components) == (params["width"], params["height"], 3), view
        field[idx // params["num_cams_x"], idx % params["num_cams_y"]] = rows
    return params, field


def test_an_hci_export_reads_as_the_benchmark_reads_a_scene(tmp_path):
    # (Frame 1 of the first: its views differ from top to bottom.)
    for fixture, frame in [("full-frames-rgb-f32-zip.holo", 1), ("full-tiny-y-f16-none.holo", 0)]:
        path = FIXTURES / "v1.3" / fixture
        hci, plain = tmp_path / f"{fixture}-hci", tmp_path / f"{fixture}-views"
        said = run("export-hci", path, "--frame", frame, "--white", "max", "-o", hci)
        white = said.strip().rsplit("white = ", 1)[1]
        run("export-views", path, "--frame", frame, "--bits", "8", "--white", white, "-o", plain)
        params, field = read_lightfield(hci)
        v, w = params["num_cams_x"], params["num_cams_y"]
        assert (v, w) == (2, 2)
        assert params["scene"] == fixture[: -len(".holo")] and params["focus_distance_m"] > 0
        assert params["baseline_mm"] > 0 and len(field) == v * w
        for (row, column), rows in field.items():
            h, k = column, w - 1 - row
            width, height, components, expected = read_png(plain / f"view_{h:03d}_{k:03d}.png")
            for got, want in zip(rows, expected):
                # A grey view is grey in all three of the camera's components.
                assert got == want if components == 3 else got == bytes(b for b in want for _ in range(3))
