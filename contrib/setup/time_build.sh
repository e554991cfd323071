#!/usr/bin/env bash
# Times a clean build of every target (no ccache) and each translation unit, the figures of
# docs/architecture.md "Build time": total wall time and the ten slowest units.
#   bash contrib/setup/time_build.sh [build-dir]      (default /tmp/nlmech-time-build)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-/tmp/nlmech-time-build}"
bash "$here/contrib/setup/install-deps.sh"
rm -rf "$build"
mkdir -p "$build"
log="$build/unit-times.txt"
: > "$log"
# The launcher runs the compiler and appends "<seconds> <source>" for every unit.
cat > "$build/timed-compile.sh" <<'LAUNCHER'
#!/usr/bin/env bash
start=$(date +%s.%N)
"$@"
rc=$?
end=$(date +%s.%N)
src="?"
for a in "$@"; do case "$a" in *.cc|*.cpp|*.cxx) src="$a";; esac; done
echo "$(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }') $src" >> "$(dirname "$0")/unit-times.txt"
exit $rc
LAUNCHER
chmod +x "$build/timed-compile.sh"
generator=()
if command -v ninja > /dev/null; then generator=(-G Ninja); fi # as contrib/setup/build.sh
cmake -S "$here" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER="$build/timed-compile.sh" \
  > "$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; exit 1; }
start=$(date +%s)
cmake --build "$build" -j "$(nproc)" > "$build/build.log" 2>&1 || { tail -30 "$build/build.log" >&2; exit 1; }
end=$(date +%s)
echo "clean build of every target with -j$(nproc): $((end - start)) s wall, $(awk '{s += $1} END {printf "%.0f", s}' "$log") s of compilation in $(wc -l < "$log") units"
echo "slowest units [s]:"
sort -rn "$log" | head -10 | sed "s|$here/||"
