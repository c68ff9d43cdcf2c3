#!/usr/bin/env bash
# The whole story on two simulated drives: a commissioned axis (modified
# parameters in every layer, curves, command table) and a used spare with
# leftovers of another machine. Backup, diff against defaults, dry-run restore,
# restore onto the spare with verification, a diff of the two drives, and an
# HTML report of how the two drives differed before the restore.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# Only what the demo runs: the build dependencies, and `lmcfg` with its
# database (no tests, benchmarks, browser or packaging tools; docs/ci.md has
# the fresh-machine time). Its own build folder, so a developer's build/ keeps
# its configuration.
t0=$(date +%s)
"$root/scripts/install-deps.sh" --demo
t1=$(date +%s)
export LMCFG_BUILD_DIR="${LMCFG_DEMO_BUILD_DIR:-$root/build-demo}"
# -O1 and no debug information: the demo's steps run in about a second and
# never under a debugger, while -O2 and debug information are a good part of a
# fresh machine's compile time (docs/ci.md "Decisions that keep it within budget").
LMCFG_TARGETS=lmcfg_cli "$root/scripts/build.sh" -DLMCFG_BUILD_TESTS=OFF -DLMCFG_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -DNDEBUG" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -DNDEBUG"
t2=$(date +%s)
printf 'demo: dependencies %d s, build %d s\n' $((t1 - t0)) $((t2 - t1))
lmcfg="$LMCFG_BUILD_DIR/lmcfg"
work="$(mktemp -d "${TMPDIR:-/tmp}/lmcfg-demo.XXXXXX")"
cp "$root/tests/fixtures/sim/commissioned-axis.json" "$work/axis.sim.json"
cp "$root/tests/fixtures/sim/used-spare.json" "$work/spare.sim.json"
cd "$work"
step() { printf '\n\033[1m== %s\033[0m\n$ %s\n' "$1" "${*:2}"; "${@:2}"; }
set +e
step "1. Back up the commissioned axis (simulated drive, state in axis.sim.json)" \
  "$lmcfg" backup --port sim:axis.sim.json --label machine=demo --label axis=X -o axis.json
step "2. What differs from factory defaults?" "$lmcfg" diff defaults axis.json
"$lmcfg" backup --port sim:spare.sim.json -o spare-before.json --quiet  # the spare as delivered (step 7)
step "3. What would a restore onto the used spare do? (dry run: nothing is written)" \
  "$lmcfg" restore axis.json --port sim:spare.sim.json --dry-run
step "4. Restore onto the spare: plan, write, verify" \
  "$lmcfg" restore axis.json --port sim:spare.sim.json --trace restore.trace --yes
step "5. Read the spare back and compare the two drives (per-unit data ignored)" \
  "$lmcfg" backup --port sim:spare.sim.json -o spare.json --quiet
step "6. The two drives now hold the same configuration" \
  "$lmcfg" diff axis.json spare.json --ignore-unit --ignore-metadata
rc=$?
step "7. A page to look at: the commissioned axis vs the spare as it was delivered (curves plotted)" \
  "$lmcfg" report axis.json spare-before.json -o report.html
report_rc=$?
((report_rc == 0)) || rc=$report_rc
set -e
printf '\nFiles are in %s (restore.trace holds every telegram of step 4).\n' "$work"
printf 'Open the report in a browser: file://%s/report.html\n' "$work"
exit "$rc"
