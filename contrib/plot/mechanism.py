#!/usr/bin/env python3
"""Draws a planar mechanism over one period (mechanism_period.csv of the harmonic-balance scene):
the links at every frame, faint, with the first frame bold, and every joint's trajectory.

usage: mechanism.py PERIOD.csv OUT.png "a-b c-d ..."
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
    links = [tuple(int(j) for j in pair.split("-")) for pair in sys.argv[3].split()]
    n = (len(rows[0]) - 1) // 2
    xs = [[float(r["x%d" % j]) for r in rows] for j in range(n)]
    ys = [[float(r["y%d" % j]) for r in rows] for j in range(n)]
    fig, ax = plt.subplots(figsize=(6, 6))
    for f in range(len(rows)):
        for a, b in links:
            ax.plot([xs[a][f], xs[b][f]], [ys[a][f], ys[b][f]], "-", color="0.3" if f == 0 else "0.8",
                    lw=2.5 if f == 0 else 0.8, zorder=2 if f == 0 else 1)
    for j in range(n):
        ax.plot(xs[j] + xs[j][:1], ys[j] + ys[j][:1], "-", color="C%d" % (j % 10), lw=1.2)
        ax.plot(xs[j][0], ys[j][0], "o", color="C%d" % (j % 10), ms=4)
        ax.annotate(str(j), (xs[j][0], ys[j][0]), textcoords="offset points", xytext=(4, 4), fontsize=8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("mechanism over one period (grey: links, colour: joint paths)")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    tmp = png_path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, png_path)


if __name__ == "__main__":
    main()
