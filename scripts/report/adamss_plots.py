#!/usr/bin/python3
"""Draws the plots of the bench_adamss experiments volume, scaling and mesh_independence
("Adamss: Advanced Anisotropic Mass-Spring System", Secs. 2.8.2, 2.8.3 and 2.1.2) from their
CSV files.

  adamss_plots.py volume DIR             DIR/volume.csv -> DIR/volume.png
  adamss_plots.py scaling DIR            DIR/scaling.csv, scaling_fits.csv -> DIR/scaling.png
  adamss_plots.py mesh_independence DIR  DIR/mesh_independence.csv -> DIR/mesh_independence.png
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from report_files import save_figure  # noqa: E402

COLOURS = ["black", "red", "green", "blue", "magenta", "orange", "cyan"]


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(fig, path):
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def volume(d):
    """|dV/V0| against time, one line per p (hexahedra solid, six-tet split dashed)."""
    runs = defaultdict(lambda: ([], []))
    for r in read_csv(os.path.join(d, "volume.csv")):
        t, change = runs[(r["mesh"], float(r["p_kpa"]))]
        t.append(float(r["t"]))
        change.append(max(abs(float(r["volume_change"])), 1e-12))
    fig, ax = plt.subplots(figsize=(8, 5))
    pressures = sorted({p for _, p in runs})
    for (mesh, p), (t, change) in sorted(runs.items()):
        label = ("no volume term" if p == 0 else f"p = {p:g} kPa") + f" ({mesh})"
        ax.plot(t, change, color=COLOURS[pressures.index(p) % len(COLOURS)],
                linestyle="-" if mesh == "hex" else "--", label=label)
    ax.axhline(0.01, color="grey", linestyle=":", label="1 %")
    ax.set_yscale("log")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("|dV / V0|")
    ax.set_title("Volume change under gravity, 6 x 6 x 12 cuboid (Adamss Sec. 2.8.2)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    save(fig, os.path.join(d, "volume.png"))


def scaling(d):
    """Time of the implicit steps against elements, log-log, one line per preconditioner and
    thread count, with the fitted slope and a slope-1 guide."""
    groups = defaultdict(list)
    for r in read_csv(os.path.join(d, "scaling.csv")):
        groups[(r["preconditioner"], int(r["threads"]))].append(r)
    fits = {(f["preconditioner"], int(f["threads"])): float(f["slope_cpu"])
            for f in read_csv(os.path.join(d, "scaling_fits.csv"))}
    fig, ax = plt.subplots(figsize=(8, 5))
    steps = "?"
    for i, (key, rows) in enumerate(sorted(groups.items())):
        rows.sort(key=lambda r: int(r["elements"]))
        steps = rows[0]["steps"]
        x = [int(r["elements"]) for r in rows]
        y = [float(r["cpu_seconds"]) for r in rows]
        ax.plot(x, y, marker="o", color=COLOURS[(i + 1) % len(COLOURS)],
                label=f"{key[0]}, {key[1]} thread(s): slope {fits.get(key, math.nan):.2f}")
        if i == 0:
            ax.plot(x, [y[0] * xi / x[0] for xi in x], color="grey", linestyle=":",
                    label="linear (slope 1)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("hexahedra")
    ax.set_ylabel(f"CPU seconds of {steps} steps (median)")
    ax.set_title("Backward Euler steps against size, 6 x 6 x 12 cm cuboids (Adamss Sec. 2.8.3)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, os.path.join(d, "scaling.png"))


def mesh_independence(d):
    """Stress against strain per mesh, one panel per case and axis; resolutions by line style."""
    curves = defaultdict(lambda: ([], []))
    for r in read_csv(os.path.join(d, "mesh_independence.csv")):
        strain, stress = curves[(r["case"], r["axis"], r["mesh"], int(r["cells"]))]
        strain.append(100 * float(r["strain"]))
        stress.append(float(r["stress_pa"]) / 1e3)
    panels = sorted({(c, a) for c, a, _, _ in curves})
    meshes = sorted({m for _, _, m, _ in curves})
    cells = sorted({n for _, _, _, n in curves})
    fig, axes = plt.subplots(1, len(panels), figsize=(4 * len(panels), 4.5), squeeze=False)
    for ax, (case, axis) in zip(axes[0], panels):
        for (c, a, mesh, n), (strain, stress) in sorted(curves.items()):
            if (c, a) != (case, axis):
                continue
            ax.plot(strain, stress, color=COLOURS[meshes.index(mesh) % len(COLOURS)],
                    linestyle="-" if n == cells[-1] else "--", marker=".",
                    label=f"{mesh} {n}^3")
        ax.set_title(f"{case}, along {axis}", fontsize=9)
        ax.set_xlabel("strain (%)")
        ax.set_ylabel("P (kPa)")
        ax.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=6)
    fig.suptitle("Uniaxial stretch of a 1 cm cube on each mesh (Adamss Sec. 2.1.2)")
    save(fig, os.path.join(d, "mesh_independence.png"))


PLOTS = {"volume": volume, "scaling": scaling, "mesh_independence": mesh_independence}

if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] not in PLOTS:
        sys.exit("usage: adamss_plots.py volume|scaling|mesh_independence DIR")
    PLOTS[sys.argv[1]](sys.argv[2])
