#!/usr/bin/env bash
# Installs the Debian (bookworm) packages nlmech needs, only those that are missing.
# Safe to run repeatedly; needs root (or sudo) the first time.
set -euo pipefail
packages=(
  cmake make ninja-build lld g++ ccache pkg-config libgtest-dev clang-format
  libdeal.ii-dev        # deal.II 9.4: brings Trilinos 13.2, SUNDIALS, METIS, p4est, UMFPACK, MPI
  libgmsh-dev gmsh      # gmsh C++ API for meshing .geo sources
  libeigen3-dev libfftw3-dev libsuitesparse-dev
  libcgal-dev           # CGAL: strain-space boundary meshes (convex hull, AABB tree, inside tests)
  nlohmann-json3-dev    # nlohmann::json: summary.json
  libarpack2-dev        # ARPACK: Hill's eigenproblem (implicitly restarted Arnoldi)
  libceres-dev          # Ceres: the Levenberg-Marquardt baseline of the inverse-design comparison
  libopenblas0-serial   # optimised BLAS/LAPACK behind UMFPACK/CHOLMOD (serial: one thread per MPI rank)
  openmpi-bin
  libnlopt-cxx-dev      # NLopt: bound-constrained L-BFGS of harmonic-balance design
  coinor-libipopt-dev   # Ipopt: the general nonlinear-programming baseline of the strain-limiting benchmark
  python3 python3-matplotlib python3-numpy
  python3-cvxopt        # reference conic solver for the SOCP tests
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "nlmech setup: installing missing Debian packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" > /tmp/nlmech-apt.log 2>&1 || {
  echo "nlmech setup: apt-get install failed; see /tmp/nlmech-apt.log" >&2
  tail -20 /tmp/nlmech-apt.log >&2
  exit 1
}
