#!/usr/bin/env bash
# Writes a release of lmcfg into dist/ from a git tag (docs/release.md):
#   dist/lmcfg-VERSION.tar.gz           the source, as `git archive` of the tag
#   dist/lmcfg_VERSION-1_ARCH.deb       the Debian package, built from that tarball
#   dist/lmcfg-VERSION-win64.zip        lmcfg.exe and its database (scripts/build-windows.sh)
#   dist/SHA256SUMS                     the checksums of the three
# Reproducible: every time stamp is the tag's commit time (SOURCE_DATE_EPOCH),
# the builds run from the unpacked tarball in one fixed folder with the source
# path mapped away, and the archives are written in sorted order, so two runs
# from the same tag on the same kind of machine give byte-identical files.
#   scripts/release.sh [TAG]    TAG: vX.Y.Z, the version in CMakeLists.txt's
#                               project() at that tag; default: the tag at HEAD
#   LMCFG_RELEASE_WINDOWS=0     leaves the Windows zip out (no MinGW-w64/Wine)
#   LMCFG_RELEASE_WORK=DIR      the build folder (default /tmp/lmcfg-release)
# Exit codes: 0 written; 2 usage (no such tag, tag and version disagree,
# missing tools); 1 a build step failed (its output is above).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
die() {
  echo "release: $1" >&2
  exit "${2:-2}"
}

tag="${1:-}"
if [[ -z $tag ]]; then
  tag=$(git describe --exact-match --tags HEAD 2>/dev/null) ||
    die "HEAD has no tag: name one (scripts/release.sh v0.2.0) or tag HEAD first (git tag -a vX.Y.Z)"
fi
git rev-parse -q --verify "refs/tags/$tag" >/dev/null ||
  die "no tag '$tag' in this repository (git tag -l lists them)"
version=$(git show "$tag:CMakeLists.txt" | sed -n 's/^project(lmcfg VERSION \([0-9.]*\).*/\1/p')
[[ $tag == "v$version" ]] ||
  die "tag '$tag' does not name the version its CMakeLists.txt declares ($version): expected v$version"
grep -q "^## $version " <(git show "$tag:CHANGELOG.md" 2>/dev/null) ||
  die "CHANGELOG.md at $tag has no section '## $version': write what changed for users first"
for tool in cmake cpack gzip sha256sum dpkg-deb; do
  command -v "$tool" >/dev/null || die "$tool not found: run scripts/install-deps.sh (as root)"
done

export SOURCE_DATE_EPOCH
SOURCE_DATE_EPOCH=$(git log -1 --format=%ct "$tag^{commit}")
export TZ=UTC LC_ALL=C.UTF-8
# The archives' owners and modes must not depend on who runs this.
umask 022
dist="$root/dist"
work="${LMCFG_RELEASE_WORK:-/tmp/lmcfg-release}"
name="lmcfg-$version"
src="$work/$name"
rm -rf "$work" "$dist"
mkdir -p "$work" "$dist"
t0=$(date +%s)
step() { echo "==== release: $1 ($(($(date +%s) - t0)) s since the start)"; }

step "source tarball of $tag ($(git rev-parse --short=12 "$tag^{commit}"), SOURCE_DATE_EPOCH=$SOURCE_DATE_EPOCH)"
# git archive stamps every entry with the commit time; gzip -n leaves out the
# name and time it would otherwise write into its header.
git archive --format=tar --prefix="$name/" "$tag" | gzip -n -9 >"$dist/$name.tar.gz" ||
  die "git archive of $tag failed" 1
tar -xzf "$dist/$name.tar.gz" -C "$work"

step "Debian package (Release build of the tarball, without ccache)"
# The build path is mapped away, so the binaries do not depend on $work.
map="-ffile-prefix-map=$work=/usr/src"
cmake -S "$src" -B "$src/build" -DCMAKE_BUILD_TYPE=Release -DLMCFG_BUILD_TESTS=OFF \
  -DLMCFG_BUILD_BENCH=OFF -DCMAKE_C_FLAGS="$map" -DCMAKE_CXX_FLAGS="$map" >"$work/configure.log" ||
  die "cmake configure failed ($work/configure.log)" 1
cmake --build "$src/build" -j"$(nproc)" || die "the Release build failed (its output is above)" 1
(cd "$src/build" && cpack -G DEB >"$work/cpack.log") || die "cpack failed ($work/cpack.log)" 1
deb=$(find "$src/build" -maxdepth 1 -name "lmcfg_${version}-*.deb" | head -1)
[[ -n $deb ]] || die "cpack wrote no lmcfg_${version}-*.deb ($work/cpack.log)" 1
cp "$deb" "$dist/"

if [[ ${LMCFG_RELEASE_WINDOWS:-1} == 1 ]]; then
  step "Windows zip (scripts/build-windows.sh of the tarball)"
  command -v x86_64-w64-mingw32-g++-posix >/dev/null ||
    die "the MinGW-w64 cross compiler is missing: run scripts/install-deps.sh --windows, or LMCFG_RELEASE_WINDOWS=0"
  # The dependencies built for MinGW are kept between releases (they are
  # Debian's source packages, stamped by version): the checkout's folder.
  LMCFG_WINDOWS_DIR="$root/build-windows" CCACHE_DISABLE=1 \
    LMCFG_WINDOWS_BUILD="$work/build-windows" LMCFG_WINDOWS_OUT="$work" \
    LMCFG_WINDOWS_CXX_FLAGS="$map" "$src/scripts/build-windows.sh" ||
    die "the Windows build failed (its output is above)" 1
  cp "$work/$name-win64.zip" "$dist/"
fi

step "SHA256SUMS"
(cd "$dist" && sha256sum -- *.tar.gz *.deb $(ls ./*.zip 2>/dev/null | sed 's|^\./||') >SHA256SUMS)
cat "$dist/SHA256SUMS"
step "done: $dist"
