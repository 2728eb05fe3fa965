#!/usr/bin/python3
"""Draws the benchmark report from the CSV files of bench_work_precision and bench_scaling.

  plot.py DIR [--elapsed SECONDS] [--command TEXT] [--note TEXT]
  plot.py DIR --implicit-scaling

Reads DIR/work_precision.csv, work_precision_facts.csv, scaling.csv and scaling_fits.csv;
writes one log-log error-vs-time PNG per problem (Pareto front highlighted), the mesh
convergence and scaling plots, and DIR/README.md naming each problem's Pareto front and its
best pair, with the machine and the date. If present, DIR/bullet_peer.csv (bench_bullet_peer)
adds Bullet's runs to the plots and a same-run table beside our pair, and DIR/stability.md
(stability_maps.py) gets a closing section with its summary table.
"""
import argparse
import csv
import datetime
import math
import os
import sys
from collections import defaultdict

import matplotlib
from machine import machine_text

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from report_files import save_figure, write_text  # noqa: E402

WORK_COLUMNS = ["problem", "model", "integrator", "parameter", "error", "cpu_seconds",
                "wall_seconds", "steps", "rejected_steps", "newton_iterations",
                "linear_iterations", "stable"]

PROBLEMS = {
    "cantilever_static": (
        "1. Cantilever, small deflection (static)",
        "Beam 0.1 x 0.01 x 0.01 m (2 x 2 cells across, 20 along, 480 tets), E = 100 kPa, "
        "nu = 0.3, 1000 kg/m^3, clamped at x = 0, under a body load of 1 % of gravity, so the "
        "Euler-Bernoulli tip deflection is 1.5 % of the length. Every dynamic integrator runs "
        "the damped dynamics from rest to steady state (mass-proportional damping, critical for "
        "the first mode, 2 s = 20 / omega_1); the implicit methods with long steps are "
        "pseudo-time continuation. The quasistatic solver (`quasistatic`: Newton with "
        "Jacobi-preconditioned CG, `quasistatic_cholesky`: with a sparse Cholesky factor) solves "
        "the equilibrium in one frame, at relative tolerances of the residual 1e-2 .. 1e-10. "
        "Error: relative tip "
        "deflection against Euler-Bernoulli; discrete error: against the static solution of the "
        "same mesh and model (Newton with a sparse Cholesky solve). Every converged run "
        "lands on the mesh's own deflection, which the coarse mesh puts far from "
        "Euler-Bernoulli (locking, see 1b): the error has that floor, the discrete error "
        "compares the integrators."),
    "cantilever_vibration": (
        "2. Cantilever, free vibration",
        "The same beam, undamped, released from its lowest bending mode (0.1 mm at the tip) "
        "and run for 1.5 periods. Frequency from the first and third zero crossings of the tip "
        "displacement (cubic Hermite interpolation between samples, 64 per period). Error: "
        "against the Euler-Bernoulli first frequency; discrete error: against the mesh's own "
        "lowest bending frequency (dense eigen-decomposition at rest). The coarse mesh is "
        "too stiff in bending (linear tets lock, see 1b), and backward Euler's numerical "
        "lowering of the frequency partly cancels that: its error against the analytic value "
        "can be smaller than that of an exact integration of the same mesh. Compare "
        "integrators by the discrete error."),
    "beam_large_deflection": (
        "3a. Large deformation: the beam falling under gravity",
        "The same soft beam under full gravity (linear theory would give a tip deflection of "
        "1.5 beam lengths), mass-proportional damping 5 /s, 0.5 s from rest. Error: largest "
        "node distance over the 0.01 s samples against edge_length (StVK) by Radau IIA at a "
        "very tight tolerance, relative to the largest displacement of that reference. "
        "Discrete error: against a reference of the same model (the linear model and the "
        "printed Eq 5 sign get their own; the StVK models share one)."),
    "spindle_pull": (
        "3b. Large deformation: the spindle muscle pulled by one node",
        "The spindle muscle at the training-scene resolution (187 nodes, 480 tets, fibres along "
        "the spindle, E_L 150 kPa, E_T 20 kPa, nu 0.4, 1060 kg/m^3, tendon ends fixed, damping "
        "10 /s); a belly node is pulled 1 cm radially over 0.1 s and back over 0.1 s. Errors as "
        "in 3a."),
    "patch": (
        "4. Patch test",
        "A jittered 4 x 4 x 4-cell box (4 cm, 384 tets, transversely isotropic), every boundary "
        "node driven to an affine map x = A X (up to 8 % strain, ramped in over 0.05 s), the "
        "interior damped to rest. Error: largest node distance to the affine field relative to "
        "the largest boundary displacement (the exact discrete solution is the affine field)."),
    "uniaxial_stretch": (
        "5. Adamss: uniaxial stretch of myocardium",
        "A 1 cm cube (2 x 2 x 2 cells, 48 tets), fibres along z, 1060 kg/m^3, bottom fixed, top "
        "moved 15 % along the fibres over 50 ms (lateral motion held) and held to 100 ms, "
        "mass-proportional damping 100 /s. Only the two Adamss models run it: adamss_hunter (the "
        "Hunter law of Table 2.1 through the virtual hexahedron) and adamss_springs (the cubic "
        "axial and the torsion springs of Table 2.2). Error: the nominal stress on the top face "
        "at the end against the Hunter law's uniaxial value (4425 Pa); the springs miss it by "
        "their fit. Discrete error: the largest difference of that stress from Radau IIA's at "
        "rtol 1e-9 on the same model over the samples, relative to 4425 Pa. The explicit sweep's "
        "limit is 2 / omega_max at 15 % stretch (the models stiffen)."),
    "muscle_contraction": (
        "6. Muscle: a block contracting at activation 0.5",
        "A 2 x 2 x 1 cm block (192 tets), fibres along x, base clamped, `muscle_groups` with the "
        "teran_muscle law (constants from E 30 kPa, nu 0.45: mu = 2 (A + B), A = 3 B, bulk "
        "E / (3 (1 - 2 nu)), sigma_max = mu), one muscle over every element switched on at "
        "activation 0.5 at t = 0; 1060 kg/m^3, mass-proportional damping 2 omega_1, run for "
        "20 / omega_1. Only the muscle tissue runs it: teran_muscle (no inversion handling), "
        "teran_muscle_inversion (threshold 0.25) and teran_muscle_inversion_psd (and PSD "
        "tangents). The quasistatic solver solves the equilibrium in one frame; the dynamic "
        "integrators run the damped contraction to rest. Error (= discrete error): the largest "
        "node distance of the end state from the same model's equilibrium (the bench's own "
        "Newton with a sparse Cholesky solve, activation raised in ten steps), relative to the "
        "largest displacement of that equilibrium."),
}


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        return float(text)
    except ValueError:
        return float("nan")


