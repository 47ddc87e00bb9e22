#!/usr/bin/env bash
# Configure (Ninja if present, Release) and build into build/ with 2 jobs.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${VID_BUILD_DIR:-$ROOT/build}"
GEN=()
if command -v ninja >/dev/null 2>&1; then GEN=(-G Ninja); fi
if [[ ! -f "$BUILD/CMakeCache.txt" ]]; then
  cmake -S "$ROOT" -B "$BUILD" "${GEN[@]}" -DCMAKE_BUILD_TYPE="${VID_BUILD_TYPE:-Release}"
fi
cmake --build "$BUILD" -j"${VID_JOBS:-2}"
