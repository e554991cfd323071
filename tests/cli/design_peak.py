#!/usr/bin/env python3
"""A resonance peak placed at a target frequency, through `nlmech` and a parameter file.

Runs tests/prm/design-duffing-peak.prm (the peak frequency objective). Checks: the optimiser's
peak lies at the target (1e-6 rad/s); the designed structure's frequency-response curve, traced
afterwards by the scene from the low end of its range (a second method), has its first refined
resonance peak at the same frequency (1e-6 rad/s), and so has the initial design's curve (with the
initial added mass on it) at the optimiser's initial peak; the run exits 0, nothing NaN.
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile


def value(d, key):
    v = d[key]
    return v["value"] if isinstance(v, dict) else v


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nlmech", required=True)
    ap.add_argument("--prm", required=True)
    ap.add_argument("--target", type=float, default=0.8)
    a = ap.parse_args()
    failures = []
    with tempfile.TemporaryDirectory() as out:
        p = subprocess.run([a.nlmech, a.prm, "--output-directory", out], capture_output=True, text=True)
        print(p.stdout[-2500:], p.stderr[-1500:])
        if p.returncode != 0:
            failures.append(f"exit code {p.returncode}")
        s = json.load(open(os.path.join(out, "summary.json")))
        w0 = value(s, "design_peak_frequency_initial")[0]
        w1 = value(s, "design_peak_frequency_final")[0]
        print(f"peak frequency {w0:.10f} -> {w1:.10f} rad/s (target {a.target}), "
              f"{s['design_evaluations']} evaluations, {s['design_peak_searches']} peak searches")
        if not abs(w1 - a.target) < 1e-6:
            failures.append(f"the design's peak lies at {w1}, not {a.target}")
        # The initial design's curve is traced with the parameters' initial values applied (an
        # added mass of 0.1, not none): its first peak is the optimiser's initial peak.
        if "initial_first_peak_frequency" not in s:
            failures.append("the initial design's curve found no resonance peak")
        else:
            w_initial_curve = value(s, "initial_first_peak_frequency")
            print(f"the initial design's curve: first peak at {w_initial_curve:.10f} rad/s")
            if not abs(w_initial_curve - w0) < 1e-6:
                failures.append(f"the initial curve's peak {w_initial_curve} differs from the design's initial {w0}")
        rows = list(csv.DictReader(open(os.path.join(out, "resonance_peaks.csv"))))
        if not rows:
            failures.append("the designed structure's curve found no resonance peak")
        else:
            w_curve = float(rows[0]["omega"])
            print(f"the designed structure's curve: first peak at {w_curve:.10f} rad/s")
            if not abs(w_curve - w1) < 1e-6:
                failures.append(f"the curve's peak {w_curve} differs from the design's {w1}")
        for name in ("summary.json", "design_history.csv", "frequency_response.csv"):
            if re.search(r"\bnan\b", open(os.path.join(out, name)).read(), re.I):
                failures.append(f"NaN in {name}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
