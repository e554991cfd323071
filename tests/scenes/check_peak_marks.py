#!/usr/bin/env python3
"""The frequency-response plot marks what it draws: the resonance peaks (found on the amplitude A of
eq. 2.3.14) sit on top of the drawn A curve around them, and the half-range panel marks the largest
half range of the drawn curve near each peak (the three-link mechanism's tracked point moves in a
plane, so the two measures peak at different frequencies: once 9.04 against 8.81 rad/s).
usage: check_peak_marks.py --nlmech BIN --prm FILE"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "contrib", "plot"))
import frequency_response as plot  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_peaks_")
    try:
        out = os.path.join(work, "results")
        run = subprocess.run([args.nlmech, args.prm, "--output-directory", out], capture_output=True, text=True)
        if run.returncode != 0:
            print(run.stdout + run.stderr)
            return 1
        rows = plot.read(os.path.join(out, "frequency_response.csv"))
        peaks = plot.read(os.path.join(out, "resonance_peaks.csv"))
        ok = len(peaks) >= 1 and os.path.getsize(os.path.join(out, "frequency_response.png")) > 0
        centres = sorted(float(p["omega"]) for p in peaks)
        for p in peaks:
            w, a = float(p["omega"]), float(p["amplitude_A"])
            k = centres.index(w)
            lo = (centres[k - 1] + w) / 2 if k > 0 else -1e300
            hi = (centres[k + 1] + w) / 2 if k + 1 < len(centres) else 1e300
            drawn = max(float(r["amplitude_A"]) for r in rows if lo <= float(r["omega"]) <= hi)
            good = a >= drawn * (1 - 1e-9)
            ok = ok and good
            print(f"{'ok  ' if good else 'FAIL'}: peak at w = {w:.6f}: marked A = {a:.9g} >= drawn curve's "
                  f"largest A nearby {drawn:.9g}")
        for (w, h), c in zip(plot.half_range_maxima(rows, peaks), centres):
            drawn = max(float(r["half_range"]) for r in rows)
            print(f"ok  : half-range mark near the peak at {c:.4f}: w = {w:.4f}, half range {h:.6g}")
        return 0 if ok else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
