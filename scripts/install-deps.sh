#!/usr/bin/env bash
# Installs everything lmcfg needs to build and test, from Debian's packages and
# the npm registry. Idempotent: installs only what is missing. Run as root (or
# with sudo available).
#   install-deps.sh          build + test + CI (browser, packaging, fuzzing)
#   install-deps.sh --demo   only what building `lmcfg` and its database needs
#                            (scripts/demo.sh)
#   install-deps.sh --windows  also the MinGW-w64 cross compiler, Wine and what
#                            scripts/build-windows.sh needs to build lmcfg.exe's
#                            dependencies from Debian's source packages (docs/windows.md)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
mode=all
windows=0
for arg in "$@"; do
  case $arg in
    --demo) mode=demo ;;
    --windows) windows=1 ;;
    *) echo "install-deps: unknown option $arg (expected --demo or --windows)" >&2; exit 2 ;;
  esac
done

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
windows_packages=(
  g++-mingw-w64-x86-64-posix                      # cross compiler (posix threads: std::thread, std::mutex)
  libz-mingw-w64-dev                              # zlib for libgit2, prebuilt by Debian for MinGW
  wine64                                          # runs lmcfg.exe and its tests (scripts/test-windows.sh)
  dpkg-dev                                        # apt-get source: SQLite, pugixml, libgit2 from Debian's sources
  zip                                             # build-windows/lmcfg-<version>-win64.zip
  tcl                                             # tclsh: SQLite's makefile generates its amalgamation with Tcl scripts
)
packages=("${build_packages[@]}")
[[ $mode == all ]] && packages+=("${test_packages[@]}")
((windows)) && packages+=("${windows_packages[@]}")
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
# scripts/build-windows.sh builds SQLite, pugixml and libgit2 from Debian's
# source packages (apt-get source): a deb-src entry for each archive the deb
# entries already name (same URIs, suites and keys).
if ((windows)); then
  src_list=/etc/apt/sources.list.d/lmcfg-deb-src.sources
  if ! apt-get source --print-uris -qq pugixml >/dev/null 2>&1; then
    : >"$src_list.tmp"
    for f in /etc/apt/sources.list.d/*.sources; do
      [[ -f $f && $f != "$src_list" ]] || continue
      grep -q 'deb.debian.org\|snapshot.debian.org' "$f" || continue
      sed 's/^Types: deb$/Types: deb-src/' "$f" >>"$src_list.tmp"
      echo >>"$src_list.tmp"
    done
    if [[ -f /etc/apt/sources.list ]]; then
      grep -E '^deb [^[]*debian' /etc/apt/sources.list | sed 's/^deb /deb-src /' \
        >/etc/apt/sources.list.d/lmcfg-deb-src.list || true
    fi
    mv "$src_list.tmp" "$src_list"
    echo "install-deps: added deb-src entries ($src_list)"
    apt-get update -qq
  fi
fi
[[ $mode == all ]] && "$root/scripts/install-node-deps.sh"
exit 0
