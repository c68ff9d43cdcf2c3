#!/usr/bin/env bash
# Configures and builds into build/ (or $LMCFG_BUILD_DIR). Extra arguments go to cmake.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${LMCFG_BUILD_DIR:-$root/build}"
# The project's own builds treat warnings as errors (LMCFG_WERROR; off by default for users).
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${LMCFG_BUILD_TYPE:-RelWithDebInfo}" -DLMCFG_WERROR=ON "$@" >/dev/null
cmake --build "$build" -j"$(nproc)"
