#!/usr/bin/env bash
# Installs the Node validators (ajv-cli) into tools/node/node_modules from the
# committed package-lock.json. Idempotent: does nothing when the installed tree
# already matches the lock file.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
dir="$root/tools/node"
stamp="$dir/node_modules/.lmcfg-lock.sha256"
want="$(sha256sum "$dir/package-lock.json" | cut -d' ' -f1)"
if [[ -x "$dir/node_modules/.bin/ajv" && -f "$stamp" && "$(cat "$stamp")" == "$want" ]]; then
  exit 0
fi
command -v npm >/dev/null || { echo "install-node-deps.sh: npm not found (install nodejs/npm)" >&2; exit 1; }
(cd "$dir" && npm ci --no-audit --no-fund --loglevel=error)
echo "$want" > "$stamp"
