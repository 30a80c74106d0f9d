"""Reading one Mark III RGB f16 frame into numpy: holo's package against Python OpenEXR, same file, same run.

    .venv/bin/python python/benches/read.py          (after the README's Python install, plus `pip install OpenEXR`)

The frame: Mark III's geometry (440 hololines × 336 emitters × 96 views) in RGB, smooth content with 1 % noise,
stored as f16 (85 MB of samples), uncompressed and zip. Each reader runs in its own process, nine times, the
readers taking turns (paired: a slow moment of a shared machine falls on all of them alike); the table gives the
median time to get every sample into numpy, and the median of the whole process (start, imports, read, exit) (holo: float32, its default, and float16 with
`dtype=numpy.float16`, the stored type; OpenEXR: the stored float16, which is what it hands back) and the process's peak memory above what it held before reading (the resident
set's high-water mark), against the float32 frame's size (170 MB).
"""

import json
import pathlib
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import holo

REPEATS = 9
READERS = ["holo", "holo-f16", "openexr"]


def make(path, compression):
    mark3 = holo.Layout.load("mark3").geometry.to_dict()
    rgb = holo.Layout.load("mark1").geometry.to_dict()["channels"]
    mark3["channels"] = rgb
    g = holo.Geometry.from_dict(mark3)
    c, h, e, v = g.shape
    rng = np.random.default_rng(0)
    ramp = (
        0.5
        + 0.2 * np.sin(np.arange(h) / 40.0)[None, :, None, None]
        + 0.2 * np.cos(np.arange(e) / 30.0)[None, None, :, None]
        + 0.05 * np.sin(np.arange(v) / 10.0)[None, None, None, :]
        + 0.02 * np.arange(c)[:, None, None, None]
    )
    frame = (ramp + 0.01 * rng.standard_normal((c, h, e, v))).clip(0, None).astype(np.float32)
    holo.write(path, frame, g, sample_type="f16", compression=compression, overwrite=True)
    return frame.nbytes


def child(reader, path):
    """Runs in its own process: read the frame once, report seconds and extra peak memory (bytes)."""
    import OpenEXR  # noqa: F401 (imported before the baseline, like holo)

    before = peak_bytes()
    started = time.perf_counter()
    if reader == "holo":
        frame = holo.open(path).frame(0)
        total = float(frame[0, 0, 0, 0])
    elif reader == "holo-f16":
        frame = holo.open(path).frame(0, dtype=np.float16)
        total = float(frame[0, 0, 0, 0])
    else:
        f = OpenEXR.File(path, separate_channels=True)
        channels = f.parts[0].channels
        total = sum(float(ch.pixels[0, 0]) for ch in channels.values())
    seconds = time.perf_counter() - started
    after = peak_bytes()
    print(json.dumps({"seconds": seconds, "peak_bytes": after - before, "check": total}))


def peak_bytes():
    """The process's resident-set high-water mark."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def measure(path):
    """Each reader REPEATS times, in turns: {reader: (median read s, median process s, max peak bytes)}."""
    runs = {reader: [] for reader in READERS}
    for _ in range(REPEATS):
        for reader in READERS:
            started = time.perf_counter()
            out = subprocess.run([sys.executable, __file__, "--child", reader, str(path)], capture_output=True, text=True)
            process = time.perf_counter() - started
            if out.returncode != 0:
                raise SystemExit(f"{reader} on {path}: {out.stderr.strip()}")
            runs[reader].append(dict(json.loads(out.stdout), process=process))
    return {
        reader: (
            statistics.median(r["seconds"] for r in rs),
            statistics.median(r["process"] for r in rs),
            max(r["peak_bytes"] for r in rs),
        )
        for reader, rs in runs.items()
    }


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--child":
        child(sys.argv[2], sys.argv[3])
        return
    if len(sys.argv) == 4 and sys.argv[1] == "--make":
        print(make(sys.argv[2], sys.argv[3]))
        return
    with tempfile.TemporaryDirectory() as tmp:
        print("| compression | reader | median s | MiB/s of f16 samples | whole process, s | peak memory above baseline | ÷ frame (f32) |")
        print("|---|---|---:|---:|---:|---:|---:|")
        for compression in ["none", "zip"]:
            path = pathlib.Path(tmp) / f"mark3-rgb-{compression}.holo"
            # Made in a process of its own: a child's high-water mark can start
            # from its parent's, so the parent stays small.
            made = subprocess.run([sys.executable, __file__, "--make", str(path), compression], capture_output=True, text=True)
            if made.returncode != 0:
                raise SystemExit(made.stderr.strip())
            frame_bytes = int(made.stdout)
            stored = frame_bytes // 2
            results = measure(path)
            for reader, (seconds, process, peak) in results.items():
                print(
                    f"| {compression} | {reader} | {seconds:.3f} | {stored / seconds / 2**20:.0f} | {process:.3f} | "
                    f"{peak / 2**20:.0f} MiB | {peak / frame_bytes:.2f} |"
                )
            for reader, words in [("holo", "holo"), ("holo-f16", "holo float16")]:
                read = results[reader][0] / results["openexr"][0]
                whole = results[reader][1] / results["openexr"][1]
                print(f"| {compression} | {words} ÷ OpenEXR time | {read:.2f} | | {whole:.2f} | | |")


if __name__ == "__main__":
    main()
