#!/usr/bin/env python3
"""Checks of the dim-characterization sampling runs against the uninterrupted serial run:
  --mode checkpoint  a run stopped after a few samples (as if killed) and then resumed gives the
                     same samples, and the resumed run recomputes only the missing ones;
  --mode mpi         the run on two ranks gives the same samples.
Each sample is an independent deterministic solve, so the results must agree to round-off.
usage: check_sampling_runs.py --nlmech BIN --prm FILE --mode checkpoint|mpi"""
import argparse
import csv
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "mpi"))
from serial_and_np2 import run_serial_and_np2  # noqa: E402


def samples(folder):
    rows = {}
    for name in sorted(os.listdir(folder)):
        if name.startswith("samples-") and name.endswith(".csv"):
            for r in csv.DictReader(open(os.path.join(folder, name))):
                rows[r["key"]] = (float(r["principal"]), float(r["orthogonal"]))
    return rows


def compare(a, b, what):
    if sorted(a) != sorted(b) or not a:
        print(f"FAIL: {what}: different sample sets ({len(a)} vs {len(b)})")
        return False
    worst = max(max(abs(x - y) for x, y in zip(a[k], b[k])) for k in a)
    print(f"{what}: {len(a)} samples, largest difference {worst:.3e}")
    ok = worst <= 1e-9
    print(f"{'ok  ' if ok else 'FAIL'}: {what} agrees to 1e-9")
    return ok


def run(nlmech, prm, out, extra_prm=None):
    path = prm
    if extra_prm:
        path = out + ".prm"
        with open(path, "w") as f:
            f.write(open(prm).read() + extra_prm)
    return subprocess.run([nlmech, path, "--output-directory", out], capture_output=True, text=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--mode", choices=["checkpoint", "mpi"], required=True)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_dim_")
    try:
        if args.mode == "mpi":
            folders = run_serial_and_np2(args.nlmech, args.prm, work)
            return 0 if folders and compare(samples(folders[1]), samples(folders[2]), "np 2 vs serial") else 1
        reference = os.path.join(work, "reference")
        r = run(args.nlmech, args.prm, reference)
        if r.returncode != 0:
            print(r.stdout, r.stderr)
            return 1
        resumed = os.path.join(work, "resumed")
        stopped = run(args.nlmech, args.prm, resumed, "subsection Sampling\n  set Stop after = 5\nend\n")
        checks = {
            "the stopped run exits non-zero": stopped.returncode != 0,
            "it says it stopped": "Sampling stopped after 5 new samples" in stopped.stderr,
            "it left no results folder": not os.path.exists(resumed),
            "it left 5 checkpointed samples": len([f for f in os.listdir(resumed + ".checkpoint")
                                                   if f.endswith(".sample")]) == 5,
        }
        again = run(args.nlmech, args.prm, resumed)
        checks["the resumed run succeeds"] = again.returncode == 0
        for name, ok in checks.items():
            print(f"{'ok  ' if ok else 'FAIL'}: {name}")
        if not all(checks.values()):
            print(stopped.stderr, again.stdout, again.stderr)
            return 1
        return 0 if compare(samples(reference), samples(resumed), "resumed vs uninterrupted") else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
