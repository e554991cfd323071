#!/usr/bin/env python3
"""Plots a mesh-study CSV written by nlmech: error against DOFs and error against wall time.

usage: mesh_study.py STUDY.csv OUT.png [TITLE] [CONTEXT_COLUMN]
CONTEXT_COLUMN: another error column drawn beside, dashed (e.g. the error against beam theory).
The PNG is written under a temporary name and renamed into place.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    csv_path, png_path = sys.argv[1], sys.argv[2]
    title = sys.argv[3] if len(sys.argv) > 3 else "mesh study"
    context = sys.argv[4] if len(sys.argv) > 4 else None
    with open(csv_path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [list(map(float, r)) for r in reader if r]
    error_column = header[4]
    dofs = [r[3] for r in rows]
    error = [r[4] for r in rows]
    time = [r[5] for r in rows]
    positive = [i for i, e in enumerate(error) if e > 0]

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, x, label in ((axes[0], dofs, "degrees of freedom"), (axes[1], time, "wall time [s]")):
        ax.loglog([x[i] for i in positive], [error[i] for i in positive], "o-", color="C0",
                  label=error_column.replace("_", " "))
        if context and context in header:
            c = [r[header.index(context)] for r in rows]
            ax.loglog([x[i] for i in range(len(c)) if c[i] > 0], [v for v in c if v > 0], "s--", color="C1",
                      label=context.replace("_", " ") + " (context)")
            ax.legend(fontsize=8)
        for i in positive:
            ax.annotate(str(int(rows[i][0])), (x[i], error[i]), textcoords="offset points", xytext=(4, 4), fontsize=8)
        ax.set_xlabel(label)
        ax.set_ylabel("relative error" if context else error_column.replace("_", " "))
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title("error against DOFs")
    axes[1].set_title("error against run time")
    fig.suptitle(title)
    fig.tight_layout()
    tmp = png_path + ".tmp.png"
    fig.savefig(tmp, dpi=110)
    os.replace(tmp, png_path)


if __name__ == "__main__":
    main()