def finite(x):
    return not (math.isnan(x) or math.isinf(x))


def check_columns(rows, path):
    if not rows:
        sys.exit(f"plot.py: {path}: no rows")
    missing = [c for c in WORK_COLUMNS if c not in rows[0]]
    if missing:
        sys.exit(f"plot.py: {path}: missing columns {', '.join(missing)}")


def pareto_front(runs, key):
    """Runs not beaten in both CPU time and error by another run, fastest first."""
    points = sorted((r for r in runs if finite(r[key])), key=lambda r: (r["cpu"], r[key]))
    front, best = [], float("inf")
    for r in points:
        if r[key] < best:
            front.append(r)
            best = r[key]
    return front


def best_pair(front, key):
    """The (model, integrator) with the most runs on the front; ties: the lower error."""
    counts = defaultdict(list)
    for r in front:
        counts[(r["model"], r["integrator"])].append(r[key])
    return max(counts.items(), key=lambda kv: (len(kv[1]), -min(kv[1])))[0] if counts else None


# What each integrator of the work-precision runs is (docs/solvers.md describes them).
INTEGRATOR_TEXT = {
    "newtonian": "Jeffrey's Eq 11", "symplectic_euler": "semi-implicit",
    "explicit_euler": "forward; \"Adamss\", Sec. 2.5.2",
    "backward_euler": "linearised, one Newton step",
    "backward_euler_newton": "up to 8 Newton iterations",
    "backward_euler_adaptive": "the step halved or doubled by the Krylov iterations it needs, "
                               "\"Adamss\" Sec. 2.5.5",
    "abm3": "Adams-Bashforth-Moulton predictor-corrector, adaptive",
    "rk4_adaptive": "classical Runge-Kutta with step doubling, Jeffrey's Appendix A",
    "radau_iia": "3-stage, analytical Jacobian, adaptive",
    "quasistatic": "equilibrium per frame, Jacobi-preconditioned CG",
    "quasistatic_cholesky": "equilibrium per frame, Cholesky-preconditioned CG",
    "static_newton": "the static reference",
}
PARAMETER_TEXT = {"h": "step h", "rtol": "relative tolerance",
                  "upper_iterations": "upper_iterations"}


