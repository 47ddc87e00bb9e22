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
  "$VENV/bin/pip" install -q -e "$ROOT/eval[test,batch,fuzz]" "pybind11>=2.12,<3"
  echo "$REQ_HASH" > "$STAMP"
else
  echo "[setup] python venv up to date"
fi
echo "[setup] done"
