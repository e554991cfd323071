#!/usr/bin/env python3
"""Benchmark: the ANM at the sizes of the ANM paper's own models (seed 003, Tables 1-3), through the
binary as a user runs it (every core, the shipped .prm files), beside the paper's figures.

1. Inverse design, shipped scenes: prm/inverse-bar-4k.prm (paper bar: 4552 vertices, 2.38 s),
   prm/inverse-plant-15k.prm (plant: 14842 vertices, 7.07 s), prm/inverse-hanger.prm (hanger,
   two targets: 24323 vertices, 26.83 s for all solves). Inverse ANM wall time (for the hanger also
   every solve of the second target and the reduced basis), the round-trip check, peak memory.
2. Forward statics of the bar (E = 0.1 MPa, sagging under its weight) at growing sizes: ANM against
   Newton with line search (10 load steps) and kinetic damping on the same mesh and tolerance.
3. Growth: the exponent p of time ~ n^p of the forward and the inverse ANM over the bar sizes.
4. Inverse baselines on the 4.5k bar (paper Table 2): Newton with adaptive load steps, and
   Levenberg-Marquardt from the paper's two initial guesses with an iteration and time cap.
The paper ran an i7-3770K with 6 threads; this table runs whatever machine it is on.

usage: anm_seed_sizes.py [--nlmech build/nlmech] [--repeats 1] [--sizes 0.008,0.004,0.003,0.0022]
                         [--skip-inverse-scenes] [--skip-forward] [--skip-baselines] [--lm-cap 600]
"""
import argparse
import json
import math
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

SCENES = [  # shipped file, paper model, paper vertices, paper inverse ANM time [s]
    ("inverse-bar-4k.prm", "bar", 4552, 2.38),
    ("inverse-plant-15k.prm", "plant", 14842, 7.07),
    ("inverse-hanger.prm", "hanger (2 targets)", 24323, 26.83),
]

BAR = """set Scene type = {scene}
subsection Mesh
  set Mesh file          = {mesh}
  set Geometry constants = L = 0.3, W = 0.03, H = 0.03
  set Element size       = {h}
end
subsection Material
  set Young's modulus = {E}
  set Poisson's ratio = 0.45
  set Density         = 1100
end
subsection Solver
  set Methods            = {methods}
  set Residual tolerance = 1e-9
{extra}end
"""


