#!/usr/bin/env bash
# Configures and builds into build/ (or $LMCFG_BUILD_DIR). Extra arguments go to cmake;
# $LMCFG_TARGETS names the targets to build (default: all).
# Uses ccache when it is installed (scripts/install-deps.sh installs it): a
# rebuild of unchanged files, in any build folder of any checkout below the
# same parent, is a cache hit.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${LMCFG_BUILD_DIR:-$root/build}"
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  # Paths below the checkout's parent are hashed relative to it; the tests'
  # precompiled header needs the sloppiness (ccache manual, "Precompiled headers").
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(dirname "$root")}"
  export CCACHE_SLOPPINESS="${CCACHE_SLOPPINESS:-pch_defines,time_macros,include_file_mtime,include_file_ctime}"
fi
# The project's own builds treat warnings as errors (LMCFG_WERROR; off by default for users).
# $LMCFG_TEST_UNITY_BATCH_SIZE: test files per unity batch (tests/CMakeLists.txt).
batch=()
[[ -n ${LMCFG_TEST_UNITY_BATCH_SIZE:-} ]] && batch=(-DLMCFG_TEST_UNITY_BATCH_SIZE="$LMCFG_TEST_UNITY_BATCH_SIZE")
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${LMCFG_BUILD_TYPE:-RelWithDebInfo}" -DLMCFG_WERROR=ON \
  "${launcher[@]}" "${batch[@]}" "$@" >/dev/null
# LMCFG_TARGETS: build only these targets (default: all).
targets=()
for t in ${LMCFG_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$build" -j"$(nproc)" "${targets[@]}"
