#!/usr/bin/env python3
"""Draws a rod network over one period (rod_period.csv of the harmonic-balance scene) in two
views: the edges at every frame, faint, the first frame bold; the views are the plane of the two
largest extents of the network and the plane of the largest extent and the largest motion.

usage: rods.py PERIOD.csv OUT.png "a-b c-d ..."
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
    edges = [tuple(int(j) for j in pair.split("-")) for pair in sys.argv[3].split()]
    n = (len(rows[0]) - 1) // 3
    pos = [[[float(r["%s%d" % (c, v)]) for c in "xyz"] for v in range(n)] for r in rows]
    extent = [max(p[v][c] for v in range(n)) - min(p[v][c] for v in range(n)) for p in pos[:1] for c in range(3)]
    motion = [max(max(p[v][c] for p in pos) - min(p[v][c] for p in pos) for v in range(n)) for c in range(3)]
    by_extent = sorted(range(3), key=lambda c: -extent[c])
    first = by_extent[0]
    views = [(first, by_extent[1])]
    second = max((c for c in range(3) if c != first), key=lambda c: motion[c])
    if (first, second) != views[0]:
        views.append((first, second))
    fig, axes = plt.subplots(1, len(views), figsize=(6 * len(views), 5))
    if len(views) == 1:
        axes = [axes]
    for ax, (u, w) in zip(axes, views):
        for f, p in enumerate(pos):
            for a, b in edges:
                ax.plot([p[a][u], p[b][u]], [p[a][w], p[b][w]], "-", color="C0" if f == 0 else "0.75",
                        lw=1.6 if f == 0 else 0.6, zorder=2 if f == 0 else 1)
        ax.set_xlabel("xyz"[u] + " [m]")
        ax.set_ylabel("xyz"[w] + " [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    fig.suptitle("rod network over one period (blue: t = 0, grey: other frames)")
    fig.tight_layout()
    tmp = png_path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, png_path)


if __name__ == "__main__":
    main()
