#!/usr/bin/env python3
"""A run killed half-way leaves the last complete results as they were, nothing half-written.

Runs a scene to completion into OUT, then runs it again into OUT and kills it (SIGKILL, then
SIGTERM) while it works. Checks: the process was still running when killed; OUT still holds the
first run's files byte for byte (summary.json parses, no file added or changed); whatever the
killed run wrote lies only in OUT.incomplete; a third run, uninterrupted, completes and exits 0.
"""
import argparse
import hashlib
import json
import os
import signal
import subprocess
import sys
import tempfile
import time


def snapshot(directory):
    out = {}
    for root, _, files in os.walk(directory):
        for name in files:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                out[os.path.relpath(path, directory)] = hashlib.sha256(f.read()).hexdigest()
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nlmech", required=True)
    ap.add_argument("--prm", required=True)
    ap.add_argument("--after", type=float, default=0.7, help="seconds before the kill")
    a = ap.parse_args()
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "results")
        cmd = [a.nlmech, a.prm, "--output-directory", out, "--threads", "1"]
        first = subprocess.run(cmd, capture_output=True, text=True)
        if first.returncode != 0:
            print(first.stdout[-2000:], first.stderr[-2000:])
            print("FAIL: the first run did not complete")
            return 1
        before = snapshot(out)
        json.load(open(os.path.join(out, "summary.json")))
        for sig in (signal.SIGKILL, signal.SIGTERM):
            p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(a.after)
            if p.poll() is not None:
                failures.append(f"the run ended before the {sig.name} after {a.after} s: nothing was tested")
                continue
            p.send_signal(sig)
            p.wait()
            after = snapshot(out)
            if after != before:
                changed = sorted(set(after) ^ set(before) | {k for k in after if before.get(k) != after[k]})
                failures.append(f"{sig.name}: the complete results changed: {changed[:5]}")
            else:
                print(f"{sig.name} after {a.after} s (exit {p.returncode}): the last complete results "
                      f"are intact ({len(before)} files); the killed run's files lie in "
                      f"{os.path.basename(out)}.incomplete: {os.path.isdir(out + '.incomplete')}")
        third = subprocess.run(cmd, capture_output=True, text=True)
        if third.returncode != 0:
            failures.append(f"the run after the kills exits {third.returncode}")
        elif os.path.isdir(out + ".incomplete"):
            failures.append("a completed run left its staging folder behind")
        else:
            json.load(open(os.path.join(out, "summary.json")))
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
