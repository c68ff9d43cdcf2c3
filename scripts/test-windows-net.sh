#!/usr/bin/env bash
# End to end over the network: lmcfg.exe's Winsock transports under Wine
# (tcp://, rfc2217://, linudp://) against simulated drives served by the Linux
# build, and lmcfg.exe's own `sim --tcp` read by the Linux build. Each backup
# must equal the Linux build's backup of the same drive (`lmcfg diff`:
# identical). docs/windows.md.
#   scripts/test-windows-net.sh [LINUX_LMCFG [LMCFG_EXE]]
# Defaults: build/lmcfg and build-windows/build/lmcfg.exe (scripts/build.sh,
# scripts/build-windows.sh). The RFC 2217 check needs ser2net (Debian package;
# skipped with a note when missing). Prints PASS/FAIL lines with durations and
# "N passed, M failed"; exit 1 on a failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lmcfg="$(realpath "${1:-$root/build/lmcfg}")"
exe="$(realpath "${2:-$root/build-windows/build/lmcfg.exe}")"
source "$root/scripts/wine-env.sh"
ser2net="${LMCFG_SER2NET:-/usr/sbin/ser2net}"
wine_require test-windows-net "scripts/build.sh, scripts/build-windows.sh, install-deps.sh --windows" "$lmcfg" "$exe"
wine_checks net
# Each run bounded: a hang is a failure with its exit code (124), not a stuck CI.
win() { timeout "${LMCFG_WINE_TIMEOUT:-240}" "$wine" "$exe" "$@"; }
lin() { timeout "${LMCFG_WINE_TIMEOUT:-240}" "$lmcfg" "$@"; }
link=(--baud 57600 --id 0x11 --checksum none)
fixtures="$root/tests/fixtures/sim"

# same NAME A.json B.json: PASS when lmcfg diff says identical.
same() { "$lmcfg" diff "$2" "$3" >"$1.diff" 2>&1; }

# 1. tcp://: the same drive (Linux `lmcfg sim --tcp`) backed up by both builds.
t0=$(date +%s)
cp "$fixtures/commissioned-axis.json" a.sim.json
start_bg a 30 "$lmcfg" sim --state a.sim.json --tcp 127.0.0.1:0
port_a="$(first a)"
tl=$(date +%s)
lin backup --port "tcp://127.0.0.1:$port_a" "${link[@]}" -o tcp-linux.json -q 2>tcp-linux.err
rc_l=$?
t1=$(date +%s)
win backup --port "tcp://127.0.0.1:$port_a" "${link[@]}" -o tcp-win.json -q 2>tcp-win.err
rc=$?
echo "  backup over tcp://: Linux exit $rc_l in $((t1 - tl)) s, lmcfg.exe exit $rc in $(($(date +%s) - t1)) s"
if ((rc == 0 && rc_l == 0)) && same tcp tcp-linux.json tcp-win.json; then
  ok "lmcfg.exe backup --port tcp:// equals the Linux backup (lmcfg diff: identical)"
else
  bad "lmcfg.exe backup --port tcp:// (exit $rc, Linux $rc_l): $(tail -2 tcp-win.err) $(tail -2 tcp-linux.err) $(tail -3 tcp.diff 2>/dev/null)"
fi

# 2. A restore with verify over tcp:// onto a spare drive, and the Linux
# build's restore of the same file onto an identical spare: the two drives
# then read back the same (restore leaves the LinRS link parameters alone,
# so the spare is compared with a spare, not with the file).
t0=$(date +%s)
cp "$fixtures/used-spare.json" b.sim.json
cp "$fixtures/used-spare.json" b2.sim.json
start_bg b 30 "$lmcfg" sim --state b.sim.json --tcp 127.0.0.1:0
port_b="$(first b)"
start_bg b2 30 "$lmcfg" sim --state b2.sim.json --tcp 127.0.0.1:0
port_b2="$(first b2)"
win restore tcp-linux.json --port "tcp://127.0.0.1:$port_b" "${link[@]}" --yes -q >restore.out 2>restore.err
rc=$?
t1=$(date +%s)
lin restore tcp-linux.json --port "tcp://127.0.0.1:$port_b2" "${link[@]}" --yes -q >restore-linux.out 2>restore-linux.err
rc_l=$?
echo "  restore over tcp://: lmcfg.exe exit $rc in $((t1 - t0)) s, Linux exit $rc_l in $(($(date +%s) - t1)) s"
if ((rc == 0 && rc_l == 0)) &&
  lin backup --port "tcp://127.0.0.1:$port_b" "${link[@]}" -o b-after.json -q 2>/dev/null &&
  lin backup --port "tcp://127.0.0.1:$port_b2" "${link[@]}" -o b2-after.json -q 2>/dev/null &&
  same restore b2-after.json b-after.json; then
  ok "lmcfg.exe restore --port tcp:// verified; the drive reads back as the one the Linux build restored"
else
  bad "lmcfg.exe restore --port tcp:// (exit $rc, Linux $rc_l): $(tail -3 restore.err) $(tail -3 restore-linux.err) $(tail -5 restore.diff 2>/dev/null)"
