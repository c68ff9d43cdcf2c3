# Sourced by the scripts that run lmcfg.exe under Wine (test-windows.sh,
# test-windows-net.sh, test-windows-units.sh), after they set $root: the
# output folder, the Wine prefix and program, and the check that what a run
# needs is there.
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
