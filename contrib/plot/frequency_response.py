#!/usr/bin/env python3
"""Plots a frequency-response CSV written by nlmech's harmonic-balance scene: amplitude against
driving frequency, stable branches solid, unstable dashed, folds and resonance peaks marked, and
the linear modal analysis response dotted where the CSV has it.

usage: frequency_response.py RESPONSE.csv OUT.png [TITLE] [PEAKS.csv]
The PNG is written under a temporary name and renamed into place.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    rows = read(sys.argv[1])
    png_path = sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "frequency response"
    peaks = read(sys.argv[4]) if len(sys.argv) > 4 and os.path.exists(sys.argv[4]) else []
    w = [float(r["omega"]) for r in rows]
    a = [float(r["half_range"]) for r in rows]
    stable = [int(r["stable"]) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    # Segments between consecutive points, styled by stability of both ends.
    start = 0
    for i in range(1, len(rows) + 1):
        if i == len(rows) or stable[i] != stable[start]:
            end = min(i + 1, len(rows))
            style = "-" if stable[start] != 0 else "--"
            label = {1: "stable", 0: "unstable", -1: "stability not computed"}[stable[start]]
            ax.plot(w[start:end], a[start:end], style, color="C0", label=label)
            start = i
    if rows and "lma_half_range" in rows[0]:
        ax.plot(w, [float(r["lma_half_range"]) for r in rows], ":", color="C1", label="linear modal analysis")
    folds = [i for i, r in enumerate(rows) if r["fold"] == "1"]
    if folds:
        ax.plot([w[i] for i in folds], [a[i] for i in folds], "o", color="C3", label="fold")
    if peaks:
        ax.plot([float(p["omega"]) for p in peaks], [float(p["half_range"]) for p in peaks], "^", color="C2",
                label="resonance peak")
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles))
    ax.legend(unique.values(), unique.keys())
    ax.set_xlabel("driving frequency w [rad/s]")
    ax.set_ylabel("amplitude (half range) [m]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    tmp = png_path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, png_path)


if __name__ == "__main__":
    main()
