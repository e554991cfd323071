#!/usr/bin/env python3
"""Benchmark: wall time of nlmech runs on 1 and 2 threads and on 1 and 2 MPI ranks, as a user runs them.

Every case is a parameter file run through the binary (`nlmech FILE.prm --threads N`, or
`mpirun -np N nlmech FILE.prm`, where deal.II gives each rank its share of the cores); the table
shows the median wall time of --repeats runs per configuration and the speed-ups over one thread
and one rank, beside the run's own figures (unknowns, steps), so that a faster run that computed
something else would show.

usage: parallel_scaling.py [--nlmech build/nlmech] [--repeats 3] [--cases anm-bar-10k,swinging-sheet-60]
                           [--configs threads1,threads2,ranks1,ranks2]
"""
import argparse
import json
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


def shipped(name, overrides="", keys=()):
    """A shipped prm/ file, mesh paths made absolute, `overrides` (prm text) appended."""
    return {"base": os.path.join(SOURCE, "prm", name), "overrides": overrides, "keys": keys}


CASES = {
    # Forward neo-Hookean ANM on the sagging bar of anm_statics.py, h = 3 mm: about 10k vertices.
    "anm-bar-10k": shipped("hyperelastic-bar.prm", """subsection Mesh
  set Element size = 0.003
end
subsection Solver
  set Methods = anm
end
""", ("n_vertices", "anm.steps", "anm.factorizations")),
    # Inverse design of the plant-like shape at the ANM paper's size (14.4k vertices), as shipped.
    "inverse-plant-15k": shipped("inverse-plant-15k.prm", "", ("n_vertices", "anm.steps", "anm.factorizations")),
    # The harmonic-balance frequency-response curve of the layered solid, as shipped.
    "hbm-layered-solid": shipped("layered-solid.prm", "", ("n_unknowns", "points", "unstable_points")),
    # The strain-limited swinging sheet at 60 x 60 quads, one scheme, first second.
    "swinging-sheet-60": shipped("swinging-sheet.prm", """subsection Sheet
  set Resolution = 60
end
subsection Time stepping
  set End time = 0.5
  set Schemes = SAP
end
""", ("max_violation_SAP",)),
    # DIM characterisation of the threefold chainmail: independent samples.
    "dim-threefold": shipped("dim-threefold.prm", "", ("stretch_directions", "bending_directions")),
}

CONFIGS = {
    "threads1": (1, ["--threads", "1"]),
    "threads2": (1, ["--threads", "2"]),
    "ranks1": (1, ["--threads", "1"]),
    "ranks2": (2, ["--threads", "1"]),
}


def write_prm(case, work):
    base = case["base"]
    base_dir = os.path.dirname(base)
    with open(base) as f:
        text = f.read()

    def absolute(m):
        path = m.group(2).strip()
        if not os.path.isabs(path):
            path = os.path.normpath(os.path.join(base_dir, path))
        return m.group(1) + path + (m.group(3) or "")

    text = re.sub(r"(set\s+Mesh file\s*=\s*)([^#\n]*?)(\s*#.*)?$", absolute, text, flags=re.M)
    prm = os.path.join(work, "case.prm")
    with open(prm, "w") as f:
        f.write(text + "\n" + case["overrides"])
    return prm


def run(nlmech, prm, config, work):
    ranks, extra = CONFIGS[config]
    out = os.path.join(work, "out-" + config)
    shutil.rmtree(out, ignore_errors=True)
    command = [nlmech, prm, "--output-directory", out] + extra
    if config.startswith("ranks"):
        mpirun = shutil.which("mpirun")
        command = [mpirun, "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + command
    env = dict(os.environ)
    env.pop("DEAL_II_NUM_THREADS", None)
    start = time.perf_counter()
    result = subprocess.run(command, capture_output=True, text=True, env=env)
    seconds = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{result.stderr}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    return seconds, summary


def lookup(summary, key):
    value = summary
    for part in key.split("."):
        if not isinstance(value, dict) or part not in value:
            return "-"
        value = value[part]
    if isinstance(value, dict):
        value = value.get("value", "-")
    return value


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--nlmech", default=os.path.join(SOURCE, "build", "nlmech"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--cases", default=",".join(CASES))
    parser.add_argument("--configs", default=",".join(CONFIGS))
    a = parser.parse_args()
    configs = a.configs.split(",")
    print(f"# nlmech parallel scaling, {time.strftime('%Y-%m-%d')}, {platform.node()}, "
          f"{len(os.sched_getaffinity(0))} cores, median of {a.repeats}\n")
    header = ["case"] + [f"{c} [s]" for c in configs]
    if "threads1" in configs and "threads2" in configs:
        header.append("2 threads / 1")
    if "ranks1" in configs and "ranks2" in configs:
        header.append("2 ranks / 1")
    header.append("figures (last run)")
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for name in a.cases.split(","):
        case = CASES[name]
        with tempfile.TemporaryDirectory() as work:
            prm = write_prm(case, work)
            medians, summary = {}, {}
            for config in configs:
                times = []
                for _ in range(a.repeats):
                    seconds, summary = run(a.nlmech, prm, config, work)
                    times.append(seconds)
                medians[config] = statistics.median(times)
            row = [name] + [f"{medians[c]:.2f}" for c in configs]
            if "threads1" in medians and "threads2" in medians:
                row.append(f"{medians['threads1'] / medians['threads2']:.2f}x")
            if "ranks1" in medians and "ranks2" in medians:
                row.append(f"{medians['ranks1'] / medians['ranks2']:.2f}x")
            row.append(", ".join(f"{k} {lookup(summary, k)}" for k in case["keys"]))
            print("| " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()
