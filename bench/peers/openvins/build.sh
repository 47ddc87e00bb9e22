#!/usr/bin/env bash
# Builds OpenVINS (commit 6948812, GPL-3) from the shared tarball, without ROS, and our
# ov_driver against it. Nothing of OpenVINS enters the source tree: the tarball is unpacked into
# the build tree and compiled as it is.
#
#   bench/peers/openvins/build.sh [BUILD_DIR]     (default: <repo>/build-peers)
#
# Env: OV_TARBALL (default <repo>/../shared/peers/open_vins-6948812.tar.gz), JOBS (default 2),
#      NICE (default 19: other builds on the machine go first), OV_ARCH (default x86-64-v3, the
#      level the project itself builds at, cmake/arch_flags.cmake; "baseline" = no -march).
# Needs: bash scripts/setup.sh --peers (Boost), plus the project's default deps (Eigen, OpenCV
# with contrib/aruco, Ceres, yaml-cpp).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../build_common.sh" "$@"  # ROOT BUILD JOBS NICE
TARBALL="${OV_TARBALL:-$ROOT/../shared/peers/open_vins-6948812.tar.gz}"
ARCH="${OV_ARCH:-x86-64-v3}"

peers_arch_flags "$ARCH"
# -faligned-new: OpenVINS is C++14; with AVX, Eigen members need 32-byte aligned operator new
# in std::make_shared (C++17 does it by default, C++14 needs the flag).
CXXFLAGS_ALL="$ARCH_FLAGS -faligned-new"

SRC="$BUILD/src/open_vins"
peers_unpack "$TARBALL" .unpacked_ "$BUILD/src"

# -g0 in the Release flags (which come after its own "-g3" on the command line): no debug info,
# which only cuts compile time and memory on this shared machine; code generation is the same.
# ov_msckf's CMake builds ov_core + ov_init + ov_msckf into one libov_msckf_lib when neither
# catkin nor ament is found (cmake/ROS1.cmake, "BUILDING WITHOUT ROS!"). ENABLE_ROS=OFF makes
# that explicit even on a machine with ROS.
echo "[peers] configuring OpenVINS ($CXXFLAGS_ALL)"
cmake -S "$SRC/ov_msckf" -B "$BUILD/ov_msckf" -DCMAKE_BUILD_TYPE=Release -DENABLE_ROS=OFF \
  -DCMAKE_CXX_FLAGS="$CXXFLAGS_ALL" -DCMAKE_CXX_FLAGS_RELEASE="-O3 -DNDEBUG -g0" \
  -Wno-dev > "$BUILD/ov_msckf.configure.log"
echo "[peers] building libov_msckf_lib (nice $NICE, -j$JOBS)"
nice -n "$NICE" cmake --build "$BUILD/ov_msckf" --target ov_msckf_lib -j "$JOBS"

echo "[peers] building ov_driver"
cmake -S "$ROOT/bench/peers/openvins" -B "$BUILD/driver" -DCMAKE_BUILD_TYPE=Release \
  -DOV_SRC="$SRC" -DOV_LIB_DIR="$BUILD/ov_msckf" -DCMAKE_CXX_FLAGS="$CXXFLAGS_ALL" \
  -DCMAKE_RUNTIME_OUTPUT_DIRECTORY="$BUILD/bin" > "$BUILD/driver.configure.log"
nice -n "$NICE" cmake --build "$BUILD/driver" -j "$JOBS"
echo "[peers] done: $BUILD/bin/ov_driver"
