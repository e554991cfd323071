#!/usr/bin/env python3
"""Benchmark: the Asymptotic Numerical Method against its baselines, on the same meshes and tolerances.

Forward (scene hyperelastic-statics): a soft neo-Hookean bar (0.3 m x 0.03 m x 0.03 m, E = 0.1 MPa)
sagging under its own weight, by ANM, Newton with line search (10 load steps; our CHOLMOD Newton and
Trilinos NOX with Amesos KLU, energy merit function) and kinetic damping.
Inverse (scene inverse-design): the rest shape of the same bar at E = 1 MPa that hangs straight,
by ANM, Newton with line search on the residual (20 load steps) and Levenberg-Marquardt.
Prints wall times (median of --repeats), factorisation counts, iterations and the speed-ups, and the
share of ANM time spent in factorisation and back-substitution.

usage: anm_statics.py [--nlmech build/nlmech] [--repeats 3] [--sizes 0.015,0.01,0.007]
                      [--inverse-sizes 0.015,0.01] [--inverse-repeats 1]
"""
import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))

COMMON = """subsection Mesh
  set Mesh file          = {mesh}
  set Geometry constants = L = 0.3, W = 0.03, H = 0.03
  set Element size       = {h}
end
"""
FORWARD = """set Scene type = hyperelastic-statics
""" + COMMON + """subsection Material
  set Young's modulus = 1e5
  set Poisson's ratio = 0.45
  set Density         = 1100
end
subsection Solver
  set Methods            = anm, newton, newton-nox, kinetic-damping
  set Residual tolerance = 1e-9
  set Newton load steps  = 10
end
"""
INVERSE = """set Scene type = inverse-design
""" + COMMON + """subsection Material
  set Young's modulus = 1e6
  set Poisson's ratio = 0.45
  set Density         = 1100
end
subsection Solver
  set Methods            = anm, newton, levenberg-marquardt
  set Residual tolerance = 1e-9
  set Newton load steps  = 20
end
"""


def run(nlmech, text, work):
    prm = os.path.join(work, "bench.prm")
    with open(prm, "w") as f:
        f.write(text)
    out = os.path.join(work, "out")
    result = subprocess.run([nlmech, prm, "--output-directory", out], capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"nlmech failed:\n{result.stdout}\n{result.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def value(entry):
    return entry["value"] if isinstance(entry, dict) else entry


def median_of(runs, method, key):
    """Median over the runs, or NaN when the method failed (its summary has no such figure)."""
    values = [value(r[method][key]) for r in runs if key in r.get(method, {})]
    return statistics.median(values) if values else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nlmech", default=os.path.join(SOURCE, "build", "nlmech"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--sizes", default="0.015,0.01,0.007", help="forward element sizes [m]")
    parser.add_argument("--inverse-sizes", default="0.015,0.01", help="inverse element sizes [m]")
    parser.add_argument("--skip-forward", action="store_true")
    parser.add_argument("--skip-inverse", action="store_true")
    parser.add_argument("--inverse-repeats", type=int, default=1,
                        help="Levenberg-Marquardt takes minutes: fewer repeats for the inverse table")
    args = parser.parse_args()
    mesh = os.path.join(SOURCE, "meshes", "cantilever.geo")
    print(f"# ANM statics benchmark, {time.strftime('%Y-%m-%d')}, {platform.node()}, {os.cpu_count()} cores, "
          f"median of {args.repeats} (forward) and {args.inverse_repeats} (inverse)")
    work = tempfile.mkdtemp(prefix="nlmech_anm_bench_")
    try:
        print("\n## Forward: ANM vs Newton (10 load steps; own and NOX) vs kinetic damping\n")
        print("| vertices | ANM [s] | ANM steps | ANM fact. | Newton [s] | Newton its | NOX [s] | NOX its "
              "| KD [s] | KD steps | KD fact. | Newton/ANM | NOX/ANM | KD/ANM | ANM share fact.+solve |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for h in ([] if args.skip_forward else args.sizes.split(",")):
            runs = [run(args.nlmech, FORWARD.format(mesh=mesh, h=h), work) for _ in range(args.repeats)]
            a, n, x, k = (median_of(runs, m, "wall_time") for m in ("anm", "newton", "newton_nox", "kinetic_damping"))
            share = statistics.median(
                (value(r["anm"]["factorization_time"]) + value(r["anm"]["back_substitution_time"]))
                / value(r["anm"]["wall_time"]) for r in runs)
            r0 = runs[0]
            print(f"| {r0['n_vertices']} | {a:.2f} | {r0['anm']['steps']} | {r0['anm']['factorizations']} | {n:.2f} "
                  f"| {r0['newton']['iterations']} | {x:.2f} | {r0['newton_nox']['iterations']} "
                  f"| {k:.2f} | {r0['kinetic_damping']['time_steps']} "
                  f"| {r0['kinetic_damping']['factorizations']} | {n / a:.1f}x | {x / a:.1f}x | {k / a:.1f}x "
                  f"| {100 * share:.0f} % |",
                  flush=True)
        print("\n## Inverse: ANM vs Newton (20 load steps) vs Levenberg-Marquardt\n")
        print("| vertices | ANM [s] | ANM steps | ANM fact. | Newton [s] | Newton its | LM [s] | LM its | LM converged "
              "| Newton/ANM | LM/ANM | round trip / diagonal |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for h in ([] if args.skip_inverse else args.inverse_sizes.split(",")):
            runs = [run(args.nlmech, INVERSE.format(mesh=mesh, h=h), work) for _ in range(args.inverse_repeats)]
            a, n, l = (median_of(runs, m, "wall_time") for m in ("anm", "newton", "levenberg_marquardt"))
            r0 = runs[0]
            print(f"| {r0['n_vertices']} | {a:.2f} | {r0['anm']['steps']} | {r0['anm']['factorizations']} | {n:.2f} "
                  f"| {r0['newton'].get('iterations', 'failed: ' + r0['newton'].get('failure', '?').strip()[:60])} | {l:.2f} | {r0['levenberg_marquardt']['iterations']} "
                  f"| {r0['levenberg_marquardt']['converged']} | {n / a:.0f}x | {l / a:.0f}x "
                  f"| {value(r0['round_trip_error_relative_to_diagonal']):.1e} |", flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
