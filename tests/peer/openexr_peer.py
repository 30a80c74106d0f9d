#!/usr/bin/env python3
"""The .holo format checked by a reader and a writer nobody here wrote:
the OpenEXR project's own Python bindings (PyPI `OpenEXR`, 3.3 or later,
whose `OpenEXR.File` gives parts, headers and channels as numpy arrays).

    openexr_peer.py check DIR
        For every DIR/NAME.expect.json (from `cargo run --example peer_vectors`)
        open DIR/NAME.holo with OpenEXR and check: parts, part names, windows,
        compression, the channel list and its pixel type, every holo.* attribute
        (present, of the EXR type the spec gives, value exact; no others), the
        probe samples (bit-exact), and each part's SHA-256 digest recomputed
        from the channel data by the definition of the spec.

    openexr_peer.py write DIR
        Write spec-conforming .holo files with OpenEXR alone (mono and RGB, HALF
        and FLOAT, one with a cropped data window, one with two parts), the
        digest computed here, and for each NAME.holo a NAME.peer.json listing
        what was written (geometry, doubles as bit patterns, every sample as
        f32 bits over the display window) for `examples/peer_read.rs`.

    openexr_peer.py rewrite SRC OUT
        Read each SRC/*.holo with OpenEXR and write it back out with OpenEXR
        (same header dict, same channels) as OUT/NAME.openexr.holo with a
        NAME.openexr.peer.json, and report how the header OpenEXR writes
        differs from the one holo wrote.

    openexr_peer.py vectors DIR [DIR ...]
        The frozen test vectors (fixtures/v1.*/*.holo, spec §12) read with
        OpenEXR: every part decodes; every header seal and every part's
        digest recomputed by the spec's definitions; a full-parallax file's
        parts (spec §8) one per view in the order p = (f*W + k)*V + h, each
        holding holo.view (h k) and the colours alone as channels; the worked
        examples' samples equal to their formulas. With OpenImageIO's
        `oiiotool` on the PATH, it must see every part as a subimage with the
        same per-channel minimum, maximum and mean.

Each check prints one line (`PASS ...` or `FAIL ...`); `info` lines report
without judging. The last line is `N passed, M failed`; the exit status is 1
when anything failed, 2 when the installed OpenEXR offers no usable API.

The digest (spec §7): SHA-256 over the samples of the whole display window,
row by row (y), within a row channel by channel in channel-list order (ASCII
order of the names), within a channel x by x, each sample as the
little-endian bytes of its stored type (HALF: 2, FLOAT: 4), +0.0 outside the
data window; stored as "sha256:" and 64 lower-case hex digits.
"""

import contextlib
import fractions
import glob
import hashlib
import io
import json
import os
import struct
import sys

try:
    import numpy as np
except ImportError as e:  # pragma: no cover
    print(f"FAIL setup: numpy is not installed ({e})")
    print("0 passed, 1 failed")
    sys.exit(2)

try:
    import OpenEXR
except ImportError as e:  # pragma: no cover
    print(f"FAIL setup: the OpenEXR Python package is not installed ({e}); pip install OpenEXR")
    print("0 passed, 1 failed")
    sys.exit(2)


# --------------------------------------------------------------------------
# Reporting


class Checks:
    def __init__(self):
        self.passed = 0
        self.failed = 0

    def check(self, ok, what, detail=""):
        if ok:
            self.passed += 1
            print(f"PASS {what}")
        else:
            self.failed += 1
            print(f"FAIL {what}" + (f": {detail}" if detail else ""))
        return ok

    def info(self, text):
        print(f"info {text}")

    def finish(self):
        print(f"{self.passed} passed, {self.failed} failed")
        return 0 if self.failed == 0 else 1


def openexr_version():
    return getattr(OpenEXR, "__version__", None) or getattr(OpenEXR, "OPENEXR_VERSION", "unknown")


def require_file_api():
    """OpenEXR 3.3+ has OpenEXR.File with .parts; 1.x (and 3.2) only InputFile/OutputFile."""
    if not hasattr(OpenEXR, "File") or not hasattr(OpenEXR, "Part"):
        print(
            f"FAIL setup: OpenEXR {openexr_version()} offers only the old InputFile/OutputFile API; "
            "this script needs OpenEXR.File (the pybind11 API of OpenEXR 3.3 and later): pip install -U OpenEXR"
        )
        print("0 passed, 1 failed")
        sys.exit(2)


require_file_api()


# --------------------------------------------------------------------------
# Helpers


def f64_bits(x):
    return struct.unpack("<Q", struct.pack("<d", float(x)))[0]


def f64_from_bits(b):
    return struct.unpack("<d", struct.pack("<Q", int(b)))[0]


def f32_bits(x):
    return int(np.float32(x).view(np.uint32))


PIXEL_TYPES = {"f16": (OpenEXR.HALF, np.dtype("<f2")), "f32": (OpenEXR.FLOAT, np.dtype("<f4"))}

COMPRESSIONS = {
    "none": OpenEXR.NO_COMPRESSION,
    "rle": OpenEXR.RLE_COMPRESSION,
    "zips": OpenEXR.ZIPS_COMPRESSION,
    "zip": OpenEXR.ZIP_COMPRESSION,
    "piz": OpenEXR.PIZ_COMPRESSION,
    "pxr24": OpenEXR.PXR24_COMPRESSION,
    "b44": OpenEXR.B44_COMPRESSION,
    "b44a": OpenEXR.B44A_COMPRESSION,
    "dwaa": OpenEXR.DWAA_COMPRESSION,
    "dwab": OpenEXR.DWAB_COMPRESSION,
}
COMPRESSION_NAMES = {v: k for k, v in COMPRESSIONS.items()}