def models_and_integrators_text(runs):
    """The force models and integrators of these runs, each integrator with the parameter its
    runs vary and that parameter's range: the report says what it holds, not what it once did."""
    models = sorted({r["model"] for r in runs})
    ranges = defaultdict(list)
    for r in runs:
        if finite(r["parameter"]):
            ranges[(r["integrator"], r["parameter_name"])].append(r["parameter"])
    integrators = []
    for name in sorted({r["integrator"] for r in runs}):
        kinds = sorted(k for k in ranges if k[0] == name)
        spans = ", ".join(f"{PARAMETER_TEXT.get(k[1], k[1])} {value_range(ranges[k])}"
                          for k in kinds)
        what = "; ".join(t for t in (INTEGRATOR_TEXT.get(name, ""), spans) if t)
        integrators.append(f"`{name}`" + (f" ({what})" if what else ""))
    return (f"Force models, {len(models)} (the registry's presets, docs/registry.md): "
            + ", ".join(f"`{m}`" for m in models) + ". "
            f"Integrators, {len(integrators)}, with the parameter their runs vary: "
            + "; ".join(integrators) + ". Steps h in seconds; the explicit methods' steps are "
            "fractions of the stability limit 2 / omega_max of the model at rest (1.5, 0.9, "
            "0.5, 0.25 and 0.125 in a full run, 0.5 with --quick; rounded down to whole steps "
            "per sample interval), so their h differ between models.")


def value_range(values):
    low, high = min(values), max(values)
    return f"{low:.3g}" if low == high else f"{low:.3g} .. {high:.3g}"


def load_csv_runs(path):
    rows = read_csv(path)
    check_columns(rows, path)
    return load_runs(rows)


def load_runs(rows):
    runs = []
    for row in rows:
        runs.append({
            "problem": row["problem"], "model": row["model"], "integrator": row["integrator"],
            "parameter": number(row["parameter"]), "parameter_name": row.get("parameter_name", ""),
            "error": number(row["error"]), "discrete": number(row.get("discrete_error", "nan")),
            "cpu": number(row["cpu_seconds"]), "wall": number(row["wall_seconds"]),
            "steps": int(row["steps"]), "rejected": int(row["rejected_steps"]),
            "stable": row["stable"] == "1", "note": row.get("note", ""),
            "tets": int(number(row.get("tets", "0")) if finite(number(row.get("tets", "0"))) else 0),
        })
    return runs


COLOURS = {"newtonian": "tab:blue", "symplectic_euler": "tab:cyan", "explicit_euler": "tab:gray",
           "backward_euler": "tab:orange", "backward_euler_newton": "tab:red",
           "radau_iia": "tab:green", "static_newton": "tab:purple",
           "backward_euler_adaptive": "tab:brown", "abm3": "tab:olive", "rk4_adaptive": "gold",
           "quasistatic": "tab:pink", "quasistatic_cholesky": "darkviolet"}
MARKERS = {"edge_length": "o", "edge_length_literal": "s", "stvk_displacement": "^",
           "stvk_displacement_paper_literal": "v", "tensor_mass": "D",
           "teran_muscle": "o", "teran_muscle_inversion": "s", "teran_muscle_inversion_psd": "^"}
FLOOR = 1e-16  # exact results are drawn here on the log axis

# bench_bullet_peer: Bullet's forces (legend name, marker, colour) and our pair beside them.
BULLET_FORCES = {"bullet_linear_elasticity": ("linear elasticity", "X", "black"),
                 "bullet_neohookean": ("Neo-Hookean", "P", "dimgray")}
PEER_PAIR = ("stvk_displacement", "backward_euler")


def is_bullet(r):
    return r["model"].startswith("bullet_")


def stable_bullet(peer):
    """Bullet's stable runs of the step sweep (its Krylov-cap sweep stays in bullet_peer.md)."""
    return [r for r in peer if is_bullet(r) and r["stable"] and r["parameter_name"] == "h"]


def bullet_name(model):
    return "Bullet " + BULLET_FORCES.get(model, (model[len("bullet_"):],))[0]


def bullet_style(model):
    return BULLET_FORCES.get(model, (None, "*", "black"))[1:]


