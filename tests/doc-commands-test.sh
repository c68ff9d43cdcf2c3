#!/usr/bin/env bash
# Every `lmcfg` command the user documents show in their ```sh blocks runs, in
# the order shown, against a simulated drive (registered with ctest:
# tests/CMakeLists.txt). The drive is `lmcfg sim` on a real pseudo-terminal,
# the demo axis at the factory link (57600 Bd, MACID 11h, no checksum), which
# stands in for `/dev/ttyUSB0`; a ```toml block is the plant.toml the commands
# after it read. A command's exit code must be 0, or the one its comment
# states as "exit N". `lmcfg serve` runs until the `curl` its comment shows has
# answered 200 (on a free port: --listen 127.0.0.1:0), then gets SIGTERM and
# must exit 0. Lines that are not lmcfg commands (./scripts/..., cmake, sudo)
# are listed as not run; a ./scripts/ one must exist and be executable.
# README.md must also mark ./scripts/test.sh as the test command (CI runs it),
# and link every subcommand of `lmcfg --help` to an existing section of
# docs/cli.md.
#   tests/doc-commands-test.sh LMCFG_BINARY SOURCE_DIR DOC...   (DOC relative to SOURCE_DIR)
set -euo pipefail
lmcfg=$1 src=$2
shift 2
fail=0 ran=0
work="$(mktemp -d "${TMPDIR:-/tmp}/lmcfg-doc-commands.XXXXXX")"
sim_pid="" serve_pid=""
cleanup() {
  [[ -n "$serve_pid" ]] && kill "$serve_pid" 2>/dev/null
  [[ -n "$sim_pid" ]] && kill "$sim_pid" 2>/dev/null
  wait 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
say() { printf '%s\n' "$*"; }
bad() { say "FAIL: $*"; fail=1; }

# The README: the test command, and one line per subcommand linking docs/cli.md.
readme="$src/README.md"
grep -q '^\./scripts/test\.sh  *# THE TEST COMMAND' "$readme" || bad "README.md: no line './scripts/test.sh   # THE TEST COMMAND ...'"
anchors="$(grep '^#' "$src/docs/cli.md" | sed -e 's/^#* //' | tr 'A-Z' 'a-z' | sed -e 's/[^a-z0-9 -]//g' -e 's/ /-/g')"
section() { awk -v s="$1" '$0 == s {on=1; next} /^[^ ]/ {on=0} on && /^  [^ ]/ {print $1}'; }
for s in $("$lmcfg" --help | section "Subcommands:"); do
  line="$(grep -E "^- .*\[\`$s\`\]\(docs/cli\.md#" "$readme" || true)"
  [[ -n "$line" ]] || { bad "README.md: no line '- [\`$s\`](docs/cli.md#...)'"; continue; }
  for a in $(grep -oE "\[\`$s\`\]\(docs/cli\.md#[^)]*\)" <<<"$line" | sed -e 's/.*#//' -e 's/)$//'); do
    grep -qx -- "$a" <<<"$anchors" || bad "README.md: $s links to docs/cli.md#$a, which is no heading there"
  done
done

# The simulated drive on a pty.
cp "$src/tests/fixtures/sim/commissioned-axis.json" "$work/axis.sim.json"
cd "$work"
export XDG_STATE_HOME="$work/state"
: >sim.out
"$lmcfg" sim --state axis.sim.json >sim.out 2>sim.err </dev/null &
sim_pid=$!
for _ in $(seq 100); do (($(wc -l <sim.out) >= 2)) && break; sleep 0.1; done
pty="$(sed -n 1p sim.out)"
expected_options="link options: --port $pty --baud 57600 --id 0x11 --checksum none"
[[ "$(sed -n 2p sim.out)" == "$expected_options" ]] || { say "lmcfg sim did not start: $(cat sim.out sim.err)"; exit 1; }

run_serve() {  # run_serve COMMAND COMMENT
  local url path code
  # shellcheck disable=SC2086
  $1 --listen 127.0.0.1:0 >serve.out 2>serve.err </dev/null &
  serve_pid=$!
  for _ in $(seq 100); do [[ -s serve.out ]] && break; sleep 0.1; done
  url="$(head -1 serve.out)"
  [[ "$url" == http://127.0.0.1:* ]] || { bad "$1: printed no URL: $(cat serve.err)"; return; }
  path="$(grep -oE 'curl http://127\.0\.0\.1:8470[^ ]*' <<<"$2" | sed 's|curl http://127.0.0.1:8470||')"
  if [[ -n "$path" ]]; then
    code="$(curl -s -o curl.out -w '%{http_code}' "$url$path")"
    [[ "$code" == 200 ]] || bad "curl $url$path: HTTP $code: $(cat curl.out)"
    say "  curl $url$path: HTTP $code, $(wc -c <curl.out) bytes"
  fi
  kill -TERM "$serve_pid"
  local rc=0
  wait "$serve_pid" || rc=$?
  serve_pid=""
  ((rc == 0)) || bad "$1: exit $rc after SIGTERM (expected 0): $(tail -3 serve.err)"
}

for doc in "$@"; do
  say "== $doc"
  lang=""
  while IFS= read -r raw; do
    line="${raw#"${raw%%[! ]*}"}"  # without the indentation of a list item's block
    if [[ "$line" == '```'* ]]; then
      if [[ -n "$lang" ]]; then lang=""; else lang="${line#\`\`\`}"; [[ -n "$lang" ]] || lang=other; fi
      [[ "$lang" == toml ]] && : >plant.toml
      continue
    fi
    [[ -n "$lang" ]] || continue
    if [[ "$lang" == toml ]]; then
      printf '%s\n' "${line//\/dev\/ttyUSB0/$pty}" >>plant.toml
      continue
    fi
    [[ "$lang" == sh ]] || continue
    line="${line#\$ }"
    cmd="${line%%  #*}" comment=""
    [[ "$cmd" != "$line" ]] && comment="${line#*  #}"
    cmd="${cmd%"${cmd##*[! ]}"}"
    [[ -n "$cmd" && "$cmd" != '#'* ]] || continue
    if [[ "$cmd" != lmcfg\ * ]]; then
      if [[ "$cmd" == ./scripts/* ]]; then
        [[ -x "$src/${cmd%% *}" ]] || bad "$doc: ${cmd%% *} is not an executable script"
      fi
      say "  not run: $cmd"
      continue
    fi
    run="${cmd//\/dev\/ttyUSB0/$pty}"
    run="$lmcfg${run#lmcfg}"
    ran=$((ran + 1))
    if [[ "$cmd" == "lmcfg serve "* ]]; then
      say "  run (until SIGTERM): $cmd"
      run_serve "$run" "$comment"
      continue
    fi
    want=0
    [[ "$comment" =~ exit\ ([0-9]+) ]] && want=${BASH_REMATCH[1]}
    rc=0
    # shellcheck disable=SC2086
    $run >out.txt 2>err.txt </dev/null || rc=$?
    say "  exit $rc: $cmd"
    ((rc == want)) || bad "$doc: '$cmd' exited $rc, expected $want: $(tail -3 err.txt)"
  done <"$src/$doc"
done
((ran >= 8)) || bad "only $ran lmcfg commands found in $*"
((fail == 0)) && say "ran the $ran lmcfg commands of $* against the simulated drive"
exit $fail