SPEC_TYPES = {
    "holo.version": "v2i",
    "holo.parallax": "string",
    "holo.hololines": "int",
    "holo.emitters": "int",
    "holo.views": "int",
    "holo.hololinePitch": "double",
    "holo.hololineTopY": "double",
    "holo.emitterPitch": "double",
    "holo.emitterLeftX": "double",
    "holo.emitterZ": "double",
    "holo.viewerDistance": "double",
    "holo.viewerHeight": "double",
    "holo.viewSpacing": "string",
    "holo.viewFirst": "double",
    "holo.viewLast": "double",
    "holo.viewAngles": "string",
    "holo.radiometry": "string",
    "holo.scale": "double",
    "holo.unit": "string",
    "holo.frame": "int",
    "holo.frameCount": "int",
    "holo.digest": "string",
    "holo.headerDigest": "string",
    "holo.source": "string",
}


def spec_type(name):
    """The EXR type the spec gives a holo.* attribute (None: not defined)."""
    if name.startswith("holo.wavelength."):
        return "double"
    return SPEC_TYPES.get(name)


def api_type(v):
    """The EXR attribute type behind a value as OpenEXR.File presents it."""
    if isinstance(v, bool):
        return "bool"
    if isinstance(v, int):
        return "int"
    if isinstance(v, str):
        return "string"
    if isinstance(v, float):
        return "float"
    if isinstance(v, fractions.Fraction):
        return "rational"
    if isinstance(v, np.ndarray):
        if v.dtype == np.float64 and v.shape == (1,):
            return "double"
        if v.dtype == np.int32 and v.shape == (2,):
            return "v2i"
        if v.dtype == np.float32 and v.shape == (2,):
            return "v2f"
        return f"ndarray[{v.dtype},{v.shape}]"
    return type(v).__name__


def read_exr(path):
    """OpenEXR.File of a path; anything the bindings print (they print and
    skip a part whose pixels fail to decode) is returned too."""
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        f = OpenEXR.File(path, separate_channels=True)
    return f, out.getvalue()


def window(box):
    """(xmin, ymin, xmax, ymax) of a box2i as OpenEXR.File presents it."""
    lo, hi = box
    return (int(lo[0]), int(lo[1]), int(hi[0]), int(hi[1]))


def full_channels(part, display, dtype):
    """Each channel over the display window, +0.0 outside the data window."""
    dx0, dy0, dx1, dy1 = window(part.header["dataWindow"])
    x0, y0, x1, y1 = display
    out = {}
    for name, ch in part.channels.items():
        full = np.zeros((y1 - y0 + 1, x1 - x0 + 1), dtype=dtype)
        full[dy0 - y0 : dy1 - y0 + 1, dx0 - x0 : dx1 - x0 + 1] = ch.pixels
        out[name] = full
    return out


def frame_digest(full, dtype):
    """Spec §7: rows, then channels in ASCII order of names, then x; LE bytes."""
    names = sorted(full)
    stack = np.stack([full[n].astype(dtype, copy=False) for n in names], axis=1)  # (rows, channels, x)
    return "sha256:" + hashlib.sha256(np.ascontiguousarray(stack).tobytes()).hexdigest()


def raw_headers(path):
    """The headers as stored: per part a list of (name, type, value bytes), in
    file order. Independent of OpenEXR, to see exact type names and order."""
    with open(path, "rb") as fh:
        data = fh.read(4 << 20)
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file (bad magic number)")
    version = struct.unpack("<I", data[4:8])[0]
    flags = version >> 8
    multipart = bool(flags & 0x10)
    at = 8
    parts = []
    while True:
        attrs = []
        while True:
            end = data.index(b"\0", at)
            if end == at:
                at += 1
                break
            name = data[at:end].decode("ascii", "replace")
            tend = data.index(b"\0", end + 1)
            typ = data[end + 1 : tend].decode("ascii", "replace")
            size = struct.unpack("<i", data[tend + 1 : tend + 5])[0]
            value = data[tend + 5 : tend + 5 + size]
            attrs.append((name, typ, value))
            at = tend + 5 + size
        parts.append(attrs)
        if not multipart or data[at : at + 1] == b"\0":
            break
    return {"version": version & 0xFF, "flags": flags, "multipart": multipart, "parts": parts}


def header_spans(data):
    """Spec §7.2, from the bytes alone: per part, (start, end) of its attribute
    list (first name through its terminating NUL, exclusive end) and the
    (start, end) of holo.headerDigest's value, or None."""
    multipart = bool(struct.unpack("<I", data[4:8])[0] >> 8 & 0x10)
    at, spans = 8, []
    while True:
        start, own = at, None
        while data[at] != 0:
            name_end = data.index(b"\0", at)
            type_end = data.index(b"\0", name_end + 1)
            size = struct.unpack("<i", data[type_end + 1 : type_end + 5])[0]
            if data[at:name_end] == b"holo.headerDigest":
                own = (type_end + 5, type_end + 5 + size)
            at = type_end + 5 + size
        at += 1
        spans.append(((start, at), own))
        if not multipart or data[at] == 0:
            return spans


def header_digest(data, span, own):
    """SHA-256 of the first 8 bytes and the part's header with the digest's own
    64 hex digits read as '0' (spec §7.2)."""
    header = bytearray(data[:8] + data[span[0] : span[1]])
    lo, hi = own[0] + len("sha256:") - span[0] + 8, own[1] - span[0] + 8
    header[lo:hi] = b"0" * (hi - lo)
    return "sha256:" + hashlib.sha256(bytes(header)).hexdigest()


