#!/usr/bin/env bash
# End to end: lmcfg.exe under Wine against simulated drives served by the
# Linux build (`lmcfg sim` on pseudo-terminals), through Wine's COM port
# mapping ($WINEPREFIX/dosdevices/com7 -> /dev/pts/N). docs/windows.md.
#   scripts/test-windows.sh [LINUX_LMCFG [LMCFG_EXE]]
# Defaults: build/lmcfg and build-windows/build/lmcfg.exe (scripts/build.sh,
# scripts/build-windows.sh). Prints "N passed, M failed"; exit 1 on a failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lmcfg="$(realpath "${1:-$root/build/lmcfg}")"
exe="$(realpath "${2:-$root/build-windows/build/lmcfg.exe}")"
out="${LMCFG_WINDOWS_DIR:-$root/build-windows}"
export WINEPREFIX="$out/wine" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
wine=/usr/lib/wine/wine64
[[ -x $wine ]] || wine="$(command -v wine64 || command -v wine || true)"
for f in "$lmcfg" "$exe" "$wine"; do
  [[ -n $f && -e $f ]] || {
    echo "test-windows: $f missing (scripts/build.sh, scripts/build-windows.sh, install-deps.sh --windows)" >&2
    exit 2
  }
done
[[ -f $WINEPREFIX/system.reg ]] || { echo "test-windows: no Wine prefix $WINEPREFIX (scripts/build-windows.sh makes it)" >&2; exit 2; }
work="$(mktemp -d "$out/e2e.XXXXXX")"
cd "$work"
export XDG_STATE_HOME="$work/linux-state"
passed=0
failed=0
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  rm -f "$WINEPREFIX/dosdevices/com7" "$WINEPREFIX/dosdevices/com8"
}
trap cleanup EXIT
ok() { echo "PASS: $*"; passed=$((passed + 1)); }
bad() { echo "FAIL: $*"; failed=$((failed + 1)); }
# Each run bounded: a hang is a failure with its exit code (124), not a stuck CI.
win() { timeout "${LMCFG_WINE_TIMEOUT:-240}" "$wine" "$exe" "$@"; }

# serve NAME STATE COM: `lmcfg sim` on a pty, mapped to COM (com7, com8).
serve() {
  cp "$2" "$1.sim.json"
  "$lmcfg" sim --state "$1.sim.json" >"$1.out" 2>"$1.err" </dev/null &
  pids+=($!)
  for _ in $(seq 100); do (($(wc -l <"$1.out") >= 2)) && break; sleep 0.1; done
  local pty
  pty="$(sed -n 1p "$1.out")"
  [[ $pty == /dev/pts/* ]] || { echo "test-windows: lmcfg sim did not start: $(cat "$1.err")" >&2; exit 1; }
  ln -sfn "$pty" "$WINEPREFIX/dosdevices/$3"
  echo "$pty"
}
fixtures="$root/tests/fixtures/sim"
pty_a="$(serve a "$fixtures/commissioned-axis.json" com7)"
pty_b="$(serve b "$fixtures/used-spare.json" com8)"
link=(--baud 57600 --id 0x11 --checksum none)

# 1. The same drive backed up by Linux and by lmcfg.exe through COM7.
t0=$(date +%s)
"$lmcfg" backup --port "$pty_a" "${link[@]}" -o linux.json -q 2>linux-backup.err ||
  bad "Linux backup: $(tail -2 linux-backup.err)"
win backup --port COM7 "${link[@]}" -o win.json -q 2>win-backup.err
rc=$?
echo "  lmcfg.exe backup --port COM7: exit $rc in $(($(date +%s) - t0)) s (both backups)"
if ((rc == 0)) && "$lmcfg" diff linux.json win.json >diff.out 2>&1; then
  ok "lmcfg.exe backup --port COM7 equals the Linux backup (lmcfg diff: identical)"
else
  bad "lmcfg.exe backup (exit $rc): $(tail -3 win-backup.err) $(tail -3 diff.out)"
fi

# 2. Restore onto the other drive through COM8, verified.
win restore win.json --port COM8 "${link[@]}" --yes -q >restore.out 2>restore.err
rc=$?
if ((rc == 0)) && "$lmcfg" backup --port "$pty_b" "${link[@]}" -o b-after.json -q 2>/dev/null &&
  "$lmcfg" diff win.json b-after.json >/dev/null 2>&1; then
  ok "lmcfg.exe restore --port COM8 verified; the Linux backup of that drive equals the file"
else
  bad "lmcfg.exe restore --port COM8: exit $rc: $(tail -3 restore.err)"
fi

# 3. A busy port: a second lmcfg.exe gets exit 4 and the holder's name.
win backup --port COM7 "${link[@]}" -o busy.json -q 2>holder.err &
holder=$!
sleep 3
win info --port COM7 "${link[@]}" >second.out 2>second.err
rc=$?
wait "$holder"
msg="$(cat second.err)"
if ((rc == 4)) && [[ $msg =~ port\ COM7\ is\ in\ use\ by\ lmcfg\ backup\ \(PID\ [0-9]+\) ]]; then
  ok "a second lmcfg.exe on COM7: exit 4, '${BASH_REMATCH[0]}'"
else
  bad "a second lmcfg.exe on COM7: exit $rc (expected 4): $msg"
fi

# 4. Ctrl-C: Wine turns SIGINT into a console control event for the program.
win restore win.json --port COM8 "${link[@]}" --yes -q >int.out 2>int.err &
runner=$!
sleep 4
kill -INT "$runner" 2>/dev/null
wait "$runner"
rc=$?
if ((rc == 130)); then
  ok "Ctrl-C (SIGINT to Wine) during restore: exit 130: $(tail -1 int.err)"
else
  echo "  Ctrl-C: exit $rc (expected 130): $(tail -2 int.err)"
  bad "Ctrl-C during lmcfg.exe restore: exit $rc, expected 130"
fi

# 5. fleet backup into a git archive that Linux git accepts.
cat >plant.toml <<'EOF'
[[line]]
name = "line1"
port = "COM7"
baud = 57600
[[line.drive]]
name = "press3/z-axis"
id = 0x11
EOF
win fleet backup plant.toml --archive archive -q >fleet.out 2>fleet.err
rc=$?
if ((rc == 0)) && git -C archive fsck --strict >fsck.out 2>&1 && [[ -n $(git -C archive log --oneline) ]]; then
  ok "lmcfg.exe fleet backup: archive with $(git -C archive rev-list --count HEAD) commit(s), git fsck --strict clean"
else
  bad "lmcfg.exe fleet backup: exit $rc: $(tail -3 fleet.err) $(tail -3 fsck.out 2>/dev/null)"
fi

# 6. What Windows does not have says so: exit 2 and a clear message.
win sim --pty >sim.out 2>sim.err
rc=$?
if ((rc == 2)) && grep -q 'not available on Windows' sim.err; then
  ok "lmcfg.exe sim: exit 2, $(head -1 sim.err)"
else
  bad "lmcfg.exe sim: exit $rc: $(cat sim.err)"
fi

echo "test-windows: $work"
echo "$passed passed, $failed failed"
((failed == 0))
