#!/usr/bin/env bash
# README command 1: set up, build, and run the main demo scene (a gmsh cantilever under an end load
# with a mesh-refinement study). Results land in results/cantilever/.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/contrib/setup/build.sh"
cd "$here"
"$here/build/nlmech" prm/cantilever.prm
echo "Results: $here/results/cantilever (summary.json, mesh_study.png, solution.pvd, ...)"