def seal(path):
    """Fill in every part's holo.headerDigest in place (a writer's last step,
    spec §7.2): the placeholder written with the header has the same length."""
    with open(path, "r+b") as fh:
        data = fh.read()
        patched = bytearray(data)
        for span, own in header_spans(data):
            if own is not None:
                patched[own[0] : own[1]] = header_digest(data, span, own).encode("ascii")
        fh.seek(0)
        fh.write(patched)


def check_seals(c, label, path, required):
    """Every part's holo.headerDigest recomputed from the file's bytes."""
    with open(path, "rb") as fh:
        data = fh.read()
    for i, (span, own) in enumerate(header_spans(data)):
        if own is None:
            c.check(not required, f"{label} part {i}: no holo.headerDigest, as its version allows", "missing")
            continue
        stored = data[own[0] : own[1]].decode("ascii", "replace")
        c.check(header_digest(data, span, own) == stored,
                f"{label} part {i}: holo.headerDigest recomputed from the stored header (spec §7.2) matches",
                f"stored {stored}, computed {header_digest(data, span, own)}")


def header_layout_info(c, label, raw):
    """Report what the file's header holds beyond the required attributes."""
    c.info(
        f"{label}: EXR version {raw['version']}, flags 0x{raw['flags'] << 8:x} "
        f"({'multi-part' if raw['multipart'] else 'single-part'}), {len(raw['parts'])} header(s)"
    )
    for i, attrs in enumerate(raw["parts"]):
        names = [a[0] for a in attrs]
        order = "sorted by name" if names == sorted(names) else "NOT sorted by name: " + " ".join(names)
        extra = [n for n in ("name", "type", "chunkCount") if n in names]
        c.info(f"{label}: header {i}: {len(attrs)} attributes, {order}; of name/type/chunkCount it has: {', '.join(extra) or 'none'}")


# --------------------------------------------------------------------------
# check: holo's files read by OpenEXR


def check_file(c, directory, expect_path):
    with open(expect_path) as fh:
        ex = json.load(fh)
    name = ex["file"]
    path = os.path.join(directory, name)
    label = name
    pixel_type, dtype = PIXEL_TYPES[ex["sample_type"]]
    try:
        f, printed = read_exr(path)
    except Exception as e:  # noqa: BLE001
        c.check(False, f"{label}: OpenEXR opens it", f"{type(e).__name__}: {e}")
        return
    c.check(not printed.strip(), f"{label}: OpenEXR opens it and decodes every part without complaint", printed.strip())
    parts = f.parts
    if not c.check(len(parts) == len(ex["parts"]), f"{label}: {len(ex['parts'])} part(s)", f"OpenEXR sees {len(parts)}"):
        return

    try:
        raw = raw_headers(path)
    except Exception as e:  # noqa: BLE001
        raw = None
        c.check(False, f"{label}: raw header parse", str(e))
    if raw is not None:
        c.check(
            raw["multipart"] == (len(ex["parts"]) > 1),
            f"{label}: multi-part flag is {'set' if len(ex['parts']) > 1 else 'clear'}",
            f"flags 0x{raw['flags'] << 8:x}",
        )
        header_layout_info(c, label, raw)

    sealed = any(a.get("sealed") for part in ex["parts"] for a in part["attributes"])
    check_seals(c, label, path, sealed)

    dw = ex["display_window"]
    display = (dw["min"][0], dw["min"][1], dw["max"][0], dw["max"][1])
    expected_shared = {a["name"]: a for a in ex["shared_attributes"]}

    for index, (p, exp) in enumerate(zip(parts, ex["parts"])):
        pl = f"{label} part {index}"
        h = p.header
        c.check(p.name() == exp["name"], f"{pl}: name {exp['name']}", f"found {p.name()!r}")
        c.check(p.type() == OpenEXR.scanlineimage, f"{pl}: scan-line image", f"found {p.type()}")
        comp = COMPRESSION_NAMES.get(p.compression(), str(p.compression()))
        c.check(comp == ex["compression"], f"{pl}: compression {ex['compression']}", f"found {comp}")
        c.check(window(h["displayWindow"]) == display, f"{pl}: display window {display}", f"found {window(h['displayWindow'])}")
        ew = exp["data_window"]
        edw = (ew["min"][0], ew["min"][1], ew["max"][0], ew["max"][1])
        c.check(window(h["dataWindow"]) == edw, f"{pl}: data window {edw}", f"found {window(h['dataWindow'])}")
        c.check(h.get("pixelAspectRatio") == ex["pixel_aspect"], f"{pl}: pixel aspect ratio {ex['pixel_aspect']}",
                f"found {h.get('pixelAspectRatio')}")
        c.check(h.get("lineOrder") == OpenEXR.INCREASING_Y, f"{pl}: line order increasing y", f"found {h.get('lineOrder')}")

        chans = [ch.name for ch in h["channels"]]
        c.check(chans == ex["channels"], f"{pl}: channel list ({len(ex['channels'])} channels, ASCII order)",
                f"found {chans[:6]}... ({len(chans)})")
        types = {str(ch.type()) for ch in p.channels.values()}
        c.check(all(ch.type() == pixel_type for ch in p.channels.values()), f"{pl}: every channel is {ex['exr_pixel_type']}",
                f"found {types}")
        sampling = {(ch.xSampling, ch.ySampling) for ch in h["channels"]}
        c.check(sampling == {(1, 1)}, f"{pl}: every channel sampled 1x1", f"found {sampling}")

        # holo.* attributes: exactly the expected ones.
        expected = dict(expected_shared)
        expected.update({a["name"]: a for a in exp["attributes"]})
        present = sorted(k for k in h if k.startswith("holo."))
        missing = sorted(set(expected) - set(present))
        unexpected = sorted(set(present) - set(expected))
        c.check(not missing and not unexpected, f"{pl}: exactly the {len(expected)} expected holo.* attributes",
                f"missing {missing}, unexpected {unexpected}")
        raw_types = {}
        if raw is not None and index < len(raw["parts"]):
            raw_types = {a[0]: a[1] for a in raw["parts"][index]}
        for an, a in sorted(expected.items()):
            if an not in h:
                continue
            v = h[an]
            t = api_type(v)
            c.check(t == a["type"], f"{pl}: {an} has type {a['type']} (OpenEXR.File)", f"found {t}")
            if raw_types:
                c.check(raw_types.get(an) == a["type"], f"{pl}: {an} stored as type {a['type']}", f"stored as {raw_types.get(an)}")
            if a["type"] == "double":
                got = float(np.asarray(v).reshape(-1)[0])
                c.check(f64_bits(got) == a["bits"], f"{pl}: {an} = {a['value']!r} exactly",
                        f"found {got!r} (bits {f64_bits(got):#x} vs {a['bits']:#x})")
            elif a["type"] == "v2i":
                got = [int(x) for x in np.asarray(v).reshape(-1)]
                c.check(got == a["value"], f"{pl}: {an} = {a['value']}", f"found {got}")
            elif an == "holo.viewAngles":
                try:
                    nums = [float(s) for s in str(v).split()]
                    ok = [f64_bits(x) for x in nums] == a["bits"]
                except ValueError:
                    nums, ok = str(v), False
                c.check(ok, f"{pl}: {an} is the {len(a['bits'])} view angles exactly", f"found {nums}")
            elif a.get("sealed"):
                pass  # checked below, recomputed from the stored header
            else:
                c.check(v == a["value"], f"{pl}: {an} = {a['value']!r}", f"found {v!r}")

        fps = ex.get("frames_per_second")
        if fps is not None:
            got = h.get("framesPerSecond")
            c.check(isinstance(got, fractions.Fraction) and (got.numerator, got.denominator) == tuple(fps),
                    f"{pl}: framesPerSecond {fps[0]}/{fps[1]}", f"found {got!r}")

        # Samples.
        bad = []
        n = 0
        dx0, dy0, dx1, dy1 = window(h["dataWindow"])
        for pr in ex["probes"]:
            if pr["part"] != index:
                continue
            n += 1
            ch = p.channels.get(pr["channel"])
            if ch is None:
                bad.append(f"{pr['channel']} missing")
                continue
            x, y = pr["x"], pr["y"]
            if dx0 <= x <= dx1 and dy0 <= y <= dy1:
                got = ch.pixels[y - dy0, x - dx0]
            else:
                got = np.float32(0.0)
            if f32_bits(np.float32(got)) != pr["bits"]:
                bad.append(f"{pr['channel']}({x},{y}) = {float(got)!r}, expected {pr['value']!r}")
        c.check(not bad and n > 0, f"{pl}: {n} probe samples bit-exact", "; ".join(bad[:5]) + (f" (+{len(bad) - 5})" if len(bad) > 5 else ""))

        # Digest.
        full = full_channels(p, display, dtype)
        computed = frame_digest(full, dtype)
        c.check(computed == h.get("holo.digest"), f"{pl}: digest recomputed from the samples equals holo.digest",
                f"computed {computed}, stored {h.get('holo.digest')}")
        c.check(computed == ex["digests"][index], f"{pl}: digest equals the WriteReport's",
                f"computed {computed}, report {ex['digests'][index]}")


