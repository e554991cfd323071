#!/usr/bin/env bash
# README command 2: set up, build, and run the test suite with ctest.
# Default tier: labels quick and mpi. NLMECH_TEST_TIER=all adds the slow tests.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/contrib/setup/build.sh"
cd "${NLMECH_BUILD_DIR:-$here/build}"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
if [ "${NLMECH_TEST_TIER:-default}" = all ]; then
  ctest --output-on-failure -j 2
else
  ctest --output-on-failure -j 2 -L 'quick|mpi'
fi
