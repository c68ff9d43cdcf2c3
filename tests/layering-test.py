#!/usr/bin/env python3
"""The build enforces the layering of lib/ (docs/architecture.md): with the
include flags of each layer's own sources (compile_commands.json), a header of
every layer it declares compiles and a header of any other layer does not.
usage: layering-test.py BUILD_DIR SOURCE_DIR"""
import concurrent.futures, json, os, re, shlex, subprocess, sys, tempfile

build, source = sys.argv[1], sys.argv[2]


def declared_layers(cmake_text):
    """{layer: {layers it may include, itself among them}} from the
    lmcfg_layer(NAME LAYERS ... LIBS ...) calls of lib/CMakeLists.txt, the one
    place the layering is declared."""
    allowed = {}
    for m in re.finditer(r"^lmcfg_layer\(([^)]*)\)", cmake_text, re.M):
        words = m.group(1).split()
        layer, deps, mode = words[0], {words[0]}, None
        for w in words[1:]:
            if w in ("LAYERS", "LIBS"):
                mode = w
            elif mode == "LAYERS" and not w.startswith("${"):
                # A variable holds the platform's extra layers (Windows'): the
                # layering checked here is the Linux build's.
                deps.add(w)
        allowed[layer] = deps
    return allowed


ALLOWED = declared_layers(open(os.path.join(source, "lib", "CMakeLists.txt")).read())
if len(ALLOWED) < 2:
    sys.exit("layering-test: found no lmcfg_layer() calls in lib/CMakeLists.txt")
commands = json.load(open(os.path.join(build, "compile_commands.json")))
header_of = {}
for layer in ALLOWED:
    hs = sorted(f for f in os.listdir(os.path.join(source, "lib", layer)) if f.endswith(".hpp"))
    header_of[layer] = f"{layer}/{hs[0]}"
failures, checks = [], 0
# Pairs refused whatever lib/CMakeLists.txt declares (the compile checks below
# test the declaration, so a wrong one would pass them): the HTTP server
# (lib/web) knows nothing of the service, its routes or its console.
MUST_REFUSE = [("web", "serve")]
for layer, other in MUST_REFUSE:
    checks += 1
    if layer not in ALLOWED or other not in ALLOWED:
        failures.append(f"lib/CMakeLists.txt declares no layer {layer if layer not in ALLOWED else other}")
    elif other in ALLOWED[layer]:
        failures.append(f"lib/CMakeLists.txt lets lib/{layer} use {other}: it must not "
                        f"(tests/layering-test.py MUST_REFUSE)")


def check(job):
    """One include check: the preprocessor alone (-E) with the layer's flags,
    since what the layering decides is which headers the include path reaches;
    the precompiled header (-include cmake_pch.hxx) is left out: it brings
    only outside libraries. Returns a failure or None."""
    layer, other, entry, src = job
    args = shlex.split(entry["command"])
    i, o = args.index("-c"), args.index("-o")
    # Without the compile of the source (-c FILE), its object (-o FILE) and
    # its dependency file (-MD -MT X -MF Y): the build's own files stay as
    # the build wrote them.
    drop = {i, i + 1, o, o + 1}
    for k, a in enumerate(args):
        if a in ("-MD", "-MMD"):
            drop.add(k)
        elif a in ("-MF", "-MT", "-MQ"):
            drop.update((k, k + 1))
    cmd = [a for k, a in enumerate(args) if k not in drop]
    while "-include" in cmd:
        k = cmd.index("-include")
        del cmd[k:k + 2]
    cmd += ["-E", src, "-o", os.devnull]
    ok = subprocess.run(cmd, cwd=entry["directory"], capture_output=True).returncode == 0
    if ok != (other in ALLOWED[layer]):
        return (f"lib/{layer} including {header_of[other]}: "
                f"{'compiles' if ok else 'fails'}, expected "
                f"{'success' if other in ALLOWED[layer] else 'failure'}")
    return None


with tempfile.TemporaryDirectory() as tmp:
    jobs = []
    for layer in ALLOWED:
        # A layer's own source, or (unity build, CMakeLists.txt) one of its
        # target's batch files: the same flags either way.
        entry = next(c for c in commands
                     if (f"/lib/{layer}/" in c["file"] and c["file"].endswith(".cpp"))
                     or f"/lmcfg_{layer}.dir/Unity/" in c["file"])
        for other in ALLOWED:
            src = os.path.join(tmp, f"{layer}-{other}.cpp")
            with open(src, "w") as f:
                f.write(f'#include "{header_of[other]}"\n')
            jobs.append((layer, other, entry, src))
    with concurrent.futures.ThreadPoolExecutor(os.cpu_count() or 2) as pool:
        for failure in pool.map(check, jobs):
            checks += 1
            if failure:
                failures.append(failure)
for f in failures:
    print("layering-test:", f)
print(f"layering-test: {checks - len(failures)} of {checks} include checks as declared")
sys.exit(1 if failures else 0)
