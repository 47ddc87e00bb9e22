#!/usr/bin/env bash
# Install the build tree into a prefix, build tests/consumer against it with find_package, and
# run it on a 5 s simulated sequence written by the installed vid_sim. Usage: check.sh BUILD_DIR
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
BUILD="$(cd "$1" && pwd)"
WORK="$BUILD/consumer"
rm -rf "$WORK" && mkdir -p "$WORK"
cmake --install "$BUILD" --prefix "$WORK/prefix" > "$WORK/install.log"
cmake -S "$HERE" -B "$WORK/build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$WORK/prefix" \
  > "$WORK/configure.log"
cmake --build "$WORK/build" -j2 > "$WORK/build.log"
CONFIG="$WORK/prefix/share/vid_msckf/config/sim"
"$WORK/prefix/bin/vid_sim" --scenario "$CONFIG/vid17_like_short.yaml" --out "$WORK/seq" --seed 3 --duration 5 \
  --features-only --quiet
"$WORK/build/vid_consumer" "$WORK/seq" "$CONFIG" | tee "$WORK/consumer.log"
