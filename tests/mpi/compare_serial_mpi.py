#!/usr/bin/env python3
"""Runs a scene serially and under `mpirun -np 2` and compares vertex_displacements.csv.

usage: compare_serial_mpi.py --nlmech BIN --prm FILE [--tolerance 1e-8]
Passes when the vertex positions coincide and max|u_mpi - u_serial| / max|u_serial| <= tolerance.
"""
import argparse
import csv
import os
import shutil
import sys
import tempfile

from serial_and_np2 import run_serial_and_np2


def read(path):
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        return header, [list(map(float, row)) for row in reader]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--tolerance", type=float, default=1e-8)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_mpi_")
    try:
        results = {}
        folders = run_serial_and_np2(args.nlmech, args.prm, work)
        if folders is None:
            return 1
        for ranks, out in folders.items():
            results[ranks] = read(os.path.join(out, "vertex_displacements.csv"))
        header, serial = results[1]
        _, parallel = results[2]
        dim = len(header) // 2
        if len(serial) != len(parallel):
            print(f"FAIL: {len(serial)} vertices serially, {len(parallel)} under MPI")
            return 1
        position = max(abs(a - b) for s, p in zip(serial, parallel) for a, b in zip(s[:dim], p[:dim]))
        scale = max(abs(v) for s in serial for v in s[dim:])
        difference = max(abs(a - b) for s, p in zip(serial, parallel) for a, b in zip(s[dim:], p[dim:]))
        relative = difference / scale
        print(f"vertices: {len(serial)}, max |u| = {scale:.6g} m, max |u_np2 - u_np1| = {difference:.3g} m, "
              f"relative {relative:.3g} (tolerance {args.tolerance:g}), position mismatch {position:.3g}")
        ok = position == 0.0 and relative <= args.tolerance
        print("ok" if ok else "FAIL")
        return 0 if ok else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
