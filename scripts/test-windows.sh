#!/usr/bin/env bash
# End to end: lmcfg.exe under Wine against simulated drives served by the
# Linux build (`lmcfg sim` on pseudo-terminals), through Wine's COM port
# mapping ($WINEPREFIX/dosdevices/com7 -> /dev/pts/N). docs/windows.md.
#   scripts/test-windows.sh [LINUX_LMCFG [LMCFG_EXE]]
# Defaults: build/lmcfg and build-windows/build/lmcfg.exe (scripts/build.sh,
# scripts/build-windows.sh). Prints each check's result and duration, then
# "N passed, M failed"; exit 1 on a failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lmcfg="$(realpath "${1:-$root/build/lmcfg}")"
exe="$(realpath "${2:-$root/build-windows/build/lmcfg.exe}")"
source "$root/scripts/wine-env.sh"
wine_require test-windows "scripts/build.sh, scripts/build-windows.sh, install-deps.sh --windows" "$lmcfg" "$exe"
work="$(mktemp -d "$out/e2e.XXXXXX")"
cd "$work"
export XDG_STATE_HOME="$work/linux-state"
# lmcfg.exe's state (undo records, journal, recovery records, port locks) in
# the prefix: each run starts without what an earlier run left.
rm -rf "$WINEPREFIX"/drive_c/users/*/AppData/Local/lmcfg
passed=0
failed=0
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  rm -f "$WINEPREFIX"/dosdevices/com{5,7,8}
}
trap cleanup EXIT
t_check=$(date +%s)
took() { echo "$(($(date +%s) - t_check)) s"; }
ok() { echo "PASS ($(took)): $*"; passed=$((passed + 1)); t_check=$(date +%s); }
bad() { echo "FAIL ($(took)): $*"; failed=$((failed + 1)); t_check=$(date +%s); }
# Each run bounded: a hang is a failure with its exit code (124), not a stuck CI.
win() { timeout "${LMCFG_WINE_TIMEOUT:-120}" "$wine" "$exe" "$@"; }
# wait_bounded PID SECONDS: its exit status; killed (137) when it takes longer.
# text FILE: its lines without the \r that lmcfg.exe's text-mode output adds.
text() { tr -d '\r' <"$1"; }
wait_bounded() {
  local i
  for ((i = 0; i < $2 * 10; i++)); do
    kill -0 "$1" 2>/dev/null || break
    sleep 0.1
  done
  kill -0 "$1" 2>/dev/null && kill -KILL "$1"
  wait "$1"
}
# wait_for FILE PATTERN SECONDS: until FILE holds a line matching PATTERN.
wait_for() {
  local i
  for ((i = 0; i < $3 * 10; i++)); do
    grep -qs -- "$2" $1 && return 0
    sleep 0.1
  done
  return 1
}
lock_dir() { echo "$WINEPREFIX"/drive_c/users/*/AppData/Local/lmcfg/lock; }
state_dir() { echo "$WINEPREFIX"/drive_c/users/*/AppData/Local/lmcfg; }

# serve NAME STATE COM: `lmcfg sim` on a pty, mapped to COM (com7, com8).
serve() {
  [[ $2 == "$1.sim.json" ]] || cp "$2" "$1.sim.json"
  : >"$1.out" # there before the loop below reads it
  "$lmcfg" sim --state "$1.sim.json" >"$1.out" 2>"$1.err" </dev/null &
  pids+=($!)
  local _
  for _ in $(seq 100); do (($(wc -l <"$1.out") >= 2)) && break; sleep 0.1; done
  local pty
  pty="$(sed -n 1p "$1.out")"
  [[ $pty == /dev/pts/* ]] || { echo "test-windows: lmcfg sim did not start: $(cat "$1.err")" >&2; exit 1; }
  ln -sfn "$pty" "$WINEPREFIX/dosdevices/$3"
}
pty_of() { sed -n 1p "$1.out"; }
fixtures="$root/tests/fixtures/sim"
link=(--baud 57600 --id 0x11 --checksum none)
t_start=$(date +%s)
"$wine" wineboot >/dev/null 2>&1 # the wineserver up once, not inside the first check

# 1. The same drive backed up by Linux and by lmcfg.exe through COM7.
serve a "$fixtures/commissioned-axis.json" com7
"$lmcfg" backup --port "$(pty_of a)" "${link[@]}" -o linux.json -q 2>linux-backup.err ||
  bad "Linux backup: $(tail -2 linux-backup.err)"
t0=$(date +%s)
win backup --port COM7 "${link[@]}" -o win.json -q --trace win-backup.trace 2>win-backup.err
rc=$?
echo "  lmcfg.exe backup --port COM7: exit $rc in $(($(date +%s) - t0)) s, $(grep -c TX win-backup.trace) telegrams"
if ((rc == 0)) && "$lmcfg" diff linux.json win.json >diff.out 2>&1; then
  ok "lmcfg.exe backup --port COM7 equals the Linux backup (lmcfg diff: identical)"
else
  bad "lmcfg.exe backup (exit $rc): $(tail -3 win-backup.err) $(tail -3 diff.out)"
fi

# 2. Restore onto the other drive through COM8, verified. --include-comm: the
# communication parameters too (the drive restarts with them and is found
# again), so that the Linux backup of the drive then equals the file.
serve b "$fixtures/used-spare.json" com8
t0=$(date +%s)
win restore win.json --port COM8 "${link[@]}" --yes --include-comm --trace restore.trace >restore.out 2>restore.err
rc=$?
echo "  lmcfg.exe restore --port COM8: exit $rc in $(($(date +%s) - t0)) s, $(grep -c TX restore.trace) telegrams: $(tail -1 restore.err)"
if ((rc == 0)) && grep -q 'verified: the drive matches' restore.err &&
  "$lmcfg" backup --port "$(pty_of b)" "${link[@]}" -o b-after.json -q 2>b-after.err &&
  "$lmcfg" diff win.json b-after.json >b-diff.out 2>&1; then
  ok "lmcfg.exe restore --port COM8 verified; the Linux backup of that drive equals the file"
else
  bad "lmcfg.exe restore --port COM8: exit $rc: $(tail -3 restore.err) $(tail -3 b-diff.out 2>/dev/null)"
fi

# 3. fleet backup into a git archive that Linux git accepts.
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

# 4. A busy port: a second lmcfg.exe gets exit 4 and the holder's name, the
# text of the Linux build. The holder backs up a drive that answers 30 ms late
# (about 20 s for the backup), so it holds COM7 however slowly the second starts.
sed 's/^{/{"timing_us": {"turnaround": 30000},/' "$fixtures/commissioned-axis.json" >slow.sim.json
serve slow slow.sim.json com7
"$wine" "$exe" backup --port COM7 "${link[@]}" -o busy.json -q >holder.out 2>holder.err &
holder=$!
holder_rec=""
wait_for "$(lock_dir)/port-COM7.holder" 'holder=lmcfg backup' 60 && holder_rec="$(cat "$(lock_dir)/port-COM7.holder")"
win info --port COM7 "${link[@]}" >second.out 2>second.err
rc=$?
msg="$(text second.err)"
# A holder that dies leaves no lock: Windows closes its handles.
kill -KILL "$holder" 2>/dev/null
wait "$holder" 2>/dev/null
win info --port COM7 "${link[@]}" >after.out 2>after.err
after_rc=$?
# The Linux build, holder and second, on the same slow drive's pty.
"$lmcfg" backup --port "$(pty_of slow)" "${link[@]}" -o linux-busy.json -q 2>linux-holder.err &
lholder=$!
info="$(pty_of slow | sed 's|/|%2F|g').holder" # port_lock.cpp's record of that pty
records="/run/lock/lmcfg/$info ${XDG_RUNTIME_DIR:-/nonexistent}/lmcfg/$info /tmp/lmcfg-lock/$info"
wait_for "$records" "^pid=$lholder\$" 30 # its own: pty numbers are reused
"$lmcfg" info --port "$(pty_of slow)" "${link[@]}" >linux-second.out 2>linux-second.err
lrc=$?
kill -KILL "$lholder" 2>/dev/null
wait "$lholder" 2>/dev/null
for r in $records; do grep -qs "^pid=$lholder\$" "$r" && rm -f "$r"; done
want="$(sed "s|$(pty_of slow)|COM7|; s|(PID [0-9]*)|(PID N)|" linux-second.err)"
pid_in_msg="$(sed -n 's/.*(PID \([0-9]*\)).*/\1/p' <<<"$msg")"
if ((rc == 4 && lrc == 4)) && [[ $(sed 's|(PID [0-9]*)|(PID N)|' <<<"$msg") == "$want" ]] &&
  [[ -n $pid_in_msg && $holder_rec == *"pid=$pid_in_msg"* ]]; then
  ok "a second lmcfg.exe on COM7: exit 4, '$msg' (the Linux build's text; PID $pid_in_msg is the holder's Windows process ID, as its lock file records)"
else
  bad "a second lmcfg.exe on COM7: exit $rc (expected 4): '$msg'; Linux: exit $lrc '$(cat linux-second.err)'; lock record: '$holder_rec'"
fi
if ((after_rc == 0)); then
  ok "COM7 after its holder was killed: lmcfg.exe info exit 0 (the lock died with the process)"
else
  bad "COM7 after its holder was killed: exit $after_rc: $(text after.err)"
fi

# 5. Ctrl-C during a restore: Wine turns SIGINT into CTRL_C_EVENT for the
# program's console control handler. Sent once the restore writes (its
# recovery record exists from the first write to the last step): the telegram in flight completes
# (the trace ends with its answer), exit 130, the recovery record stays; the
# same restore run again converges, verifies and removes it.
serve c "$fixtures/used-spare.json" com8
"$wine" "$exe" restore win.json --port COM8 "${link[@]}" --yes --include-comm --trace int.trace \
  >int.out 2>int.err &
runner=$!
for _ in $(seq 600); do
  [[ -e $(state_dir)/restore-COM8-11h.json ]] && break
  sleep 0.1
done
sleep 0.5
kill -INT "$runner" 2>/dev/null
wait_bounded "$runner" 60
rc=$?
record="$(ls "$(state_dir)"/restore-COM8-11h.json 2>/dev/null)"
last="$(tail -1 int.trace | cut -d' ' -f2)"
if ((rc == 130)) && grep -q 'the telegram in flight was completed' int.err && [[ $last == RX && -n $record ]]; then
  ok "Ctrl-C (SIGINT to Wine) during lmcfg.exe restore: exit 130, the last telegram answered, the recovery record left: $(tail -1 int.err | cut -c1-120)..."
else
  bad "Ctrl-C during lmcfg.exe restore: exit $rc (expected 130), last trace line '$last', recovery record '${record:-none}': $(tail -2 int.err)"
fi
win restore win.json --port COM8 "${link[@]}" --yes --include-comm >rerun.out 2>rerun.err
rc=$?
if ((rc == 0)) && grep -q 'verified: the drive matches' rerun.err && [[ ! -e $record ]]; then
  ok "the interrupted restore run again: verified, the recovery record removed"
else
  bad "the interrupted restore run again: exit $rc: $(tail -2 rerun.err)"
fi

# 6. Errors with the Linux build's exit codes and texts (the port's name and
# the operating system's own words aside): no answer on a COM port with
# nothing behind it, a COM port that does not exist, a bad --baud.
: >silent.out
python3 -c 'import os, pty, time; m, s = pty.openpty(); print(os.ttyname(s), flush=True); time.sleep(600)' \
  >silent.out &
pids+=($!)
wait_for silent.out '^/dev/' 10
silent="$(cat silent.out)"
ln -sfn "$silent" "$WINEPREFIX/dosdevices/com5"
win info --port COM5 "${link[@]}" >none.out 2>none.err
rc=$?
"$lmcfg" info --port "$silent" "${link[@]}" >lnone.out 2>lnone.err
lrc=$?
if ((rc == 4 && lrc == 4)) && [[ $(text none.err) == "$(sed "s|$silent|COM5|g" lnone.err)" ]]; then
  ok "no answer on COM5: exit 4, the Linux text: $(text none.err)"
else
  bad "no answer on COM5: exit $rc, Linux $lrc: '$(cat none.err)' / '$(cat lnone.err)'"
fi
win info --port COM99 "${link[@]}" >com99.out 2>com99.err
rc=$?
"$lmcfg" info --port /dev/ttyUSB99 "${link[@]}" >lcom99.out 2>lcom99.err
lrc=$?
if ((rc == 2 && lrc == 2)) && grep -q '^lmcfg info: cannot open serial port COM99: .*; check --port and that the adapter is plugged in' com99.err &&
  grep -q '^lmcfg info: cannot open serial port /dev/ttyUSB99: .*; check --port and that the adapter is plugged in' lcom99.err; then
  ok "COM99 (no such port): exit 2 as on Linux: $(text com99.err)"
else
  bad "COM99: exit $rc, Linux $lrc: '$(cat com99.err)' / '$(cat lcom99.err)'"
fi
win info --port COM7 --baud 12345 --id 0x11 >baud.out 2>baud.err
rc=$?
"$lmcfg" info --port "$silent" --baud 12345 --id 0x11 >lbaud.out 2>lbaud.err
lrc=$?
if ((rc == 2 && lrc == 2)) && [[ -s baud.err && $(text baud.err) == "$(cat lbaud.err)" ]]; then
  ok "--baud 12345: exit 2, the Linux text: $(text baud.err)"
else
  bad "--baud 12345: exit $rc, Linux $lrc: '$(cat baud.err)' / '$(cat lbaud.err)'"
fi

# 7. What Windows does not have says so: exit 2 and a clear message.
win sim --pty >sim.out 2>sim.err
rc=$?
if ((rc == 2)) && grep -q 'not available on Windows' sim.err; then
  ok "lmcfg.exe sim: exit 2, $(head -1 sim.err)"
else
  bad "lmcfg.exe sim: exit $rc: $(cat sim.err)"
fi

echo "test-windows: $work"
echo "$passed passed, $failed failed in $(($(date +%s) - t_start)) s"
((failed == 0))
