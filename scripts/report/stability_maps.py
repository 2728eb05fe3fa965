#!/usr/bin/python3
"""Stability maps and their summary from the CSV files of bench_stability_sweep.

  stability_maps.py DIR

Reads DIR/stability_sweep.csv, critical_step.csv and extreme_cases.csv; writes one map per
integrator and model (DIR/stability_<integrator>_<model>.png: Young's modulus across, time
step up, one panel per Poisson ratio, each cell stable / recovered / failed, the predicted
critical step h_c = L/c drawn over it), the critical-step plot (DIR/critical_step.png) and
DIR/stability.md.
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from report_files import save_figure, write_text  # noqa: E402

OUTCOMES = ["stable", "recovered", "failed"]
COLOURS = ["#4daf4a", "#ffbf00", "#e41a1c"]
SWEEP_COLUMNS = ["integrator", "model", "young", "poisson", "step", "outcome", "energy_growth",
                 "inverted_max", "guard_recoveries", "guard_halvings", "guard_failures",
                 "wall_seconds", "guarded_wall_seconds", "failure"]


def read_csv(path, columns=None):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if columns and rows and list(rows[0].keys()) != columns:
        sys.exit(f"{path}: expected columns {','.join(columns)}, got {','.join(rows[0].keys())}")
    return rows


def read_optional_csv(path):
    """The rows of a file the sweep writes only without --grid-only; none when it is absent."""
    return read_csv(path) if os.path.exists(path) else []


def wave_limit(critical, poisson):
    """Young's modulus -> predicted h_c for one Poisson ratio (first model listed)."""
    first = critical[0]["model"] if critical else None
    return {float(r["young"]): float(r["predicted_hc"]) for r in critical
            if r["model"] == first and math.isclose(float(r["poisson"]), poisson)}


