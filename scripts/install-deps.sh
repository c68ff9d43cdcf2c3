#!/usr/bin/env bash
# Installs everything lmcfg needs to build and test, from Debian's packages and
# the npm registry. Idempotent: installs only what is missing. Run as root (or
# with sudo available).
#   install-deps.sh          build + test + CI (browser, packaging, fuzzing)
#   install-deps.sh --demo   only what building `lmcfg` and its database needs
#                            (scripts/demo.sh)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode=all
[[ "${1:-}" == --demo ]] && mode=demo

build_packages=(
  build-essential cmake pkg-config git ccache     # toolchain (ccache: scripts/build.sh uses it when present)
  libsqlite3-dev sqlite3                          # UPID database
  libpugixml-dev nlohmann-json3-dev               # XML and JSON files
  libgit2-dev libtomlplusplus-dev                 # fleet: git archive, TOML inventory
  libcli11-dev                                    # command line
  libcpp-httplib-dev libssl-dev                   # lmcfg serve: HTTP server and webhook client
  help2man                                        # man page, generated from --help at build time
)
test_packages=(
  catch2                                          # tests (Catch2 v2)
  prometheus                                      # promtool checks lmcfg serve's /metrics
  openssl curl                                    # lmcfg serve TLS test: self-signed certificate, curl --cacert
  libbenchmark-dev                                # CPU benchmarks
  libxml2-utils                                   # xmllint: validates the XSD in tests
  nodejs npm                                      # ajv-cli: validates the JSON Schema in tests
  clang libclang-rt-14-dev                        # libFuzzer targets with sanitizers
  clang-format                                    # scripts/check-format.sh (CI)
  man-db groff-base bsdextrautils                 # man page: render (man -l), col -b
  bash-completion                                 # completion test
  dpkg-dev file debootstrap                       # cpack -G DEB (dpkg-shlibdeps), scripts/test-deb.sh
  chromium                                        # headless browser: tests load every lmcfg report page
  python3-dev pybind11-dev python3-pytest         # Python bindings (docs/python.md) and their tests
  ser2net                                         # RFC 2217 transport tests and bench against the real server
)
packages=("${build_packages[@]}")
[[ $mode == all ]] && packages+=("${test_packages[@]}")
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
[[ $mode == all ]] && "$root/scripts/install-node-deps.sh"
exit 0
