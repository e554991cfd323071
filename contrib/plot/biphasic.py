#!/usr/bin/env python3
"""Plots of the biphasic-sheet scene: total energy over time per scheme (thesis Fig. 3.4) and the
polar curve of the stretch limits with the sampled directions (SOCP paper Fig. 2, top row).
Usage: biphasic.py energy.csv limits.csv energy.png limits.png"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    energy_csv, limits_csv, energy_png, limits_png = sys.argv[1:5]
    series = {}
    with open(energy_csv) as f:
        for row in csv.DictReader(f):
            series.setdefault(row["scheme"], ([], []))
            series[row["scheme"]][0].append(float(row["time"]))
            series[row["scheme"]][1].append(float(row["total"]))
    fig, ax = plt.subplots(figsize=(6, 4))
    for name, (t, e) in series.items():
        ax.plot(t, e, label=name)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("total energy [J] (kinetic + elastic + gravity + contact)")
    ax.set_title("Energy over time")
    ax.legend()
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(energy_png, dpi=120)

    curve, samples, target = [], [], None
    with open(limits_csv) as f:
        next(f)
        target = curve
        for line in f:
            if line.startswith("#samples"):
                target = samples
                continue
            a, b = (float(v) for v in line.split(","))
            target.append((a, b))
    fig = plt.figure(figsize=(4.5, 4.5))
    ax = fig.add_subplot(projection="polar")
    # The limit is symmetric: d and -d are the same direction, so show alpha and alpha + pi.
    for shift in (0, math.pi):
        ax.plot([a + shift for a, _ in curve], [b for _, b in curve], color="C0")
        ax.plot([a + shift for a, _ in samples], [b for _, b in samples], "o", color="C3", markersize=4)
    top = max(b for _, b in curve)
    ax.set_rlim(0, top * 1.05)
    ax.set_title("stretch limit b(alpha) and sampled directions")
    fig.tight_layout()
    fig.savefig(limits_png, dpi=120)


if __name__ == "__main__":
    main()
