#!/usr/bin/python3
"""The degraded-network table (scripts/bench_network): compares the force at the device of each
run with the reference run's (no relay), on the task's own clock (t = 0 when the operator
enables the device), and writes network.csv and network.md.
Usage: network_table.py WORK_DIR OUT_DIR BRIDGE_YAML REFERENCE RUN...  (runs: folders in WORK_DIR)"""
import csv
import io
import math
import os
import sys

import yaml
from report_files import write_text

STEP = 0.001          # s: both runs sampled on a 1 ms grid
TASK_END = 7.0        # s: the palpation's last keyframe
RECOVERED_WITHIN = 0.1  # N (+10 % of the reference force): the force tracks the reference again
RECOVERED_FOR = 0.02  # s: for this long
STAMP_ALLOWANCE = 0.0002  # s, as in the bridge's continuity test


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def bridge_params(path):
    with open(path) as f:
        params = yaml.safe_load(f)
    return {k: float(params[k]) for k in ("max_force", "max_force_rate", "model_timeout")}


class Run:
    def __init__(self, folder):
        enable = [r for r in rows(os.path.join(folder, "enable.csv")) if r["enabled"] == "1"]
        if not enable:
            raise ValueError(f"{folder}: the operator never enabled the device")
        self.t0 = float(enable[0]["recv"])
        self.servo = [(float(r["stamp"]) - self.t0, int(float(r["seq"])),
                       (float(r["fx"]), float(r["fy"]), float(r["fz"])))
                      for r in rows(os.path.join(folder, "servo.csv"))]
        contact = rows(os.path.join(folder, "contact.csv"))
        relayed = [float(r["recv"]) - self.t0 for r in contact if r["topic"] == "/tissue/contact_relayed"]
        direct = [float(r["recv"]) - self.t0 for r in contact if r["topic"] == "/tissue/contact"]
        self.relayed = bool(relayed)
        self.models = relayed or direct  # what the bridge received
        self.sent = len(direct)
        status = rows(os.path.join(folder, "status.csv"))
        self.trips = int(float(status[-1]["watchdog_trips"])) if status else 0

    def grid(self):
        """Force on the 1 ms grid over the task (the last wrench at or before each instant)."""
        out, k = [], 0
        for i in range(int(TASK_END / STEP) + 1):
            t = i * STEP
            while k + 1 < len(self.servo) and self.servo[k + 1][0] <= t:
                k += 1
            out.append(self.servo[k][2] if self.servo and self.servo[k][0] <= t else (0.0, 0.0, 0.0))
        return out

    def gaps(self, longer_than):
        """(start, end) of the silences between models received (task time) longer than given."""
        m = [t for t in self.models if -1.0 <= t <= TASK_END]
        return [(a, b) for a, b in zip(m, m[1:]) if b - a > longer_than]


def compare(run, ref_grid, p):
    grid = run.grid()
    errors = [math.dist(a, b) for a, b in zip(grid, ref_grid)]
    rms = math.sqrt(sum(e * e for e in errors) / len(errors))
    steps, over = [], 0
    for (ta, sa, fa), (tb, sb, fb) in zip(run.servo, run.servo[1:]):
        if sb != sa + 1:
            continue
        step = math.dist(fa, fb)
        steps.append(step)
        over += step > p["max_force_rate"] * (tb - ta + STAMP_ALLOWANCE) + 1e-9
    peak = max((math.hypot(*f) for _, _, f in run.servo), default=0.0)
    finite = all(all(math.isfinite(v) for v in f) for _, _, f in run.servo)
    gaps = run.gaps(p["model_timeout"])
    recover = 0.0
    for _, end in gaps:
        i = max(0, int(math.ceil(end / STEP)))
        need = int(RECOVERED_FOR / STEP)
        ok = 0
        while i < len(grid) and ok < need:
            tol = RECOVERED_WITHIN + 0.1 * math.hypot(*ref_grid[i])
            ok = ok + 1 if math.dist(grid[i], ref_grid[i]) <= tol else 0
            i += 1
        recover = max(recover, (i - need) * STEP - end if ok >= need else math.inf)
    longest_gap = max((b - a for a, b in zip(run.models, run.models[1:]) if -1.0 <= a <= TASK_END),
                      default=math.nan)
    return {
        "rms_error_N": rms, "max_error_N": max(errors), "peak_force_N": peak,
        "largest_step_N_per_tick": max(steps, default=0.0), "steps_over_rate_limit": over,
        "within_limits": int(finite and over == 0 and peak <= p["max_force"] + 1e-9),
        "watchdog_trips": run.trips, "model_gaps_over_timeout": len(gaps),
        "longest_model_gap_ms": 1e3 * longest_gap,
        "time_to_recover_ms": 1e3 * recover if gaps else math.nan,
        "models_received": len([t for t in run.models if 0.0 <= t <= TASK_END]),
    }


def cell(v):
    if isinstance(v, float):
        return "-" if math.isnan(v) else ("never" if math.isinf(v) else f"{v:.3f}" if abs(v) < 10 else f"{v:.0f}")
    return str(v)


def main():
    work, out, bridge_yaml, reference, *names = sys.argv[1:]
    p = bridge_params(bridge_yaml)
    ref = Run(os.path.join(work, reference))
    ref_grid = ref.grid()
    results = []
    for name in [reference] + names:
        try:
            r = compare(Run(os.path.join(work, name)), ref_grid, p)
        except (OSError, ValueError, IndexError, KeyError) as err:
            print(f"network_table: {name}: no result ({err})", file=sys.stderr)
            continue
        results.append((name, r))
    keys = list(results[0][1].keys())
    os.makedirs(out, exist_ok=True)
    rows = io.StringIO()
    w = csv.writer(rows)
    w.writerow(["profile"] + keys)
    for name, r in results:
        w.writerow([name] + [f"{r[k]:.6g}" if isinstance(r[k], float) else r[k] for k in keys])
    write_text(os.path.join(out, "network.csv"), rows.getvalue())
    head = ["profile", "RMS error (N)", "max error (N)", "peak |F| (N)", "largest step (N/tick)",
            "steps over rate limit", "within limits", "watchdog trips", "model gaps > timeout", "longest gap (ms)",
            "time to recover (ms)", "models received"]
    assert len(head) == len(keys) + 1, "one column heading per result key"
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for name, r in results:
        lines.append("| " + " | ".join([name] + [cell(r[k]) for k in keys]) + " |")
    table = "\n".join(lines)
    write_text(os.path.join(out, "network.md"),
               "# Degraded network: the force at the device against the undelayed run\n\n"
               "Generated by `scripts/bench_network` (see docs/deployment.md for what each column "
               "means).\n"
               f"Limits: max_force {p['max_force']:.1f} N, max_force_rate {p['max_force_rate']:.0f} N/s "
               f"({p['max_force_rate'] * 1e-3:.1f} N per 1 ms tick), model_timeout "
               f"{1e3 * p['model_timeout']:.0f} ms.\n\n" + table + "\n")
    print(table)


if __name__ == "__main__":
    main()