def draw_panel(ax, runs, key, title):
    groups = defaultdict(list)
    for r in runs:
        if finite(r[key]):
            groups[(r["model"], r["integrator"])].append(r)
    for (model, integrator), group in sorted(groups.items()):
        group.sort(key=lambda r: r["cpu"])
        ax.plot([r["cpu"] for r in group], [max(r[key], FLOOR) for r in group],
                marker=MARKERS.get(model, "o"), color=COLOURS.get(integrator, "black"),
                linewidth=0.8, markersize=4, alpha=0.8)
    front = pareto_front(runs, key)
    if front:
        ax.step([r["cpu"] for r in front], [max(r[key], FLOOR) for r in front], where="post",
                color="black", linestyle="--", linewidth=1.2)
        ax.scatter([r["cpu"] for r in front], [max(r[key], FLOOR) for r in front],
                   s=70, facecolors="none", edgecolors="black", zorder=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU time (s, one thread)")
    ax.set_ylabel("relative error")
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="major", alpha=0.3)


def draw_bullet(ax, bullet, key):
    """Bullet's step sweep, a dotted line per force, drawn below our runs."""
    for model in sorted({r["model"] for r in bullet}):
        marker, colour = bullet_style(model)
        points = sorted((r for r in bullet if r["model"] == model and finite(r[key])),
                        key=lambda r: r["cpu"])
        ax.plot([r["cpu"] for r in points], [max(r[key], FLOOR) for r in points],
                marker=marker, color=colour, linestyle=":", linewidth=1.0, markersize=7,
                alpha=0.75, zorder=1.5)


def bullet_handles(bullet):
    from matplotlib.lines import Line2D
    return [Line2D([], [], marker=bullet_style(m)[0], color=bullet_style(m)[1], linestyle=":",
                   markersize=7, label=f"{bullet_name(m)} (backward Euler)")
            for m in sorted({r["model"] for r in bullet})]


def legend_handles(runs):
    from matplotlib.lines import Line2D
    integrators = sorted({r["integrator"] for r in runs})
    models = sorted({r["model"] for r in runs})
    handles = [Line2D([], [], color=COLOURS.get(i, "black"), label=i) for i in integrators]
    handles += [Line2D([], [], marker=MARKERS.get(m, "o"), color="black", linestyle="", label=m)
                for m in models]
    handles.append(Line2D([], [], color="black", linestyle="--", marker="o",
                          markerfacecolor="none", label="Pareto front"))
    return handles


