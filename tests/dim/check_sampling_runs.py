#!/usr/bin/env python3
"""Checks of the dim-characterization sampling runs against the uninterrupted serial run:
  --mode checkpoint  a run stopped after a few samples (as if killed) and then resumed gives the
                     same samples, and the resumed run recomputes only the missing ones;
  --mode mpi         the run on two ranks gives the same samples;
  --mode threads     the run on two task threads (samples side by side) gives the same samples as
                     on one, digit for digit (a race in the BLAS under CHOLMOD once broke this);
  --mode integrity   a checkpoint is not trusted blindly: a sample edited by hand (a limit changed, a
                     negative gap) or written by another code version is recomputed, a directory with
                     samples but no plan.txt is refused, and summary.json says how many were resumed.
Each sample is an independent deterministic solve, so the results must agree to round-off.
usage: check_sampling_runs.py --nlmech BIN --prm FILE --mode checkpoint|mpi|threads|integrity"""
import json
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


def compare(a, b, what, tolerance=1e-9):
    if sorted(a) != sorted(b) or not a:
        print(f"FAIL: {what}: different sample sets ({len(a)} vs {len(b)})")
        return False
    worst = max(max(abs(x - y) for x, y in zip(a[k], b[k])) for k in a)
    print(f"{what}: {len(a)} samples, largest difference {worst:.3e}")
    ok = worst <= tolerance
    print(f"{'ok  ' if ok else 'FAIL'}: {what} agrees to {tolerance:g}")
    return ok


def run(nlmech, prm, out, extra_prm=None, extra_args=()):
    path = prm
    if extra_prm:
        path = out + ".prm"
        with open(path, "w") as f:
            f.write(open(prm).read() + extra_prm)
    return subprocess.run([nlmech, path, "--output-directory", out, *extra_args], capture_output=True, text=True)


def fnv1a(text):
    h = 1469598103934665603
    for c in text.encode():
        h = ((h ^ c) * 1099511628211) % (1 << 64)
    return f"{h:016x}"


def counts(folder):
    with open(os.path.join(folder, "summary.json")) as f:
        return json.load(f)["checkpoint_in_plane"]


def integrity(nlmech, prm, work):
    out = os.path.join(work, "run")
    checkpoint = out + ".checkpoint"
    first = run(nlmech, prm, out)
    if first.returncode != 0:
        print(first.stdout, first.stderr)
        return 1
    reference = samples(out)
    n = len(reference)
    checks = {f"first run computes all {n}": counts(out)["computed"] == n and counts(out)["resumed"] == 0}
    again = run(nlmech, prm, out)
    checks["a second run resumes all"] = again.returncode == 0 and counts(out)["resumed"] == n
    checks["the log says how many were resumed"] = f"{n} resumed" in again.stdout
    files = sorted(f for f in os.listdir(checkpoint) if f.endswith(".sample"))
    # A limit changed by hand, and a negative gap: both fail the checksum and are recomputed.
    edited, gap = os.path.join(checkpoint, files[0]), os.path.join(checkpoint, files[1])
    lines = open(edited).read().split("\n")
    numbers = lines[0].split()
    numbers[3] = repr(float(numbers[3]) * 1.5)
    open(edited, "w").write("\n".join([" ".join(numbers)] + lines[1:]))
    lines = open(gap).read().split("\n")
    numbers = lines[0].split()
    numbers[7] = "-0.01"
    open(gap, "w").write("\n".join([" ".join(numbers)] + lines[1:]))
    # A sample as another build would have written it: a valid checksum over another code version.
    stale = os.path.join(checkpoint, files[2])
    plan = open(os.path.join(checkpoint, "plan.txt")).read()
    fingerprint = plan[: plan.rfind("code ")]
    key = files[2][: -len(".sample")]
    lines = open(stale).read().split("\n")
    old = "0000000000000000"
    lines[1] = "code " + old
    lines[2] = "checksum " + fnv1a(fingerprint + "\n" + key + "\n" + lines[0] + "\n" + old)
    open(stale, "w").write("\n".join(lines))
    third = run(nlmech, prm, out)
    c = counts(out) if third.returncode == 0 else {}
    checks["the edited samples are recomputed"] = c.get("recomputed_damaged_or_edited") == 2
    checks["the other version's sample is recomputed"] = c.get("recomputed_other_code_version") == 1
    checks["the rest are resumed"] = c.get("resumed") == n - 3 and c.get("computed") == 3
    checks["the log says why"] = "edited or invalid" in third.stdout and "older build" in third.stdout
    same = third.returncode == 0 and compare(reference, samples(out), "after recomputing")
    os.remove(os.path.join(checkpoint, "plan.txt"))
    fourth = run(nlmech, prm, out)
    checks["samples without plan.txt are refused"] = fourth.returncode != 0 and "no plan.txt" in fourth.stderr
    for name, ok in checks.items():
        print(f"{'ok  ' if ok else 'FAIL'}: {name}")
    if not all(checks.values()):
        print(third.stdout, third.stderr, fourth.stderr)
    return 0 if all(checks.values()) and same else 1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--mode", choices=["checkpoint", "mpi", "threads", "integrity"], required=True)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_dim_")
    try:
        if args.mode == "integrity":
            return integrity(args.nlmech, args.prm, work)
        if args.mode == "mpi":
            folders = run_serial_and_np2(args.nlmech, args.prm, work)
            return 0 if folders and compare(samples(folders[1]), samples(folders[2]), "np 2 vs serial") else 1
        if args.mode == "threads":
            one, two = os.path.join(work, "threads1"), os.path.join(work, "threads2")
            for folder, n in ((one, "1"), (two, "2")):
                r = run(args.nlmech, args.prm, folder, extra_args=("--threads", n))
                if r.returncode != 0:
                    print(r.stdout, r.stderr)
                    return 1
            return 0 if compare(samples(one), samples(two), "2 threads vs 1", 0.0) else 1
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