def cmd_check(directory):
    c = Checks()
    c.info(f"OpenEXR Python {openexr_version()} (OpenEXR.File API), numpy {np.__version__}, Python {sys.version.split()[0]}")
    expects = sorted(glob.glob(os.path.join(directory, "*.expect.json")))
    c.check(len(expects) > 0, f"{directory}: has *.expect.json files", "none found")
    for e in expects:
        try:
            check_file(c, directory, e)
        except Exception as err:  # noqa: BLE001
            c.check(False, f"{os.path.basename(e)}: checking ran to the end", f"{type(err).__name__}: {err}")
    return c.finish()


# --------------------------------------------------------------------------
# write: .holo files made by OpenEXR alone

DEG = np.pi / 180.0


def geometry(hololines, emitters, views, first, last, spacing, channels, angles=None):
    hp, ep = 1.1e-4 + 1e-9 / 7, 2.2e-4 + 1e-9 / 3
    return {
        "parallax": "horizontal",
        "hololines": hololines,
        "emitters": emitters,
        "views": views,
        "view_spacing": spacing,
        "view_angles": angles,
        "doubles": {
            "hololine_pitch_m": hp,
            "hololine_top_y_m": (hololines - 1) * hp / 2,
            "emitter_pitch_m": ep,
            "emitter_left_x_m": -(emitters - 1) * ep / 2,
            "emitter_z_m": 0.0314159265358979,
            "viewer_distance_m": 0.55 + 1e-12,
            "viewer_height_m": 0.01 / 3,
            "view_first_rad": first,
            "view_last_rad": last,
        },
        "channels": channels,
    }


