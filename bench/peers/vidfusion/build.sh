#!/usr/bin/env bash
# Builds VID-Fusion (commit 25c6771, GPL-3; VINS-Mono based) from the shared tarball, without
# ROS, and our vidfusion_driver against it. Nothing of VID-Fusion enters the source tree: the
# tarball is unpacked into the build tree and its files are compiled as they are; ROS is
# replaced by our shim (bench/peers/vidfusion/shim, GPL-3.0-or-later).
#
#   bench/peers/vidfusion/build.sh [BUILD_DIR]     (default: <repo>/build-peers)
#
# Env: VF_TARBALL (default <repo>/../shared/peers/VID-Fusion-25c6771.tar.gz), JOBS (default 2),
#      NICE (default 19), VF_ARCH (default x86-64-v3, the level the project builds at,
#      cmake/arch_flags.cmake; "baseline" = no -march).
# Needs: bash scripts/setup.sh --peers (Boost), plus the project's default deps (Eigen, OpenCV,
# Ceres, yaml-cpp).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../build_common.sh" "$@"  # ROOT BUILD JOBS NICE
TARBALL="${VF_TARBALL:-$ROOT/../shared/peers/VID-Fusion-25c6771.tar.gz}"
ARCH="${VF_ARCH:-x86-64-v3}"

peers_arch_flags "$ARCH"
# -faligned-new: C++14; with AVX, the Eigen members of their classes (IntegrationBase, ...)
# need 32-byte aligned operator new (C++17 does it by default).
CXXFLAGS_ALL="$ARCH_FLAGS -faligned-new -Wno-deprecated-declarations"

SRC="$BUILD/src/VID-Fusion"
peers_unpack "$TARBALL" .vidfusion_unpacked_ "$SRC"

# Release -O3 (their vid_estimator CMake asks for -O3 in Release), -g0: no debug info (compile
# time and memory only on this shared machine).
echo "[peers] configuring VID-Fusion + vidfusion_driver ($CXXFLAGS_ALL)"
cmake -S "$ROOT/bench/peers/vidfusion" -B "$BUILD/vidfusion" -DCMAKE_BUILD_TYPE=Release \
  -DVF_SRC="$SRC" -DCMAKE_CXX_FLAGS="$CXXFLAGS_ALL" -DCMAKE_CXX_FLAGS_RELEASE="-O3 -DNDEBUG -g0" \
  -DCMAKE_RUNTIME_OUTPUT_DIRECTORY="$BUILD/bin" -Wno-dev > "$BUILD/vidfusion.configure.log"
echo "[peers] building (nice $NICE, -j$JOBS)"
nice -n "$NICE" cmake --build "$BUILD/vidfusion" -j "$JOBS"
echo "[peers] done: $BUILD/bin/vidfusion_driver"
