#!/usr/bin/env bash
# The unit tests cross-built for Windows (scripts/build-windows.sh --tests),
# run under Wine: every test file but those tests/CMakeLists.txt lists in
# LMCFG_TESTS_NOT_ON_WINDOWS (each with its reason), and without the test
# cases tagged [git-cli]: they check the archive with the git program through
# the shell (serve_rig.hpp git()), which a Windows program under Wine cannot
# run (scripts/test-windows-serve.sh runs git fsck on what lmcfg.exe wrote).
# docs/windows.md.
#   scripts/test-windows-units.sh [LMCFG_TESTS_EXE [CATCH ARGS...]]
# Default: build-windows/build/tests/lmcfg_tests.exe. Prints the failed test
# cases, "N passed, M failed" (test cases) and the duration; exit 1 on a failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exe="$(realpath "${1:-$root/build-windows/build/tests/lmcfg_tests.exe}")"
shift || true
(($# > 0)) || set -- "~[git-cli]"
source "$root/scripts/wine-env.sh"
wine_require test-windows-units "scripts/build-windows.sh --tests, install-deps.sh --windows" "$exe"
work="$(mktemp -d "$out/units.XXXXXX")"
# The tests find the sources and the database by their Linux paths, which
# Wine reaches through drive Z: from a working directory on it.
cd "$root/build-windows/build"
export XDG_STATE_HOME="$work/state" TMP="$work" TEMP="$work"
t0=$(date +%s)
timeout "${LMCFG_WINE_TIMEOUT:-3600}" "$wine" "$exe" --use-colour no "$@" >"$work/units.crlf" 2>&1
rc=$?
tr -d '\r' <"$work/units.crlf" >"$work/units.log" # a Windows program's lines end in CRLF
secs=$(($(date +%s) - t0))
# Catch2's console reporter: a failed case is a block whose header (between
# two lines of dashes) names it and whose body says FAILED.
awk 'length($0) == 79 && /^-+$/ { if (++d % 2 == 1) { getline name; head = name } next }
     /FAILED:|due to unexpected exception|due to a fatal error condition/ { if (head != "" && !(head in seen)) { seen[head] = 1; print "FAIL: " head } }' \
  "$work/units.log"
summary="$(grep -E '^(test cases:|All tests passed)' "$work/units.log" | tail -1)"
echo "test-windows-units: $work/units.log"
if [[ -z $summary ]]; then
  echo "FAIL: lmcfg_tests.exe ended without a summary (exit $rc after $secs s): $(tail -5 "$work/units.log")"
  exit 1
fi
cases="$(grep -oE '[0-9]+ test cases?' <<<"$summary" | grep -oE '^[0-9]+' || true)"
passed="$(grep -oE '[0-9]+ passed' <<<"$summary" | grep -oE '^[0-9]+' || true)"
failed="$(grep -oE '[0-9]+ failed' <<<"$summary" | grep -oE '^[0-9]+' || true)"
if [[ $summary == "All tests passed"* ]]; then
  passed="$(grep -oE '\(([0-9]+) assertions? in ([0-9]+) test cases?\)' <<<"$summary" | grep -oE '[0-9]+ test' | grep -oE '^[0-9]+')"
  failed=0
fi
echo "$summary"
echo "${passed:-0} passed, ${failed:-0} failed (test cases${cases:+ of $cases}), $secs s under Wine (exit $rc)"
((rc == 0))