def py_cases():
    rgb = [("R", 633e-9), ("G", 532e-9), ("B", 445e-9)]
    angles = [a * DEG for a in (-20.0, -11.5, -2.0, 3.3, 12.0, 21.0)]
    return [
        dict(name="py_mono_f16_zip", g=geometry(19, 11, 5, -0.25, 0.25, "tan", [("Y", 532e-9)]),
             st="f16", comp="zip", frames=1, crop=None, part_names=False, seed=11),
        dict(name="py_mono_f32_none", g=geometry(7, 5, 12, -0.4, 0.35, "sin", [("Y", 1.064e-6)]),
             st="f32", comp="none", frames=1, crop=None, part_names=False, seed=12),
        dict(name="py_rgb_f16_piz_cropped", g=geometry(16, 20, 3, -0.1, 0.1, "angle", rgb),
             st="f16", comp="piz", frames=1, crop=(4, 2, 15, 12), part_names=False, seed=13),
        dict(name="py_rgb_f32_zip_named", g=geometry(33, 10, 6, angles[0], angles[-1], "explicit", rgb, angles),
             st="f32", comp="zip", frames=1, crop=None, part_names=True, seed=14, version=(1, 2),
             radiometry=("linear", 0.5, "W/(sr m^2)"), source="openexr_peer.py (OpenEXR Python bindings)"),
        dict(name="py_multi2_rgb_f16_zips", g=geometry(9, 8, 4, -0.3, 0.3, "tan", rgb),
             st="f16", comp="zips", frames=2, crop=None, part_names=True, seed=15, first_frame=5, version=(1, 2),
             fps=fractions.Fraction(30000, 1001)),
    ]


def random_samples(rng, shape, st):
    """Non-zero radiance over several decades, some tiny, some near the f16 maximum."""
    x = 10.0 ** rng.uniform(-4.0, 2.5, shape) * rng.uniform(0.5, 1.0, shape)
    r = rng.uniform(0.0, 1.0, shape)
    tiny = rng.uniform(1e-6, 6e-5, shape) if st == "f16" else rng.uniform(1e-44, 1e-38, shape)
    x = np.where(r < 0.05, tiny, x)
    x = np.where((r >= 0.05) & (r < 0.08), rng.uniform(30000.0, 65000.0, shape), x)
    out = x.astype(np.float16 if st == "f16" else np.float32)
    assert np.all(out > 0) and np.all(np.isfinite(out))
    return out


def channel_names(views, colours):
    digits = max(3, len(str(views - 1)))
    return sorted(f"v{v:0{digits}d}.{c}" for v in range(views) for c in colours)


def holo_header(g, st, comp, crop, radiometry, source, version=(1, 0)):
    """Header dict: the EXR type of each value is what OpenEXR.File infers:
    int -> int, str -> string, 1-element float64 array -> double,
    2-element int32 array -> v2i."""
    d = g["doubles"]

    def dbl(x):
        return np.array([x], dtype=np.float64)

    w, h = g["emitters"], g["hololines"]
    x0, y0, x1, y1 = crop if crop else (0, 0, w - 1, h - 1)
    hdr = {
        "compression": COMPRESSIONS[comp],
        "type": OpenEXR.scanlineimage,
        "displayWindow": (np.array([0, 0], dtype=np.int32), np.array([w - 1, h - 1], dtype=np.int32)),
        "dataWindow": (np.array([x0, y0], dtype=np.int32), np.array([x1, y1], dtype=np.int32)),
        "holo.version": np.array(list(version), dtype=np.int32),
        "holo.parallax": g["parallax"],
        "holo.hololines": h,
        "holo.emitters": w,
        "holo.views": g["views"],
        "holo.hololinePitch": dbl(d["hololine_pitch_m"]),
        "holo.hololineTopY": dbl(d["hololine_top_y_m"]),
        "holo.emitterPitch": dbl(d["emitter_pitch_m"]),
        "holo.emitterLeftX": dbl(d["emitter_left_x_m"]),
        "holo.emitterZ": dbl(d["emitter_z_m"]),
        "holo.viewerDistance": dbl(d["viewer_distance_m"]),
        "holo.viewerHeight": dbl(d["viewer_height_m"]),
        "holo.viewSpacing": g["view_spacing"],
        "holo.viewFirst": dbl(d["view_first_rad"]),
        "holo.viewLast": dbl(d["view_last_rad"]),
        "holo.radiometry": radiometry[0],
        "holo.scale": dbl(radiometry[1]),
        "holo.unit": radiometry[2],
    }
    if g["view_angles"] is not None:
        hdr["holo.viewAngles"] = " ".join(repr(float(a)) for a in g["view_angles"])
    for cname, wl in g["channels"]:
        hdr[f"holo.wavelength.{cname}"] = dbl(wl)
    if source:
        hdr["holo.source"] = source
    if version >= (1, 1):
        # From 1.1 the emitter grid's proportions (spec §3.1), as a float.
        hdr["pixelAspectRatio"] = float(np.float32(d["emitter_pitch_m"] / d["hololine_pitch_m"]))
    if version >= (1, 2):
        # A placeholder of the digest's length, filled in once written (seal()).
        hdr["holo.headerDigest"] = "sha256:" + "0" * 64
    return hdr


def peer_json(file_name, writer, st, comp, g, radiometry, frames):
    """What peer_read.rs needs; every double also as its bit pattern."""
    return {
        "file": file_name,
        "writer": writer,
        "sample_type": st,
        "compression": comp,
        "geometry": {
            "parallax": g["parallax"],
            "hololines": g["hololines"],
            "emitters": g["emitters"],
            "views": g["views"],
            "view_spacing": g["view_spacing"],
            "view_angles": g["view_angles"],
            "view_angles_bits": None if g["view_angles"] is None else [f64_bits(a) for a in g["view_angles"]],
            "doubles": g["doubles"],
            "doubles_bits": {k: f64_bits(v) for k, v in g["doubles"].items()},
            "channels": [{"name": n, "wavelength_m": wl, "wavelength_bits": f64_bits(wl)} for n, wl in g["channels"]],
        },
        "radiometry": {"encoding": radiometry[0], "scale": radiometry[1], "scale_bits": f64_bits(radiometry[1]),
                       "unit": radiometry[2]},
        "frames": frames,
    }


