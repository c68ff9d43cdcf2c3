# Sourced by the scripts that run lmcfg.exe under Wine (test-windows.sh,
# test-windows-net.sh, test-windows-serve.sh, test-windows-units.sh), after
# they set $root: the output folder, the Wine prefix and program, the check
# that what a run needs is there, and the frame of a script of checks.
out="${LMCFG_WINDOWS_DIR:-$root/build-windows}"
export WINEPREFIX="$out/wine" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
wine=/usr/lib/wine/wine64
[[ -x $wine ]] || wine="$(command -v wine64 || command -v wine || true)"

# wine_require NAME HINT FILE...: exits 2 naming the first missing file (or
# the Wine program) with HINT, or a missing prefix.
wine_require() {
  local name=$1 hint=$2 f
  shift 2
  for f in "$@" "$wine"; do
    [[ -n $f && -e $f ]] || {
      echo "$name: $f missing ($hint)" >&2
      exit 2
    }
  done
  [[ -f $WINEPREFIX/system.reg ]] || {
    echo "$name: no Wine prefix $WINEPREFIX (scripts/build-windows.sh makes it)" >&2
    exit 2
  }
}

# wine_checks TAG: the frame of a script of PASS/FAIL checks
# (test-windows-net.sh, test-windows-serve.sh): a scratch folder $work
# ($out/TAG.XXXXXX, made the current folder, the Linux build's state in it),
# the counters ok and bad add to (each line with the seconds since the
# check's $t0), $start_all, and $pids: background processes, killed when the
# script exits.
wine_checks() {
  work="$(mktemp -d "$out/$1.XXXXXX")"
  cd "$work" || exit 1
  export XDG_STATE_HOME="$work/linux-state"
  passed=0
  failed=0
  pids=()
  start_all=$(date +%s)
  trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done' EXIT
}
ok() { echo "PASS: $* ($(($(date +%s) - t0)) s)"; passed=$((passed + 1)); }
bad() { echo "FAIL: $* ($(($(date +%s) - t0)) s)"; failed=$((failed + 1)); }

# start_bg NAME SECONDS CMD...: CMD in the background (stdout in NAME.out,
# stderr in NAME.err), waiting up to SECONDS for its first line (a pty's
# path, a port, the service's URL), which `first NAME` prints. Not in a
# subshell: the PID goes to $pids. Exits 1 naming CMD when nothing came.
start_bg() {
  local name=$1 seconds=$2
  shift 2
  "$@" >"$name.out" 2>"$name.err" </dev/null &
  pids+=($!)
  for _ in $(seq $((seconds * 10))); do [[ -s $name.out ]] && break; sleep 0.1; done
  [[ -s $name.out ]] || {
    echo "$(basename "$0" .sh): $* did not start: $(cat "$name.err")" >&2
    exit 1
  }
  sleep 0.2 # the whole first line
}
first() { sed -n 1p "$1.out" | tr -d '\r'; } # lmcfg.exe's stdout has CRLF lines
