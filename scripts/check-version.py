#!/usr/bin/env python3
"""The version is declared once, in CMakeLists.txt's project(lmcfg VERSION
X.Y.Z); the places that must name it by hand agree with it (ctest
version_pins):

- every find_package(lmcfg X.Y ...) in examples/, docs/ and README.md asks for
  the declared major.minor (lmcfgConfigVersion.cmake accepts the same minor
  version only: SameMinorVersion, since 0.x may change the API);
- README.md's Debian package file name lmcfg_X.Y.Z-1_ARCH.deb;
- CHANGELOG.md has a section for the declared version.

usage: check-version.py SOURCE_DIR"""
import os
import re
import sys


def main(root):
    with open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(lmcfg VERSION (\d+)\.(\d+)\.(\d+)", f.read())
    if not m:
        print("CMakeLists.txt: no project(lmcfg VERSION X.Y.Z)")
        return 1
    version = ".".join(m.groups())
    minor = ".".join(m.groups()[:2])
    files = ["README.md"]
    for top in ("docs", "examples"):
        for folder, _, names in os.walk(os.path.join(root, top)):
            for name in sorted(names):
                if name.endswith((".md", ".txt", ".cmake")):
                    files.append(os.path.relpath(os.path.join(folder, name), root))
    problems = []
    for rel in files:
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                for pin in re.findall(r"find_package\(lmcfg (\d+\.\d+)", line):
                    if pin != minor:
                        problems.append(f"{rel}:{number}: find_package(lmcfg {pin}) but the "
                                        f"project is {version}: ask for {minor}")
                for deb in re.findall(r"lmcfg_(\d+\.\d+\.\d+)-1_", line):
                    if deb != version:
                        problems.append(f"{rel}:{number}: package lmcfg_{deb} but the "
                                        f"project is {version}")
    with open(os.path.join(root, "CHANGELOG.md"), encoding="utf-8") as f:
        if not re.search(r"^## " + re.escape(version) + r"\b", f.read(), re.M):
            problems.append(f"CHANGELOG.md: no section '## {version}' for the declared version")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
