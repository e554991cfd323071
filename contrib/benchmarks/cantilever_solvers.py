#!/usr/bin/env python3
"""Benchmark: linear-elastic cantilever (quadratic tetrahedra) at about 10k, 100k and 300k DOFs.

For each size the same gmsh mesh is solved by the sparse direct solver (MUMPS through Trilinos
Amesos) and by CG preconditioned with ML algebraic multigrid, each in its own nlmech process, and
the figures are printed side by side: assembly time, solve time (set-up included), CG iterations,
peak resident memory, and the tip-deflection error against Timoshenko beam theory. Times are the
medians of --repeats runs.

usage: cantilever_solvers.py [--nlmech build/nlmech] [--repeats 3] [--sizes 10000,100000,300000] [--np 1]
"""
import argparse
import csv
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))

# DOFs of the P2 cantilever against element size, fitted to two measured meshes (19926 DOFs at
# h = 0.025 m, 76269 at h = 0.01462 m): DOFs ~ h^-2.5 in this range (few elements across the section).
def element_size(dofs):
    return 0.01462 * (76269.0 / dofs) ** (1.0 / 2.5)


PRM = """set Scene type = cantilever
subsection Mesh
  set Mesh file = {mesh}
end
subsection Mesh study
  set Element sizes = {h}
  set Write fields = false
end
subsection Discretization
  set Polynomial degree = 2
end
subsection Linear solver
  set Method = {method}
  set Direct solver = mumps
  set Relative tolerance = 1e-10
end
"""


def timer_section(text, name):
    for line in text.splitlines():
        cells = [c.strip() for c in line.split("|")]
        if len(cells) > 3 and cells[1].startswith(name):
            return float(cells[3].rstrip("s"))
    return float("nan")


def run_once(nlmech, np_, h, method, work):
    prm = os.path.join(work, f"bench_{method}.prm")
    with open(prm, "w") as f:
        f.write(PRM.format(mesh=os.path.join(SOURCE, "meshes", "cantilever.geo"), h=h, method=method))
    out = os.path.join(work, f"out_{method}")
    prefix = [] if np_ == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(np_)]
    run = subprocess.run(prefix + [nlmech, prm, "--output-directory", out], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"nlmech failed:\n{run.stdout}\n{run.stderr}")
    with open(os.path.join(out, "mesh_study.csv")) as f:
        row = next(csv.DictReader(f))
    with open(os.path.join(out, "timing.txt")) as f:
        timing = f.read()
    return {
        "dofs": int(row["n_dofs"]),
        "assembly": timer_section(timing, "assembly"),
        "solve": float(row["solve_time_s"]),
        "iterations": int(float(row["solver_iterations"])),
        "memory": float(row["peak_memory_MiB"]),
        "error": float(row["tip_deflection_relative_error_vs_timoshenko"]),
        "tip": float(row["tip_deflection_m"]),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nlmech", default=os.path.join(SOURCE, "build", "nlmech"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--sizes", default="10000,100000,300000")
    parser.add_argument("--np", type=int, default=1)
    args = parser.parse_args()
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT", "1")
    os.environ.setdefault("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")

    print(f"# cantilever solver benchmark, {time.strftime('%Y-%m-%d')}, {platform.node()}, "
          f"{os.cpu_count()} cores, {args.np} MPI rank(s), median of {args.repeats}")
    header = ("| DOFs | assembly [s] | direct solve [s] | CG+AMG solve [s] | CG its | direct/AMG time "
              "| peak MiB direct | peak MiB AMG | tip error direct | tip error AMG | tip direct vs AMG (rel.) |")
    print(header)
    print("|" + "---|" * (header.count("|") - 1))
    work = tempfile.mkdtemp(prefix="nlmech_bench_")
    try:
        for target in [int(s) for s in args.sizes.split(",")]:
            h = element_size(target)
            runs = {m: [run_once(args.nlmech, args.np, h, m, work) for _ in range(args.repeats)]
                    for m in ("direct", "cg-amg")}
            med = {m: {k: statistics.median(r[k] for r in runs[m]) for k in runs[m][0]} for m in runs}
            d, a = med["direct"], med["cg-amg"]
            agreement = abs(d["tip"] - a["tip"]) / abs(d["tip"])
            print(f"| {int(d['dofs'])} | {statistics.median([d['assembly'], a['assembly']]):.3f} | {d['solve']:.3f} "
                  f"| {a['solve']:.3f} | {int(a['iterations'])} | {d['solve'] / a['solve']:.2f} "
                  f"| {d['memory']:.0f} | {a['memory']:.0f} | {d['error']:.2e} | {a['error']:.2e} | {agreement:.1e} |",
                  flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