def plot_problem(problem, runs, out_dir, bullet=()):
    """bullet: Bullet's stable runs of bullet_peer.csv, drawn beside ours, not in the fronts."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    stable = [r for r in runs if r["stable"]]
    for ax, key, title in ((axes[0], "error", "error as defined by the problem"),
                           (axes[1], "discrete", "discrete error (same mesh and model, exact)")):
        draw_panel(ax, stable, key, title)
        draw_bullet(ax, bullet, key)
    fig.suptitle(PROBLEMS.get(problem, (problem,))[0])
    fig.legend(handles=legend_handles(runs) + bullet_handles(bullet), loc="lower center", ncol=6,
               fontsize=8)
    fig.tight_layout(rect=(0, 0.1, 1, 0.95))
    path = os.path.join(out_dir, f"{problem}.png")
    save_figure(fig, path, dpi=110)
    plt.close(fig)
    return os.path.basename(path)


def log_slope(xs, ys):
    lx, ly = [math.log(x) for x in xs], [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((x - mx) ** 2 for x in lx)
    return sum((x - mx) * (y - my) for x, y in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def finish_loglog(fig, ax, xlabel, ylabel, title, path, legend_size):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=legend_size)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def plot_mesh_convergence(runs, out_dir):
    fig, ax = plt.subplots(figsize=(7, 5))
    slopes = {}
    by_model = defaultdict(list)
    for r in runs:
        if finite(r["error"]):
            by_model[r["model"]].append(r)
    for model, group in sorted(by_model.items()):
        group.sort(key=lambda r: r["parameter"])
        h = [0.01 / r["parameter"] for r in group]
        e = [r["error"] for r in group]
        slopes[model] = log_slope(h[-3:], e[-3:]) if len(h) >= 3 else log_slope(h, e)
        ax.plot(h, e, marker=MARKERS.get(model, "o"), label=f"{model} (slope {slopes[model]:.2f})")
    finish_loglog(fig, ax, "cell size across the beam (m)", "tip deflection error vs Euler-Bernoulli",
                  "1. Cantilever: mesh convergence (static Newton)",
                  os.path.join(out_dir, "cantilever_static_mesh.png"), legend_size=8)
    return slopes


def plot_scaling(samples, fits, out_dir, name="scaling.png",
                 title="Time per force evaluation, explicit step and implicit step"):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    groups = defaultdict(list)
    for s in samples:
        groups[(s["quantity"], s["model"])].append(s)
    styles = {"force_evaluation": "-", "explicit_step": "--", "implicit_step": ":"}
    for (quantity, model), group in sorted(groups.items()):
        group.sort(key=lambda s: int(s["tets"]))
        slope = fits.get((quantity, model), float("nan"))
        ax.plot([int(s["tets"]) for s in group], [number(s["wall_seconds"]) for s in group],
                linestyle=styles.get(quantity, "-"), marker=MARKERS.get(model, "o"),
                label=f"{quantity}, {model} (slope {slope:.2f})")
    finish_loglog(fig, ax, "tets", "seconds (median, one thread)", title,
                  os.path.join(out_dir, name), legend_size=7)


def draw_implicit_scaling(d):
    samples = [r for r in read_csv(os.path.join(d, "scaling.csv")) if r["quantity"] == "implicit_step"]
    fits = {(r["quantity"], r["model"]): number(r["slope"])
            for r in read_csv(os.path.join(d, "scaling_fits.csv"))}
    plot_scaling(samples, fits, d, "scaling_implicit.png",
                 "Implicit step (backward Euler, PCG to 1e-6) by preconditioner, box grids")


def fmt(x, digits=3):
    if not finite(x):
        return "n/a"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def run_label(r):
    unit = " s" if r["parameter_name"] == "h" else ""
    return f"{r['parameter_name']} = {fmt(r['parameter'])}{unit}"


def problem_section(problem, runs, facts, image):
    title, text = PROBLEMS.get(problem, (problem, ""))
    lines = [f"## {title}", "", text, ""]
    if facts:
        lines += ["| quantity | value | unit | meaning |", "|---|---|---|---|"]
        lines += [f"| {f['quantity']} | {fmt(number(f['value']), 6)} | {f['unit']} | {f['meaning']} |"
                  for f in facts]
        lines.append("")
    lines += [f"![{problem}]({image})", ""]
    stable = [r for r in runs if r["stable"]]
    unstable = defaultdict(int)
    for r in runs:
        if not r["stable"]:
            unstable[r["integrator"]] += 1
    for key, label in (("error", "error"), ("discrete", "discrete error")):
        front = pareto_front(stable, key)
        pair = best_pair(front, key)
        lines += [f"Pareto front ({label}, CPU time):", "",
                  "| model | integrator | parameter | error | discrete error | CPU s | steps |",
                  "|---|---|---|---|---|---|---|"]
        lines += [f"| {r['model']} | {r['integrator']} | {run_label(r)} | {fmt(r['error'])} | "
                  f"{fmt(r['discrete'])} | {fmt(r['cpu'])} | {r['steps']} |" for r in front]
        if pair:
            lines += ["", f"Best pair ({label}): **{pair[0]} + {pair[1]}** "
                      f"({sum(1 for r in front if (r['model'], r['integrator']) == pair)} of "
                      f"{len(front)} front points)."]
        lines.append("")
    stopped = [r for r in runs if r["stable"] and "time limit" in r["note"]]
    if stopped:
        lines.append("Stopped at the per-run CPU-time limit (no error measured): " +
                     ", ".join(f"{r['model']} + {r['integrator']} {run_label(r)}" for r in stopped) +
                     ".")
        lines.append("")
    if unstable:
        lines.append("Unstable runs (non-finite state, blow-up or integrator failure): " +
                     ", ".join(f"{k} {v}" for k, v in sorted(unstable.items())) +
                     f" of {len(runs)} runs.")
        lines.append("")
    return lines


def ratio(a, b):
    return a / b if finite(a) and finite(b) and b > 0 else float("nan")


def cell(r, *extra):
    return " / ".join([fmt(r[k]) for k in ("error", "discrete", "cpu")] + [fmt(x) for x in extra])


def bullet_table(peer, bullet):
    """At each step h: our pair of bullet_peer.csv, then each Bullet force and its CPU ratio."""
    ours = {r["parameter"]: r for r in peer
            if (r["model"], r["integrator"]) == PEER_PAIR and r["parameter_name"] == "h"}
    forces = sorted({r["model"] for r in bullet})
    by_step = {(r["model"], r["parameter"]): r for r in bullet if r["parameter_name"] == "h"}
    lines = ["| h (s) | ours: error / discrete / CPU s | " +
             " | ".join(f"{bullet_name(m)}: error / discrete / CPU s / ratio" for m in forces) +
             " |", "|---|---|" + "---|" * len(forces)]
    for h in sorted({h for _, h in by_step}, reverse=True):
        mine = ours.get(h)
        cells = [fmt(h), cell(mine) if mine else "n/a"]
        cells += [cell(by_step[m, h], ratio(by_step[m, h]["cpu"], mine["cpu"] if mine else 0))
                  if (m, h) in by_step else "n/a" for m in forces]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def combined_front_text(stable, bullet, key):
    """Bullet's runs on the front over our runs and Bullet's, each with how much it beats the
    error of the faster front run before it."""
    front = pareto_front(stable + bullet, key)
    on = [f"{bullet_name(r['model'])} {run_label(r)} (error {fmt(r[key])} in {fmt(r['cpu'])} s"
          + (f", {fmt(1 - r[key] / front[i - 1][key], 2)} below the faster "
             f"{front[i - 1]['model']} + {front[i - 1]['integrator']})" if i else ")")
          for i, r in enumerate(front) if is_bullet(r)]
    return "; ".join(on) if on else "none of Bullet's runs"


def bullet_section(runs, peer, d):
    """Bullet beside our pair in bullet_peer.csv, the combined fronts and Bullet's failures."""
    bullet = stable_bullet(peer)
    if not bullet:
        return []
    link = "[bullet_peer.md](bullet_peer.md)" if os.path.exists(
        os.path.join(d, "bullet_peer.md")) else "`bullet_peer.md`"
    stable = [r for r in runs if r["stable"]]
    fronts = [f"{label}: {combined_front_text(stable, bullet, key)}"
              for key, label in (("error", "error"), ("discrete", "discrete error"))]
    unstable = [f"{r['model']} + {r['integrator']} {run_label(r)}"
                + (f" ({r['note']})" if r["note"] else "")
                for r in peer if is_bullet(r) and not r["stable"]]
    lines = ["Bullet beside our pair, same run (Bullet 3.24's deformable solver, see " + link +
             "): these times come from `bullet_peer.csv`'s own run, measured in the same process "
             "as its " + " + ".join(PEER_PAIR) + " rows, so they are compared with the rows of "
             "that file, not with the work-precision runs above. Ratio: CPU time Bullet / ours.",
             ""] + bullet_table(peer, bullet) + [
             "", "On the Pareto front over our work-precision runs and Bullet's (CPU time, so it "
             "mixes the clocks of two runs), " + "; ".join(fronts) + "."]
    if unstable:
        lines += ["", "Bullet runs marked unstable, not drawn: " + ", ".join(unstable) + "."]
    return lines + [""]


