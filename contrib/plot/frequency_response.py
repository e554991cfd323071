#!/usr/bin/env python3
"""Plots a frequency-response CSV written by nlmech's harmonic-balance scene against the driving
frequency, in two panels that each mark what they draw:
  top     amplitude A (thesis eq. 2.3.14, the integral of |v| of the tracked point over a period): the
          measure the resonance peaks are found on, so the peaks are marked here;
  bottom  half range (max - min) / 2 of the tracked coordinate, with the largest half range of each
          peak's neighbourhood on that curve marked (it may sit at another frequency than the peak
          of A, e.g. for a planar point whose path is not a line).
Stable branches solid, unstable dashed, folds marked, the linear modal analysis dotted where the
CSV has it.

usage: frequency_response.py RESPONSE.csv OUT.png [TITLE] [PEAKS.csv]
The PNG is written under a temporary name and renamed into place.
"""
import csv
import os
import sys


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def half_range_maxima(rows, peaks):
    """Per resonance peak: the point of largest half range between the neighbouring peaks'
    midpoints (the maximum of the bottom curve around that peak)."""
    w = [float(r["omega"]) for r in rows]
    h = [float(r["half_range"]) for r in rows]
    centres = sorted(float(p["omega"]) for p in peaks)
    out = []
    for k, c in enumerate(centres):
        lo = (centres[k - 1] + c) / 2 if k > 0 else -float("inf")
        hi = (centres[k + 1] + c) / 2 if k + 1 < len(centres) else float("inf")
        inside = [i for i in range(len(w)) if lo <= w[i] <= hi]
        if inside:
            i = max(inside, key=lambda j: h[j])
            out.append((w[i], h[i]))
    return out


def draw(ax, rows, key, lma_key, ylabel):
    w = [float(r["omega"]) for r in rows]
    y = [float(r[key]) for r in rows]
    stable = [int(r["stable"]) for r in rows]
    start = 0
    for i in range(1, len(rows) + 1):
        if i == len(rows) or stable[i] != stable[start]:
            end = min(i + 1, len(rows))
            style = "-" if stable[start] != 0 else "--"
            label = {1: "stable", 0: "unstable", -1: "stability not computed"}[stable[start]]
            ax.plot(w[start:end], y[start:end], style, color="C0", label=label)
            start = i
    if rows and lma_key in rows[0]:
        ax.plot(w, [float(r[lma_key]) for r in rows], ":", color="C1", label="linear modal analysis")
    folds = [i for i, r in enumerate(rows) if r["fold"] == "1"]
    if folds:
        ax.plot([w[i] for i in folds], [y[i] for i in folds], "o", color="C3", label="fold")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)


def legend(ax):
    handles, labels = ax.get_legend_handles_labels()
    unique = dict(zip(labels, handles))
    ax.legend(unique.values(), unique.keys(), fontsize=8)


def main():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = read(sys.argv[1])
    png_path = sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "frequency response"
    peaks = read(sys.argv[4]) if len(sys.argv) > 4 and os.path.exists(sys.argv[4]) else []
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    draw(top, rows, "amplitude_A", "lma_amplitude_A", "amplitude A, eq. 2.3.14 [m]")
    if peaks:
        top.plot([float(p["omega"]) for p in peaks], [float(p["amplitude_A"]) for p in peaks], "^", color="C2",
                 label="resonance peak (of A)")
    legend(top)
    top.set_title(title)
    draw(bottom, rows, "half_range", "lma_half_range", "half range of the tracked coordinate [m]")
    maxima = half_range_maxima(rows, peaks)
    if maxima:
        bottom.plot([m[0] for m in maxima], [m[1] for m in maxima], "v", color="C2",
                    label="largest half range near each peak")
    legend(bottom)
    bottom.set_xlabel("driving frequency w [rad/s]")
    fig.tight_layout()
    tmp = png_path + ".tmp.png"
    fig.savefig(tmp, dpi=120)
    os.replace(tmp, png_path)


if __name__ == "__main__":
    main()