def frame_json(part_index, number, name, digest, data_window, full):
    x0, y0, x1, y1 = data_window
    return {
        "part": part_index,
        "number": number,
        "name": name,
        "digest": digest,
        "data_window": {"x": x0, "y": y0, "width": x1 - x0 + 1, "height": y1 - y0 + 1},
        # f32 bit patterns over the display window, row by row.
        "samples": {n: full[n].astype(np.float32).view(np.uint32).tolist() for n in sorted(full)},
    }


def write_case(c, out, case):
    g, st, comp = case["g"], case["st"], case["comp"]
    pixel_type, dtype = PIXEL_TYPES[st]
    rng = np.random.default_rng(case["seed"])
    w, h = g["emitters"], g["hololines"]
    x0, y0, x1, y1 = case["crop"] if case["crop"] else (0, 0, w - 1, h - 1)
    names = channel_names(g["views"], [n for n, _ in g["channels"]])
    radiometry = case.get("radiometry", ("linear", 1.0, "relative"))
    first = case.get("first_frame", 0)
    parts, frames = [], []
    for i in range(case["frames"]):
        full, data = {}, {}
        for n in names:
            full[n] = np.zeros((h, w), dtype=dtype)
            full[n][y0 : y1 + 1, x0 : x1 + 1] = random_samples(rng, (y1 - y0 + 1, x1 - x0 + 1), st)
            data[n] = np.ascontiguousarray(full[n][y0 : y1 + 1, x0 : x1 + 1])
        digest = frame_digest(full, dtype)
        version = case.get("version", (1, 0))
        hdr = holo_header(g, st, comp, case["crop"], radiometry, case.get("source"), version)
        hdr["holo.frame"] = first + i
        hdr["holo.frameCount"] = case["frames"]
        hdr["holo.digest"] = digest
        if case.get("fps") is not None:
            hdr["framesPerSecond"] = case["fps"]
        part_name = f"frame{i:05d}" if case["part_names"] else ""
        parts.append(OpenEXR.Part(hdr, {n: OpenEXR.Channel(n, data[n]) for n in names}, part_name))
        frames.append(frame_json(i, first + i, part_name or None, digest, (x0, y0, x1, y1), full))
    path = os.path.join(out, case["name"] + ".holo")
    if os.path.exists(path):
        os.remove(path)
    try:
        OpenEXR.File(parts).write(path)
    except Exception as e:  # noqa: BLE001
        c.check(False, f"{case['name']}.holo: OpenEXR writes it", f"{type(e).__name__}: {e}")
        return
    c.check(os.path.exists(path), f"{case['name']}.holo: OpenEXR wrote {case['frames']} part(s), {len(names)} {st} channels, {comp}")
    if case.get("version", (1, 0)) >= (1, 2):
        seal(path)
        check_seals(c, f"{case['name']}.holo", path, True)

    # Read it back with OpenEXR: the digest written is the digest of what is stored.
    f, printed = read_exr(path)
    ok = not printed.strip() and len(f.parts) == case["frames"]
    for i, p in enumerate(f.parts):
        again = frame_digest(full_channels(p, (0, 0, w - 1, h - 1), dtype), dtype)
        ok = ok and again == frames[i]["digest"] and p.header.get("holo.digest") == frames[i]["digest"]
    c.check(ok, f"{case['name']}.holo: read back by OpenEXR, digests match", printed.strip())
    raw = raw_headers(path)
    header_layout_info(c, f"{case['name']}.holo", raw)
    wrong = [(a[0], a[1]) for part in raw["parts"] for a in part if a[0].startswith("holo.") and a[1] != spec_type(a[0])]
    c.check(not wrong, f"{case['name']}.holo: OpenEXR stored every holo.* attribute with the spec's type", str(wrong))

    doc = peer_json(case["name"] + ".holo", f"OpenEXR {openexr_version()} Python bindings (openexr_peer.py write)",
                    st, comp, g, radiometry, frames)
    with open(os.path.join(out, case["name"] + ".peer.json"), "w") as fh:
        json.dump(doc, fh)


def cmd_write(out):
    c = Checks()
    c.info(f"OpenEXR Python {openexr_version()} (OpenEXR.File API), numpy {np.__version__}")
    os.makedirs(out, exist_ok=True)
    for case in py_cases():
        try:
            write_case(c, out, case)
        except Exception as err:  # noqa: BLE001
            c.check(False, f"{case['name']}: writing ran to the end", f"{type(err).__name__}: {err}")
    return c.finish()


# --------------------------------------------------------------------------
# rewrite: holo's files re-encoded by OpenEXR


def attribute_diff(c, label, ours, theirs):
    """Differences between two files' raw headers (holo's and OpenEXR's)."""
    if ours["flags"] != theirs["flags"]:
        c.info(f"{label}: version flags holo 0x{ours['flags'] << 8:x}, OpenEXR 0x{theirs['flags'] << 8:x}")
    for i, (a, b) in enumerate(zip(ours["parts"], theirs["parts"])):
        an, bn = [x[0] for x in a], [x[0] for x in b]
        at, bt = {x[0]: x[1] for x in a}, {x[0]: x[1] for x in b}
        av, bv = {x[0]: x[2] for x in a}, {x[0]: x[2] for x in b}
        only_holo = [n for n in an if n not in bt]
        only_exr = [n for n in bn if n not in at]
        types = [f"{n} {at[n]}/{bt[n]}" for n in an if n in bt and at[n] != bt[n]]
        values = [n for n in an if n in bv and at.get(n) == bt.get(n) and av[n] != bv[n]]
        common_a = [n for n in an if n in bt]
        common_b = [n for n in bn if n in at]
        c.info(
            f"{label}: header {i}: only in holo's: {only_holo or '-'}; only in OpenEXR's: {only_exr or '-'}; "
            f"type differs: {types or '-'}; value differs: {values or '-'}; "
            f"order of common attributes {'same' if common_a == common_b else 'differs'}"
        )