def draw_map(rows, integrator, model, critical, out_dir):
    youngs = sorted({float(r["young"]) for r in rows})
    poissons = sorted({float(r["poisson"]) for r in rows})
    steps = sorted({float(r["step"]) for r in rows})
    cells = {(float(r["young"]), float(r["poisson"]), float(r["step"])): r["outcome"] for r in rows}
    fig, axes = plt.subplots(1, len(poissons), figsize=(3.2 * len(poissons), 3.4), sharey=True,
                             squeeze=False)
    for ax, nu in zip(axes[0], poissons):
        grid = [[OUTCOMES.index(cells.get((E, nu, h), "failed")) for E in youngs] for h in steps]
        ax.imshow(grid, cmap=ListedColormap(COLOURS), vmin=0, vmax=2, origin="lower",
                  aspect="auto")
        ax.set_xticks(range(len(youngs)))
        ax.set_xticklabels([f"{E:.0e}".replace("e+0", "e") for E in youngs], rotation=60,
                           fontsize=7)
        ax.set_yticks(range(len(steps)))
        ax.set_yticklabels([f"{h:.0e}" for h in steps], fontsize=7)
        ax.set_title(f"nu = {nu:g}", fontsize=9)
        ax.set_xlabel("Young's modulus (Pa)", fontsize=8)
        limit = wave_limit(critical, nu)
        if limit:  # h_c = L/c in the cell coordinates (log interpolation between rows)
            xs = [i for i, E in enumerate(youngs) if E in limit]
            ys = [(math.log10(limit[youngs[i]]) - math.log10(steps[0])) /
                  (math.log10(steps[1]) - math.log10(steps[0])) if len(steps) > 1 else 0
                  for i in xs]
            ax.plot(xs, ys, "k--", linewidth=1.2, label="h_c = L/c")
            ax.set_ylim(-0.5, len(steps) - 0.5)
    axes[0][0].set_ylabel("time step (s)", fontsize=8)
    handles = [Patch(color=c, label=o) for c, o in zip(COLOURS, OUTCOMES)]
    handles.append(plt.Line2D([], [], color="k", linestyle="--", label="h_c = L/c (Eq 2.150)"))
    fig.legend(handles=handles, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.suptitle(f"{integrator} + {model}", fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    name = f"stability_{integrator}_{model}.png"
    save_figure(fig, os.path.join(out_dir, name), dpi=90)
    plt.close(fig)
    return name


def draw_critical(critical, out_dir):
    fig, ax = plt.subplots(figsize=(6, 4))
    for nu, marker in ((0.3, "o"), (0.49, "s")):
        for model, colour in zip(sorted({r["model"] for r in critical}), ["C0", "C1", "C2"]):
            rows = [r for r in critical if r["model"] == model and math.isclose(float(r["poisson"]), nu)]
            E = [float(r["young"]) for r in rows]
            ax.loglog(E, [float(r["limit_symplectic_euler"]) or float("nan") for r in rows],
                      marker, color=colour, fillstyle="none",
                      label=f"symplectic Euler limit, {model}, nu {nu}")
        rows = [r for r in critical if math.isclose(float(r["poisson"]), nu)]
        first = rows[0]["model"] if rows else None
        rows = [r for r in rows if r["model"] == first]
        ax.loglog([float(r["young"]) for r in rows], [float(r["predicted_hc"]) for r in rows],
                  "k--" if nu == 0.3 else "k:", label=f"h_c = L/c, nu {nu}")
    ax.set_xlabel("Young's modulus (Pa)")
    ax.set_ylabel("time step (s)")
    ax.set_title("Predicted critical step vs measured explicit limit", fontsize=10)
    ax.legend(fontsize=6)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    save_figure(fig, os.path.join(out_dir, "critical_step.png"), dpi=90)
    plt.close(fig)


def summary(rows, critical, extremes, maps):
    lines = ["# Stability on stiff and extreme tissue", "",
             "From `bench_stability_sweep` (a 2 cm block of 162 tets clamped at its base, "
             "released from a 10 % shear, mass damping 1/s, no gravity; one step per frame for "
             "max(50 steps, 5 ms); each cell run bare and, if that fails, under the stability "
             "guard). stable: the bare run stays finite, its energy below 10x the start, every "
             "node within 10 block sizes and, for the models that cannot take inversion (the "
             "StVK forms: `edge_length` on both paths, `stvk_displacement` with both signs), "
             "every tet above 1 % of its rest volume; recovered: the bare run fails and the guarded run "
             "passes; failed: both fail (the guard ended the run with its message, the state of "
             "the last good frame restored). The verdict covers the run's length only: a slow "
             "growth (forward Euler at a small step) can pass it. Radau IIA at fixed steps "
             "(`radau_iia_fixed`) runs the two correct energies on their fast paths only "
             "(`edge_length`, `tensor_mass`): the other StVK paths evaluate the same energy. "
             "Every other integrator runs every preset of the registry: the adaptive steppers "
             "(`backward_euler_adaptive`, `abm3`, `rk4_adaptive`) frames of h with h their "
             "first and longest step; the quasistatic solver only the muscle tissue (the "
             "presets with an activated model), each frame the equilibrium at its end; the "
             "PSD-projected muscle preset only the integrators that solve with the stiffness.",
             "",
             "| integrator | model | stable | recovered | failed | guard halvings |",
             "|---|---|---|---|---|---|"]
    counts = defaultdict(lambda: defaultdict(int))
    halvings = defaultdict(int)
    for r in rows:
        key = (r["integrator"], r["model"])
        counts[key][r["outcome"]] += 1
        halvings[key] += int(r["guard_halvings"])
    for key in sorted(counts):
        c = counts[key]
        lines.append(f"| {key[0]} | {key[1]} | {c['stable']} | {c['recovered']} | "
                     f"{c['failed']} | {halvings[key]} |")
    lines += ["", "Maps (Young's modulus across, time step up, one panel per Poisson ratio):", ""]
    lines += [f"![{m}]({m})" for m in maps]
    if critical:
        lines += ["", "## Critical step", "",
                  "h_c = L/c (\"Adamss: Advanced Anisotropic Mass-Spring System\", Eq. 2.150; "
                  "L the shortest edge, c = sqrt((lambda + 2 mu) / "
                  "rho)) against 2/omega_max of the assembled stiffness and the largest stable "
                  "step found by bisection (300-step runs).", "",
                  "| model | E (Pa) | nu | h_c = L/c (s) | 2/omega_max (s) | symplectic Euler (s) | "
                  "Newtonian (s) | measured / h_c |", "|---|---|---|---|---|---|---|---|"]
        for r in critical:
            hc, se = float(r["predicted_hc"]), float(r["limit_symplectic_euler"])
            lines.append(f"| {r['model']} | {float(r['young']):.0e} | {r['poisson']} | {hc:.3g} | "
                         f"{float(r['two_over_omega_max']):.3g} | {se:.3g} | "
                         f"{float(r['limit_newtonian']):.3g} | {se / hc:.3g} |")
        lines += ["", "![critical step](critical_step.png)"]
    if extremes:
        lines += ["", "## Extreme cases (E = 10 kPa, nu = 0.45)", "",
                  "The same block: `compression_80pct` drives its top down by 80 % of its "
                  "height in 0.2 s; `forced_inversion` starts with the top corner node pushed "
                  "through the block (two tets inverted); `twist_180deg` turns the top by 180 "
                  "degrees in 0.2 s; `impact_20m_per_s` starts every free node at 20 m/s "
                  "towards the clamped base (3.2 times the dilatational wave speed, 6.2 m/s); "
                  "`sliver_elements` flattens the block 50:1 and releases it from the 10 % "
                  "shear. 0.3 s each, bare and guarded; energy growth against the larger of "
                  "the initial energy and mu V / 2 (a unit strain of the block). In the two "
                  "driven cases (compression, twist) the drive puts energy in: the growth is "
                  "recorded, but only the guard's energy balance, which counts the drive's "
                  "work, fails a run there.", "",
                  "| case | integrator | step (s) | model | outcome | inverted tets (max) | "
                  "guard halvings | what failed |", "|---|---|---|---|---|---|---|---|"]
        for r in extremes:
            lines.append(f"| {r['case']} | {r['integrator']} | {r['step']} | {r['model']} | "
                         f"{r['outcome']} | {r['inverted_max']} | {r['guard_halvings']} | "
                         f"{r['failure']} |")
    return "\n".join(lines) + "\n"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: stability_maps.py DIR")
    d = sys.argv[1]
    rows = read_csv(os.path.join(d, "stability_sweep.csv"), SWEEP_COLUMNS)
    critical = read_optional_csv(os.path.join(d, "critical_step.csv"))
    extremes = read_optional_csv(os.path.join(d, "extreme_cases.csv"))
    groups = defaultdict(list)
    for r in rows:
        groups[(r["integrator"], r["model"])].append(r)
    maps = [draw_map(g, i, m, critical, d) for (i, m), g in sorted(groups.items())]
    if critical:
        draw_critical(critical, d)
    write_text(os.path.join(d, "stability.md"), summary(rows, critical, extremes, maps))
    plot = ", critical_step.png" if critical else ""
    print(f"wrote {len(maps)} maps{plot} and stability.md in {d}")


if __name__ == "__main__":
    main()
