#!/usr/bin/env bash
# End to end: `lmcfg.exe ui --no-browser` under Wine, with COM7 and COM8
# mapped to simulated drives that the Linux build serves on pseudo-terminals
# (`lmcfg sim`), driven from Linux with curl as the page's browser would: the
# printed address's token exchanged for the cookie, the CSRF value read from
# the page, the drive found on COM7, backed up into the folder (equal to the
# Linux build's backup), restored onto a used spare on COM8 through the plan,
# which then equals the file (the Linux `lmcfg diff`), the checks, Quit.
# docs/ui.md "Windows".
#   scripts/test-windows-ui.sh [LINUX_LMCFG [LMCFG_EXE]]
# Defaults: build/lmcfg and build-windows/build/lmcfg.exe. Needs curl and
# python3. Prints PASS/FAIL lines with durations and "N passed, M failed";
# exit 1 on a failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lmcfg="$(realpath "${1:-$root/build/lmcfg}")"
exe="$(realpath "${2:-$root/build-windows/build/lmcfg.exe}")"
source "$root/scripts/wine-env.sh"
wine_require test-windows-ui "scripts/build.sh, scripts/build-windows.sh, install-deps.sh --windows" "$lmcfg" "$exe"
for tool in curl python3; do
  command -v "$tool" >/dev/null || {
    echo "test-windows-ui: $tool missing (scripts/install-deps.sh)" >&2
    exit 2
  }
