"""A mesh to a .holo file, to the display's fringes, to what an eye sees.

    .venv/bin/python python/examples/mesh_to_view.py [MESH] [--layout mark1] [--out DIR]

Converts MESH (default: the bundled Spot, fixtures/mesh/spot/spot.obj) for the layout's display, reads the frame
back as a numpy array, assembles it into the display's frame-buffer images, and simulates what eyes on the viewer
line see. With matplotlib installed it plots the fringe's first rows and the eyes' pictures into DIR/seen.png;
without it, it prints the figures.
"""

import argparse
import pathlib
import tempfile

import numpy as np

import holo

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mesh", nargs="?", default=str(ROOT / "fixtures" / "mesh" / "spot" / "spot.obj"))
    parser.add_argument("--layout", default="mark1")
    parser.add_argument("--out", default=None, help="folder for the files (default: a new temporary folder)")
    a = parser.parse_args()
    out = pathlib.Path(a.out) if a.out else pathlib.Path(tempfile.mkdtemp(prefix="holo-"))
    out.mkdir(parents=True, exist_ok=True)

    layout = holo.Layout.load(a.layout)
    holo_path = out / "scene.holo"
    report = holo.convert_mesh(a.mesh, layout, holo_path, overwrite=True)
    print(f"converted {a.mesh}: {report['triangles']} triangles → {holo_path}")

    f = holo.open(holo_path)
    frame = f.frame(0)
    print(f"frame: {frame.shape} [channel, hololine, emitter, view], mean radiance {frame.mean():.4f}")

    images = holo.assemble(frame, layout)
    for name, image in zip(layout.image_names, images):
        print(f"fringe image {name}: {image.shape} uint8, codes {image.min()}..{image.max()}")

    g = layout.geometry
    eyes_m = [-0.02, 0.0, 0.02]
    seen = holo.view(frame, layout, eyes_m)
    for x, picture in zip(eyes_m, seen):
        print(f"eye at {x * 1e3:+.0f} mm: picture {picture.shape}, mean brightness {picture.mean():.4f}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no plot (pip install matplotlib)")
        return
    fig, axes = plt.subplots(1, len(seen) + 1, figsize=(4 * (len(seen) + 1), 3.5))
    # The fringe where the scene is: the rows and columns around its busiest pixel.
    fringe = images[0][:, :, 0].astype(np.int16)
    row, column = np.unravel_index(np.argmax(np.abs(fringe - np.median(fringe))), fringe.shape)
    r0, c0 = max(0, row - 32), max(0, column - 256)
    axes[0].imshow(fringe[r0 : r0 + 64, c0 : c0 + 512], cmap="gray", vmin=0, vmax=255, aspect="auto")
    axes[0].set_title(f"fringe {layout.image_names[0]}, rows {r0}–{r0 + 63}")
    aspect = g.hololine_pitch_m / g.emitter_pitch_m
    for ax, x, picture in zip(axes[1:], eyes_m, seen):
        rgb = picture if picture.shape[2] == 3 else np.repeat(picture, 3, axis=2)
        ax.imshow(np.clip(rgb / max(float(rgb.max()), 1e-9), 0, 1) ** (1 / 2.2), aspect=aspect)
        ax.set_title(f"eye at {x * 1e3:+.0f} mm")
    for ax in axes:
        ax.set_xticks([])
        ax.set_yticks([])
    fig.tight_layout()
    fig.savefig(out / "seen.png", dpi=100)
    print(f"wrote {out / 'seen.png'}")


if __name__ == "__main__":
    main()