def run(nlmech, prm, work, cwd=None):
    """Runs nlmech on prm; returns (summary, timing sections {name: seconds}, wall [s], peak RSS [MiB])."""
    out = os.path.join(work, "out")
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ)
    env.pop("DEAL_II_NUM_THREADS", None)
    start = time.perf_counter()
    with open(os.path.join(work, "log"), "w") as log:
        process = subprocess.Popen([nlmech, prm, "--output-directory", out], stdout=log,
                                   stderr=subprocess.STDOUT, cwd=cwd, env=env)
        _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - start
    if os.waitstatus_to_exitcode(status) != 0:
        with open(os.path.join(work, "log")) as log:
            sys.exit(f"nlmech {prm} failed:\n{log.read()}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    sections = {}
    with open(os.path.join(out, "timing.txt")) as f:
        for line in f:
            m = re.match(r"\|\s*(.+?)\s*\|\s*\d+\s*\|\s*([\d.e+-]+)(m?s)\s*\|", line)
            if m:
                sections[m.group(1)] = float(m.group(2)) / (1000.0 if m.group(3) == "ms" else 1.0)
    return summary, sections, wall, usage.ru_maxrss / 1024.0


def value(entry):
    return entry["value"] if isinstance(entry, dict) else entry


def median(values):
    values = [v for v in values if v == v]
    return statistics.median(values) if values else float("nan")


def slope(points):
    """Least-squares slope of log t against log n."""
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nlmech", default=os.path.join(SOURCE, "build", "nlmech"))
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--sizes", default="0.008,0.004,0.003,0.0022", help="bar element sizes [m]")
    parser.add_argument("--skip-inverse-scenes", action="store_true")
    parser.add_argument("--skip-forward", action="store_true")
    parser.add_argument("--skip-baselines", action="store_true")
    parser.add_argument("--lm-cap", type=float, default=600, help="Levenberg-Marquardt time cap per guess [s]")
    args = parser.parse_args()
    nlmech = os.path.abspath(args.nlmech)
    print(f"# ANM at the paper's sizes, {time.strftime('%Y-%m-%d')}, {platform.node()}, {os.cpu_count()} cores, "
          f"median of {args.repeats}; paper: i7-3770K, 6 threads")
    work = tempfile.mkdtemp(prefix="nlmech_anm_sizes_")
    prm_dir = os.path.join(SOURCE, "prm")
    try:
        if not args.skip_inverse_scenes:
            print("\n## Inverse design, shipped scenes\n")
            print("| scene | vertices | tets | inverse ANM [s] | all solves [s] | paper [s] | ours / paper "
                  "| series [s] | fact. [s] | forward check [s] | run [s] | peak RSS [MiB] | round trip / diag. |")
            print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
            for name, model, paper_n, paper_t in SCENES:
                runs = [run(nlmech, os.path.join(prm_dir, name), work, cwd=prm_dir) for _ in range(args.repeats)]
                anm = median(value(s["anm"]["wall_time"]) for s, _, _, _ in runs)
                solves = median(value(s["anm"]["wall_time"]) + t.get("multi-target: inverse solves", 0.0)
                                for s, t, _, _ in runs)
                s0, t0, _, _ = runs[0]
                print(f"| {name} ({model}, paper {paper_n}) | {s0['n_vertices']} | {s0['n_tetrahedra']} | {anm:.2f} "
                      f"| {solves:.2f} | {paper_t:.2f} | {solves / paper_t:.2f} "
                      f"| {median(value(s['anm']['series_time']) for s, _, _, _ in runs):.2f} "
                      f"| {median(value(s['anm']['factorization_time']) for s, _, _, _ in runs):.2f} "
                      f"| {median(t.get('forward check', float('nan')) + t.get('multi-target: forward checks', 0.0) for _, t, _, _ in runs):.2f} "
                      f"| {median(w for _, _, w, _ in runs):.1f} | {max(m for _, _, _, m in runs):.0f} "
                      f"| {value(s0['round_trip_error_relative_to_diagonal']):.1e} |", flush=True)
            print("\n(all solves: for the hanger the inverse ANM of both targets, their series at the solution and the "
                  "reduced basis, as the paper's Table 2 counts them; the forward check column has the forward "
                  "solve of every case)")
        if not args.skip_forward:
            mesh = os.path.join(SOURCE, "meshes", "cantilever.geo")
            print("\n## Bar at growing sizes: forward ANM vs Newton and kinetic damping; inverse ANM\n")
            print("| vertices | tets | forward ANM [s] | Newton [s] | KD [s] | Newton/ANM | KD/ANM | inverse ANM [s] "
                  "| peak RSS fwd [MiB] | peak RSS inv [MiB] |")
            print("|---|---|---|---|---|---|---|---|---|---|")
            forward, inverse = [], []
            for h in args.sizes.split(","):
                prm = os.path.join(work, "bar.prm")
                with open(prm, "w") as f:
                    f.write(BAR.format(scene="hyperelastic-statics", mesh=mesh, h=h, E=1e5,
                                       methods="anm, newton, kinetic-damping", extra=""))
                fw = [run(nlmech, prm, work) for _ in range(args.repeats)]
                with open(prm, "w") as f:
                    f.write(BAR.format(scene="inverse-design", mesh=mesh, h=h, E=1e6, methods="anm", extra=""))
                iv = [run(nlmech, prm, work) for _ in range(args.repeats)]
                a = median(value(s["anm"]["wall_time"]) for s, _, _, _ in fw)
                n = median(value(s["newton"]["wall_time"]) for s, _, _, _ in fw)
                k = median(value(s["kinetic_damping"]["wall_time"]) for s, _, _, _ in fw)
                i = median(value(s["anm"]["wall_time"]) for s, _, _, _ in iv)
                s0 = fw[0][0]
                forward.append((s0["n_vertices"], a))
                inverse.append((s0["n_vertices"], i))
                print(f"| {s0['n_vertices']} | {s0['n_tetrahedra']} | {a:.2f} | {n:.2f} | {k:.2f} | {n / a:.1f}x "
                      f"| {k / a:.1f}x | {i:.2f} | {max(m for *_, m in fw):.0f} | {max(m for *_, m in iv):.0f} |",
                      flush=True)
            if len(forward) > 1:
                print(f"\nGrowth, time ~ n^p over {forward[0][0]}..{forward[-1][0]} vertices (least squares): "
                      f"forward ANM p = {slope(forward):.2f}, inverse ANM p = {slope(inverse):.2f} (target: p <= 1.3)")
        if not args.skip_baselines:
            mesh = os.path.join(SOURCE, "meshes", "cantilever.geo")
            prm = os.path.join(work, "bar.prm")
            extra = ("  set Newton load steps = 20\n  set Newton max iterations = 15\n"
                     "  set Levenberg-Marquardt initial guesses = target, reversed-load\n"
                     f"  set Levenberg-Marquardt max time = {args.lm_cap}\n")
            with open(prm, "w") as f:
                f.write(BAR.format(scene="inverse-design", mesh=mesh, h=0.004, E=1e6,
                                   methods="anm, newton, levenberg-marquardt", extra=extra))
            s, _, wall, rss = run(nlmech, prm, work)
            a = value(s["anm"]["wall_time"])
            print(f"\n## Inverse baselines, bar {s['n_vertices']} vertices / {s['n_tetrahedra']} tets "
                  f"(paper: 4552 / 19552; LevMar 25m18s from the target, 8m23s from the reversed-load guess)\n")
            print("| method | converged | iterations | load steps (rejected) | time [s] | / inverse ANM | paper [s] |")
            print("|---|---|---|---|---|---|---|")
            print(f"| inverse ANM | yes | {s['anm']['steps']} steps | - | {a:.2f} | 1 | 2.38 |")
            nw = s["newton"]
            if nw.get("completed"):
                print(f"| Newton, adaptive load steps | yes | {nw['iterations']} | {nw['load_steps']} "
                      f"({nw['rejected_load_steps']}), smallest {nw['smallest_load_increment']:.2g} "
                      f"| {value(nw['wall_time']):.2f} | {value(nw['wall_time']) / a:.0f}x | - |")
            else:
                print(f"| Newton, adaptive load steps | no: {nw.get('failure', '')} | | | "
                      f"{value(nw['wall_time']):.2f} | | - |")
            for guess, paper in (("target", 1518.0), ("reversed-load", 503.0)):
                lm = s["levenberg_marquardt"].get(guess)
                if lm is None:
                    continue
                if "iterations" not in lm:
                    print(f"| LM from {guess} | no initial guess | | | | | {paper:.0f} |")
                    continue
                t = value(lm["wall_time"]) + value(lm.get("initial_guess_time", 0.0))
                state = "yes" if lm["converged"] else ("capped" if lm["capped"] else "no")
                print(f"| LM from {guess} (cap {args.lm_cap:.0f} s) | {state} (residual {lm['final_relative_residual']:.1e}) "
                      f"| {lm['iterations']} | - | {t:.1f} | {t / a:.0f}x | {paper:.0f} |")
            print(f"\n(run {wall:.0f} s, peak RSS {rss:.0f} MiB; LM time includes its initial guess's forward solve)")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
