#!/usr/bin/env bash
# End to end: `lmcfg.exe serve` under Wine over a line of a simulated drive
# that the Linux build serves (`lmcfg sim --tcp`), driven from Linux with curl
# as a plant's scripts and a technician's browser would: the scheduled backup
# into an archive that Linux git reads (fsck) and that equals the Linux
# build's backup of the same drive, a change made behind the service's back
# found as drift (webhook to a Python receiver, notify command as a batch
# file run by Wine's cmd.exe), plan and execute back to the approved
# configuration, the Host and Origin checks, tokens, HTTPS (Mbed TLS), what
# the Windows build refuses at start, and Ctrl-C. docs/windows.md.
#   scripts/test-windows-serve.sh [LINUX_LMCFG [LMCFG_EXE]]
# Defaults: build/lmcfg and build-windows/build/lmcfg.exe. Needs curl,
# python3, git and openssl; promtool when installed. Prints PASS/FAIL lines with durations and
# "N passed, M failed"; exit 1 on a failure.
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
lmcfg="$(realpath "${1:-$root/build/lmcfg}")"
exe="$(realpath "${2:-$root/build-windows/build/lmcfg.exe}")"
source "$root/scripts/wine-env.sh"
wine_require test-windows-serve "scripts/build.sh, scripts/build-windows.sh, install-deps.sh --windows" "$lmcfg" "$exe"
for tool in curl python3 git openssl; do
  command -v "$tool" >/dev/null || {
    echo "test-windows-serve: $tool missing (scripts/install-deps.sh)" >&2
    exit 2
  }
done
wine_checks serve
win() { timeout "${LMCFG_WINE_TIMEOUT:-120}" "$wine" "$exe" "$@"; }
winpath() { echo "Z:${1//\//\\}"; } # Wine's drive Z: is the Linux root
link=(--baud 57600 --id 0x11 --checksum none)

# api METHOD PATH [BODY]: the answer's body on stdout, the status in $status.
api() {
  local body=${3-}
  status=$(curl -s -m 20 -o api.body -w '%{http_code}' -X "$1" "${hdr[@]}" \
    ${body:+-H 'Content-Type: application/json' --data "$body"} "$url$2")
  cat api.body
}
hdr=()
# json FIELD: a field of the last answer (api.body), via Python.
json() { python3 -c "import json,sys; d=json.load(open('api.body')); print(eval('d'+sys.argv[1]))" "$1" 2>/dev/null; }
# wait_job ID: polls the job until it ends (60 s); its JSON in api.body.
wait_job() {
  for _ in $(seq 120); do
    api GET "/api/v1/jobs/$1" >/dev/null
    [[ $(json '["state"]') == done || $(json '["state"]') == failed ]] && return
    sleep 0.5
  done
}
# drive_status: the position's status.
drive_status() { api GET "/api/v1/drives/cell1%2Faxis" >/dev/null && json '["status"]'; }

# The drive, a webhook receiver and the notify command.
cp "$root/tests/fixtures/sim/commissioned-axis.json" a.sim.json
start_bg sim 60 "$lmcfg" sim --state a.sim.json --tcp 127.0.0.1:0
port="$(first sim)"
cat >receiver.py <<'EOF'
import http.server, sys
class H(http.server.BaseHTTPRequestHandler):
    def do_POST(self):
        body = self.rfile.read(int(self.headers.get("Content-Length", 0)))
        with open("hooks.jsonl", "ab") as f:
            f.write(body + b"\n")
        self.send_response(204)
        self.end_headers()
    def log_message(self, *a):
        pass
s = http.server.HTTPServer(("127.0.0.1", 0), H)
print(s.server_address[1], flush=True)
s.serve_forever()
EOF
start_bg hook 60 python3 receiver.py
hook_port="$(first hook)"
printf '@echo off\r\nmore >> "%s"\r\n' "$(winpath "$work/events.txt")" >notify.cmd
cat >plant.toml <<EOF
[schedule]
backup_every = "6h"
status_every = "6h"
[notify]
webhook = "http://127.0.0.1:$hook_port/lmcfg"
command = '$(winpath "$work/notify.cmd")'
[[line]]
name = "cell1"
port = "tcp://127.0.0.1:$port"
baud = 57600
checksum = "none"
[[line.drive]]
name = "cell1/axis"
id = 0x11
EOF

