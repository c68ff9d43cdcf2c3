#!/usr/bin/env python3
"""The installed API is deliberate (lib/public-headers.txt): every header it
lists exists, every "layer/file.hpp" a listed header includes is listed too
(so an installed header never names one that was not installed), and no listed
header includes a third-party header the installed package does not promise
(sqlite3.h, git2.h, httplib.h: internals of the layers that use them).
usage: public-api-test.py SOURCE_DIR"""
import os, re, sys

source = sys.argv[1]
lib = os.path.join(source, "lib")
listed = [l.strip() for l in open(os.path.join(lib, "public-headers.txt"))
          if l.strip() and not l.startswith("#")]
PRIVATE_DEPS = ("sqlite3.h", "git2.h", "git2/", "httplib.h", "toml++", "pybind11")
failures = []
for h in listed:
    path = os.path.join(lib, h)
    if not os.path.exists(path):
        if os.path.exists(path + ".in"):
            path += ".in"
        else:
            failures.append(f"lib/public-headers.txt: {h} does not exist")
            continue
    for n, line in enumerate(open(path), 1):
        m = re.match(r'\s*#\s*include\s*[<"]([^>"]+)[>"]', line)
        if not m:
            continue
        inc = m.group(1)
        if '"' in line and "/" in inc and inc not in listed:
            failures.append(f"lib/{h}:{n}: includes \"{inc}\", which lib/public-headers.txt does not list")
        if any(inc.startswith(p) or inc == p for p in PRIVATE_DEPS):
            failures.append(f"lib/{h}:{n}: includes <{inc}>, a dependency the installed API does not promise")
for f in failures:
    print("public-api-test:", f)
print(f"public-api-test: {len(listed)} public headers, {len(failures)} problems")
sys.exit(1 if failures else 0)
