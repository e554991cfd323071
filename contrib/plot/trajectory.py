#!/usr/bin/env python3
"""Plots the tracked point's trajectory over one period (trajectory.csv of the harmonic-balance
scene): each coordinate's displacement from its mean against time, and the path in the plane of
its two largest motions.

usage: trajectory.py TRAJECTORY.csv OUT.png [TITLE]
The PNG is written under a temporary name and renamed into place.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    png_path = sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "trajectory"
    t = [float(r["t"]) for r in rows]
    coords = {c: [float(r[c]) for r in rows] for c in ("x", "y", "z")}
    means = {c: sum(v) / len(v) for c, v in coords.items()}
    ranges = {c: max(v) - min(v) for c, v in coords.items()}
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    for c in ("x", "y", "z"):
        if ranges[c] > 0:
            a1.plot(t, [v - means[c] for v in coords[c]], label=c)
    a1.set_xlabel("t [s]")
    a1.set_ylabel("displacement from the mean [m]")
    a1.legend()
    a1.grid(True, alpha=0.3)
    big = sorted(ranges, key=ranges.get, reverse=True)[:2]
    u, v = sorted(big)
    a2.plot(coords[u] + coords[u][:1], coords[v] + coords[v][:1], "-", color="C2")
    a2.plot(coords[u][0], coords[v][0], "o", color="C3", label="t = 0")
    a2.set_xlabel(u + " [m]")
    a2.set_ylabel(v + " [m]")
    a2.set_aspect("equal", adjustable="datalim")
    a2.legend()
    a2.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    tmp = png_path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, png_path)


if __name__ == "__main__":
    main()
