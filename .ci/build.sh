#!/usr/bin/env bash
# Configures (once) and builds build/ in Release with ccache; quiet when up to date.
# Usage: .ci/build.sh [extra cmake -D options...]
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build="${SHAPEDIAMETER_BUILD_DIR:-$root/build}"
export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/shapediameter-ccache}"
# Paths relative to the checkout, so a fresh clone elsewhere (CI) hits the same cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
export CCACHE_NOHASHDIR=1

mkdir -p "$build"
if [[ ! -f "$build/CMakeCache.txt" || $# -gt 0 ]]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >"$build/configure.log" 2>&1 \
    || { cat "$build/configure.log" >&2; echo "error: CMake configure failed (log above)" >&2; exit 1; }
fi
cmake --build "$build" -j "${SHAPEDIAMETER_BUILD_JOBS:-2}" >"$build/build.log" 2>&1 \
  || { grep -B2 -A12 -m5 -E "error|Error" "$build/build.log" >&2 || tail -n 60 "$build/build.log" >&2
       echo "error: build failed (full log: $build/build.log)" >&2; exit 1; }