def cmd_rewrite(src, out):
    c = Checks()
    c.info(f"OpenEXR Python {openexr_version()} (OpenEXR.File API), numpy {np.__version__}")
    os.makedirs(out, exist_ok=True)
    files = sorted(p for p in glob.glob(os.path.join(src, "*.holo")) if not p.endswith(".openexr.holo"))
    c.check(len(files) > 0, f"{src}: has .holo files", "none found")
    for path in files:
        base = os.path.basename(path)[: -len(".holo")]
        label = f"{base}.openexr.holo"
        try:
            f, printed = read_exr(path)
            h0 = f.parts[0].header
            st = "f16" if next(iter(f.parts[0].channels.values())).type() == OpenEXR.HALF else "f32"
            _, dtype = PIXEL_TYPES[st]
            comp = COMPRESSION_NAMES[f.parts[0].compression()]
            target = os.path.join(out, label)
            if os.path.exists(target):
                os.remove(target)
            # chunkCount is OpenEXR's to compute; drop the copy read from holo's file
            # so that the header shows what OpenEXR itself writes.
            for p in f.parts:
                p.header.pop("chunkCount", None)
            f.write(target)
            c.check(os.path.exists(target), f"{label}: OpenEXR read holo's {base}.holo and wrote it back ({comp})")
            # A program that rewrites a sealed header seals it again (spec §7.2).
            seal(target)
            check_seals(c, label, target, "holo.headerDigest" in h0)
            g2, printed2 = read_exr(target)
            c.check(not printed.strip() and not printed2.strip() and len(g2.parts) == len(f.parts),
                    f"{label}: OpenEXR reads its re-encoded copy", (printed + printed2).strip())
            attribute_diff(c, base, raw_headers(path), raw_headers(target))

            display = window(h0["displayWindow"])
            views = int(h0["holo.views"])
            colours = sorted({n.split(".", 1)[1] for n in f.parts[0].channels}, key="RGBY".index)
            angles = None
            if h0["holo.viewSpacing"] == "explicit":
                angles = [float(s) for s in h0["holo.viewAngles"].split()]

            def d(k):
                return float(np.asarray(h0[k]).reshape(-1)[0])

            g = {
                "parallax": h0["holo.parallax"],
                "hololines": int(h0["holo.hololines"]),
                "emitters": int(h0["holo.emitters"]),
                "views": views,
                "view_spacing": h0["holo.viewSpacing"],
                "view_angles": angles,
                "doubles": {
                    "hololine_pitch_m": d("holo.hololinePitch"),
                    "hololine_top_y_m": d("holo.hololineTopY"),
                    "emitter_pitch_m": d("holo.emitterPitch"),
                    "emitter_left_x_m": d("holo.emitterLeftX"),
                    "emitter_z_m": d("holo.emitterZ"),
                    "viewer_distance_m": d("holo.viewerDistance"),
                    "viewer_height_m": d("holo.viewerHeight"),
                    "view_first_rad": d("holo.viewFirst"),
                    "view_last_rad": d("holo.viewLast"),
                },
                "channels": [(col, d(f"holo.wavelength.{col}")) for col in colours],
            }
            radiometry = (h0.get("holo.radiometry", "linear"), d("holo.scale") if "holo.scale" in h0 else 1.0,
                          h0.get("holo.unit", "relative"))
            frames = []
            for i, p in enumerate(g2.parts):
                full = full_channels(p, display, dtype)
                digest = frame_digest(full, dtype)
                c.check(digest == p.header.get("holo.digest"), f"{label} part {i}: digest of OpenEXR's copy equals holo.digest")
                frames.append(frame_json(i, int(p.header.get("holo.frame", i)), p.name() or None, digest,
                                         window(p.header["dataWindow"]), full))
            doc = peer_json(label, f"OpenEXR {openexr_version()} Python bindings re-encoding holo's {base}.holo",
                            st, comp, g, radiometry, frames)
            with open(os.path.join(out, f"{base}.openexr.peer.json"), "w") as fh:
                json.dump(doc, fh)
        except Exception as err:  # noqa: BLE001
            c.check(False, f"{label}: rewrite ran to the end", f"{type(err).__name__}: {err}")
    return c.finish()


# --------------------------------------------------------------------------
# vectors: the frozen test vectors read by OpenEXR (and OpenImageIO)


def oiio_stats(path):
    """Per subimage, (min, max, avg) lists as `oiiotool --stats` prints them;
    None when oiiotool is not installed."""
    import shutil
    import subprocess

    if shutil.which("oiiotool") is None:
        return None
    out = subprocess.run(["oiiotool", "--stats", "-a", "--info", path], capture_output=True, text=True).stdout
    stats, current = [], None
    for line in out.splitlines():
        line = line.strip()
        if line.startswith("subimage"):
            current = {}
            stats.append(current)
        elif current is not None and line.startswith("Stats ") and line.endswith("(float)"):
            key, values = line[len("Stats "):].split(":", 1)
            current[key.strip()] = [float(x) for x in values.replace("(float)", "").split()]
    if not stats:  # a single image has no "subimage" lines
        current = {}
        for line in out.splitlines():
            line = line.strip()
            if line.startswith("Stats ") and line.endswith("(float)"):
                key, values = line[len("Stats "):].split(":", 1)
                current[key.strip()] = [float(x) for x in values.replace("(float)", "").split()]
        stats.append(current)
    return stats


