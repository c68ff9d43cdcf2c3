#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (ctest). With
# LMCFG_SANITIZE=1 the build uses AddressSanitizer and UBSan (in build-asan/).
#   --build-only  install and build, run no test (CI builds ahead in a lane
#                 of its own, then runs this script whole: docs/ci.md)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
test_step=1
case ${1:-} in
  "") ;;
  --build-only) test_step=0 ;;
  *) echo "test.sh: unknown option $1 (expected --build-only)" >&2; exit 2 ;;
esac
"$root/scripts/install-deps.sh"
# Debug information is most of the compile time at -O2 (docs/ci.md "Where
# the compile time goes"): the test builds carry line tables only, enough for
# a backtrace or a sanitizer report with file:line. LMCFG_DEBUG_INFO=-g for a
# build to step through in a debugger.
debug="${LMCFG_DEBUG_INFO:-}"
if [[ "${LMCFG_SANITIZE:-0}" == 1 ]]; then
  export LMCFG_BUILD_DIR="${LMCFG_BUILD_DIR:-$root/build-asan}"
  # No Python module: CPython would load it without the sanitizer runtime.
  sanitize=(-DLMCFG_SANITIZE=ON -DLMCFG_BUILD_BENCH=OFF -DLMCFG_PYTHON=OFF)
  if command -v clang++ >/dev/null; then
    # With clang the same build also holds the libFuzzer targets (LMCFG_FUZZ:
    # coverage instrumentation on top of ASan + UBSan), so scripts/fuzz.sh
    # runs them from this folder instead of compiling everything a third time
    # (docs/ci.md).
    export CC=clang CXX=clang++
    sanitize+=(-DLMCFG_FUZZ=ON)
    debug="${debug:--gline-tables-only}"
  fi
  debug="${debug:--g1}"
  build_args=("${sanitize[@]}")
else
  export LMCFG_BUILD_DIR="${LMCFG_BUILD_DIR:-$root/build}"
  debug="${debug:--g1}"
  build_args=()
fi
"$root/scripts/build.sh" "${build_args[@]}" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 $debug -DNDEBUG" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O2 $debug -DNDEBUG"
((test_step)) || exit 0
cd "$LMCFG_BUILD_DIR"
# install-deps.sh installed Chromium: the report pages' browser checks must run, not skip.
export LMCFG_REQUIRE_BROWSER=1
# ser2net and promtool too (Debian packages ser2net, prometheus): their checks must run.
export LMCFG_REQUIRE_PROMTOOL=1
export LMCFG_REQUIRE_SER2NET=1  # the RFC 2217 tests run against the real ser2net
# The golden-vector counts, printed for the record.
./tests/lmcfg_tests "[codec][golden]" | grep "seed003 golden"
exclude=()
if [[ "${LMCFG_SANITIZE:-0}" == 1 ]]; then
  # Checks of the sources' text and layering (a compile of their own, or
  # Python): they run no sanitized code, and the regular build ran them.
  exclude=(-E '^(layering_wrong_include_fails_to_build|public_api_headers_closed|test_map|unit_sizes|cli_docs_cover_every_subcommand)$')
  # The labels unit and e2e: every code path of ours, in-process and as the
  # lmcfg program. The external label's tests reach the same code through
  # programs the build does not make (Chromium, ser2net, promtool, git, node)
  # and ran in the regular build; under the sanitizers they would double the
  # phase's run time (docs/ci.md). LMCFG_SANITIZE_ALL=1 runs them too.
  if [[ "${LMCFG_SANITIZE_ALL:-0}" != 1 ]]; then
    exclude+=(-LE external)
    # The two statistical runs (tests/ops/test_reliability_soak.cpp,
    # tests/client/test_reliability_link.cpp) take a tenth of their cycles and
    # one fault sequence: the same code paths, which is what the sanitizers
    # check; the regular build ran them whole and checked their statistics.
    export LMCFG_SOAK_CYCLES="${LMCFG_SOAK_CYCLES:-100}" LMCFG_SEED="${LMCFG_SEED:-20261123}"
  fi
fi
ctest --output-on-failure -j"$(nproc)" --timeout 600 "${exclude[@]}"
