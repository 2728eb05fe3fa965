#!/usr/bin/env python3
"""Plots of the material experiments of bench_adamss ("Adamss: Advanced Anisotropic
Mass-Spring System", Sec. 2.8.1): DIR/stretch.png, DIR/spring_fit.png and DIR/shear.png from the
CSV files of the same names that `bench_adamss stretch|spring_fit|shear --out DIR` writes.

    adamss_material.py DIR [stretch] [spring_fit] [shear]   (no name: every CSV present)
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from report_files import save_figure  # noqa: E402

AXIS_COLOUR = {"fibre": "tab:red", "sheet": "tab:green", "normal": "tab:blue"}


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def grouped(rows, *keys):
    groups = defaultdict(list)
    for r in rows:
        groups[tuple(r[k] for k in keys)].append(r)
    return groups


def column(rows, key, scale=1.0):
    return [float(r[key]) * scale for r in rows]


def positive(xs, ys):
    pairs = [(x, y) for x, y in zip(xs, ys) if x > 0 and y > 0]
    return [p[0] for p in pairs], [p[1] for p in pairs]


def finish(fig, path):
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    print(f"wrote {path}")


def plot_stretch(d):
    rows = read_rows(os.path.join(d, "stretch.csv"))
    panels = {k: v for k, v in grouped(rows, "specimen", "topology").items()
              if any(float(r["strain"]) > 0 for r in v)}  # a run that stopped at once: no panel
    columns = min(3, len(panels))
    lines = (len(panels) + columns - 1) // columns
    fig, axes = plt.subplots(lines, columns, figsize=(4.6 * columns, 3.8 * lines), squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, ((specimen, topology), panel) in zip(axes.flat, panels.items()):
        for (loading, axis), curve in grouped(panel, "loading", "axis").items():
            colour = AXIS_COLOUR.get(axis, "tab:purple" if loading == "traction" else "tab:orange")
            strain = column(curve, "strain", 100)
            x, theory = positive(strain, column(curve, "theory_Pa", 1e-3))
            ax.plot(x, theory, "-", color=colour, lw=1.2)
            x, stress = positive(strain, column(curve, "stress_Pa", 1e-3))
            ax.plot(x, stress, "o", color=colour, ms=4, mfc="none",
                    label=f"{axis}" + ("" if loading == "clamped" and "turned" not in specimen
                                       else f", {loading} ends"))
        ax.set_yscale("log")
        ax.set_title(f"{specimen}, {topology}", fontsize=10)
        ax.set_xlabel("strain (%)")
        ax.set_ylabel("nominal stress P (kPa)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("Uniaxial stretch, Hunter law via the virtual hexahedron: "
                 "simulation (points), theory (lines)", fontsize=10)
    finish(fig, os.path.join(d, "stretch.png"))


PAIR_COLOUR = {"sf": "tab:red", "fn": "tab:orange", "ns": "tab:blue"}


def plot_spring_fit(d):
    rows = read_rows(os.path.join(d, "spring_fit.csv"))
    panels = grouped(rows, "specimen", "topology", "measure")
    columns = min(2, len(panels))
    lines = (len(panels) + columns - 1) // columns
    fig, axes = plt.subplots(lines, columns, figsize=(5.2 * columns, 3.9 * lines), squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.axis("off")
    for ax, ((specimen, topology, measure), panel) in zip(axes.flat, panels.items()):
        for (coefficients, axis), curve in grouped(panel, "coefficients", "axis").items():
            colour = AXIS_COLOUR.get(axis) or PAIR_COLOUR.get(axis, "tab:gray")
            x = column(curve, "strain", 100)
            if coefficients == "table_2.2":
                ax.plot(x, column(curve, "theory_Pa", 1e-3), "-", color=colour, lw=1.2,
                        label=f"{axis}: Hunter")
            ax.plot(x, column(curve, "value_Pa", 1e-3),
                    "o" if coefficients == "table_2.2" else "x", color=colour, ms=4, mfc="none",
                    label=f"{axis}: {coefficients.replace('_', ' ')}")
        ax.set_yscale("log")
        shear = measure == "shear_energy"
        test = "simple shear" if shear else "uniaxial stretch"
        ax.set_title(f"{specimen}, {topology}: {test}", fontsize=10)
        ax.set_xlabel("shear gamma (%)" if shear else "strain (%)")
        ax.set_ylabel("energy density W (kPa)" if shear else "nominal stress P (kPa)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.suptitle("Cubic axial and torsion springs: Table 2.2 (o) and fitted (x) "
                 "against the Hunter law (lines)", fontsize=10)
    finish(fig, os.path.join(d, "spring_fit.png"))


def plot_shear(d):
    rows = read_rows(os.path.join(d, "shear.csv"))
    panels = grouped(rows, "specimen")
    fig, axes = plt.subplots(1, len(panels), figsize=(5 * len(panels), 4), squeeze=False)
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, ((specimen,), panel) in zip(axes[0], panels.items()):
        for i, ((plane,), curve) in enumerate(grouped(panel, "plane").items()):
            colour = colours[i % len(colours)]
            shear = column(curve, "shear")
            x, energy = positive(shear, column(curve, "energy_J", 1e3))
            ax.plot(x, energy, "-", color=colour, lw=1.2, label=f"{plane}: energy")
            x, work = positive(shear, column(curve, "work_J", 1e3))
            ax.plot(x, work, "o", color=colour, ms=4, mfc="none", label=f"{plane}: work")
        ax.set_yscale("log")
        ax.set_title(specimen, fontsize=10)
        ax.set_xlabel("shear gamma")
        ax.set_ylabel("energy, work (mJ)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    fig.suptitle("Simple shear, Hunter law via the virtual hexahedron: applied work (Eq. 2.151, "
                 "points) and stored energy (lines)", fontsize=10)
    finish(fig, os.path.join(d, "shear.png"))


PLOTS = {"stretch": plot_stretch, "spring_fit": plot_spring_fit, "shear": plot_shear}


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    d = sys.argv[1]
    names = sys.argv[2:] or [n for n in PLOTS if os.path.exists(os.path.join(d, f"{n}.csv"))]
    for name in names:
        if name not in PLOTS:
            print(f"adamss_material.py: unknown plot '{name}'", file=sys.stderr)
            return 2
        PLOTS[name](d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
