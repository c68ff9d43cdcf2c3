#!/usr/bin/env bash
# Installs everything lmcfg needs to build and test, from Debian's packages and
# the npm registry. Idempotent: installs only what is missing. Run as root (or
# with sudo available).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"

packages=(
  build-essential cmake pkg-config git            # toolchain
  libsqlite3-dev sqlite3                          # UPID database
  libpugixml-dev nlohmann-json3-dev               # XML and JSON files
  libgit2-dev libtomlplusplus-dev                 # fleet: git archive, TOML inventory
  libcpp-httplib-dev libssl-dev prometheus        # serve: HTTP server/client; promtool checks /metrics
  catch2 libcli11-dev                             # tests (Catch2 v2) and command line
  libbenchmark-dev                                # CPU benchmarks
  libxml2-utils                                   # xmllint: validates the XSD in tests
  nodejs npm                                      # ajv-cli: validates the JSON Schema in tests
  clang libclang-rt-14-dev                        # libFuzzer targets with sanitizers
  clang-format                                    # scripts/check-format.sh (CI)
  help2man man-db groff-base bsdextrautils        # man page: generate, render (man -l), col -b
  bash-completion                                 # completion test
  dpkg-dev file debootstrap                       # cpack -G DEB (dpkg-shlibdeps), scripts/test-deb.sh
  chromium                                        # headless browser: tests load every lmcfg report page
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# node/npm may come from elsewhere on the machine: only ask apt when the commands are absent.
if command -v node >/dev/null && command -v npm >/dev/null; then
  missing=("${missing[@]/nodejs}")
  missing=("${missing[@]/npm}")
fi
missing=($(printf '%s\n' "${missing[@]}" | grep -v '^$' || true))
if ((${#missing[@]})); then
  sudo_cmd=""
  [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  echo "install-deps: installing ${missing[*]}"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
"$root/scripts/install-node-deps.sh"
