#!/usr/bin/env python3
"""The backbone of x'' + (k/m) x + (k3/m) x^3 = 0 (harmonic-balance scene, Backbone subsection) against
the exact frequency of the free oscillation of amplitude A (its half range):
  w(A) = pi sqrt(w0^2 + e A^2) / (2 K(m)),  m = e A^2 / (2 (w0^2 + e A^2)),  e = k3/m, w0^2 = k/m,
with K the complete elliptic integral of the first kind (by the arithmetic-geometric mean).
usage: check_duffing_backbone.py --nlmech BIN --prm FILE [--tolerance 1e-6]"""
import argparse
import csv
import math
import os
import shutil
import subprocess
import sys
import tempfile


def elliptic_k(m):
    a, b = 1.0, math.sqrt(1 - m)
    for _ in range(60):
        a, b = (a + b) / 2, math.sqrt(a * b)
    return math.pi / (2 * a)


def exact_frequency(amplitude, w0_squared=1.0, e=1.0):
    m = e * amplitude**2 / (2 * (w0_squared + e * amplitude**2))
    return math.pi * math.sqrt(w0_squared + e * amplitude**2) / (2 * elliptic_k(m))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--tolerance", type=float, default=1e-6)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_backbone_")
    try:
        out = os.path.join(work, "results")
        run = subprocess.run([args.nlmech, args.prm, "--output-directory", out], capture_output=True, text=True)
        print(run.stdout + run.stderr)
        if run.returncode != 0:
            print("FAIL: nlmech exited with", run.returncode)
            return 1
        rows = list(csv.DictReader(open(os.path.join(out, "backbone.csv"))))
        ok = len(rows) >= 5
        print(f"{'ok  ' if ok else 'FAIL'}: {len(rows)} backbone points")
        for r in rows:
            a, w = float(r["half_range"]), float(r["omega"])
            error = abs(w / exact_frequency(a) - 1)
            good = error <= args.tolerance
            ok = ok and good
            print(f"{'ok  ' if good else 'FAIL'}: A = {a:.6f}: w = {w:.12f}, exact {exact_frequency(a):.12f}, "
                  f"relative error {error:.2e} <= {args.tolerance:g}")
            # The harmonic coefficients written with it: the first cosine is the prescribed amplitude.
            good = abs(float(r["x1_cos1"]) - float(r["amplitude_cos1"])) <= 1e-12 and abs(float(r["x1_sin1"])) <= 1e-12
            ok = ok and good
        evaluation = list(csv.DictReader(open(os.path.join(out, "evaluation.csv"))))
        good = len(evaluation) == 2 and all(e["converged"] == "1" for e in evaluation)
        print(f"{'ok  ' if good else 'FAIL'}: the evaluation frequencies converged")
        ok = ok and good
        return 0 if ok else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
