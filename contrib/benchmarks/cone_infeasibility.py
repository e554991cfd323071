#!/usr/bin/env python3
"""Near-infeasible cone problems, ours beside CVXOPT on the same problems in one run.

The problem: |x| <= 1 and |x - (2 + g)| <= 1 (two 2D second-order cones), min x^2 / 2, infeasible
by the gap g. Ours (build/contrib/benchmarks/cone_infeasibility: automatic = direct method, the
homogeneous self-dual embedding as fallback; embedded = the embedding alone) against CVXOPT's
coneqp (the QP as posed) and conelp (the LP with P dropped: CVXOPT detects infeasibility in
conelp only). Prints status and iterations per gap.

usage: cone_infeasibility.py --ours BUILD/contrib/benchmarks/cone_infeasibility
"""
import argparse
import csv
import io
import subprocess
import sys


def cvxopt_rows(gaps):
    try:
        from cvxopt import matrix, solvers
    except ImportError:
        return {g: ("(no cvxopt)", "", "(no cvxopt)", "") for g in gaps}
    solvers.options["show_progress"] = False
    rows = {}
    for g in gaps:
        G = matrix([0.0, -1.0, 0.0, -1.0], (4, 1))
        h = matrix([1.0, 0.0, 1.0, -(2.0 + g)])
        dims = {"l": 0, "q": [2, 2], "s": []}
        out = []
        for kind in ("coneqp", "conelp"):
            try:
                if kind == "coneqp":
                    r = solvers.coneqp(matrix([[1.0]]), matrix([0.0]), G, h, dims)
                else:
                    r = solvers.conelp(matrix([0.0]), G, h, dims)
                out += [r["status"], str(r["iterations"])]
            except Exception as e:  # CVXOPT raises for some near-infeasible QPs
                out += [f"raised: {e}", ""]
        rows[g] = tuple(out)
    return rows


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--ours", required=True)
    args = parser.parse_args()
    ours = list(csv.DictReader(io.StringIO(subprocess.run([args.ours], capture_output=True, text=True,
                                                           check=True).stdout)))
    gaps = sorted({float(r["gap"]) for r in ours}, reverse=True)
    theirs = cvxopt_rows(gaps)
    print("| gap | ours, automatic | its | ours, embedding alone | its | CVXOPT coneqp | its | "
          "CVXOPT conelp (P dropped) | its |")
    print("|---|---|---|---|---|---|---|---|---|")
    for g in gaps:
        a = next(r for r in ours if float(r["gap"]) == g and r["method"] == "automatic")
        e = next(r for r in ours if float(r["gap"]) == g and r["method"] == "embedded")
        q_status, q_its, l_status, l_its = theirs[g]
        print(f"| {g:.0e} | {a['status']} | {a['iterations']} | {e['status']} | {e['iterations']} | "
              f"{q_status} | {q_its} | {l_status} | {l_its} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
