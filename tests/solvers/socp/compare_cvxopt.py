#!/usr/bin/env python3
"""Our interior-point cone QP solver against CVXOPT's coneqp (python3-cvxopt) on small random SOCPs
and small cloth projections: objectives to 1e-6 relative, solutions close, same status."""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from cvxopt import matrix, solvers, spmatrix


def read_problem(path):
    with open(path) as f:
        tokens = f.read().split()
    n, rows, ncones = int(tokens[0]), int(tokens[1]), int(tokens[2])
    pos = 3
    P = np.array(tokens[pos:pos + n], float); pos += n
    q = np.array(tokens[pos:pos + n], float); pos += n
    h = np.array(tokens[pos:pos + rows], float); pos += rows
    cones = [int(c) for c in tokens[pos:pos + ncones]]; pos += ncones
    nnz = int(tokens[pos]); pos += 1
    trip = np.array(tokens[pos:pos + 3 * nnz], float).reshape(-1, 3)
    return P, q, h, cones, trip


def write_problem(path, P, q, h, cones, trip):
    with open(path, "w") as f:
        f.write(f"{len(q)} {len(h)} {len(cones)}\n")
        for v in (P, q, h):
            f.write(" ".join(repr(float(x)) for x in v) + "\n")
        f.write(" ".join(str(c) for c in cones) + "\n")
        f.write(f"{len(trip)}\n")
        for r, c, v in trip:
            f.write(f"{int(r)} {int(c)} {float(v)!r}\n")


def random_problem(rng, n, m, d):
    P = rng.uniform(0.1, 2.0, n)
    q = rng.normal(size=n)
    x0 = rng.normal(size=n)
    trip, h = [], []
    for i in range(m):
        cols = rng.choice(n, 3, replace=False)
        G = rng.normal(size=(d, 3))
        s0 = rng.normal(size=d)
        s0[0] = np.linalg.norm(s0[1:]) + rng.uniform(0.1, 1.0)
        h.extend(G @ x0[cols] + s0)
        for r in range(d):
            for k, c in enumerate(cols):
                trip.append((i * d + r, c, G[r, k]))
    return P, q, np.array(h), [d] * m, np.array(trip)


def cvxopt_solve(P, q, h, cones, trip):
    n, rows = len(q), len(h)
    G = spmatrix(trip[:, 2].tolist(), trip[:, 0].astype(int).tolist(), trip[:, 1].astype(int).tolist(), (rows, n))
    Pm = spmatrix(P.tolist(), list(range(n)), list(range(n)), (n, n))
    solvers.options.update({"show_progress": False, "abstol": 1e-9, "reltol": 1e-9, "feastol": 1e-9,
                            "maxiters": 200})
    r = solvers.coneqp(Pm, matrix(q), G, matrix(h), dims={"l": 0, "q": cones, "s": []})
    x = np.array(r["x"]).ravel()
    return r["status"], 0.5 * x @ (P * x) + q @ x, x


def ours(tool, path, workdir):
    out = os.path.join(workdir, "solution.txt")
    subprocess.run([tool, "solve", path, out], check=True)
    lines = open(out).read().split()
    return lines[0], float(lines[2]), np.array(lines[3:], float)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--tool", required=True)
    args = parser.parse_args()
    rng = np.random.default_rng(11)
    failures, worst = 0, 0.0
    with tempfile.TemporaryDirectory() as workdir:
        cases = []
        for k in range(12):
            cases.append((f"random {k}", random_problem(rng, 20 + 5 * k, 15 + 3 * k, 3 + k % 3)))
        for n, limit, seed in ((4, 1.01, 1), (6, 1.05, 2), (8, 1.01, 3)):
            path = os.path.join(workdir, "cloth.txt")
            subprocess.run([args.tool, "cloth", str(n), str(limit), str(seed), path], check=True)
            cases.append((f"cloth {n}x{n} limit {limit}", read_problem(path)))
        for name, problem in cases:
            path = os.path.join(workdir, "problem.txt")
            write_problem(path, *problem)
            status_ref, obj_ref, x_ref = cvxopt_solve(*problem)
            status, obj, x = ours(args.tool, path, workdir)
            rel = abs(obj - obj_ref) / max(1.0, abs(obj_ref))
            dx = np.linalg.norm(x - x_ref) / max(1.0, np.linalg.norm(x_ref))
            worst = max(worst, rel)
            ok = status == "solved" and status_ref == "optimal" and rel <= 1e-6 and dx <= 1e-4
            failures += not ok
            print(f"{'ok ' if ok else 'BAD'} {name}: ours {status} {obj:.12g}, cvxopt {status_ref} {obj_ref:.12g}, "
                  f"objective difference {rel:.2e}, solution difference {dx:.2e}")
    print(f"largest relative objective difference {worst:.2e} over {len(cases)} problems")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
