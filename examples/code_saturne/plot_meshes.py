#!/usr/bin/env python3
"""Draws the plane z = 0 of the code_saturne example's meshes, as code_saturne ended given steps.

Usage: plot_meshes.py OUT.png TITLE:RUN_DIR:STEP [TITLE:RUN_DIR:STEP ...]
  RUN_DIR  a run's result directory (meshmove_faces.bin, coords.bin: written by the case's user
           routines); STEP the time step whose end is drawn.
Each panel shows the cylinder's surroundings, cells shaded by their area against the original
mesh (the plane's faces of the symmetry zone, 5). Needs numpy and matplotlib.
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

SYMMETRY = 5


def read_faces(path):
    """The face mesh usalcl wrote: coordinates (nv, 3), CSR faces, owners, neighbours, zones."""
    with open(path, "rb") as f:
        nv, nf, nfv, _ = np.fromfile(f, dtype=np.int32, count=4)
        coords = np.fromfile(f, dtype=np.float64, count=3 * nv).reshape(nv, 3)
        offsets = np.fromfile(f, dtype=np.int32, count=nf + 1) - 1
        vertices = np.fromfile(f, dtype=np.int32, count=nfv) - 1
        np.fromfile(f, dtype=np.int32, count=2 * nf)  # owners, neighbours
        patch = np.fromfile(f, dtype=np.int32, count=nf)
    return coords, offsets, vertices, patch


def read_step(path, nv, step):
    """The coordinates code_saturne ended time step `step` with, (nv, 3)."""
    record = np.dtype([("step", np.int32), ("xyz", np.float64, (nv, 3))])
    with open(path, "rb") as f:
        (n,) = np.fromfile(f, dtype=np.int32, count=1)
        if n != nv:
            raise SystemExit(f"{path}: {n} vertices, the faces have {nv}")
        steps = np.fromfile(f, dtype=record)
    hit = steps[steps["step"] == step]
    if len(hit) == 0:
        raise SystemExit(f"{path}: no step {step} (last: {steps['step'][-1]})")
    return hit[0]["xyz"]


def area(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def panel(ax, title, run_dir, step):
    coords, offsets, vertices, patch = read_faces(f"{run_dir}/meshmove_faces.bin")
    xyz = read_step(f"{run_dir}/coords.bin", len(coords), step)
    polys0, polys = [], []
    for f in np.nonzero(patch == SYMMETRY)[0]:
        v = vertices[offsets[f] : offsets[f + 1]]
        if np.all(np.abs(coords[v, 2]) < 1e-9):
            polys0.append(coords[v, :2])
            polys.append(xyz[v, :2])
    ratio = np.array([area(p) / area(p0) for p, p0 in zip(polys, polys0)])
    pc = PolyCollection(polys, array=ratio, cmap="viridis", clim=(0, 1), edgecolors="k", linewidths=0.3)
    ax.add_collection(pc)
    ax.set_xlim(-2.5, 3.5)
    ax.set_ylim(-3, 3)
    ax.set_aspect("equal")
    ax.set_title(f"{title}\nstep {step}, smallest area ratio {ratio.min():.3f}", fontsize=9)
    ax.tick_params(labelsize=7)
    return pc


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    out, specs = sys.argv[1], sys.argv[2:]
    fig, axes = plt.subplots(1, len(specs), figsize=(4.2 * len(specs), 4.6), squeeze=False)
    for ax, spec in zip(axes[0], specs):
        title, run_dir, step = spec.rsplit(":", 2)
        pc = panel(ax, title, run_dir, int(step))
    fig.colorbar(pc, ax=axes[0].tolist(), shrink=0.8, label="cell area / original area")
    fig.savefig(out, dpi=90, bbox_inches="tight")


if __name__ == "__main__":
    main()
