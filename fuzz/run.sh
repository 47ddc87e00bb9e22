#!/usr/bin/env bash
# Build the libFuzzer targets (clang, ASan+UBSan) and run every fuzz target for N seconds,
# one after the other; one result line per target. Exit 1 if any target crashed (its input is
# kept in BUILD/crashes/TARGET/), 2 on a usage error. See fuzz/README.md.
#   --seconds N    per target (default 600)
#   --build DIR    build and work folder (default build-fuzz/ at the repo root)
#   --only T,T     run only these targets (csv dataset yaml lcm py_loaders py_bag)
#   --no-build     reuse the built targets
set -uo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SECONDS_PER=600
BUILD="$ROOT/build-fuzz"
ONLY="csv,dataset,yaml,lcm,py_loaders,py_bag"
DO_BUILD=1
usage() { echo "fuzz/run.sh: error: $1 (see fuzz/run.sh --help)" >&2; exit 2; }
while (($#)); do
  case "$1" in
    --seconds) [[ $# -ge 2 && "$2" =~ ^[0-9]+$ && "$2" -gt 0 ]] || usage "--seconds needs a positive integer"
               SECONDS_PER="$2"; shift 2 ;;
    --build) [[ $# -ge 2 ]] || usage "--build needs a folder"; BUILD="$(realpath -m "$2")"; shift 2 ;;
    --only) [[ $# -ge 2 ]] || usage "--only needs target names"; ONLY="$2"; shift 2 ;;
    --no-build) DO_BUILD=0; shift ;;
    -h|--help) sed -n '2,9p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) usage "unknown option '$1'" ;;
  esac
done
IFS=',' read -ra TARGETS <<< "$ONLY"
for t in "${TARGETS[@]}"; do
  [[ " csv dataset yaml lcm py_loaders py_bag " == *" $t "* ]] || usage "unknown target '$t'"
done
PY="${VID_PYTHON:-$ROOT/.venv/bin/python}"

if [[ "$ONLY" == *py_* ]] && ! "$PY" -c "import atheris" 2>/dev/null; then
  echo "fuzz/run.sh: $PY has no atheris (bash scripts/setup.sh installs it)" >&2; exit 1
fi
if ((DO_BUILD)); then
  # Only the io sources and the targets (fuzz/CMakeLists.txt), not the whole project.
  mkdir -p "$BUILD"
  { CC=clang CXX=clang++ cmake -S "$ROOT/fuzz" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE= &&
    cmake --build "$BUILD" -j"${VID_JOBS:-2}"; } >"$BUILD/build.log" 2>&1 \
    || { tail -30 "$BUILD/build.log" >&2; echo "fuzz/run.sh: build failed (log $BUILD/build.log)" >&2; exit 1; }
  # The crash inputs found so far must pass under the sanitizers before fuzzing goes on.
  "$BUILD/fuzz_regressions" --gtest_brief=1 >"$BUILD/regressions.log" 2>&1 \
    || { cat "$BUILD/regressions.log" >&2; echo "fuzz/run.sh: regression tests failed" >&2; exit 1; }
fi

# Scratch files of the targets (tmpfs when there is one); atheris exits without cleaning up.
SCRATCH="$(mktemp -d "$( [[ -d /dev/shm ]] && echo /dev/shm || echo "${TMPDIR:-/tmp}")/vid_fuzz.XXXXXX")"
trap 'rm -rf "$SCRATCH"' EXIT
export VID_FUZZ_SCRATCH="$SCRATCH"

failed=0
for t in "${TARGETS[@]}"; do
  corpus="$BUILD/corpus/$t" crashes="$BUILD/crashes/$t" log="$BUILD/logs/$t.log"
  mkdir -p "$corpus" "$crashes" "$(dirname "$log")"
  seeds="$ROOT/fuzz/corpus/$t"
  dict=()
  [[ -f "$ROOT/fuzz/dict/$t.dict" ]] && dict=(-dict="$ROOT/fuzz/dict/$t.dict")
  # The first folder collects new inputs; the committed seeds are read only.
  flags=(-max_total_time="$SECONDS_PER" -timeout=20 -print_final_stats=1 -artifact_prefix="$crashes/"
         "${dict[@]}" "$corpus" "$seeds")
  if [[ "$t" == py_* ]]; then
    # atheris: Python allocates more; the limit still catches runaway memory.
    "$PY" "$ROOT/fuzz/py/${t#py_}_fuzz.py" -rss_limit_mb=4096 "${flags[@]}" >"$log" 2>&1
  else
    "$BUILD/fuzz_$t" -rss_limit_mb=2048 "${flags[@]}" >"$log" 2>&1
  fi
  rc=$?
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$')
  last=$(grep -E '^#[0-9]+.*(cov|ft):' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' <<<"$last" | grep -o '[0-9]*')
  ft=$(grep -o 'ft: [0-9]*' <<<"$last" | grep -o '[0-9]*')
  rate=$(grep -o 'exec/s: [0-9]*' <<<"$last" | grep -o '[0-9]*')
  crashed=0
  if ((rc != 0)); then crashed=1; failed=1; fi
  printf '%-11s seconds=%s executions=%s exec/s=%s coverage=%s features=%s crashes=%d%s\n' "$t" "$SECONDS_PER" \
    "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "$crashed" \
    "$( ((crashed)) && echo " (log $log, inputs in $crashes/)")"
done
exit "$failed"
