#!/usr/bin/env python3
"""Polar plots of a discrete interlocking material's directional limits (thesis Fig. 4.6 b-d):
the free range of travel c = (eps_s - eps_c) / (1 + eps_c) (eq. 4.4.1) for uniaxial stretching,
and the principal and orthogonal curvatures reached under uniaxial bending of either sign.
Directions are sampled in [0, 180) degrees and mirrored to fill the circle.
Usage: dim_limits.py limits.csv stretch.png bending.png "material name" """
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def closed(theta, values):
    """Mirror [0, pi) to [0, 2 pi) and close the curve."""
    t = theta + [x + math.pi for x in theta]
    v = values + values
    return t + [t[0] + 2 * math.pi], v + [v[0]]


def main():
    limits_csv, stretch_png, bending_png, name = sys.argv[1:5]
    rows = list(csv.DictReader(open(limits_csv)))

    def col(key):
        """Angles [rad] and values of the rows where the column has a value (a test may have been
        sampled at fewer directions than the other, or not at all: empty fields)."""
        kept = [r for r in rows if r.get(key, "") != ""]
        return [math.radians(float(r["theta_deg"])) for r in kept], [float(r[key]) for r in kept]

    if any(abs(v) > 0 for v in col("eps_stretch")[1]):
        fig = plt.figure(figsize=(5, 5))
        ax = fig.add_subplot(projection="polar")
        if col("travel_c")[1]:
            t, c = closed(*col("travel_c"))
            ax.plot(t, c, "o-", label="c (eq. 4.4.1)")
            ax.set_title(f"{name}: in-plane range of travel c")
        else:  # `Positive only`: the stretch limits were sampled, compression (and so c) was not
            t, e = closed(*col("eps_stretch"))
            ax.plot(t, e, "o-", label="stretch limit (Green strain)")
            ax.set_title(f"{name}: in-plane stretch limit (compression not sampled)")
        ax.legend(loc="lower right")
        fig.tight_layout()
        fig.savefig(stretch_png, dpi=120)
        plt.close(fig)

    if any(abs(v) > 0 for v in col("kappa_positive")[1]):
        fig, axes = plt.subplots(1, 2, figsize=(10, 5), subplot_kw={"projection": "polar"})
        for ax, (pos, neg, title) in zip(
            axes,
            [
                ("kappa_positive", "kappa_negative", "principal curvature limit [1/mm]"),
                ("kappa_o_at_positive", "kappa_o_at_negative", "orthogonal curvature reached [1/mm]"),
            ],
        ):
            for key, style, label in [(pos, "o-", "positive bending"), (neg, "s--", "negative bending")]:
                theta, values = col(key)
                if not values:
                    continue  # not sampled (`Positive only`)
                t, v = closed(theta, [abs(x) for x in values])
                ax.plot(t, v, style, label=label)
            ax.set_title(f"{name}: |{title}|", fontsize=10)
            ax.legend(loc="lower right", fontsize=8)
        fig.tight_layout()
        fig.savefig(bending_png, dpi=120)
        plt.close(fig)


if __name__ == "__main__":
    main()
