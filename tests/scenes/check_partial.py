#!/usr/bin/env python3
"""A solve that cannot finish: exit status 1, one error line naming the lambda reached, results kept
and marked partial, no NaN anywhere.

usage: check_partial.py --nlmech BIN --prm FILE --expect TEXT [--partial-file NAME] [--no-lambda]
                        [--status partial|check_failed] [--expect-json KEY=VALUE ...]
With --status check_failed the run finished but one of its own verifications failed: the same
checks, with "failed_checks" listed in summary.json.
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
    parser.add_argument("--status", default="partial", choices=["partial", "check_failed"])
    parser.add_argument("--expect-in-file", action="append", default=[],
                        help="NAME:TEXT: the result file NAME contains TEXT")
    parser.add_argument("--expect-json", action="append", default=[],
                        help="KEY=VALUE: a summary.json entry (a.b inside objects) with this value; "
                             "KEY>=VALUE: a number at least this")
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
            f"summary marked {args.status}": summary.get("status") == args.status,
            "failed checks listed": args.status != "check_failed" or len(summary.get("failed_checks", [])) >= 1,
            f"partial result {args.partial_file} written": os.path.isfile(os.path.join(out, args.partial_file)),
            "no NaN in results": re.search(r"\b(nan|inf)\b", texts, re.IGNORECASE) is None,
        }
        for item in args.expect_in_file:
            name, text = item.split(":", 1)
            path = os.path.join(out, name)
            content = open(path).read() if os.path.isfile(path) else ""
            checks[f"{name} contains '{text}'"] = text in content
        for item in args.expect_json:
            at_least = ">=" in item
            key, value = item.split(">=" if at_least else "=", 1)
            entry = summary
            for part in key.split("."):
                entry = entry.get(part, {}) if isinstance(entry, dict) else {}
            entry = entry.get("value", entry) if isinstance(entry, dict) else entry
            if at_least:
                checks[f"summary {key} >= {value}"] = isinstance(entry, (int, float)) and entry >= float(value)
            else:
                checks[f"summary {key} == {value}"] = str(entry).lower() == value.lower()
        for name, ok in checks.items():
            print(f"{'ok  ' if ok else 'FAIL'}: {name}")
        return 0 if all(checks.values()) else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