done
wine_checks ui
trap 'for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done; unmap; rm -f "$WINEPREFIX"/dosdevices/com{7,8}' EXIT
# lmcfg.exe's state (undo records, journal, locks): this run's own.
rm -rf "$WINEPREFIX"/drive_c/users/*/AppData/Local/lmcfg
win() { timeout "${LMCFG_WINE_TIMEOUT:-120}" "$wine" "$exe" "$@"; }
winpath() { echo "Z:${1//\//\\}"; } # Wine's drive Z: is the Linux root
link=(--baud 57600 --id 0x11 --checksum none)
"$wine" wineboot >/dev/null 2>&1 # the wineserver up once, not inside the first check

# sim NAME FIXTURE COM: `lmcfg sim` on a pty, mapped to COM (com7, com8).
sim() {
  cp "$root/tests/fixtures/sim/$2" "$1.sim.json"
  start_bg "$1" 60 "$lmcfg" sim --state "$1.sim.json"
  local pty
  pty="$(first "$1")"
  [[ $pty == /dev/pts/* ]] || { echo "test-windows-ui: lmcfg sim printed '$pty'" >&2; exit 1; }
  ln -sfn "$pty" "$WINEPREFIX/dosdevices/$3"
  # Also in Wine's own port table: Wine's mount manager then lists the port
  # (QueryDosDevice, HARDWARE\DEVICEMAP\SERIALCOMM) from its next start.
  "$wine" reg add 'HKLM\Software\Wine\Ports' /v "${3^^}" /t REG_SZ /d "$pty" /f >/dev/null 2>&1
}
unmap() {
  local c
  for c in COM7 COM8; do "$wine" reg delete 'HKLM\Software\Wine\Ports' /v "$c" /f >/dev/null 2>&1; done
}
sim a commissioned-axis.json com7
sim b used-spare.json com8
"${wine%/*}/wineserver" -k 2>/dev/null || wineserver -k 2>/dev/null # restarted with COM7, COM8
"$lmcfg" backup --port "$(first a)" "${link[@]}" -o linux.json -q 2>linux-backup.err || {
  echo "test-windows-ui: the Linux backup failed: $(cat linux-backup.err)" >&2
  exit 1
}

# The page, as a browser of this computer uses it: cookies in a jar, forms
# as application/x-www-form-urlencoded with the page's CSRF value.
# get PATH: the body in page.body, the status in $status.
get() { status=$(curl -s -m 20 -b jar -c jar -o page.body -w '%{http_code}' "$base$1"); }
# post PATH FIELD=VALUE...: a form; the status in $status, Location in $location.
post() {
  local path=$1 args=()
  shift
  for f in "csrf=$csrf" "$@"; do args+=(--data-urlencode "$f"); done
  status=$(curl -s -m 20 -b jar -c jar -o page.body -D head.txt -w '%{http_code}' "${args[@]}" \
    "$base$path")
  location=$(sed -n 's/^[Ll]ocation: *//p' head.txt | tr -d '\r')
}
# json EXPR: a field of page.body.
json() { python3 -c "import json,sys; d=json.load(open('page.body')); print(eval('d'+sys.argv[1]))" "$1" 2>/dev/null; }
# job: the job the last form started (its 303 to /job?id=N), waited for
# (120 s); its JSON in page.body, its state in $state.
job() {
  state=""
  [[ $status == 303 && $location == /job\?id=* ]] || { state="not started ($status: $(head -c 300 page.body))"; return; }
  local id=${location#/job?id=}
  for _ in $(seq 240); do
    get "/api/v1/job/$id"
    state=$(json '["state"]')
    [[ $state != running ]] && return
    sleep 0.5
  done
}

# 1. The address on stdout, its token exchanged for the cookie.
t0=$(date +%s)
port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')
mkdir -p folder
start_bg ui 60 "$wine" "$exe" ui --no-browser --no-practice --listen "127.0.0.1:$port" \
  --folder "$(winpath "$work/folder")"
ui_pid=${pids[-1]}
url="$(first ui)"
base="http://127.0.0.1:$port"
status=$(curl -s -m 20 -c jar -o page.body -D head.txt -w '%{http_code}' "$url")
get /
csrf=$(sed -n 's/.*name="csrf" value="\([0-9A-Fa-f]*\)".*/\1/p' page.body | head -1)
if [[ $url == "$base/?token="* && $(grep -ci '^set-cookie: lmcfg_ui=' head.txt) == 1 && $status == 200 &&
  -n $csrf ]] && grep -q '<h1>Connect a drive</h1>' page.body; then
  ok "lmcfg.exe ui printed $base/?token=..., the token became the cookie, the connect page with its CSRF value"
else
  bad "the address and the cookie: url '$url', status $status, csrf '$csrf': $(tail -3 ui.err)"
fi

# 2. The COM ports as the page lists them, and what Windows says of each.
t0=$(date +%s)
get /api/v1/ports
ports=$(python3 -c "
import json; d=json.load(open('page.body'))
print('; '.join('%s [device %r, description %r]' % (p['port'], p.get('device',''), p.get('description','')) for p in d['ports']))" 2>&1)
if grep -q '"COM7"' page.body && grep -q '"COM8"' page.body && grep -q 'Device\\\\Serial' page.body; then
  ok "the ports: $ports"
else
  bad "COM7 and COM8 not listed: $ports"
fi

# 3. The checks of lmcfg serve: no cookie, a foreign Host, no CSRF value.
t0=$(date +%s)
no_cookie=$(curl -s -m 20 -o /dev/null -w '%{http_code}' "$base/api/v1/drives")
foreign=$(curl -s -m 20 -b jar -o /dev/null -w '%{http_code}' -H 'Host: evil.example' "$base/")
no_csrf=$(curl -s -m 20 -b jar -o /dev/null -w '%{http_code}' --data 'port=COM7' "$base/find")
if [[ $no_cookie == 403 && $foreign == 421 && $no_csrf == 403 ]]; then
  ok "no cookie 403, a foreign Host 421, a form without the CSRF value 403"
else
  bad "the checks: no cookie $no_cookie, foreign Host $foreign, no CSRF $no_csrf"
fi

# 4. Find the drive on COM7, back it up: the file equals the Linux backup.
t0=$(date +%s)
post /find port=COM7 baud=57600 from=16 to=18
job
a_key=$(json '["result"]["found"][0]')
post /backup "key=$a_key"
job
file=$(json '["result"]["file"]')
if [[ $state == "done" && -n $file && -f folder/$file ]] &&
  "$lmcfg" diff linux.json "folder/$file" >diff-a.out 2>&1; then
  ok "found $a_key on COM7, backed up into folder/$file, equal to the Linux backup (lmcfg diff: identical)"
else
  bad "find and back up on COM7: key '$a_key', state '$state', file '$file': $(head -c 400 page.body) $(tail -3 diff-a.out 2>/dev/null)"
fi

# 5. Restore that file onto the used spare on COM8: plan, then execute.
t0=$(date +%s)
post /find port=COM8 baud=57600 from=16 to=18
job
b_key=$(json '["result"]["found"][0]')
post /plan "key=$b_key" "file=$file"
job
plan_id=$(json '["result"]["plan_id"]')
get "/plan?id=$plan_id"
plan_ok=0
grep -q 'id="verdict"' page.body && grep -q 'id="execute"' page.body && plan_ok=1
post /execute "plan=$plan_id" "reason=spare for axis 1 (Wine test)" skip_incompatible=1
job
if [[ $state == "done" && $plan_ok == 1 ]]; then
  ok "restored onto $b_key on COM8 through plan $plan_id: $(json '["result"].get("outcome", "")' | head -c 120)"
else
  bad "the restore onto COM8: plan '$plan_id' (page ok: $plan_ok), state '$state': $(head -c 600 page.body)"
fi

# 6. Verified from Linux: the spare now equals the file, except the link
# values a restore keeps (--ignore-unit, as the page's own comparison).
t0=$(date +%s)
"$lmcfg" backup --port "$(first b)" "${link[@]}" -o b-after.json -q 2>b-after.err &&
  "$lmcfg" diff --ignore-unit "folder/$file" b-after.json >diff-b.out 2>&1
rc=$?
post /compare "key=$b_key" "against=$file"
job
if ((rc == 0)) && [[ $(json '["result"]["identical"]') == True ]]; then
  ok "the spare equals the file: Linux lmcfg diff --ignore-unit identical, the page's comparison too"
else
  bad "the spare after the restore: Linux diff exit $rc: $(tail -5 diff-b.out) $(tail -2 b-after.err); page: $(head -c 300 page.body)"
fi

# 7. Quit: the page answers, lmcfg.exe ends with exit 0.
t0=$(date +%s)
post /quit
for _ in $(seq 300); do kill -0 "$ui_pid" 2>/dev/null || break; sleep 0.1; done
if kill -0 "$ui_pid" 2>/dev/null; then
  bad "Quit (status $status): lmcfg.exe still runs after 30 s"
else
  wait "$ui_pid"
  rc=$?
  if ((rc == 0)) && [[ $status == 200 ]]; then ok "Quit: the page said so, exit 0"; else bad "Quit: status $status, exit $rc: $(tail -3 ui.err)"; fi
fi

# 8. Without --folder: the default folder is Documents\lmcfg of the user;
# SIGINT (Wine's Ctrl-C) with nothing running ends it, exit 0. `lmcfg.exe`
# alone from a script (no console of its own) prints the usage, exit 2.
t0=$(date +%s)
"$wine" "$exe" ui --no-browser --no-practice --listen 127.0.0.1:0 >def.out 2>def.err </dev/null &
def_pid=$!
pids+=("$def_pid")
for _ in $(seq 300); do grep -q 'backups go to' def.err && break; sleep 0.1; done
folder_line=$(grep -o 'backups go to .*' def.err | tr -d '\r')
kill -INT "$def_pid" 2>/dev/null
for _ in $(seq 200); do kill -0 "$def_pid" 2>/dev/null || break; sleep 0.1; done
kill -0 "$def_pid" 2>/dev/null && kill -KILL "$def_pid"
wait "$def_pid" 2>/dev/null
int_rc=$?
win >usage.out 2>usage.err
rc=$?
if [[ $folder_line =~ backups\ go\ to\ C:\\users\\[^\\]+\\Documents\\lmcfg$ ]] && ((int_rc == 0 && rc == 2)) &&
  grep -q 'Usage: lmcfg SUBCOMMAND' usage.err; then
  ok "the default folder: '$folder_line'; SIGINT: exit 0; lmcfg.exe alone from a script: the usage, exit 2"
else
  bad "default folder '$folder_line' ($(tail -2 def.err)); SIGINT: exit $int_rc; lmcfg.exe alone: exit $rc"
fi

echo "test-windows-ui: $passed passed, $failed failed ($(($(date +%s) - start_all)) s)"
((failed == 0))
