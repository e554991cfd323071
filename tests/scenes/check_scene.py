#!/usr/bin/env python3
"""Runs an nlmech scene and checks figures of its summary.json against stated bounds.

usage: check_scene.py --nlmech BIN --prm FILE [--np N] --expect 'KEY OP VALUE' ... [--expect-file NAME ...]
                      [--expect-progress TASK]
KEY names a summary.json entry ({"value": v, "unit": u} or a plain number), `a.b` one inside object a;
OP is <, <=, >, >=, ==.
--expect-progress TASK: the run's "[TASK] p% done" lines cover the whole run: p never falls, only the
last line reads 100 %, and there are lines below 50 % (one line for the run, not one per phase).
The run goes to a fresh temporary folder; exit status 0 only if the run succeeds and every check holds.
"""
import argparse
import json
import operator
import os
import re
import shutil
import subprocess
import sys
import tempfile

OPS = {"<=": operator.le, ">=": operator.ge, "<": operator.lt, ">": operator.gt, "==": operator.eq}


def mpi_prefix(n):
    if n <= 1:
        return []
    return ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(n)]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--expect", action="append", default=[])
    parser.add_argument("--expect-file", action="append", default=[])
    parser.add_argument("--expect-absent", action="append", default=[],
                        help="a summary.json key that must not be there (a figure not sampled)")
    parser.add_argument("--expect-progress", action="append", default=[],
                        help="a progress task whose lines must cover the whole run once")
    args = parser.parse_args()

    work = tempfile.mkdtemp(prefix="nlmech_scene_")
    out = os.path.join(work, "results")
    try:
        command = mpi_prefix(args.np) + [args.nlmech, args.prm, "--output-directory", out]
        run = subprocess.run(command, capture_output=True, text=True)
        sys.stdout.write(run.stdout)
        sys.stderr.write(run.stderr)
        if run.returncode != 0:
            print(f"FAIL: nlmech exited with status {run.returncode}")
            return 1
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        failures = 0
        for expectation in args.expect:
            key, op, bound = expectation.split()
            entry = summary
            for part in key.split("."):
                entry = entry[part]
            value = entry["value"] if isinstance(entry, dict) else entry
            ok = OPS[op](value, float(bound))
            failures += not ok
            print(f"{'ok  ' if ok else 'FAIL'}: {key} = {value:.6g} {op} {bound}")
        for key in args.expect_absent:
            ok = key not in summary
            failures += not ok
            print(f"{'ok  ' if ok else 'FAIL'}: {key} not reported")
        for task in args.expect_progress:
            done = [float(m.group(1)) for m in
                    re.finditer(r"^\[" + re.escape(task) + r"\]\s+([0-9.]+)% done", run.stdout, re.M)]
            rising = all(b >= a for a, b in zip(done, done[1:]))
            full_once = bool(done) and done[-1] >= 99.95 and all(p < 99.95 for p in done[:-1])
            ok = rising and full_once and min(done) < 50
            failures += not ok
            print(f"{'ok  ' if ok else 'FAIL'}: [{task}] progress over the whole run "
                  f"({len(done)} lines: {', '.join(f'{p:.1f}' for p in done[:3])} .. "
                  f"{', '.join(f'{p:.1f}' for p in done[-3:])})")
        for name in args.expect_file:
            ok = os.path.isfile(os.path.join(out, name)) and os.path.getsize(os.path.join(out, name)) > 0
            failures += not ok
            print(f"{'ok  ' if ok else 'FAIL'}: result file {name} written")
        return 1 if failures else 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
