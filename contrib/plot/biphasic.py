#!/usr/bin/env python3
"""Plots of the biphasic-sheet scene: total energy over time per scheme (thesis Fig. 3.4) and the
polar curve of the stretch limits with the sampled directions (SOCP paper Fig. 2, top row).
With stretch_reached.csv, the largest stretch each scheme reached per direction is drawn beside the
requested curve. Usage: biphasic.py energy.csv limits.csv energy.png limits.png [stretch_reached.csv]"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    energy_csv, limits_csv, energy_png, limits_png = sys.argv[1:5]
    reached_csv = sys.argv[5] if len(sys.argv) > 5 else None
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
    reached = {}
    if reached_csv:
        with open(reached_csv) as f:
            rows = list(csv.reader(f))
        for j, name in enumerate(rows[0][2:], start=2):
            reached[name] = [(float(r[0]), float(r[j])) for r in rows[1:] if len(r) > j]
    polar_limits(curve, samples, reached, limits_png)


def polar_limits(curve, samples, reached, png):
    """The requested curve, its sampled directions and the largest stretch reached per direction,
    zoomed to the limits (the radial axis starts below 1, not at 0, so a 1 % limit is visible), with
    b = 1 drawn as the reference ring and the material axes labelled."""
    fig = plt.figure(figsize=(5.5, 5.5))
    ax = fig.add_subplot(projection="polar")
    top = max([b for _, b in curve] + [s for values in reached.values() for _, s in values])
    low = 1 - 0.35 * (top - 1)
    ax.set_rorigin(low - 0.15 * (top - low))
    ax.set_rlim(low, top + 0.08 * (top - low))

    def both_ways(points):
        # d and -d are one direction: show alpha and alpha + pi, closed.
        pts = sorted(points) + [(a + math.pi, b) for a, b in sorted(points)]
        return [a for a, _ in pts] + [pts[0][0] + 2 * math.pi], [b for _, b in pts] + [pts[0][1]]

    ring = [2 * math.pi * k / 360 for k in range(361)]
    ax.plot(ring, [1.0] * len(ring), color="0.4", linestyle=":", linewidth=1, label="b = 1 (no stretch)")
    ax.plot(*both_ways(curve), color="C0", linewidth=2, label="requested limit b(alpha)")
    sa, sb = both_ways(samples)
    ax.plot(sa[:-1], sb[:-1], "o", color="C3", markersize=4, label="sampled directions")
    for k, (name, values) in enumerate(reached.items()):
        ax.plot(*both_ways(values), color=f"C{k + 1}", linewidth=1, label=f"largest stretch reached, {name}")
    lowest = min(b for _, b in curve)
    ticks = sorted({1.0, round(lowest, 6), round(top, 6)})
    ax.set_rticks(ticks)
    ax.set_yticklabels([f"{t:g}" for t in ticks], fontsize=8)
    ax.set_rlabel_position(67.5)
    ax.set_xticks([0, math.pi / 2, math.pi, 3 * math.pi / 2])
    ax.set_xticklabels(["warp (x)", "weft (z)", "warp", "weft"])
    ax.set_title("stretch limit per material direction", pad=14)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.06), fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(png, dpi=120)


if __name__ == "__main__":
    main()
