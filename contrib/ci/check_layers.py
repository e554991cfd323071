#!/usr/bin/env python3
"""Layers look down: base -> mesh -> models -> solvers -> dim -> scenes -> app.

Every #include <nlmech/LAYER/...> in include/nlmech/X/ and source/X/ must name a layer at or below
X. Prints each include that points up a layer (file:line, what it includes) and exits 1 if any.

usage: check_layers.py [SOURCE_DIR]   (default: the checkout this script is in)
"""
import os
import re
import sys

LAYERS = ["base", "mesh", "models", "solvers", "dim", "scenes", "app"]
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]nlmech/([a-z_]+)/')


def layer_of(path, root):
    rel = os.path.relpath(path, root).split(os.sep)
    if rel[0] == "include" and len(rel) > 2 and rel[1] == "nlmech":
        return rel[2]
    if rel[0] == "source" and len(rel) > 1:
        return rel[1]
    return None


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))))
    violations = checked = 0
    for top in ("include", "source"):
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".h", ".cc")):
                    continue
                path = os.path.join(folder, name)
                layer = layer_of(path, root)
                if layer not in LAYERS:
                    continue
                checked += 1
                with open(path, encoding="utf-8") as f:
                    for number, line in enumerate(f, 1):
                        m = INCLUDE.match(line)
                        if m and m.group(1) in LAYERS and LAYERS.index(m.group(1)) > LAYERS.index(layer):
                            violations += 1
                            print(f"{os.path.relpath(path, root)}:{number}: {layer} includes "
                                  f"{m.group(1)} ({line.strip()})")
    print(f"{checked} files, {violations} includes pointing up a layer "
          f"({' -> '.join(LAYERS)})")
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main())