fi

# 3. rfc2217://: ser2net's RFC 2217 accepter in front of a drive on a pty.
t0=$(date +%s)
if [[ -x $ser2net ]]; then
  cp "$fixtures/commissioned-axis.json" c.sim.json
  start_bg c 30 "$lmcfg" sim --state c.sim.json
  pty_c="$(first c)"
  port_c="$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')"
  cat >ser2net.yaml <<EOF
%YAML 1.1
---
connection: &line
  accepter: telnet(rfc2217),tcp,127.0.0.1,$port_c
  connector: serialdev,$pty_c,57600n81,local
  options:
    kickolduser: true
    mdns: false
EOF
  "$ser2net" -n -d -c "$work/ser2net.yaml" -P "$work/ser2net.pid" 2>ser2net.log &
  pids+=($!)
  for _ in $(seq 50); do grep -q "$(printf '0100007F:%04X' "$port_c") 00000000:0000 0A" /proc/net/tcp && break; sleep 0.1; done
  tl=$(date +%s)
  lin backup --port "rfc2217://127.0.0.1:$port_c" "${link[@]}" -o rfc-linux.json -q 2>rfc-linux.err
  rc_l=$?
  t1=$(date +%s)
  win backup --port "rfc2217://127.0.0.1:$port_c" "${link[@]}" -o rfc-win.json -q 2>rfc-win.err
  rc=$?
  echo "  backup over rfc2217:// (ser2net): Linux exit $rc_l in $((t1 - tl)) s, lmcfg.exe exit $rc in $(($(date +%s) - t1)) s"
  if ((rc == 0 && rc_l == 0)) && same rfc rfc-linux.json rfc-win.json; then
    ok "lmcfg.exe backup --port rfc2217:// (ser2net) equals the Linux backup (lmcfg diff: identical)"
  else
    bad "lmcfg.exe backup --port rfc2217:// (exit $rc, Linux $rc_l): $(tail -2 rfc-win.err) $(tail -2 rfc-linux.err) $(tail -3 rfc.diff 2>/dev/null)"
  fi
else
  echo "  rfc2217:// not checked: $ser2net missing (Debian package ser2net)"
fi

# 4. linudp://: `lmcfg sim --linudp` on a UDP port; lmcfg.exe sends from 41136.
t0=$(date +%s)
cp "$fixtures/commissioned-axis.json" d.sim.json
start_bg d 30 "$lmcfg" sim --linudp --udp 127.0.0.1:0 --state d.sim.json
port_d="$(first d)"
tl=$(date +%s)
lin backup --port "linudp://127.0.0.1:$port_d" -o udp-linux.json -q 2>udp-linux.err
rc_l=$?
t1=$(date +%s)
win backup --port "linudp://127.0.0.1:$port_d" -o udp-win.json -q 2>udp-win.err
rc=$?
echo "  backup over linudp://: Linux exit $rc_l in $((t1 - tl)) s, lmcfg.exe exit $rc in $(($(date +%s) - t1)) s"
if ((rc == 0 && rc_l == 0)) && same udp udp-linux.json udp-win.json; then
  ok "lmcfg.exe backup --port linudp:// equals the Linux backup (lmcfg diff: identical)"
else
  bad "lmcfg.exe backup --port linudp:// (exit $rc, Linux $rc_l): $(tail -2 udp-win.err) $(tail -2 udp-linux.err) $(tail -3 udp.diff 2>/dev/null)"
fi

# 5. lmcfg.exe sim --tcp: the Windows build's simulator, read by the Linux build.
t0=$(date +%s)
cp "$fixtures/commissioned-axis.json" e.sim.json
start_bg e 30 timeout "${LMCFG_WINE_TIMEOUT:-240}" "$wine" "$exe" sim --state e.sim.json --tcp 127.0.0.1:0
port_e="$(first e)"
lin backup --port "tcp://127.0.0.1:$port_e" "${link[@]}" -o winsim.json -q 2>winsim.err
rc=$?
if ((rc == 0)) && same winsim tcp-linux.json winsim.json; then
  ok "lmcfg.exe sim --tcp: the Linux backup of its drive equals the Linux sim's (lmcfg diff: identical)"
else
  bad "lmcfg.exe sim --tcp (port '$port_e'): Linux backup exit $rc: $(tail -2 winsim.err) $(tail -2 e.err) $(tail -3 winsim.diff 2>/dev/null)"
fi

# 6. Nobody listening: exit 4 and the address in the message, within the connect timeout.
t0=$(date +%s)
closed="$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')"
win info --port "tcp://127.0.0.1:$closed" "${link[@]}" >closed.out 2>closed.err
rc=$?
if ((rc == 4)) && grep -q "tcp 127.0.0.1:$closed: cannot connect" closed.err; then
  ok "lmcfg.exe on a closed tcp:// port: exit 4, $(head -1 closed.err)"
else
  bad "lmcfg.exe on a closed tcp:// port: exit $rc (expected 4): $(cat closed.err)"
fi

echo "test-windows-net: $work"
echo "$passed passed, $failed failed, $(($(date +%s) - start_all)) s"
((failed == 0))