# 1. The service starts, schedules its first backup, and the archive it
# writes is a git repository whose file equals the Linux build's backup.
t0=$(date +%s)
# Straight under Wine, not through timeout: step 5 sends it SIGINT.
start_bg serve 60 "$wine" "$exe" serve plant.toml --archive archive --listen 127.0.0.1:0
url="$(first serve)"
for _ in $(seq 120); do [[ $(drive_status) == ok ]] && break; sleep 0.5; done
st=$(drive_status)
"$lmcfg" backup --port "tcp://127.0.0.1:$port" "${link[@]}" -o linux.json -q 2>linux.err
rc_l=$?
if [[ $url == http://127.0.0.1:* && $st == ok && $rc_l == 0 ]] && git -C archive fsck --no-progress >fsck.err 2>&1 &&
  "$lmcfg" diff linux.json archive/cell1/axis.json >diff.txt 2>&1; then
  ok "lmcfg.exe serve: scheduled backup, status ok, git fsck accepts the archive, its file equals the Linux backup"
else
  bad "lmcfg.exe serve start and first backup: url '$url', status '$st', Linux exit $rc_l: $(tail -2 serve.err) $(cat fsck.err 2>/dev/null) $(tail -2 diff.txt 2>/dev/null)"
fi

# 2. A change behind the service's back: a backup finds it (drift), the
# webhook and the notify command get the event.
t0=$(date +%s)
"$lmcfg" set 0010 9 --rom --yes --quiet --port "tcp://127.0.0.1:$port" "${link[@]}" >set.out 2>&1
api POST "/api/v1/drives/cell1%2Faxis/backup" >/dev/null
job=$(json '["job"]')
wait_job "$job"
outcome=$(json '["outcome"]')
for _ in $(seq 40); do grep -q '"drift"' hooks.jsonl events.txt 2>/dev/null && [[ -s events.txt ]] && break; sleep 0.5; done
st=$(drive_status)
if [[ $outcome == done && $st == drift ]] && grep -q '"event":"drift"' hooks.jsonl 2>/dev/null &&
  grep -q '"event":"drift"' events.txt 2>/dev/null; then
  ok "drift found by an API backup; the webhook (Python receiver) and the notify command (batch file) got the event"
else
  bad "drift: job $job '$outcome', status '$st', webhook '$(tail -c 200 hooks.jsonl 2>/dev/null)', command '$(tail -c 200 events.txt 2>/dev/null)': $(grep -i notify serve.err | tail -2)"
fi

# 3. Plan and execute the approved configuration back onto the drive.
t0=$(date +%s)
# A plan reads the drive on the line's worker: while that takes longer than
# the service's bounded wait (Wine is slow) the answer is 503 "line busy" with
# Retry-After, and asking again gets the read's answer (docs/serve.md "Live reads").
for _ in $(seq 60); do
  api POST "/api/v1/drives/cell1%2Faxis/plan" '{}' >/dev/null
  [[ $status == 503 ]] || break
  sleep 2
done
plan=$(json '["plan_id"]')
api POST "/api/v1/plans/$plan/execute" '{"reason":"put back after a test change","ticket":"T-1"}' >/dev/null
job=$(json '["job"]')
wait_job "$job"
outcome=$(json '["outcome"]')
st=$(drive_status)
subject=$(git -C archive log -1 --format=%s)
if [[ $outcome == "restored and verified" && $st == ok && $subject == "fleet restore: cell1/axis <- "* ]]; then
  ok "plan and execute: restored and verified, status ok, the restore commit recorded ($subject)"
else
  bad "plan $plan / job $job: outcome '$outcome', status '$st', last commit '$subject': $(tail -c 300 api.body)"
fi

# 4. What a web page in a browser may not do, and /metrics.
t0=$(date +%s)
host_status=$(curl -s -m 10 -o /dev/null -w '%{http_code}' -H "Host: evil.example" "$url/api/v1/drives")
origin_status=$(curl -s -m 10 -o /dev/null -w '%{http_code}' -X POST -H "Origin: http://evil.example" "$url/api/v1/drives/cell1%2Faxis/backup")
console_status=$(curl -s -m 10 -o console.html -w '%{http_code}' "$url/")
curl -s -m 10 "$url/metrics" >metrics.txt
metrics_ok=1
if command -v promtool >/dev/null; then promtool check metrics <metrics.txt >promtool.txt 2>&1 || metrics_ok=0; fi
if [[ $host_status == 421 && $origin_status == 403 && $console_status == 200 && $metrics_ok == 1 ]] &&
  grep -q '^lmcfg_drive_drift{drive="cell1/axis",line="cell1"} 0' metrics.txt && grep -q 'cell1/axis' console.html; then
  ok "foreign Host 421, foreign Origin 403, the console's page 200, /metrics$(command -v promtool >/dev/null && echo ' (promtool check metrics)')"
else
  bad "Host $host_status, Origin $origin_status, console $console_status, metrics ok $metrics_ok: $(head -3 promtool.txt 2>/dev/null) $(grep -c . metrics.txt) lines"
fi

# 5. Ctrl-C: the service finishes what is in flight and stops (exit 0).
t0=$(date +%s)
serve_pid=${pids[-1]}
kill -INT "$serve_pid"
rc=124
for _ in $(seq 60); do
  if ! kill -0 "$serve_pid" 2>/dev/null; then
    wait "$serve_pid"
    rc=$?
    break
  fi
  sleep 0.5
done
if ((rc == 0)) && grep -q "lmcfg serve: stopped" serve.err; then
  ok "Ctrl-C (SIGINT to Wine): 'stopping ... stopped', exit 0"
else
  bad "Ctrl-C: exit $rc: $(tail -3 serve.err)"
fi

# 6. Tokens: a viewer's token reads, nothing else does.
t0=$(date +%s)
token=$(win serve token add grafana --role viewer --tokens tokens 2>token.err | tr -d '\r')
start_bg serve2 60 "$wine" "$exe" serve plant.toml --archive archive --listen 127.0.0.1:0 --tokens tokens
url="$(first serve2)"
hdr=()
api GET /api/v1/drives >/dev/null
no_token=$status
hdr=(-H "Authorization: Bearer $token")
api GET /api/v1/drives >/dev/null
viewer_get=$status
api POST "/api/v1/drives/cell1%2Faxis/backup" >/dev/null
viewer_post=$status
hdr=()
kill -INT "${pids[-1]}"
if [[ ${#token} == 64 && $no_token == 401 && $viewer_get == 200 && $viewer_post == 403 ]]; then
  ok "serve token add, then --tokens: no token 401, a viewer's GET 200, its POST 403"
else
  bad "tokens: token '${token:0:8}...' (${#token} chars), no token $no_token, viewer GET $viewer_get, POST $viewer_post: $(cat token.err) $(tail -2 serve2.err)"
fi

# 7. HTTPS (Mbed TLS in the Windows build) with tokens, listening on every
# address (other hosts need both): curl over TLS 1.2 with an AEAD suite gets
# its answer; TLS 1.1, a CBC suite and plain HTTP get nothing.
t0=$(date +%s)
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout key.pem \
  -out cert.pem -days 2 -subj /CN=127.0.0.1 -addext subjectAltName=IP:127.0.0.1 >openssl.txt 2>&1
start_bg serve3 60 "$wine" "$exe" serve plant.toml --archive archive --listen 0.0.0.0:0 --tokens tokens \
  --tls-cert cert.pem --tls-key key.pem
url="$(first serve3)"
url="https://127.0.0.1:${url##*:}"
tls() { curl -s -m 10 --cacert cert.pem -H "Authorization: Bearer $token" -o /dev/null -w '%{http_code}' "$@" "$url/api/v1/drives"; }
aead=$(curl -sv -m 10 --cacert cert.pem -H "Authorization: Bearer $token" -o /dev/null "$url/api/v1/drives" 2>&1 | grep -o 'SSL connection using [^ ]* / [^ ]*' | tr -d '\r')
https_status=$(tls)
tls11=$(tls --tls-max 1.1)
cbc=$(tls --tls-max 1.2 --ciphers ECDHE-ECDSA-AES128-SHA:ECDHE-RSA-AES128-SHA:AES128-SHA)
plain=$(curl -s -m 10 -o /dev/null -w '%{http_code}' "http://127.0.0.1:${url##*:}/api/v1/drives")
kill -INT "${pids[-1]}"
if [[ $https_status == 200 && $aead == *"TLSv1.2 / ECDHE-ECDSA-AES128-GCM-SHA256" && $tls11 == 000 && $cbc == 000 && $plain == 000 ]]; then
  ok "HTTPS on 0.0.0.0 with tokens: $aead, 200; TLS 1.1, a CBC suite and plain HTTP refused"
else
  bad "HTTPS: '$aead' $https_status, TLS 1.1 $tls11, CBC $cbc, plain $plain: $(tail -2 serve3.err) $(tail -2 openssl.txt)"
fi

# 8. What the Windows build refuses at start, with the exit code of refused input.
t0=$(date +%s)
refusals=()
check_refusal() { # NAME EXPECTED_EXIT TEXT ARGS...
  local name=$1 want=$2 text=$3
  shift 3
  win "$@" >/dev/null 2>"$name.err"
  local rc=$?
  grep -qF -- "$text" "$name.err" && ((rc == want)) || refusals+=("$name: exit $rc, $(tr -d '\r' <"$name.err" | tail -1)")
}
check_refusal tls 2 "--tls-cert c.pem / --tls-key k.pem: cannot load them as a PEM certificate and its private key" \
  serve plant.toml --archive archive --tls-cert c.pem --tls-key k.pem
check_refusal exposed 2 "is not a loopback address: serving other hosts needs --tokens and --tls-cert/--tls-key" \
  serve plant.toml --archive archive --listen 0.0.0.0:0
sed 's#^webhook = "http://#webhook = "https://#' plant.toml >https.toml
check_refusal https 2 "this build of lmcfg serve posts to http:// webhooks only" \
  serve https.toml --archive archive
printf 'x viewer %064d\n' 0 >open-tokens
chmod 0666 open-tokens
check_refusal open-tokens 2 "the tokens file is writable by Everyone" \
  serve plant.toml --archive archive --tokens open-tokens
if ((${#refusals[@]} == 0)); then
  ok "refused at start: TLS files that do not load, a non-loopback --listen without tokens and TLS, an https:// webhook, a tokens file others may write"
else
  bad "refusals: ${refusals[*]}"
fi

echo "$passed passed, $failed failed ($(($(date +%s) - start_all)) s; $work)"
((failed == 0))
