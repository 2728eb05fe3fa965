#!/usr/bin/env python3
"""Markdown tables from the CSV files scripts/bench_training writes: training_graph.md from
haptic, graph and surface; with --box, update_rate.md from box.csv (the 10 x 10 x n box)."""
import csv
import os
import sys
import time

from machine import machine_text


def rows(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def table(header, body):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(r) + " |" for r in body]
    return "\n".join(out)


def share(value):
    """A fraction as a percentage, or '' when the run did not record it."""
    return f"{100 * float(value):.0f} %" if value else ""


def main(folder):
    print("# Speed of the distributed training system\n")
    print(f"Measured by `scripts/bench_training` on {machine_text()}, "
          f"{time.strftime('%Y-%m-%d')}; every node a process of its own on this machine, "
          "real master, TCPROS over loopback.\n")
    haptic = rows(os.path.join(folder, "haptic.csv"))
    if haptic:
        h = haptic[-1]
        print("## Haptic bridge alone (probe plays the device at 1 kHz and the simulation at 100 Hz)\n")
        print(table(["quantity", "p50", "p99", "max"], [
            ["bridge tick period (us), its own clock", h["bridge_period_p50_us"],
             h["bridge_period_p99_us"], h["bridge_period_max_us"]],
            ["wrench inter-arrival at the device (us)", h["wrench_gap_p50_us"],
             h["wrench_gap_p99_us"], h["wrench_gap_max_us"]],
            ["device pose -> force reflecting it (us)", h["latency_p50_us"],
             h["latency_p99_us"], h["latency_max_us"]],
        ]))
        print(f"\n{h['latency_samples']} latency samples ({h['steps_missed']} steps not seen "
              f"before the next), {h['bridge_ticks']} ticks, rate {h['bridge_rate_hz']} Hz, "
              f"{h['bridge_overruns']} overruns, SCHED_FIFO {'yes' if h['bridge_realtime'] == '1' else 'no'}, "
              f"{h['bridge_lock_misses']} input lock misses, {h['bridge_wrenches_dropped']} wrenches dropped. "
              "The bridge's p99 is the largest of the p99s of its 2 s statistics windows.\n")
    graph = rows(os.path.join(folder, "graph.csv"))
    if graph:
        print("## Training graph, liver palpation (and the beating heart), scripted operator (100 Hz target)\n")
        body = []
        for g in graph:
            body.append([g["label"].replace("_", " "), g["step_rate_hz"], g["step_wall_p50_ms"],
                         g["step_wall_p99_ms"], g["step_wall_max_ms"], g["real_time_factor_p50"],
                         f"{g['steps_behind']} / {g['steps']}", g.get("unstable_steps", ""),
                         g.get("first_status_s", ""), g["peak_contact_force_n"],
                         g.get("contact_depth_max_mm", ""), share(g.get("contact_share", "")),
                         g.get("peak_displacement_mm", ""), g.get("tool_lag_max_mm", ""),
                         g["bridge_period_p99_us"], g["bridge_period_max_us"],
                         g["wrench_gap_max_us"]])
        print(table(["mesh", "steps/s", "step p50 (ms)", "step p99 (ms)", "step max (ms)",
                     "real-time factor", "behind / steps", "failed steps", "first status (s)",
                     "peak contact (N)", "tool depth max (mm)", "steps in contact",
                     "peak tissue displacement (mm)", "tool lag max (mm)",
                     "bridge period p99 (us)", "bridge period max (us)",
                     "wrench gap max (us)"], body))
        print("\nA step is contact detection + one integrator advance + the surface message; "
              "its wall time comes from /tissue/status. Tool depth: the deepest contact point's "
              "depth in the tissue; steps in contact: the share of steps with a contact force. "
              "Peak tissue displacement: the largest "
              "node displacement the status reported (the press's depth; the liver also sags "
              "under gravity after its release at the start); tool lag: the contact's tool "
              "proxy behind the instrument tip.\n")
    surface = rows(os.path.join(folder, "surface.csv"))
    if surface:
        print("## Topic transport of a TissueSurface (on /bench/surface, 100 Hz, between two processes)\n")
        body = [[s["vertices"], s["bytes"], s["latency_p50_us"], s["latency_p99_us"],
                 s["latency_max_us"], s["bytes_with_triangles"], s["latency_with_triangles_p50_us"]]
                for s in surface]
        print(table(["vertices", "bytes", "latency p50 (us)", "p99 (us)", "max (us)",
                     "bytes with triangles", "latency with triangles p50 (us)"], body))
        print("\nLatency: from the stamp set just before publish() to the subscriber's callback "
              "(serialisation, loopback TCP, deserialisation).")


def box_main(folder):
    """The update rate against tets (box.csv) beside Jeffrey's Figs 2-3."""
    box = rows(os.path.join(folder, "box.csv"))
    print("# Update rate against the number of tets in the running graph\n")
    print(f"Measured by `scripts/bench_training` (part `box`) on {machine_text()}, "
          f"{time.strftime('%Y-%m-%d')}; every node a process of its own on this machine "
          "(the renderer included), real master, TCPROS over loopback.\n")
    body = []
    for b in box:
        wall, simulated = float(b["step_wall_p50_ms"]), float(b["step_time_p50_ms"])
        per_frame = 10.0 * wall / simulated if simulated > 0 else float("nan")
        body.append([b["label"].replace("_tets", ""), b["step_rate_hz"], b["step_wall_p50_ms"],
                     b["step_time_p50_ms"], f"{per_frame:.2f}", f"{1000.0 / per_frame:.0f}",
                     b["real_time_factor_p50"], f"{b['steps_behind']} / {b['steps']}",
                     b.get("unstable_steps", ""), b.get("peak_displacement_mm", ""),
                     b["bridge_period_p99_us"]])
    print(table(["tets", "steps/s", "step wall p50 (ms)", "simulated per step p50 (ms)",
                 "wall per 10 ms simulated (ms)", "update rate it allows (Hz)",
                 "real-time factor", "behind / steps", "failed steps",
                 "peak displacement (mm)", "bridge period p99 (us)"], body))
    print("\nA step is one frame of the simulation node: contact detection, the integrator's "
          "advance (Newtonian substeps of 0.1 ms) and the surface message; a step that overran "
          "makes the next cover the wall time that passed, up to the scene's longest frame "
          "(100 ms), so behind the clock the simulated time per step grows and the steps per "
          "second fall faster than the work per simulated second rises. The update rate it "
          "allows is 10 ms divided by the wall time per 10 ms simulated.")


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--box"]
    folder = args[0] if args else "."
    box_main(folder) if "--box" in sys.argv[1:] else main(folder)
