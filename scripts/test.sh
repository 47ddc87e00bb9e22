#!/usr/bin/env bash
# The README's test command: install dependencies, build, run every C++ and Python test and a
# short fuzzing of every parser. One "[test] <stage>: N s" line per stage (where CI's time goes);
# the closing lines are CTest's and pytest's summaries.
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${VID_BUILD_DIR:-$ROOT/build}"
T0=$SECONDS
stage_done() { echo "[test] $1: $((SECONDS - T0)) s"; T0=$SECONDS; }
bash "$ROOT/scripts/setup.sh" || exit 1
stage_done "setup (apt, venv, estimator wheel)"
bash "$ROOT/scripts/build.sh" || exit 1
stage_done "build"
export VID_BUILD_DIR="$BUILD"
# Fuzz smoke (issue #26): build fuzz/ (io sources only, clang) and run each target
# VID_FUZZ_SECONDS; one line per target.
bash "$ROOT/fuzz/run.sh" --seconds "${VID_FUZZ_SECONDS:-15}" --build "${VID_FUZZ_BUILD_DIR:-$ROOT/build-fuzz}"
fuzz_rc=$?
stage_done "fuzz (build + smoke)"
ctest --test-dir "$BUILD" -j"${VID_JOBS:-2}" --output-on-failure --timeout 1200
ctest_rc=$?
stage_done "ctest"
# pytest-xdist, one worker per core; --dist loadfile keeps a module's tests (and the runs its
# fixtures cache) on one worker, so nothing is simulated twice (819 s -> 463 s on 2 cores).
"$ROOT/.venv/bin/python" -m pytest "$ROOT/tests/python" -q -p no:cacheprovider -n "${VID_JOBS:-2}" --dist loadfile
pytest_rc=$?
[[ $ctest_rc -eq 0 && $pytest_rc -eq 0 && $fuzz_rc -eq 0 ]]
