#!/usr/bin/env python3
"""Plots of the harmonic-balance design study (subsection Design of the harmonic-balance scene).

usage: design.py history   design_history.csv OUT.png        objective against evaluation
       design.py trajectories design_trajectories.csv OUT.png tracked point before / after / target
       design.py sweep     sensitivity_sweep.csv OUT.png      prediction error against step (slope 2)
       design.py curves    frequency_response_initial.csv frequency_response.csv OUT.png [W]
Each PNG is written under a temporary name and renamed into place.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def save(fig, path):
    tmp = path + ".tmp.png"
    fig.tight_layout()
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)


def history(rows, out):
    fig, ax = plt.subplots(figsize=(6, 4))
    it = [int(r["iteration"]) for r in rows]
    f = [float(r["objective"]) for r in rows]
    ax.plot(it, f, "o-", ms=3)
    if all(v > 0 for v in f):
        ax.set_yscale("log")
    ax.set_xlabel("objective evaluation")
    ax.set_ylabel("objective")
    ax.set_title("design history (L-BFGS)")
    ax.grid(True, alpha=0.3)
    save(fig, out)


def trajectories(rows, out, per_point=0):
    """One panel per driving frequency and objective point: before, after and target over one
    period about their means (one coordinate: against the phase; more: the first two)."""
    freqs = sorted({float(r["frequency"]) for r in rows})
    coords = sorted({int(k.split("_")[1]) for k in rows[0] if k.startswith("before_")})
    per_point = per_point or len(coords)
    points = [coords[i:i + per_point] for i in range(0, len(coords), per_point)]
    fig, axes = plt.subplots(len(points), len(freqs), figsize=(5 * len(freqs), 4.5 * len(points)),
                             squeeze=False)
    for col, w in enumerate(freqs):
        sub = [r for r in rows if float(r["frequency"]) == w]
        for row, point in enumerate(points):
            ax = axes[row][col]
            for kind, style in (("before", "C0--"), ("after", "C1-"), ("target", "k:")):
                if "%s_%d" % (kind, point[0]) not in sub[0]:
                    continue
                cols = [[float(r["%s_%d" % (kind, c)]) for r in sub] for c in point]
                cols = [[v - sum(c) / len(c) for v in c] for c in cols]
                if len(cols) == 1:
                    phase = [float(r["phase"]) for r in sub]
                    ax.plot(phase + [2 * math.pi], cols[0] + cols[0][:1], style, label=kind)
                    ax.set_xlabel("phase w t [rad]")
                    ax.set_ylabel("displacement from the mean [m]")
                else:
                    ax.plot(cols[0] + cols[0][:1], cols[1] + cols[1][:1], style, label=kind)
                    ax.set_xlabel("coordinate %d [m]" % point[0])
                    ax.set_ylabel("coordinate %d [m]" % point[1])
                    ax.set_aspect("equal", adjustable="datalim")
            ax.set_title(("point %d " % row if len(points) > 1 else "tracked point ") + "at w = %.4g rad/s" % w)
            ax.grid(True, alpha=0.3)
            ax.legend()
    save(fig, out)


def sweep(rows, out):
    fig, ax = plt.subplots(figsize=(6, 4))
    for w in sorted({float(r["frequency"]) for r in rows}):
        sub = [r for r in rows if float(r["frequency"]) == w]
        dp = [float(r["dp_norm"]) for r in sub]
        err = [float(r["prediction_error"]) for r in sub]
        ax.loglog(dp, err, "o-", label="w = %.4g rad/s" % w)
        if dp:
            ref = [err[-1] * (d / dp[-1]) ** 2 for d in dp]
            ax.loglog(dp, ref, "k:", label="slope 2")
    ax.set_xlabel("|dp|")
    ax.set_ylabel("|z(p + dp) - z - S dp| / |z|")
    ax.set_title("first-order prediction error")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    save(fig, out)


def curves(before, after, out, w):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot([float(r["omega"]) for r in before], [float(r["amplitude_A"]) for r in before], "C0-",
            label="initial design")
    ax.plot([float(r["omega"]) for r in after], [float(r["amplitude_A"]) for r in after], "C1-",
            label="design found")
    if w is not None:
        ax.axvline(w, color="k", ls="--", lw=1, label="design frequency (driving or peak)")
    ax.set_xlabel("w [rad/s]")
    ax.set_ylabel("amplitude A (2.3.14) [m]")
    ax.set_title("frequency response before and after design")
    ax.grid(True, alpha=0.3)
    ax.legend()
    save(fig, out)


def main():
    mode = sys.argv[1]
    if mode == "curves":
        curves(read(sys.argv[2]), read(sys.argv[3]), sys.argv[4], float(sys.argv[5]) if len(sys.argv) > 5 else None)
        return 0
    rows = read(sys.argv[2])
    if not rows:
        return 1
    if mode == "trajectories":
        trajectories(rows, sys.argv[3], int(sys.argv[4]) if len(sys.argv) > 4 else 0)
        return 0
    {"history": history, "sweep": sweep}[mode](rows, sys.argv[3])
    return 0


if __name__ == "__main__":
    sys.exit(main())
