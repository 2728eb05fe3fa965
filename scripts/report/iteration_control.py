#!/usr/bin/python3
"""Draws the iteration-count step control of backward Euler from bench_iteration_control's CSV.

  iteration_control.py DIR

Reads DIR/iteration_control.csv (the twitch: jacobian,t,active_force,iterations,step,rejected)
and DIR/iteration_instability.csv (the ladders: ladder,value,t,...); writes
DIR/iteration_control.png (the counterpart of Fig. 2.21 of "Adamss: Advanced Anisotropic
Mass-Spring System": the normalised active force and the GMRES iterations per step over time,
and below them the step the controller chose, redone steps marked) and
DIR/iteration_instability.png (the iterations per attempt of the rungs that end in a failure,
beside the rung below them that does not).
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from report_files import save_figure  # noqa: E402


def read(path, key_columns):
    series = defaultdict(list)
    with open(path) as f:
        for row in csv.DictReader(f):
            key = tuple(row[c] for c in key_columns)
            series[key].append((float(row["t"]), float(row["active_force"]),
                                int(row["iterations"]), float(row["step"]), row["rejected"] == "1"))
    return series


def twitch_plot(directory):
    series = read(os.path.join(directory, "iteration_control.csv"), ["jacobian"])
    fig, axes = plt.subplots(2, len(series), figsize=(5.5 * len(series), 6.5), sharex=True,
                             squeeze=False)
    for col, (key, rows) in enumerate(sorted(series.items())):
        kept = [r for r in rows if not r[4]]
        redone = [r for r in rows if r[4]]
        top, bottom = axes[0][col], axes[1][col]
        top.plot([r[0] for r in kept], [r[1] for r in kept], color="tab:blue", lw=1.2,
                 label="active force / its peak")
        top.set_ylabel("normalised active force", color="tab:blue")
        top.set_ylim(0, 1.05)
        right = top.twinx()
        right.plot([r[0] for r in kept], [r[2] for r in kept], color="tab:red", lw=0.6,
                   label="GMRES iterations")
        right.set_ylabel("GMRES iterations per step", color="tab:red")
        right.set_ylim(0, None)
        top.set_title(key[0].replace("_", " "))
        bottom.semilogy([r[0] for r in kept], [r[3] for r in kept], color="black", lw=0.8,
                        label="step kept")
        if redone:
            bottom.semilogy([r[0] for r in redone], [r[3] for r in redone], "x", color="tab:red",
                            label="step redone (halved)")
        bottom.set_xlabel("t (s)")
        bottom.set_ylabel("step h (s)")
        bottom.legend(loc="lower right", fontsize=8)
    fig.suptitle("muscle_twitch, backward Euler with the iteration-count control (GMRES)")
    fig.tight_layout()
    out = os.path.join(directory, "iteration_control.png")
    save_figure(fig, out, dpi=110)
    print("wrote", out)


def instability_plot(directory):
    series = read(os.path.join(directory, "iteration_instability.csv"), ["ladder", "value"])
    ladders = defaultdict(list)
    for (ladder, value), rows in series.items():
        ladders[ladder].append((float(value), rows))
    fig, axes = plt.subplots(len(ladders), 1, figsize=(9, 2.6 * len(ladders)), squeeze=False)
    for ax, ladder in zip(axes[:, 0], sorted(ladders)):
        for value, rows in sorted(ladders[ladder]):
            ax.semilogy([r[0] for r in rows], [max(r[2], 1) for r in rows], lw=0.8,
                        label=f"{value:g}")
            ax.plot(rows[-1][0], max(rows[-1][2], 1), "o", color=ax.lines[-1].get_color(), ms=3)
        ax.set_title(ladder.replace("_", " ") + " (dot: the last attempt of the run)", fontsize=9)
        ax.set_ylabel("iterations")
        ax.legend(fontsize=7, ncol=4, loc="upper right")
    axes[-1][0].set_xlabel("t (s)")
    fig.tight_layout()
    out = os.path.join(directory, "iteration_instability.png")
    save_figure(fig, out, dpi=110)
    print("wrote", out)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    twitch_plot(sys.argv[1])
    instability_plot(sys.argv[1])


if __name__ == "__main__":
    main()
