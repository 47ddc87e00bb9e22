# Preamble shared by the peer build scripts (openvins/build.sh, vidfusion/build.sh); sourced,
# not run:
#
#   source "$(dirname "${BASH_SOURCE[0]}")/../build_common.sh" "$@"
#
# Sets ROOT (the repository), BUILD (the first argument, default <repo>/build-peers; refused
# inside the source tree), JOBS (env, default 2) and NICE (env, default 19: other builds on the
# machine go first), and defines peers_arch_flags and peers_unpack (below).

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
BUILD="${1:-$ROOT/build-peers}"
JOBS="${JOBS:-2}"
NICE="${NICE:-19}"
case "$BUILD" in "$ROOT"/bench/*|"$ROOT"/vio_core/*|"$ROOT"/io/*) echo "build dir must not be in the source tree" >&2; exit 2;; esac

# peers_arch_flags ARCH: sets ARCH_FLAGS to -march=ARCH ("baseline": empty, no -march).
peers_arch_flags() {
  ARCH_FLAGS=""
  if [[ "$1" != baseline ]]; then ARCH_FLAGS="-march=$1"; fi
}

# peers_unpack TARBALL STAMP_PREFIX DIR_TO_CLEAR: unpacks TARBALL into $BUILD/src unless
# $BUILD/src/STAMP_PREFIX<first 16 hex of its sha256> exists; DIR_TO_CLEAR is removed first.
peers_unpack() {
  local tarball="$1" clear="$3" stamp
  stamp="$BUILD/src/$2$(sha256sum "$tarball" | cut -c1-16)"
  if [[ ! -f "$stamp" ]]; then
    echo "[peers] unpacking $tarball -> $BUILD/src"
    rm -rf "$clear"; mkdir -p "$BUILD/src"
    tar -xzf "$tarball" -C "$BUILD/src"
    touch "$stamp"
  fi
}
