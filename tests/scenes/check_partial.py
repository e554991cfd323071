#!/usr/bin/env python3
"""A solve that cannot finish: exit status 1, one error line naming the lambda reached, results kept
and marked partial, no NaN anywhere.

usage: check_partial.py --nlmech BIN --prm FILE --expect TEXT [--partial-file NAME] [--no-lambda]
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--expect", required=True)
    parser.add_argument("--partial-file", default="solution.vtu",
                        help="a result file the partial run must still write")
    parser.add_argument("--no-lambda", action="store_true", help="the solve has no load parameter to report")
    args = parser.parse_args()
    work = tempfile.mkdtemp(prefix="nlmech_partial_")
    try:
        out = os.path.join(work, "results")
        run = subprocess.run([args.nlmech, args.prm, "--output-directory", out], capture_output=True, text=True)
        print(run.stdout + run.stderr)
        errors = [line for line in run.stderr.splitlines() if line.startswith("nlmech: error:")]
        summary = {}
        if os.path.isfile(os.path.join(out, "summary.json")):
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
        # Text results (the VTU data are base64 and checked for finiteness when written).
        texts = ""
        for name in os.listdir(out) if os.path.isdir(out) else []:
            if name.endswith((".json", ".csv")):
                with open(os.path.join(out, name)) as f:
                    texts += f.read()
        checks = {
            "exit status 1": run.returncode == 1,
            "one error line": len(errors) == 1,
            f"message contains '{args.expect}'": args.expect in run.stderr,
            "message gives lambda": args.no_lambda or "lambda = " in run.stderr,
            "summary marked partial": summary.get("status") == "partial",
            f"partial result {args.partial_file} written": os.path.isfile(os.path.join(out, args.partial_file)),
            "no NaN in results": re.search(r"\b(nan|inf)\b", texts, re.IGNORECASE) is None,
        }
        for name, ok in checks.items():
            print(f"{'ok  ' if ok else 'FAIL'}: {name}")
        return 0 if all(checks.values()) else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
