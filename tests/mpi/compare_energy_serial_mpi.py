#!/usr/bin/env python3
"""Runs a biphasic-sheet scene serially and under `mpirun -np 2` (schemes spread over the ranks) and
compares energy.csv row by row.

usage: compare_energy_serial_mpi.py --nlmech BIN --prm FILE [--tolerance 1e-10]
Passes when both runs have the same (scheme, step) rows and every energy and violation column agrees
to `tolerance` relative to that column's largest magnitude (timings are not compared).
"""
import argparse
import csv
import os
import shutil
import sys
import tempfile

from serial_and_np2 import run_serial_and_np2

COMPARED = ["time", "kinetic", "elastic", "gravity", "contact", "total", "violation", "projection_iterations"]


def read(path):
    with open(path, newline="") as f:
        return {(row["scheme"], int(row["step"])): row for row in csv.DictReader(f)}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--tolerance", type=float, default=1e-10)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_mpi_energy_")
    try:
        rows = {}
        folders = run_serial_and_np2(args.nlmech, args.prm, work)
        if folders is None:
            return 1
        for ranks, out in folders.items():
            rows[ranks] = read(os.path.join(out, "energy.csv"))
        serial, parallel = rows[1], rows[2]
        if serial.keys() != parallel.keys():
            print(f"FAIL: {len(serial)} rows serially, {len(parallel)} under MPI, or different schemes/steps")
            return 1
        schemes = sorted({k[0] for k in serial})
        worst = 0.0
        for column in COMPARED:
            scale = max(1e-300, max(abs(float(r[column])) for r in serial.values()))
            diff = max(abs(float(serial[k][column]) - float(parallel[k][column])) for k in serial)
            print(f"{column}: max difference {diff:.3e} (relative {diff / scale:.3e})")
            worst = max(worst, diff / scale)
        print(f"{len(serial)} rows, schemes {', '.join(schemes)}: largest relative difference {worst:.3e}")
        if worst > args.tolerance:
            print(f"FAIL: above the tolerance {args.tolerance}")
            return 1
        print("PASS")
        return 0
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
