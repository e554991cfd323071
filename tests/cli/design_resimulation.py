#!/usr/bin/env python3
"""An optimised harmonic-balance design re-simulated from scratch reproduces the optimiser's result.

Runs a design scene (optimize), then its optimized.prm (Mode = apply: the optimised values set, the
periodic state found again from rest) with the Newmark check at the design frequency. Checks:
the optimiser lowered the objective; the re-run's objective equals the optimiser's best (1e-6
relative: the same state, not another branch); Newmark integration from rest to the periodic
steady state agrees with the HBM state to the scene's check tolerance; nothing NaN.
"""
import argparse
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


def run(nlmech, prm, out):
    p = subprocess.run([nlmech, prm, "--output-directory", out], capture_output=True, text=True)
    print(p.stdout[-1500:])
    summary = json.load(open(os.path.join(out, "summary.json")))
    return p.returncode, summary


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nlmech", required=True)
    ap.add_argument("--prm", required=True)
    ap.add_argument("--frequency", type=float, default=0,
                    help="the Newmark check's frequency (0: no Newmark check)")
    ap.add_argument("--decrease", type=float, default=0.05,
                    help="the least relative decrease of the objective the optimiser must reach")
    a = ap.parse_args()
    failures = []
    with tempfile.TemporaryDirectory() as work:
        first = os.path.join(work, "design")
        rc, s = run(a.nlmech, a.prm, first)
        f0, f1 = value(s, "design_initial_objective"), value(s, "design_objective")
        print(f"optimiser: objective {f0:.10g} -> {f1:.10g} in {s['design_evaluations']} evaluations "
              f"({s['design_stop_reason']}), exit {rc}")
        if not f1 < (1 - a.decrease) * f0:
            failures.append(f"the optimiser did not lower the objective by {100 * a.decrease:g} %")
        text = open(os.path.join(first, "optimized.prm")).read()
        # The Newmark check on at the design frequency (its own subsection only).
        text, n = re.subn(r"(subsection Newmark check\n(?:(?!\nend).)*?set Frequencies\s*=)[^\n]*",
                          r"\g<1> %g" % a.frequency if a.frequency > 0 else r"\g<1>", text, flags=re.S)
        if n != 1 and a.frequency > 0:
            failures.append("optimized.prm has no Newmark check subsection")
        again = os.path.join(work, "again")
        text = re.sub(r"(set Output directory\s*=)[^\n]*", r"\g<1> " + again, text)
        prm = os.path.join(work, "optimized.prm")
        open(prm, "w").write(text)
        rc2, s2 = run(a.nlmech, prm, again)
        f2 = value(s2, "design_initial_objective")
        newmark = value(s2, "newmark_max_difference_relative") if a.frequency > 0 else 0.0
        print(f"re-run of optimized.prm: objective {f2:.10g} (optimiser {f1:.10g}, relative difference "
              f"{abs(f2 - f1) / abs(f1):.2e}); Newmark vs HBM {newmark:.2e}; exit {rc2}, {s2.get('status')}")
        if rc2 != 0 or s2.get("status") != "complete":
            failures.append("the re-run of optimized.prm failed or is marked partial")
        if not abs(f2 - f1) <= 1e-6 * abs(f1):
            failures.append("the re-run's objective differs from the optimiser's")
        if not (math.isfinite(newmark) and newmark <= 1e-3):
            failures.append("Newmark disagrees with the optimised HBM state")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
