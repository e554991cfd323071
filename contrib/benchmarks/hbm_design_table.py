#!/usr/bin/env python3
"""Benchmark: thesis Table 2.1 (harmonic-balance inverse design) through `nlmech` and the six
design scenes in prm/ as a user runs them, with the thesis's figures side by side.

For each scene: N_DoF (free unknowns of the model), N_H, N_AFT, N_p, L-BFGS evaluations, the
optimisation's wall time (summary.json: design_seconds) and the whole run's, the thesis's row and
the speed ratio (thesis time / ours), the time of one gradient against one Newton iteration of the
periodic solve (the adjoint: independent of N_p), the objective before and after, the amplitude
gain and the Hill stability of the optimum. The thesis ran on an i9-7900X; where our scene's
N_DoF, N_H or N_p differ from the thesis's, the row says so and the ratio compares unlike runs.

usage: hbm_design_table.py [--nlmech build/nlmech] [--only wing,tower] [--max-evaluations N]
                           [--threads N]
"""
import argparse
import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))

# name: (prm, thesis row name, N_DoF, N_H, N_AFT, N_p, iterations, seconds)
SCENES = {
    "wing": ("design-wing.prm", "Dragon", 780, 8, 64, 3, 12, 1098.0),
    "three-link": ("design-three-link.prm", "Three-link", 8, 8, 64, 16, 146, 34.89),
    "ostrich-leg": ("design-ostrich-leg.prm", "Ostrich Leg", 14, 14, 64, 7, 128, 163.98),
    "wire-fish": ("design-wire-fish.prm", "Fish", 187, 8, 64, 3, 46, 456.96),
    "layered-solid": ("design-layered-solid.prm", "3D solid", 918, 8, 64, 7, 10, 7926.43),
    "tower": ("design-tower.prm", "Tower", 658, 8, 64, 525, 150, 5534.82),
}


def value(d, key, default=float("nan")):
    v = d.get(key, default)
    return v["value"] if isinstance(v, dict) else v


def run(nlmech, name, max_evaluations, threads):
    prm, *_ = SCENES[name]
    path = os.path.join(SOURCE, "prm", prm)
    text = open(path).read()
    if max_evaluations:
        text = re.sub(r"(set Maximum evaluations\s*=\s*)\d+", r"\g<1>%d" % max_evaluations, text)
    # The copy sits in a mirror of the source tree (meshes and targets linked) so that its relative
    # paths still resolve, and nothing is written into prm/.
    out = tempfile.mkdtemp(prefix="nlmech-design-")
    mirror = os.path.join(out, "tree")
    os.makedirs(os.path.join(mirror, "prm"))
    os.symlink(os.path.join(SOURCE, "meshes"), os.path.join(mirror, "meshes"))
    os.symlink(os.path.join(SOURCE, "prm", "targets"), os.path.join(mirror, "prm", "targets"))
    copy = os.path.join(mirror, "prm", prm)
    open(copy, "w").write(text)
    out = os.path.join(out, "results")
    cmd = [nlmech, copy, "--output-directory", out] + (["--threads", str(threads)] if threads else [])
    t0 = time.perf_counter()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t0
    try:
        summary = json.load(open(os.path.join(out, "summary.json")))
    except (OSError, ValueError):
        sys.stderr.write(p.stdout[-2000:] + p.stderr[-2000:])
        summary = {}
    return summary, wall, p.returncode, out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--nlmech", default=os.path.join(SOURCE, "build", "nlmech"))
    ap.add_argument("--only", default=",".join(SCENES))
    ap.add_argument("--max-evaluations", type=int, default=0, help="override each scene's cap (0: keep)")
    ap.add_argument("--threads", type=int, default=0)
    a = ap.parse_args()
    print("# Table 2.1 through nlmech, %s, %s, %d cores" % (time.strftime("%Y-%m-%d"), platform.processor()
          or platform.machine(), os.cpu_count()))
    head = ("scene", "N_DoF", "N_H", "N_AFT", "N_p", "evals", "design s", "run s", "thesis (DoF/H/p/it/s)",
            "thesis/ours", "grad/Newton it", "objective", "A gain", "optimum", "exit")
    print(" | ".join(head))
    print("|".join("---" for _ in head))
    for name in a.only.split(","):
        s, wall, rc, out = run(a.nlmech, name, a.max_evaluations, a.threads)
        _, thesis, t_dof, t_h, t_aft, t_p, t_it, t_s = SCENES[name]
        ours = value(s, "design_seconds")
        gain = s.get("design_amplitude_gain", [float("nan")])
        row = (name, s.get("free_unknowns", "?"), s.get("harmonics", "?"), s.get("time_samples", "?"),
               s.get("design_parameters", "?"), s.get("design_evaluations", "?"), "%.1f" % ours,
               "%.1f" % wall, "%s %d/%d/%d/%d/%.0f" % (thesis, t_dof, t_h, t_p, t_it, t_s),
               "%.0fx" % (t_s / ours) if ours == ours and ours > 0 else "-",
               "%.2f" % value(s, "design_gradient_over_newton_iteration"),
               "%.4g -> %.4g" % (value(s, "design_initial_objective"), value(s, "design_objective")),
               "%.2fx" % gain[0] if gain else "-",
               ("unstable" if s.get("design_state_unstable") else "stable") +
               " (mu %.3f)" % value(s, "design_max_multiplier_0"),
               "%d (%s)" % (rc, s.get("status", "?")))
        print(" | ".join(str(c) for c in row), flush=True)
        if s.get("design_failed_updates"):
            print("  %s: %d failed updates, last: %s" % (name, s["design_failed_updates"],
                                                       s.get("design_last_failed_update", "")))
        print("  %s: stop: %s; results in %s" % (name, s.get("design_stop_reason", "?"), out))


if __name__ == "__main__":
    main()