def summary_row(problem, runs):
    stable = [r for r in runs if r["stable"]]
    front = pareto_front(stable, "error")
    pair = best_pair(front, "error")
    discrete_pair = best_pair(pareto_front(stable, "discrete"), "discrete")
    fastest = None
    if front:
        least = min(r["error"] for r in front)
        fastest = min((r for r in front if r["error"] <= 2 * least), key=lambda r: r["cpu"])
    cells = [PROBLEMS.get(problem, (problem,))[0], " + ".join(pair) if pair else "n/a",
             f"{fastest['model']} + {fastest['integrator']} {run_label(fastest)}: error "
             f"{fmt(fastest['error'])} in {fmt(fastest['cpu'])} s" if fastest else "n/a",
             " + ".join(discrete_pair) if discrete_pair else "n/a"]
    return "| " + " | ".join(cells) + " |"


def mesh_solver_lines(mesh_runs):
    """The quasistatic solver beside the static Newton on each mesh (when both ran)."""
    cpu = defaultdict(lambda: defaultdict(list))
    error = defaultdict(lambda: defaultdict(dict))
    tets = {}
    for r in mesh_runs:
        cpu[r["integrator"]][r["parameter"]].append(r["cpu"])
        error[r["parameter"]][r["model"]][r["integrator"]] = r["error"]
        tets[r["parameter"]] = r["tets"]
    if "static_newton" not in cpu or "quasistatic_cholesky" not in cpu:
        return []
    median = lambda xs: sorted(xs)[len(xs) // 2] if xs else float("nan")  # noqa: E731
    lines = ["The quasistatic solver (`quasistatic_cholesky`, rtol 1e-8) on the same meshes, "
             "CPU time per solve (median over the models) and its largest difference from the "
             "static Newton's error:", "",
             "| cells across | tets | static Newton (s) | quasistatic_cholesky (s) | largest error "
             "difference (at the CSV's 6 digits) |", "|---|---|---|---|---|"]
    for c in sorted(tets):
        diffs = [abs(e["quasistatic_cholesky"] - e["static_newton"])
                 for e in error[c].values() if "quasistatic_cholesky" in e and "static_newton" in e
                 and finite(e["quasistatic_cholesky"]) and finite(e["static_newton"])]
        lines.append(f"| {int(c)} | {tets[c]} | {fmt(median(cpu['static_newton'][c]))} | "
                     f"{fmt(median(cpu['quasistatic_cholesky'][c]))} | "
                     f"{fmt(max(diffs)) if diffs else 'n/a'} |")
    return lines + [""]


def mesh_section(all_mesh_runs, out_dir):
    mesh_runs = [r for r in all_mesh_runs if r["integrator"] == "static_newton"]
    slopes = plot_mesh_convergence(mesh_runs, out_dir)
    cells = sorted({r["parameter"] for r in mesh_runs})
    lines = ["## 1b. Cantilever: mesh convergence", "",
             "The static problem of section 1 solved exactly (Newton with a sparse Cholesky "
             "solve, no time integration) on meshes of 1 to N cells across (10 x as many "
             "along). Linear tets lock in bending, so the error falls slowly; the slope "
             "(error against cell size) is fitted over the three finest meshes.", "",
             "![mesh convergence](cantilever_static_mesh.png)", "",
             "| model | " + " | ".join(f"{int(c)} across" for c in cells) + " | slope |",
             "|---|" + "---|" * (len(cells) + 1)]
    by_model = defaultdict(dict)
    tets = {}
    for r in mesh_runs:
        by_model[r["model"]][r["parameter"]] = r["error"]
        tets[int(r["parameter"])] = r["tets"]
    for model, errors in sorted(by_model.items()):
        lines.append(f"| {model} | " + " | ".join(fmt(errors.get(c, float("nan"))) for c in cells) +
                     f" | {fmt(slopes.get(model, float('nan')))} |")
    lines += ["", "Tets: " + ", ".join(f"{c} across {t}" for c, t in sorted(tets.items())) + ".", ""]
    return lines + mesh_solver_lines(all_mesh_runs)


def scaling_section(d):
    samples = read_csv(os.path.join(d, "scaling.csv"))
    fits = {(f["quantity"], f["model"]): number(f["slope"])
            for f in read_csv(os.path.join(d, "scaling_fits.csv"))}
    plot_scaling(samples, fits, d)
    sizes = sorted({int(s["tets"]) for s in samples})
    lines = ["## Scaling", "",
             "Box grids of 6 tets per cell (bottom fixed, gravity, transversely isotropic "
             "tissue), one thread, median of repeats: one force evaluation of each model, "
             "one Newtonian explicit step and one linearised backward Euler step "
             "(h = 10 ms, Jacobi-PCG to 1e-6) of edge_length fast. Slope: least-squares fit "
             "of log time against log tets.", "", "![scaling](scaling.png)", "",
             "| quantity | model | " + " | ".join(f"{t} tets" for t in sizes) + " | slope |",
             "|---|---|" + "---|" * (len(sizes) + 1)]
    groups = defaultdict(dict)
    for s in samples:
        groups[(s["quantity"], s["model"])][int(s["tets"])] = number(s["wall_seconds"])
    for (quantity, model), times in sorted(groups.items()):
        cells = [f"{fmt(1e3 * times[t])} ms" if t in times else "n/a" for t in sizes]
        lines.append(f"| {quantity} | {model} | " + " | ".join(cells) +
                     f" | {fmt(fits.get((quantity, model), float('nan')))} |")
    lines.append("")
    return lines


def table_after_first_paragraph(path):
    """The Markdown table right after the first paragraph below the title of path, or []."""
    with open(path) as f:
        lines = [line.rstrip("\n") for line in f]
    i = 0
    while i < len(lines) and (not lines[i].strip() or lines[i].startswith("#")):
        i += 1
    while i < len(lines) and lines[i].strip() and not lines[i].startswith("|"):
        i += 1
    while i < len(lines) and not lines[i].strip():
        i += 1
    table = []
    while i < len(lines) and lines[i].startswith("|"):
        table.append(lines[i])
        i += 1
    return table if len(table) >= 2 else []


def stability_section(d):
    path = os.path.join(d, "stability.md")
    if not os.path.exists(path):
        return []
    table = table_after_first_paragraph(path)
    text = ("The stability sweep (`bench_stability_sweep`: Young's modulus x Poisson ratio x "
            "step, and extreme cases), its maps and the critical step are in "
            "[stability.md](stability.md)")
    if not table:
        return ["## Stability on stiff and extreme tissue", "", text + ".", ""]
    return ["## Stability on stiff and extreme tissue", "", text + "; per integrator and model, "
            "the cells that stay stable, pass only under the stability guard (recovered) or "
            "fail:", ""] + table + [""]


def load_peer(d):
    """bullet_peer.csv by problem, or nothing if bench_bullet_peer did not run."""
    path = os.path.join(d, "bullet_peer.csv")
    peer = defaultdict(list)
    if os.path.exists(path):
        for r in load_csv_runs(path):
            peer[r["problem"]].append(r)
    return peer


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("dir")
    parser.add_argument("--elapsed", type=float, default=float("nan"))
    parser.add_argument("--command", default="scripts/bench")
    parser.add_argument("--note", default="", help="what else ran on the machine, for the report")
    parser.add_argument("--repeats", type=int, default=1,
                        help="the benchmark's --repeats: each time is the median of that many runs")
    parser.add_argument("--implicit-scaling", action="store_true",
                        help="only draw DIR/scaling_implicit.png from DIR/scaling.csv and "
                             "scaling_fits.csv (bench_scaling's implicit-step rows)")
    args = parser.parse_args()
    d = args.dir
    if args.implicit_scaling:
        draw_implicit_scaling(d)
        return

    work_path = os.path.join(d, "work_precision.csv")
    runs = load_csv_runs(work_path)
    peer = load_peer(d)
    facts = defaultdict(list)
    facts_path = os.path.join(d, "work_precision_facts.csv")
    if os.path.exists(facts_path):
        for f in read_csv(facts_path):
            facts[f["problem"]].append(f)

    by_problem = defaultdict(list)
    for r in runs:
        by_problem[r["problem"]].append(r)

    # The date of the run: when the benchmark wrote its CSV.
    now = datetime.datetime.fromtimestamp(os.path.getmtime(work_path)).astimezone()
    lines = ["# Benchmark report", "",
             f"Produced by `{args.command}` on {now:%Y-%m-%d %H:%M %Z}"
             + (f" in {args.elapsed / 60:.1f} min of wall time" if finite(args.elapsed) else "")
             + f"; the {len(runs)} work-precision runs took {sum(r['cpu'] for r in runs) / 60:.1f} "
             f"min of CPU time and {sum(r['wall'] for r in runs) / 60:.1f} min of wall time "
             "(references and set-up not included).",
             f"Machine: {machine_text()}." + (f" {args.note}" if args.note else "")
             + " The plots use the process CPU time of each run (one thread), measured in the "
             "same process and the same run as its error. "
             + ("Each run is timed once." if args.repeats == 1 else
                f"Each row is the run of the median CPU time of {args.repeats}."), "",
             "Files: `work_precision.csv` (one row per run: " + ", ".join(WORK_COLUMNS) +
             ", then parameter_name, discrete_error, tets, note), `work_precision_facts.csv` "
             "(analytic values, references and their accuracy), `scaling.csv`, "
             "`scaling_fits.csv`.", "",
             models_and_integrators_text(runs),
             "Pareto front: the runs no other run beats in both CPU time and error. Best pair: "
             "the model + integrator with the most runs on the front.", ""]

    summary = ["| problem | best pair (error) | fastest front run within 2x of the least error "
               "| best pair (discrete error) |", "|---|---|---|---|"]
    sections = []
    ordered = [p for p in PROBLEMS if p in by_problem] + sorted(
        p for p in by_problem if p not in PROBLEMS and p != "cantilever_static_mesh")
    for problem in ordered:
        image = plot_problem(problem, by_problem[problem], d, stable_bullet(peer.get(problem, [])))
        sections += problem_section(problem, by_problem[problem], facts.get(problem, []), image)
        sections += bullet_section(by_problem[problem], peer.get(problem, []), d)
        summary.append(summary_row(problem, by_problem[problem]))
    lines += ["## Summary", ""] + summary + [""] + sections
    if by_problem.get("cantilever_static_mesh"):
        lines += mesh_section(by_problem["cantilever_static_mesh"], d)
    if os.path.exists(os.path.join(d, "scaling.csv")):
        lines += scaling_section(d)
    lines += stability_section(d)

    write_text(os.path.join(d, "README.md"), "\n".join(lines) + "\n")
    print(f"plot.py: wrote {d}/README.md and {len(by_problem)} problem plots")


if __name__ == "__main__":
    main()
