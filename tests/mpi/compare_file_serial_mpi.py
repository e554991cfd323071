#!/usr/bin/env python3
"""Runs a scene serially and under `mpirun -np 2` and compares one numeric result file.

usage: compare_file_serial_mpi.py --nlmech BIN --prm FILE --file NAME [--tolerance 1e-10]
NAME is a .msh (the node coordinates), a .csv (every numeric column) or summary.json (the figures
named by --figure, repeatable). Passes when max |np2 - np1| / max |np1| <= tolerance over them and
the two ranks shared the element loops (summary.json: element_sharing_ranks = 2).
"""
import argparse
import csv
import json
import os
import shutil
import sys
import tempfile

from serial_and_np2 import run_serial_and_np2


def values(path, figures):
    if path.endswith(".msh"):
        with open(path) as f:
            lines = f.read().split("\n")
        start = lines.index("$Nodes")
        count = int(lines[start + 1])
        return [float(v) for line in lines[start + 2:start + 2 + count] for v in line.split()[1:]]
    if path.endswith(".json"):
        with open(path) as f:
            summary = json.load(f)
        out = []
        for name in figures:
            entry = summary
            for key in name.split("."):
                entry = entry[key]
            out.append(float(entry["value"] if isinstance(entry, dict) else entry))
        return out
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    out = []
    for row in rows[1:]:
        for v in row:
            try:
                out.append(float(v))
            except ValueError:
                pass
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--file", required=True)
    parser.add_argument("--figure", action="append", default=[])
    parser.add_argument("--tolerance", type=float, default=1e-10)
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_mpi_")
    try:
        folders = run_serial_and_np2(args.nlmech, args.prm, work)
        if folders is None:
            return 1
        serial = values(os.path.join(folders[1], args.file), args.figure)
        parallel = values(os.path.join(folders[2], args.file), args.figure)
        if len(serial) != len(parallel) or not serial:
            print(f"FAIL: {len(serial)} values serially, {len(parallel)} on 2 ranks")
            return 1
        scale = max(abs(v) for v in serial) or 1.0
        difference = max(abs(a - b) for a, b in zip(serial, parallel))
        relative = difference / scale
        print(f"{args.file}: {len(serial)} values, max |np1| = {scale:.6g}, max |np2 - np1| = {difference:.3g}, "
              f"relative {relative:.3g} (tolerance {args.tolerance:g})")
        with open(os.path.join(folders[2], "summary.json")) as f:
            shared = json.load(f).get("element_sharing_ranks", 1)
        print(f"element loops shared by {shared} rank(s) under mpirun -np 2")
        ok = relative <= args.tolerance and shared == 2
        print("ok" if ok else "FAIL")
        return 0 if ok else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
