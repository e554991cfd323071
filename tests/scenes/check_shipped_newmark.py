#!/usr/bin/env python3
"""The shipped harmonic-balance parameter files skip what a user does not need: the Newmark check
(time integration to the periodic steady state, often dearer than the whole frequency response) is
off unless the model is a small oscillator, and every file says so beside the subsection, with how
to turn it on or off.

usage: check_shipped_newmark.py PRM_DIR
"""
import os
import re
import sys

# Models whose Newmark check costs well under the frequency response (a few unknowns).
CHEAP = {"duffing", "two-spring-mass"}


def entry(text, name):
    m = re.search(r"^\s*set\s+" + re.escape(name) + r"\s*=([^#\n]*)", text, re.M)
    return m.group(1).strip() if m else None


def main():
    folder = sys.argv[1]
    failures = checked = 0
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".prm"):
            continue
        text = open(os.path.join(folder, name)).read()
        if entry(text, "Scene type") != "harmonic-balance":
            continue
        checked += 1
        kind = entry(text, "Model kind") or entry(text, "Model") or "?"
        block = re.search(r"((?:^#.*\n)*)^subsection Newmark check\n(.*?)^end", text, re.M | re.S)
        if block is None:
            print(f"ok  : {name}: no Newmark check (off by default)")
            continue
        comment, body = block.group(1), block.group(2)
        frequencies = entry(body, "Frequencies") or ""
        on = bool(frequencies)
        problems = []
        if on and kind not in CHEAP:
            problems.append(f"the Newmark check is on ({frequencies}) for a '{kind}' model")
        if "Newmark check" not in comment or "Frequencies" not in comment:
            problems.append("no comment above `subsection Newmark check` saying whether it runs, what it "
                            "costs and how to change `Frequencies`")
        failures += bool(problems)
        state = "on" if on else "off"
        print(f"{'FAIL' if problems else 'ok  '}: {name} ({kind}): Newmark check {state}"
              + ("; " + "; ".join(problems) if problems else ""))
    if checked == 0:
        print("FAIL: no harmonic-balance parameter file found in", folder)
        return 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
