#!/usr/bin/env bash
# Validates lmcfg JSON configuration files against schemas/lmcfg-config-v3.schema.json
# with ajv (JSON Schema draft 2020-12). Exit 0 when every file is valid, 1 when
# one is not, 2 on usage or setup errors. Installs ajv on first use.
#   scripts/validate-json.sh FILE.json...
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
schema="$root/schemas/lmcfg-config-v3.schema.json"
ajv="$root/tools/node/node_modules/.bin/ajv"
if [[ $# -eq 0 ]]; then
  echo "usage: $0 FILE.json..." >&2
  exit 2
fi
if [[ ! -x "$ajv" ]]; then
  "$root/scripts/install-node-deps.sh" >&2 || { echo "validate-json.sh: cannot install ajv" >&2; exit 2; }
fi
common=(--spec=draft2020 --strict=true -s "$schema")
data=()
for f in "$@"; do
  [[ -f "$f" ]] || { echo "validate-json.sh: $f: no such file" >&2; exit 2; }
  data+=(-d "$f")
done
out="$("$ajv" validate "${common[@]}" --all-errors --errors=text "${data[@]}" 2>&1)"
rc=$?
printf '%s\n' "$out" >&2
if grep -q "^schema .* is invalid" <<<"$out"; then
  echo "validate-json.sh: the schema itself is invalid" >&2
  exit 2
fi
[[ $rc -eq 0 ]] || exit 1
exit 0
