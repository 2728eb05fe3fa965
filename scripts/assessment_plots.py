#!/usr/bin/python3
"""Plots of a training assessment (matplotlib, Debian's python3-matplotlib).

  assessment_plots.py report DIR    DIR/{path,movements,force,strain}.csv and assessment.yaml
                                    (written by assess_bag or the assessment node; with
                                    DIR/tissue_surface.csv, the tissue under the tip path) ->
                                    DIR/tip_path.png, speed.png, force.png, strain.png and a
                                    short page DIR/assessment.html (score, plots, metrics)
  assessment_plots.py curve DIR     DIR/learning_curve.csv -> DIR/learning_curve.png

A plot without data is not written. Exit 0 when every plot with data was written; 2 with one
line on stderr when the input is missing or malformed.
"""
import csv
import html
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
import yaml  # noqa: E402

DPI = 100
SIZE = (6.4, 3.6)  # inches: 640 x 360 px


class InputError(Exception):
    pass


def read_csv(path):
    """Columns of a CSV with a header line, as lists of floats (empty cells: None)."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as err:
        raise InputError(f"{path}: cannot read ({err.strerror})")
    if not rows:
        raise InputError(f"{path}: expected a header line")
    header, data = rows[0], rows[1:]
    columns = {name: [] for name in header}
    for number, row in enumerate(data, start=2):
        if len(row) != len(header):
            raise InputError(f"{path}:{number}: expected {len(header)} columns, got {len(row)}")
        for name, text in zip(header, row):
            try:
                columns[name].append(float(text) if text != "" else None)
            except ValueError:
                if name == "label":
                    columns[name].append(text)
                else:
                    raise InputError(f"{path}:{number}: {name}: expected a number, got '{text}'")
    return columns


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def movement_colour(index):
    return plt.get_cmap("tab10")(index % 10)


def draw_tissue(ax, surface, a, b):
    """The tissue's rest surface projected on the view's axes a, b (0: x, 1: y, 2: z): its
    triangles filled, so the organ's outline and where the tip went over it show."""
    corners = [("ax", "ay", "az"), ("bx", "by", "bz"), ("cx", "cy", "cz")]
    triangles = [[(1e3 * surface[c[a]][i], 1e3 * surface[c[b]][i]) for c in corners]
                 for i in range(len(surface["ax"]))]
    ax.add_collection(PolyCollection(triangles, facecolors="#e8c4b8", edgecolors="none", zorder=0))
    ax.plot([], [], "s", color="#e8c4b8", ms=6, label="tissue at rest")  # legend entry


def plot_tip_path(path, out, surface=None):
    """The smoothed tip path from the front (world x right, y up: as the laparoscope looks
    along -z) and from the side (world z, the depth along the shaft, against y); each
    movement in its own colour, the pauses grey; the tissue under it when its surface is given."""
    if len(path["t"]) < 2:
        return False
    mm = [[1e3 * v for v in path[axis]] for axis in ("x", "y", "z")]
    fig, axes = plt.subplots(1, 2, figsize=SIZE)
    views = [(0, 1, "x (mm)", "y (mm)", "front view (world x, y)"),
             (2, 1, "z (mm)", "y (mm)", "side view (world z, y)")]
    moves = path["movement"]
    for ax, (a, b, xl, yl, title) in zip(axes, views):
        if surface and surface["ax"]:
            draw_tissue(ax, surface, a, b)
        ax.plot(mm[a], mm[b], color="0.55", lw=1.0, zorder=1)
        start = 0
        for k in range(1, len(moves) + 1):
            if k == len(moves) or moves[k] != moves[start]:
                if moves[start] is not None and moves[start] >= 0:
                    ax.plot(mm[a][start:k], mm[b][start:k], color=movement_colour(int(moves[start])),
                            lw=1.6, zorder=2)
                start = k
        ax.plot(mm[a][0], mm[b][0], "o", color="green", ms=5, zorder=3, label="start")
        ax.plot(mm[a][-1], mm[b][-1], "s", color="black", ms=5, zorder=3, label="end")
        ax.set_xlabel(xl)
        ax.set_ylabel(yl)
        ax.set_title(title, fontsize=9)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="best")
    save(fig, out)
    return True


def plot_speed(path, movements, out):
    if len(path["t"]) < 2:
        return False
    fig, ax = plt.subplots(figsize=SIZE)
    ax.plot(path["t"], [1e3 * v for v in path["speed"]], color="black", lw=1.0)
    contact = movements.get("contact") or [None] * len(movements["start"])
    for i, (start, end, ldlj, touched) in enumerate(zip(movements["start"], movements["end"],
                                                         movements["ldlj"], contact)):
        ax.axvspan(start, end, color=movement_colour(i), alpha=0.25, lw=0,
                   hatch="///" if touched else None)
        if ldlj is not None:
            ax.text(0.5 * (start + end), 1.0, f"{ldlj:.1f}", transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=7, color=movement_colour(i))
    ax.set_xlabel("time (s)")
    ax.set_ylabel("tip speed (mm/s)")
    ax.set_title("movements shaded (hatched: in contact); numbers: log dimensionless jerk", fontsize=9, pad=14)
    ax.grid(alpha=0.3)
    save(fig, out)
    return True


