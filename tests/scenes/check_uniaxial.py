#!/usr/bin/env python3
"""Uniaxial stretch through the CLI: the hyperelastic-statics scene on a block with symmetry rollers
and a nominal traction t on x = a, against the analytic homogeneous solution F = diag(a, b, b) of the
compressible neo-Hookean law W = mu/2 (J^(-2/3) I_1 - 3) + kappa/2 (J - 1)^2:
  P_11 = mu J^(-2/3) (a - I_1 / (3 a)) + kappa (J - 1) J / a = t,   P_22 = (same with b) = 0,
solved here by Newton. Every vertex of vertex_displacements.csv must be within the tolerance
(relative to the largest displacement) of ((a - 1) X, (b - 1) Y, (b - 1) Z).
usage: check_uniaxial.py --nlmech BIN --prm FILE --traction T --youngs E --poisson NU [--tolerance 1e-10]"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile


def stretches(t, E, nu):
    mu, kappa = E / (2 * (1 + nu)), E / (3 * (1 - 2 * nu))

    def stress(a, b):
        J, I1 = a * b * b, a * a + 2 * b * b
        p = lambda s: mu * J ** (-2 / 3) * (s - I1 / (3 * s)) + kappa * (J - 1) * J / s
        return p(a) - t, p(b)

    a, b = 1.0, 1.0
    for _ in range(100):
        f = stress(a, b)
        h = 1e-7
        fa, fb = stress(a + h, b), stress(a, b + h)
        J = [[(fa[0] - f[0]) / h, (fb[0] - f[0]) / h], [(fa[1] - f[1]) / h, (fb[1] - f[1]) / h]]
        det = J[0][0] * J[1][1] - J[0][1] * J[1][0]
        da = (-f[0] * J[1][1] + f[1] * J[0][1]) / det
        db = (-f[1] * J[0][0] + f[0] * J[1][0]) / det
        a, b = a + da, b + db
        if abs(da) + abs(db) < 1e-16:
            break
    return a, b


def main():
    parser = argparse.ArgumentParser()
    for name in ("--nlmech", "--prm"):
        parser.add_argument(name, required=True)
    for name in ("--traction", "--youngs", "--poisson"):
        parser.add_argument(name, type=float, required=True)
    parser.add_argument("--tolerance", type=float, default=1e-10)
    args = parser.parse_args()
    a, b = stretches(args.traction, args.youngs, args.poisson)
    work = tempfile.mkdtemp(prefix="nlmech_uniaxial_")
    try:
        out = os.path.join(work, "results")
        run = subprocess.run([args.nlmech, args.prm, "--output-directory", out], capture_output=True, text=True)
        print(run.stdout + run.stderr)
        if run.returncode != 0:
            print("FAIL: nlmech exited with", run.returncode)
            return 1
        worst, size = 0.0, 0.0
        rows = list(csv.DictReader(open(os.path.join(out, "vertex_displacements.csv"))))
        keys = rows[0].keys()
        print("columns:", list(keys))
        for r in rows:
            X, Y, Z = float(r["x"]), float(r["y"]), float(r["z"])
            u = (float(r["u_x"]), float(r["u_y"]), float(r["u_z"]))
            exact = ((a - 1) * X, (b - 1) * Y, (b - 1) * Z)
            worst = max(worst, max(abs(p - q) for p, q in zip(u, exact)))
            size = max(size, max(abs(q) for q in exact))
        summary = json.load(open(os.path.join(out, "summary.json")))
        newton = summary.get("anm_newton_difference_relative", {}).get("value", 1.0)
        checks = {
            f"stretches a = {a:.12f}, b = {b:.12f}: {len(rows)} vertices within {args.tolerance:g} of the "
            f"analytic displacement (largest error {worst / size:.2e} of {size:.4g} m)": worst <= args.tolerance * size,
            f"ANM and Newton agree ({newton:.1e})": newton <= 1e-9,
        }
        for name, ok in checks.items():
            print(f"{'ok  ' if ok else 'FAIL'}: {name}")
        return 0 if all(checks.values()) else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
