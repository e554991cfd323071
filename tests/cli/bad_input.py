#!/usr/bin/env python3
"""Bad input: each case must end in one clear error line, a non-zero exit and no result files.

usage: bad_input.py --nlmech BIN --source-dir DIR CASE
       bad_input.py --source-dir DIR --list      the case names, one per line
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


def design(entries, structure=""):
    """A small Duffing run (or `structure`) with subsection Design `entries`."""
    return (hbm("  set Harmonics = 3\n  set Frequency range = 0.5, 1.5\n") + structure +
            "subsection Design\n  set Mode = optimize\n  set Initial curve = false\n" + entries + "end\n")


def sheet(entries):
    return ("set Scene type = biphasic-sheet\nsubsection Sheet\n  set Resolution = 4\nend\n"
            "subsection Time stepping\n  set End time = 0.05\n  set Schemes = SAP\nend\n" + entries)


def dim(entries):
    return "set Scene type = dim-characterization\n" + entries


# Malformed meshes, written next to the parameter file and named in it relative to it.
BAD_MESHES = {
    "garbage-msh": ("garbage.msh", "%$#@ this is not a mesh\n", "syntax error"),
    "truncated-msh": ("truncated.msh", None, "Could not read"),
    "bad-geo": ("broken.geo", "Point(1) = {0, 0, 0;\nLine(2 = {1, 2};\n", "syntax error"),
}


def truncated_msh(source):
    """The first half of a valid gmsh 4.1 mesh of the unit cube: elements cut off mid-section."""
    path = os.path.join(source, "tests", "data", "unit_cube.msh")
    with open(path) as f:
        text = f.read()
    return text[: len(text) // 2]


def mesh_scenes(mesh):
    """Every scene that reads a gmsh file, pointed at `mesh`."""
    return {
        "cantilever": "set Scene type = cantilever\nsubsection Mesh\n  set Mesh file = " + mesh + "\nend\n",
        "elastic-statics": elastic(mesh),
        "manufactured": "set Scene type = manufactured-solution\nsubsection Mesh\n  set Mesh file = " + mesh +
                        "\nend\n",
        "hyperelastic-statics": "set Scene type = hyperelastic-statics\nsubsection Mesh\n  set Mesh file = " + mesh +
                                "\nend\n",
        "inverse-design": "set Scene type = inverse-design\nsubsection Mesh\n  set Mesh file = " + mesh + "\nend\n",
        "hbm-shell": hbm("") + "subsection Oscillator\n  set Model = shell\nend\nsubsection Mesh\n"
                     "  set Mesh file = " + mesh + "\nend\n",
        "dim-mesh-element": dim("subsection Material\n  set Pattern = mesh element\n  subsection Mesh element\n"
                                "    set Mesh file = " + mesh + "\n  end\nend\n"),
    }


def mesh_cases(source):
    out = {}
    for kind, (name, text, gmsh_says) in BAD_MESHES.items():
        content = truncated_msh(source) if text is None else text
        for scene, prm in mesh_scenes(name).items():
            out[f"{scene}-{kind}"] = (prm, [f"gmsh could not read", f"<{name}>", gmsh_says], {name: content})
    return out


def cases(source):
    # A two-link leg with one spring between its links, its body shaken (for mechanism parameters).
    leg = ("subsection Oscillator\n  set Model = mechanism\nend\nsubsection Mechanism\n"
           "  set Joints = 0, 0, 0.01; -0.06, 0, 0.01; 0.03, -0.12, 0.03\n  set Links = 0, 1; 0, 2\n"
           "  set Springs = 0, 1, 0, 1, 0.5, 0, 50, -1\n  set Driven joints = 0, 1\n  set Tracked joint = 2\nend\nsubsection Structure\n  set Tracked direction = x\nend\n")
    data = os.path.join(source, "tests", "data")
    return mesh_cases(source) | {
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
        "hbm-design-unknown-kind": (design("  set Parameters = spring at 0, 0, 0 = 1 in 0, 2\n  set Frequencies = 1\n"),
                                    "unknown kind <spring>"),
        "hbm-design-inverted-bounds": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 1, 0.5\n"
                                              "  set Frequencies = 1\n"), "the bounds are inverted"),
        "hbm-design-unreadable-parameter": (design("  set Parameters = mass = heavy\n  set Frequencies = 1\n"),
                                            "cannot read the parameter"),
        "hbm-design-no-frequencies": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n"),
                                      "give the driving Frequencies"),
        "hbm-design-point-outside": (design("  set Parameters = mass at 5, 5, 5 = 0 in 0, 1\n  set Frequencies = 60\n",
                                            "subsection Oscillator\n  set Model = shell\nend\nsubsection Mesh\n"
                                            "  set Mesh file = " + os.path.join(source, "meshes", "fork.geo") + "\nend\n"),
                                     "outside the model"),
        "hbm-design-malformed-target": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n  set Frequencies = 1\n"
                                               "  set Objective = trajectory\n  set Target trajectory = target.csv\n"),
                                        "malformed value <abc>", {"target.csv": "t,x\n0,1\n0.1,abc\n"}),
        "hbm-design-short-target": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n  set Frequencies = 1\n"
                                           "  set Objective = trajectory\n  set Target trajectory = target.csv\n"),
                                    "needs at least 2 N_H + 1", {"target.csv": "t,x\n0,1\n0.1,2\n0.2,1\n"}),
        "hbm-design-spring-without-mechanism": (design("  set Parameters = spring stiffness 0 = 10 in 1, 20\n"
                                                       "  set Frequencies = 1\n"),
                                                "spring parameters need a mechanism"),
        "hbm-design-bad-spring-key": (design("  set Parameters = spring attachment 0 u_c = 0.5 in 0, 1\n"
                                             "  set Frequencies = 20\n", leg), "u_a, w_a, u_b or w_b"),
        "hbm-design-missing-spring": (design("  set Parameters = spring stiffness 3 = 50 in 10, 90\n"
                                             "  set Frequencies = 20\n", leg), "no spring 3"),
        "hbm-design-missing-link": (design("  set Parameters = link length 7 = 0.1 in 0.05, 0.2\n"
                                           "  set Frequencies = 20\n", leg), "no link 7"),
        "hbm-design-link-length-zero-bound": (design("  set Parameters = link length 0 = 0.06 in 0, 0.2\n"
                                                     "  set Frequencies = 20\n", leg), "lower bound must be positive"),
        "hbm-design-peak-without-window": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n"
                                                  "  set Frequencies = 1\n  set Objective = peak amplitude\n"),
                                           "needs Peak window = LOW, HIGH"),
        "hbm-design-peak-outside-window": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n"
                                                  "  set Frequencies = 3\n  set Objective = peak amplitude\n"
                                                  "  set Peak window = 0.5, 2\n"), "lies outside the Peak window"),
        "hbm-design-peak-without-target": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n"
                                                  "  set Frequencies = 1\n  set Objective = peak frequency\n"
                                                  "  set Peak window = 0.5, 2\n"), "needs a positive Target frequency"),
        "hbm-design-no-peak-in-window": (design("  set Parameters = mass at 0, 0, 0 = 0.1 in 0, 1\n"
                                                "  set Frequencies = 0.6\n  set Objective = peak frequency\n"
                                                "  set Peak window = 0.5, 0.7\n  set Target frequency = 0.6\n"),
                                         "no resonance peak in"),
        "hbm-rods-without-polylines": (hbm("") + "subsection Oscillator\n  set Model = rods\nend\n",
                                       "Rods: Polylines are needed"),
        "sheet-compression-limit": (sheet("subsection Strain limits\n  set Limit = 1 - 0.1 * cos(alpha)\nend\n"),
                                    "bounds compression"),
        "sheet-infeasible-pins": (sheet("subsection Sheet\n  set Pin offsets = 0, 0, 0; 0.2, 0, 0\nend\n"),
                                  "the pins are farther apart than the limits allow"),
        "sheet-bad-limit-formula": (sheet("subsection Strain limits\n  set Limit = 1 + sin(\nend\n"),
                                    "cannot parse the limit formula"),
        "sheet-limit-dips-between-samples": (sheet("subsection Strain limits\n  set Limit = 1.01 - 0.05*cos(8*alpha)\nend\n"),
                                             ["is below 1", "checked on 3600 directions"]),
        "sheet-pins-beyond-the-curve": (sheet("subsection Sheet\n  set Pin offsets = 0, 0, 0; 0.025, 0, 0\nend\n"),
                                        ["the pins are farther apart than the limits allow", "1.05 times"]),
        "sheet-bad-limit-sample": (sheet("subsection Strain limits\n  set Limit samples = 0:1.02; 90\nend\n"),
                                   "is not of the form angle:limit"),
        "dim-impossible-link": (dim("subsection Material\n  set Pattern = ring chain\n  subsection Ring chain\n"
                                    "    set Tube radius = 2.5\n  end\nend\n"), "needs R > 2 r for the rings to link"),
        "dim-ring-chain-no-spacing": (dim("subsection Material\n  set Pattern = ring chain\n  subsection Ring chain\n"
                                          "    set Ring radius = 4\n    set Tube radius = 1.5\n  end\nend\n"),
                                      ["no spacing does, which needs R > 3 r", "R + r = 5.5", "2 (R - r) = 5"]),
        "dim-overlapping-elements": (dim("subsection Material\n  subsection Threefold\n    set Spacing = 4.2\n"
                                         "  end\nend\n"), "overlap in the initial pattern"),
        "dim-not-interlocked": (dim("subsection Material\n  subsection Threefold\n    set Wave height = 0\n"
                                    "    set Spacing = 9.5\n  end\nend\n"), "links 0 neighbours instead of 6"),
        "dim-nan-element": (dim("subsection Material\n  set Pattern = mesh element\n  subsection Mesh element\n"
                                "    set Mesh file = " + os.path.join(source, "meshes", "dim-torus.geo") + "\n"
                                "    set Elements = 0, 0, 0, 0, 0, 0; nan, 0, 0, 0, 0, 0\n  end\nend\n"),
                            "is not finite"),
        "dim-far-strain-out-of-range": (dim("subsection Sampling\n  set Far strain = 1.5\nend\n"),
                                        "Far strain"),
        "inverse-lm-no-initial-guess": ("set Scene type = inverse-design\nsubsection Solver\n"
                                        "  set Methods = anm, levenberg-marquardt\n"
                                        "  set Levenberg-Marquardt initial guesses =\nend\n",
                                        "initial guesses\" is empty"),
        "multi-target-topology": (multi_target(f"  set Target mesh = {os.path.join(data, 'inverted_tet.msh')}\n"),
                                  "not the main target's"),
        "multi-target-moved-support": (multi_target("  set Target displacement = 0.001; 0; 0\n"),
                                       "is not where the main target has it"),
        "multi-target-bad-expression": (multi_target("  set Target displacement = 0; 0; sin(\n"),
                                        "cannot parse the target displacement"),
    }


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--nlmech")
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--validate", action="store_true", help="check `nlmech --validate` refuses it too")
    parser.add_argument("case", nargs="?")
    args = parser.parse_args()
    if args.list:
        print("\n".join(cases(args.source_dir)))
        return 0
    case = cases(args.source_dir)[args.case]
    prm_text, expected = case[0], case[1]
    expected = [expected] if isinstance(expected, str) else expected
    inputs = case[2] if len(case) > 2 else {}
    work = tempfile.mkdtemp(prefix="nlmech_bad_")
    try:
        prm = os.path.join(work, "case.prm")
        with open(prm, "w") as f:
            f.write(prm_text)
        for name, content in inputs.items():
            with open(os.path.join(work, name), "w") as f:
                f.write(content)
        out = os.path.join(work, "results")
        command = [args.nlmech, "--validate", prm] if args.validate else [args.nlmech, prm, "--output-directory", out]
        run = subprocess.run(command, capture_output=True, text=True, cwd=work)
        print(run.stdout + run.stderr)
        errors = [line for line in run.stderr.splitlines() if line.startswith("nlmech: error:")]
        checks = {
            "non-zero exit status": run.returncode != 0,
            "exactly one error line": len(errors) == 1 and len(run.stderr.strip().splitlines()) == 1,
            **{f"message contains '{e}'": e in run.stderr for e in expected},
            "no stack dump": "Stacktrace" not in run.stderr and "--------" not in run.stderr,
            "no result files left": sorted(os.listdir(work)) == sorted(["case.prm", *inputs]),
        }
        for name, ok in checks.items():
            print(f"{'ok  ' if ok else 'FAIL'}: {name}")
        return 0 if all(checks.values()) else 1
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