def close(a, b):
    """OIIO prints six decimals."""
    return len(a) == len(b) and all(abs(x - y) <= 1e-6 + 1e-6 * abs(y) for x, y in zip(sorted(a), sorted(b)))


def check_vector(c, path, oiio):
    label = os.path.relpath(path)
    f, printed = read_exr(path)
    c.check(printed == "", f"{label}: OpenEXR decodes every part", printed.strip())
    parts = f.parts
    h0 = parts[0].header
    version = tuple(int(x) for x in h0["holo.version"])
    check_seals(c, label, path, required=version >= (1, 2))
    full = h0["holo.parallax"] == "full"
    bad_digest = []
    for i, part in enumerate(parts):
        display = window(part.header["displayWindow"])
        dtype = next(iter(part.channels.values())).pixels.dtype.newbyteorder("<")
        if frame_digest(full_channels(part, display, dtype), dtype) != part.header["holo.digest"]:
            bad_digest.append(i)
    c.check(not bad_digest, f"{label}: each of its {len(parts)} part(s)' holo.digest recomputed (spec §7.1) matches",
            f"parts {bad_digest}")
    if full:
        views, vertical = int(h0["holo.views"]), int(h0["holo.viewsVertical"])
        frames = int(h0["holo.frameCount"])
        c.check(version >= (1, 3), f"{label}: full parallax is version 1.3 or later", f"version {version}")
        c.check(len(parts) == frames * views * vertical,
                f"{label}: {frames} frame(s) of {views} x {vertical} views are {len(parts)} parts (spec §8)")
        wrong = []
        for p, part in enumerate(parts):
            fr, k, h = p // (views * vertical), (p // views) % vertical, p % views
            names = sorted(part.channels)
            ok = (tuple(int(x) for x in part.header["holo.view"]) == (h, k)
                  and names in (["B", "G", "R"], ["Y"], ["G", "R"], ["B", "R"], ["B", "G"], ["R"], ["G"], ["B"])
                  and part.header["holo.frame"] == parts[fr * views * vertical].header["holo.frame"]
                  and part.header["name"] == f"frame{fr:05d}.v{h:03d}_{k:03d}")
            if not ok:
                wrong.append(p)
        c.check(not wrong, f"{label}: part p holds view (p mod V, p div V mod W) of frame p div VW, "
                f"its channels the colours, named frameFFFFF.vHHH_KKK", f"parts {wrong}")
    name = os.path.basename(path)
    if name == "tiny-y-f16-none.holo":
        y = np.arange(2)[:, None]
        x = np.arange(3)[None, :]
        ok = all(np.array_equal(parts[0].channels[f"v{v:03d}.Y"].pixels.astype(np.float64), 1 + y + x / 4 + v / 8)
                 for v in range(2))
        c.check(ok, f"{label}: the worked example's samples are 1 + j + e/4 + v/8 (spec §12)")
    if name == "full-tiny-y-f16-none.holo":
        y = np.arange(2)[:, None]
        x = np.arange(3)[None, :]
        ok = all(np.array_equal(parts[k * 2 + h].channels["Y"].pixels.astype(np.float64),
                                1 + y + x / 4 + h / 8 + k / 16) for k in range(2) for h in range(2))
        c.check(ok, f"{label}: the full-parallax example's samples are 1 + j + e/4 + h/8 + k/16 (spec §12)")
    if oiio is None:
        return
    stats = oiio_stats(path)
    c.check(len(stats) == len(parts), f"{label}: oiiotool sees its {len(parts)} part(s) as subimages",
            f"{len(stats)} subimages")
    differ = []
    for i, (part, st) in enumerate(zip(parts, stats)):
        display = window(part.header["displayWindow"])
        chans = full_channels(part, display, np.float64)
        mins = [float(v.min()) for v in chans.values()]
        maxs = [float(v.max()) for v in chans.values()]
        avgs = [float(v.mean()) for v in chans.values()]
        if not (close(st.get("Min", []), mins) and close(st.get("Max", []), maxs) and close(st.get("Avg", []), avgs)):
            differ.append(i)
    c.check(not differ, f"{label}: oiiotool's minimum, maximum and mean of every channel of every part are OpenEXR's",
            f"parts {differ}")


def cmd_vectors(directories):
    import shutil

    c = Checks()
    oiio = shutil.which("oiiotool")
    c.info(f"OpenImageIO: {oiio or 'oiiotool not installed: OpenEXR alone'}")
    files = sorted(p for d in directories for p in glob.glob(os.path.join(d, "*.holo")))
    c.check(bool(files), f"frozen vectors found in {' '.join(directories)}", "none")
    for path in files:
        try:
            check_vector(c, path, oiio)
        except Exception as err:  # noqa: BLE001
            c.check(False, f"{path}: checked to the end", f"{type(err).__name__}: {err}")
    return c.finish()


def main(argv):
    if len(argv) == 3 and argv[1] == "check":
        return cmd_check(argv[2])
    if len(argv) == 3 and argv[1] == "write":
        return cmd_write(argv[2])
    if len(argv) == 4 and argv[1] == "rewrite":
        return cmd_rewrite(argv[2], argv[3])
    if len(argv) >= 3 and argv[1] == "vectors":
        return cmd_vectors(argv[2:])
    print(__doc__.split("\n\n")[1] if __doc__ else "", file=sys.stderr)
    print("usage: openexr_peer.py check DIR | write DIR | rewrite SRC OUT | vectors DIR...", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