def plot_force(force, threshold, out):
    if len(force["t"]) < 2:
        return False
    fig, ax = plt.subplots(figsize=SIZE)
    t, f = force["t"], force["force"]
    ax.step(t, f, where="post", color="tab:blue", lw=1.0, label="|f|")
    ax.axhline(threshold, color="tab:red", ls="--", lw=1.0, label=f"threshold {threshold:g} N")
    ax.fill_between(t, threshold, [max(v, threshold) for v in f], step="post", color="tab:red", alpha=0.3)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("tool-tissue force (N)")
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    save(fig, out)
    return True


def plot_strain(strain, out):
    if len(strain["t"]) < 2:
        return False
    fig, ax = plt.subplots(figsize=SIZE)
    ax.step(strain["t"], strain["max_strain"], where="post", color="tab:purple", lw=1.0)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("largest tissue strain (Green-Lagrange)")
    ax.grid(alpha=0.3)
    save(fig, out)
    return True


def write_page(folder, doc, figures):
    """assessment.html: the overall score, the per-metric scores, the plots, the metrics."""
    esc = html.escape
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>Training assessment</title>",
             "<style>body{font-family:sans-serif;max-width:60em;margin:auto}"
             "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 6px}</style>",
             "</head><body><h1>Training assessment</h1>",
             f"<p>Source: <code>{esc(str(doc.get('source', '')))}</code></p>"]
    score = doc.get("score")
    if score:
        overall = f"{score['overall']:.0f} / 100" if score.get("has_data") else "no data"
        parts.append(f"<h2>Overall score: {overall}</h2><p>{esc(str(score.get('rule', '')))}</p>")
        parts.append("<table><tr><th>metric</th><th>value</th><th>expert</th><th>novice</th><th>score</th></tr>")
        for key, band in (score.get("metrics") or {}).items():
            value = doc["metrics"].get(key)
            cell = f"{band['score']:.0f}" if "score" in band else "-"
            parts.append(f"<tr><td>{esc(key)}</td><td>{value:.4g}</td><td>{band['expert']:.4g}</td>"
                         f"<td>{band['novice']:.4g}</td><td>{cell}</td></tr>")
        parts.append("</table>")
    for name in figures:
        parts.append(f"<p><img src='{esc(name)}' alt='{esc(name)}'></p>")
    parts.append("<h2>Metrics</h2><table>")
    for key, value in doc["metrics"].items():
        parts.append(f"<tr><td>{esc(key)}</td><td>{value:.6g}</td></tr>")
    parts.append("</table></body></html>\n")
    with open(os.path.join(folder, "assessment.html"), "w") as f:
        f.write("\n".join(parts))


def report(folder):
    try:
        with open(os.path.join(folder, "assessment.yaml")) as f:
            doc = yaml.safe_load(f)
        threshold = float(doc["settings"]["force_threshold"])
    except (OSError, yaml.YAMLError, KeyError, TypeError, ValueError) as err:
        raise InputError(f"{os.path.join(folder, 'assessment.yaml')}: expected an assessment report ({err})")
    path = read_csv(os.path.join(folder, "path.csv"))
    movements = read_csv(os.path.join(folder, "movements.csv"))
    written = []
    surface_csv = os.path.join(folder, "tissue_surface.csv")
    surface = read_csv(surface_csv) if os.path.exists(surface_csv) else None
    if plot_tip_path(path, os.path.join(folder, "tip_path.png"), surface):
        written.append("tip_path.png")
    if plot_speed(path, movements, os.path.join(folder, "speed.png")):
        written.append("speed.png")
    if plot_force(read_csv(os.path.join(folder, "force.csv")), threshold, os.path.join(folder, "force.png")):
        written.append("force.png")
    if plot_strain(read_csv(os.path.join(folder, "strain.csv")), os.path.join(folder, "strain.png")):
        written.append("strain.png")
    write_page(folder, doc, written)
    return written + ["assessment.html"]


def curve(folder):
    data = read_csv(os.path.join(folder, "learning_curve.csv"))
    if not data["session"]:
        return []
    sessions = [int(s) for s in data["session"]]
    fig, axes = plt.subplots(1, 3, figsize=(9.6, 3.2))
    panels = [("score", "overall score (0-100)"), ("motion_time", "motion time (s)"),
              ("ldlj_median", "median log dimensionless jerk")]
    for ax, (key, label) in zip(axes, panels):
        pairs = [(s, v) for s, v in zip(sessions, data[key]) if v is not None]
        if pairs:
            ax.plot([p[0] for p in pairs], [p[1] for p in pairs], "o-", color="tab:blue")
        ax.set_xlabel("session")
        ax.set_ylabel(label)
        ax.set_xticks(sessions)
        ax.grid(alpha=0.3)
    axes[0].set_ylim(-5, 105)
    save(fig, os.path.join(folder, "learning_curve.png"))
    return ["learning_curve.png"]


def main(argv):
    if len(argv) != 3 or argv[1] not in ("report", "curve"):
        print("usage: assessment_plots.py report|curve DIR", file=sys.stderr)
        return 2
    try:
        written = report(argv[2]) if argv[1] == "report" else curve(argv[2])
    except InputError as err:
        print(f"assessment_plots: {err}", file=sys.stderr)
        return 2
    print("assessment_plots: " + (", ".join(written) if written else "no data to plot"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
