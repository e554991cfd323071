#!/usr/bin/env python3
"""Bad input: each case must end in one clear error line, a non-zero exit and no result files.

usage: bad_input.py --nlmech BIN --source-dir DIR CASE
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile

CANTILEVER = "set Scene type = cantilever\nsubsection Mesh study\n  set Element sizes = 0.1\nend\n"


def elastic(mesh, clamped="clamped"):
    return (f"set Scene type = elastic-statics\nsubsection Mesh\n  set Mesh file = {mesh}\nend\n"
            f"subsection Boundary conditions\n  set Clamped groups = {clamped}\nend\n")


def multi_target(case2):
    return ("set Scene type = inverse-design\nsubsection Material\n  set Young's modulus = 1e6\nend\n"
            "subsection Solver\n  set Multi-target design = true\nend\n"
            f"subsection Load case 2\n{case2}end\n")


def hbm(entries):
    return f"set Scene type = harmonic-balance\nsubsection Harmonic balance\n{entries}end\n"


def sheet(entries):
    return ("set Scene type = biphasic-sheet\nsubsection Sheet\n  set Resolution = 4\nend\n"
            "subsection Time stepping\n  set End time = 0.05\n  set Schemes = SAP\nend\n" + entries)


def dim(entries):
    return "set Scene type = dim-characterization\n" + entries


def cases(source):
    data = os.path.join(source, "tests", "data")
    return {
        "malformed-prm": (CANTILEVER + "subsection Material\n  sett Young's modulus 3\nend\n", "Line <6>"),
        "unknown-scene": ("set Scene type = warp-drive\n", "Unknown scene <warp-drive>. Registered scenes: biphasic-sheet, cantilever"),
        "no-scene": ("subsection Material\nend\n", "does not name a scene"),
        "unknown-parameter": (CANTILEVER + "subsection Material\n  set Colour = red\nend\n",
                              "No entry with name <Colour>"),
        "missing-mesh": (elastic("no/such/mesh.geo"), "does not exist"),
        "missing-group": (elastic(os.path.join(source, "meshes", "cantilever.geo"), "wall"),
                          "physical group <wall> does not exist"),
        "negative-youngs-modulus": (CANTILEVER + "subsection Material\n  set Young's modulus = -2e11\nend\n",
                                    "Young's modulus must be positive"),
        "incompressible-poisson": (CANTILEVER + "subsection Material\n  set Poisson's ratio = 0.5\nend\n",
                                   "Poisson's ratio must be below 0.5"),
        "inverted-element": (elastic(os.path.join(data, "inverted_tet.msh")), "has an inverted element 1"),
        "bad-number-list": (CANTILEVER.replace("0.1", "0.1, fine"), "<fine> is not a number"),
        "hbm-no-harmonics": (hbm("  set Harmonics = 0\n"), "Harmonics must be at least 1"),
        "hbm-too-few-samples": (hbm("  set Harmonics = 5\n  set Time samples = 8\n"), "at least 2 N_H + 1"),
        "hbm-negative-frequency": (hbm("  set Frequency range = -1, 2\n"), "two different positive frequencies"),
        "hbm-missing-driven-group": (hbm("") + "subsection Oscillator\n  set Model = shell\nend\n"
                                     "subsection Mesh\n  set Mesh file = " + os.path.join(source, "meshes", "fork.geo") +
                                     "\nend\nsubsection Structure\n  set Driven groups = clamp\nend\n",
                                     "physical group <clamp> does not exist"),
        "hbm-mechanism-missing-joint": (hbm("") + "subsection Oscillator\n  set Model = mechanism\nend\n"
                                        "subsection Mechanism\n  set Joints = 0, 0, 1; 1, 0, 1\n  set Links = 0, 5\n"
                                        "  set Driven joints = 0\nend\n", "A link joins a missing joint"),
        "hbm-rods-without-polylines": (hbm("") + "subsection Oscillator\n  set Model = rods\nend\n",
                                       "Rods: Polylines are needed"),
        "sheet-compression-limit": (sheet("subsection Strain limits\n  set Limit = 1 - 0.1 * cos(alpha)\nend\n"),
                                    "bounds compression"),
        "sheet-infeasible-pins": (sheet("subsection Sheet\n  set Pin offsets = 0, 0, 0; 0.2, 0, 0\nend\n"),
                                  "the pins are farther apart than the limits allow"),
        "sheet-bad-limit-formula": (sheet("subsection Strain limits\n  set Limit = 1 + sin(\nend\n"),
                                    "cannot parse the limit formula"),
        "sheet-bad-limit-sample": (sheet("subsection Strain limits\n  set Limit samples = 0:1.02; 90\nend\n"),
                                   "is not of the form angle:limit"),
        "dim-impossible-link": (dim("subsection Material\n  set Pattern = ring chain\n  subsection Ring chain\n"
                                    "    set Tube radius = 2.5\n  end\nend\n"), "needs R > 2 r for the rings to link"),
        "dim-overlapping-elements": (dim("subsection Material\n  subsection Threefold\n    set Spacing = 4.2\n"
                                         "  end\nend\n"), "overlap in the initial pattern"),
        "dim-not-interlocked": (dim("subsection Material\n  subsection Threefold\n    set Wave height = 0\n"
                                    "    set Spacing = 9.5\n  end\nend\n"), "links 0 neighbours instead of 6"),
        "dim-far-strain-out-of-range": (dim("subsection Sampling\n  set Far strain = 1.5\nend\n"),
                                        "Far strain"),
        "multi-target-topology": (multi_target(f"  set Target mesh = {os.path.join(data, 'inverted_tet.msh')}\n"),
                                  "not the main target's"),
        "multi-target-moved-support": (multi_target("  set Target displacement = 0.001; 0; 0\n"),
                                       "is not where the main target has it"),
        "multi-target-bad-expression": (multi_target("  set Target displacement = 0; 0; sin(\n"),
                                        "cannot parse the target displacement"),
    }


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech", required=True)
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("case")
    args = parser.parse_args()
    prm_text, expected = cases(args.source_dir)[args.case]
    work = tempfile.mkdtemp(prefix="nlmech_bad_")
    try:
        prm = os.path.join(work, "case.prm")
        with open(prm, "w") as f:
            f.write(prm_text)
        out = os.path.join(work, "results")
        run = subprocess.run([args.nlmech, prm, "--output-directory", out], capture_output=True, text=True, cwd=work)
        print(run.stdout + run.stderr)
        errors = [line for line in run.stderr.splitlines() if line.startswith("nlmech: error:")]
        checks = {
            "non-zero exit status": run.returncode != 0,
            "exactly one error line": len(errors) == 1 and len(run.stderr.strip().splitlines()) == 1,
            f"message contains '{expected}'": expected in run.stderr,
            "no stack dump": "Stacktrace" not in run.stderr and "--------" not in run.stderr,
            "no result files left": sorted(os.listdir(work)) == ["case.prm"],
        }
        for name, ok in checks.items():
            print(f"{'ok  ' if ok else 'FAIL'}: {name}")
        return 0 if all(checks.values()) else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
