#!/usr/bin/env python3
"""The layer graph, printed from the one place that declares it: the
lmcfg_layer(NAME [PCH] LAYERS ... LIBS ...) calls of lib/CMakeLists.txt.

usage: layer-graph.py SOURCE_DIR            print the graph
       layer-graph.py SOURCE_DIR --check    compare it with the copies in the docs
       layer-graph.py SOURCE_DIR --update   rewrite the copies in the docs

A doc holds the graph between the lines
  <!-- layer-graph: begin (scripts/layer-graph.py prints it) -->
  <!-- layer-graph: end -->
(a fenced block in between); --check fails, naming the file, when a copy
differs from what this script prints, or when docs/development.md's table of
folders lacks a layer's `lib/<layer>` (ctest layer_graph_docs)."""
import os
import re
import sys

DOCS = ["docs/architecture.md", "docs/development.md"]
BEGIN = "<!-- layer-graph: begin (scripts/layer-graph.py prints it) -->"
END = "<!-- layer-graph: end -->"
WIDTH = 79
INDENT = 11


def strip_comments(text):
    """Removes '#' comments, leaving '#' inside quoted arguments alone."""
    out = []
    for line in text.splitlines():
        quoted = False
        cut = len(line)
        for i, c in enumerate(line):
            if c == '"' and (i == 0 or line[i - 1] != "\\"):
                quoted = not quoted
            elif c == "#" and not quoted:
                cut = i
                break
        out.append(line[:cut])
    return "\n".join(out)


def commands(text):
    """Yields (name, [arguments]) for each command call of a CMake file."""
    text = strip_comments(text)
    pos = 0
    call = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*\(")
    while True:
        m = call.search(text, pos)
        if not m:
            return
        depth, i = 1, m.end()
        while depth and i < len(text):
            depth += {"(": 1, ")": -1}.get(text[i], 0)
            i += 1
        args = re.findall(r'"[^"]*"|[^\s()]+', text[m.end():i - 1])
        yield m.group(1).lower(), args
        pos = i


def external_name(lib):
    """PkgConfig::SQLITE3 -> sqlite3, pugixml::pugixml -> pugixml."""
    return lib.split("::")[-1].lower()


def read_layers(source_dir):
    """[(layer, [layers], {platform: [libraries]})] in declaration order;
    platform is "" (every build), "linux" or "windows" (if(WIN32) ... else())."""
    with open(os.path.join(source_dir, "lib", "CMakeLists.txt"), encoding="utf-8") as f:
        text = f.read()
    layers, index, variables = [], {}, {}
    conditions, in_function = [], 0
    for name, args in commands(text):
        if name == "function":
            in_function += 1
        elif name == "endfunction":
            in_function -= 1
        if in_function:
            continue
        if name == "if":
            conditions.append("windows" if args == ["WIN32"] else "")
        elif name == "else" and conditions:
            conditions[-1] = "linux" if conditions[-1] == "windows" else conditions[-1]
        elif name == "endif" and conditions:
            conditions.pop()
        platform = next((c for c in reversed(conditions) if c), "")
        if name == "set" and args:
            variables.setdefault(args[0], {})[platform] = args[1:]
        if name != "lmcfg_layer":
            continue
        layer, deps, libs, section = args[0], [], [], None
        for a in args[1:]:
            if a in ("LAYERS", "LIBS", "PCH"):
                section = a
            elif section == "LAYERS":
                deps.append(a)
            elif section == "LIBS":
                var = re.fullmatch(r"\$\{(\w+)\}", a)
                if var:
                    for plat, values in variables.get(var.group(1), {}).items():
                        libs.append((plat or platform, values))
                else:
                    libs.append((platform, [a]))
        if layer not in index:
            index[layer] = len(layers)
            layers.append((layer, deps, {}))
        by_platform = layers[index[layer]][2]
        for plat, values in libs:
            by_platform.setdefault(plat, [])
            by_platform[plat] += [external_name(v) for v in values]
    return layers


def wrap(head, words):
    """head, then the words, wrapped at WIDTH under the first word."""
    lines, line = [], head
    for w in words:
        if len(line) + 1 + len(w) > WIDTH and line.strip() and len(line) > INDENT + 3:
            lines.append(line.rstrip())
            line = " " * (INDENT + 3)
        line += ("" if line.endswith(" ") else " ") + w
    lines.append(line.rstrip())
    return lines


def graph(source_dir):
    out = ["layer      -> the layers it declares (lib/CMakeLists.txt)",
           "           +  external libraries (Windows: those of the Windows build)"]
    for layer, deps, libs in read_layers(source_dir):
        out += wrap(layer.ljust(INDENT) + "->", deps or ["-"])
        words = list(libs.get("", [])) + list(libs.get("linux", []))
        if libs.get("windows"):
            words.append("(Windows: " + " ".join(libs["windows"]) + ")")
        if words:
            out += wrap(" " * INDENT + "+ ", words)
    return out


def block(lines):
    return [BEGIN, "```"] + lines + ["```", END]


def replace_block(text, lines, path):
    """The doc's text with the block between the markers replaced."""
    doc = text.split("\n")
    try:
        b, e = doc.index(BEGIN), doc.index(END)
    except ValueError:
        sys.exit(f"layer-graph: {path}: no '{BEGIN}' ... '{END}' block")
    return "\n".join(doc[:b] + block(lines) + doc[e + 1:])


def main(argv):
    if len(argv) < 2 or len(argv) > 3 or (len(argv) == 3 and argv[2] not in ("--check", "--update")):
        sys.exit(__doc__)
    source_dir = argv[1]
    lines = graph(source_dir)
    if len(argv) == 2:
        print("\n".join(lines))
        return 0
    stale = []
    for rel in DOCS:
        path = os.path.join(source_dir, rel)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        new = replace_block(text, lines, rel)
        if new == text:
            continue
        if argv[2] == "--update":
            with open(path, "w", encoding="utf-8") as f:
                f.write(new)
            print(f"layer-graph: {rel} updated")
        else:
            stale.append(rel)
    with open(os.path.join(source_dir, "docs", "development.md"), encoding="utf-8") as f:
        table = f.read()
    missing = [layer for layer, _, _ in read_layers(source_dir) if f"`lib/{layer}`" not in table]
    for layer in missing:
        print(f"layer-graph: docs/development.md: the table of folders has no row for "
              f"`lib/{layer}` (a layer of lib/CMakeLists.txt)")
    for rel in stale:
        print(f"layer-graph: {rel}: the layer graph differs from lib/CMakeLists.txt's; "
              f"run scripts/layer-graph.py . --update and commit the result")
    return 1 if stale or missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
