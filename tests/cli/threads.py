#!/usr/bin/env python3
"""The binary uses every core by default, --threads N and DEAL_II_NUM_THREADS limit it, and a bad
--threads value ends in one clear message and a non-zero exit.

usage: threads.py --nlmech BIN --prm FILE
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(nlmech, prm, extra, env_threads=None):
    env = dict(os.environ)
    env.pop("DEAL_II_NUM_THREADS", None)
    if env_threads is not None:
        env["DEAL_II_NUM_THREADS"] = str(env_threads)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out")
        p = subprocess.run([nlmech, prm, "--output-directory", out] + extra, env=env,
                           capture_output=True, text=True, timeout=600)
        summary = None
        if p.returncode == 0:
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
        return p, summary


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nlmech", required=True)
    ap.add_argument("--prm", required=True)
    a = ap.parse_args()
    cores = len(os.sched_getaffinity(0))
    failures = []

    p, s = run(a.nlmech, a.prm, [])
    if s is None:
        failures.append(f"default run failed: {p.stderr.strip()}")
    else:
        print(f"default: {s['threads_per_rank']} thread(s) on {cores} core(s)")
        if s["threads_per_rank"] != cores:
            failures.append(f"default run: {s['threads_per_rank']} threads, expected every core ({cores})")
        if cores > 1 and s["threads_per_rank"] < 2:
            failures.append("the binary runs one thread on a multi-core machine")
        if f"x {s['threads_per_rank']} thread(s)" not in p.stdout:
            failures.append("the run's first line does not report the thread count")

    for extra, env_threads, what in (([], 1, "DEAL_II_NUM_THREADS=1"), (["--threads", "1"], None, "--threads 1"),
                                     (["--threads", "64"], 1, "--threads 64 with DEAL_II_NUM_THREADS=1")):
        p, s = run(a.nlmech, a.prm, extra, env_threads)
        if s is None:
            failures.append(f"{what}: run failed: {p.stderr.strip()}")
        elif s["threads_per_rank"] != 1:
            failures.append(f"{what}: {s['threads_per_rank']} threads, expected 1")

    for bad in (["--threads", "0"], ["--threads", "two"], ["--threads", "1.5"], ["--threads"]):
        p, s = run(a.nlmech, a.prm, bad)
        lines = [l for l in p.stderr.splitlines() if l.strip()]
        if p.returncode == 0 or not lines or "--threads" not in p.stderr or len(lines) > 3:
            failures.append(f"{' '.join(bad)}: exit {p.returncode}, stderr {p.stderr!r}")

    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
