#!/usr/bin/env bash
# Installs every dependency of VID-MSCKF on Debian 12 (run as root) and creates .venv.
# Idempotent: a second run checks, finds everything present, and changes nothing.
#   --peers   also install what the peer-estimator benchmarks need (bench/peers/: OpenVINS
#             needs Boost system/filesystem/thread/date_time). Not part of the default setup.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

PEERS=0
for arg in "$@"; do
  case "$arg" in
    --peers) PEERS=1 ;;
    -h|--help) sed -n '2,5p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) echo "[setup] unknown option: $arg (known: --peers)" >&2; exit 2 ;;
  esac
done

# clang + libclang-rt-14-dev (libFuzzer, sanitizer runtimes): the fuzz targets of fuzz/.
APT_PKGS=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libopencv-dev libceres-dev libsuitesparse-dev libyaml-cpp-dev
  liblcm-dev liblcm-bin libcli11-dev libspdlog-dev libfmt-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  python3 python3-venv python3-dev
  clang libclang-rt-14-dev
  ccache
)
# bench/peers/openvins (OpenVINS without ROS): Boost; only with --peers.
PEER_APT_PKGS=(
  libboost-system-dev libboost-filesystem-dev libboost-thread-dev libboost-date-time-dev
)
if ((PEERS)); then APT_PKGS+=("${PEER_APT_PKGS[@]}"); fi

missing=()
for p in "${APT_PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing apt packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "[setup] apt packages present"
fi

VENV="$ROOT/.venv"
PY=python3
if [[ ! -x "$VENV/bin/python" ]]; then
  echo "[setup] creating $VENV"
  # Prefer the distribution's python (matches python3-dev); fall back to PATH python3.
  if [[ -x /usr/bin/python3 ]]; then PY=/usr/bin/python3; fi
  "$PY" -m venv "$VENV"
fi
STAMP="$VENV/.vid_setup_stamp"
REQ_HASH="$(cat "$ROOT/eval/pyproject.toml" "$ROOT/scripts/setup.sh" | sha256sum | cut -d' ' -f1)"
if [[ ! -f "$STAMP" || "$(cat "$STAMP")" != "$REQ_HASH" ]]; then
  echo "[setup] installing python packages into .venv"
  "$VENV/bin/pip" install -q --upgrade pip
  # pybind11 for the Python bindings (python/): from pip, as Debian 12's 2.10 predates numpy 2's
  # C API (its arrays come out with zero strides under numpy 2).
  "$VENV/bin/pip" install -q -e "$ROOT/eval[test,batch,fuzz,view]" "pybind11>=2.12,<3"
  echo "$REQ_HASH" > "$STAMP"
else
  echo "[setup] python venv up to date"
fi

# The estimator's Python package (python/, pip + scikit-build-core): one wheel, built into
# build-py/ (incremental on a second run) and installed into .venv, so that
# `.venv/bin/python -c "import vid_msckf"` works; tests/python/test_wheel_estimator.py installs
# the same wheel into a fresh venv outside the checkout. Its C++ compiles go through the
# checkout's ccache (cmake/ccache.cmake), which scripts/build.sh shares. Built in pip's isolated
# build environment, as a user's `pip install ./python` is: .venv's own packages (the lcm wheel
# ships a CMake package) must not stand in for the Debian ones.
WHEEL_DIR="${VID_WHEEL_DIR:-$ROOT/build-py}"  # one level below the root, as build/ (ccache)
mkdir -p "$WHEEL_DIR"
echo "[setup] building the vid_msckf wheel in $WHEEL_DIR (first time: the C++ libraries, minutes)"
rm -f "$WHEEL_DIR"/dist/vid_msckf-*.whl
# CXX: the compiler scripts/build.sh's CMake picks (c++); pip's build would take Python's
# (x86_64-linux-gnu-g++, the same g++), and ccache keys on the compiler's name: 74 of 75 wheel
# compiles hit build/'s objects with it, 6 without.
if ! CXX="${CXX:-c++}" CMAKE_BUILD_PARALLEL_LEVEL="${VID_JOBS:-2}" "$VENV/bin/pip" wheel -q --no-deps \
    -w "$WHEEL_DIR/dist" -C build-dir="$WHEEL_DIR" "$ROOT/python" >"$WHEEL_DIR/pip-wheel.log" 2>&1; then
  tail -n 30 "$WHEEL_DIR/pip-wheel.log" >&2
  echo "[setup] error: building the vid_msckf wheel failed (whole log: $WHEEL_DIR/pip-wheel.log)" >&2
  exit 1
fi
"$VENV/bin/pip" install -q --no-deps --force-reinstall "$WHEEL_DIR"/dist/vid_msckf-*.whl
echo "[setup] installed $(basename "$WHEEL_DIR"/dist/vid_msckf-*.whl) into .venv"
echo "[setup] done"
