#!/usr/bin/env python3
"""--list-scenes names every scene, and each scene's --print-parameters output validates again."""
import argparse
import os
import subprocess
import sys
import tempfile


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    args = parser.parse_args()
    listing = subprocess.run([args.nlmech, "--list-scenes"], capture_output=True, text=True, check=True).stdout
    scenes = [line for line in listing.splitlines() if line and not line.startswith(" ")]
    print("scenes:", scenes)
    failures = 0
    for expected in ("cantilever", "elastic-statics", "manufactured-solution"):
        if expected not in scenes:
            print(f"FAIL: {expected} not listed")
            failures += 1
    with tempfile.TemporaryDirectory() as work:
        for scene in scenes:
            text = subprocess.run([args.nlmech, "--print-parameters", scene], capture_output=True, text=True,
                                  check=True).stdout
            path = os.path.join(work, scene + ".prm")
            with open(path, "w") as f:
                f.write(text)
            run = subprocess.run([args.nlmech, "--validate", path], capture_output=True, text=True)
            ok = run.returncode == 0 and "valid" in run.stdout
            failures += not ok
            print(f"{'ok  ' if ok else 'FAIL'}: defaults of {scene} validate {run.stderr.strip()}")
    run = subprocess.run([args.nlmech, "--frobnicate"], capture_output=True, text=True)
    ok = run.returncode != 0 and "Unknown option <--frobnicate>" in run.stderr
    failures += not ok
    print(f"{'ok  ' if ok else 'FAIL'}: unknown option rejected")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
