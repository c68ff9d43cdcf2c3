#!/usr/bin/env bash
# Build the libFuzzer targets with clang in build-fuzz/ and run each for N
# seconds (default 60) on a corpus kept in build-fuzz/corpus/<target>/, seeded
# from the test fixtures. Fails when a target crashes; the crashing input is
# copied to tests/fixtures/fuzz-regressions/<target>/ so the regular test suite
# (tests/config/test_reliability_regressions.cpp) replays it from then on.
#   scripts/fuzz.sh [SECONDS] [TARGET...]
# With LMCFG_FUZZ_RUNS=N each target instead runs N inputs from the fixed seed
# LMCFG_FUZZ_SEED (default 1), SECONDS then being only a cap: the same commit
# explores the same inputs on every machine, so a failure is reproducible and
# belongs to the change that brought it. CI runs that way; run without it
# (a random seed, as long as you like) to look for new crashes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
secs="${1:-60}"
shift || true
targets=("$@")
if [[ ${#targets[@]} -eq 0 ]]; then targets=(decoder json_config xml_config client http upload); fi
build="${LMCFG_FUZZ_BUILD:-$root/build-fuzz}"
jobs="${LMCFG_JOBS:-2}"

if [[ -f "$build/CMakeCache.txt" ]] && grep -q '^LMCFG_FUZZ:BOOL=ON' "$build/CMakeCache.txt"; then
  # A build that already has the fuzz targets (LMCFG_FUZZ_BUILD=build-asan:
  # the sanitizer build of scripts/test.sh with clang): only build them there.
  :
else
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -DLMCFG_FUZZ=ON -DLMCFG_WERROR=ON -DLMCFG_BUILD_TESTS=OFF \
    -DLMCFG_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build "$build" -j"$jobs" --target $(printf 'fuzz_%s ' "${targets[@]}")

seed() {  # seed corpus per target from the fixtures
  local t=$1 dir=$2
  mkdir -p "$dir"
  case "$t" in
    json_config) find "$root/tests/fixtures/config" -name '*.json' -exec cp -n {} "$dir/" \; ;;
    xml_config) find "$root/tests/fixtures/config" -name '*.xml' -exec cp -n {} "$dir/" \; ;;
    decoder) [[ -e "$dir/seed-read-rom" ]] || printf '\x00\x07\x01\x11\x0a\x02\x50\x00\x00\xa2\x13\x09\x00\x00\x00\x04' >"$dir/seed-read-rom" ;;
    client) [[ -e "$dir/seed-read-rom" ]] || printf '\x00\x00\x01\x11\x0a\x02\x50\x00\x00\xa2\x13\x09\x00\x00\x00\x04' >"$dir/seed-read-rom" ;;
    http) find "$root/tests/fixtures/fuzz-http" -type f -exec cp -n {} "$dir/" \; ;;
    upload) find "$root/tests/fixtures/fuzz-upload" -type f -exec cp -n {} "$dir/" \; ;;
  esac
  if [[ -d "$root/tests/fixtures/fuzz-regressions/$t" ]]; then
    find "$root/tests/fixtures/fuzz-regressions/$t" -type f ! -name '*.md' -exec cp -n {} "$dir/" \;
  fi
}

# Each target is one process on one core: $jobs of them at a time, each with
# its own log; the results are printed in the targets' order.
run_one() {  # run_one TARGET: its exit status into fuzz_TARGET.rc (0: no crash)
  local t=$1 corpus="$build/corpus/$1" artifacts="$build/artifacts/$1" rc=0
  local budget=(-max_total_time="$secs")
  if [[ -n "${LMCFG_FUZZ_RUNS:-}" ]]; then
    budget+=(-runs="$LMCFG_FUZZ_RUNS" -seed="${LMCFG_FUZZ_SEED:-1}")
  fi
  "$build/fuzz/fuzz_$t" "${budget[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" 2>"$build/fuzz_$t.log" || rc=$?
  echo "$rc" >"$build/fuzz_$t.rc"
}
for t in "${targets[@]}"; do
  seed "$t" "$build/corpus/$t"
  mkdir -p "$build/artifacts/$t"
  echo "== fuzz_$t for ${secs}s (corpus $build/corpus/$t)"
  [[ -n "${LMCFG_FUZZ_RUNS:-}" ]] &&
    echo "   ${LMCFG_FUZZ_RUNS} runs from seed ${LMCFG_FUZZ_SEED:-1}, at most ${secs}s"
  rm -f "$build/fuzz_$t.rc"
  while (($(jobs -rp | wc -l) >= jobs)); do sleep 1; done
  run_one "$t" &
done
wait
status=0
for t in "${targets[@]}"; do
  artifacts="$build/artifacts/$t"
  if [[ $(cat "$build/fuzz_$t.rc" 2>/dev/null) != 0 ]]; then
    status=1
    echo "fuzz_$t FAILED; see $build/fuzz_$t.log" >&2
    tail -40 "$build/fuzz_$t.log" >&2
    mkdir -p "$root/tests/fixtures/fuzz-regressions/$t"
    for f in "$artifacts"/crash-* "$artifacts"/leak-* "$artifacts"/timeout-* "$artifacts"/oom-*; do
      [[ -e "$f" ]] || continue
      cp -n "$f" "$root/tests/fixtures/fuzz-regressions/$t/"
      echo "  saved $(basename "$f") to tests/fixtures/fuzz-regressions/$t/" >&2
    done
  else
    grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$build/fuzz_$t.log" | sed "s/^/  fuzz_$t /" || true
  fi
done
exit $status
