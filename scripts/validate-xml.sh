#!/usr/bin/env bash
# Validates lmcfg XML configuration files against schemas/lmcfg-config-v3.xsd
# with xmllint (libxml2-utils). Exit 0 when every file is valid, 1 when one is
# not, 2 on usage or setup errors.
#   scripts/validate-xml.sh FILE.xml...
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
schema="$root/schemas/lmcfg-config-v3.xsd"
if [[ $# -eq 0 ]]; then
  echo "usage: $0 FILE.xml..." >&2
  exit 2
fi
command -v xmllint >/dev/null || { echo "validate-xml.sh: xmllint not found (apt-get install libxml2-utils)" >&2; exit 2; }
status=0
for f in "$@"; do
  if ! xmllint --noout --nonet --schema "$schema" "$f" >&2; then
    status=1
  fi
done
exit $status
