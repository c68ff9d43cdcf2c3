#!/usr/bin/env python3
"""Size limits of the sources (docs/architecture.md "Sizes"): no file in lib/,
tools/ or python/ over 700 lines, no function over 100 lines, but the tables
the allowlist below names. A function is measured from the line of its opening
brace to the line of its closing brace, comments included; lambdas and local
classes count towards the function around them. Member functions defined in a
class body are functions too. Brace-initialised data (tables) is not a function.

The measurement is a heuristic over the text (comments, strings and raw
strings removed, braces counted), not a C++ parser: a macro that opens a brace
it does not close would confuse it, and none of ours does.

usage: check-sizes.py SOURCE_DIR [--list N]
  exit 0: within the limits; 1: the files and functions over them, one a line
  as PATH:LINE: what (the allowlist is named in the message).
  --list N: print the N longest functions and files instead, and exit 0."""
import pathlib
import re
import sys

MAX_FILE_LINES = 700
MAX_FUNCTION_LINES = 100
FOLDERS = ("lib", "tools", "python")
SUFFIXES = (".cpp", ".hpp", ".h", ".py", ".pyi")
BRACED = (".cpp", ".hpp", ".h")

# Allowed over the limits, each with why. A function is named by its path and
# the start of its head as --list prints it.
ALLOWED_FUNCTIONS = {
    # A table: one case per LinRS request (LinRS §8-§12), the one request/answer
    # table the client and the simulator share; splitting it scatters the table.
    ("lib/codec/requests.cpp", "std::optional<RequestSpec> request_spec("): "table",
}
ALLOWED_FILES = {}


def strip(text):
    """The text without comments, string and character literals (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
            continue
        m = re.match(r'R"([^(\s]*)\(', text[i:i + 20]) if c == "R" and (i == 0 or not text[i - 1].isalnum()) else None
        if m:
            end = ")" + m.group(1) + '"'
            j = text.find(end, i)
            j = n if j < 0 else j + len(end)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
            continue
        # A quote after a digit is a digit separator (1'000'000), not a literal.
        if c == '"' or (c == "'" and not (i > 0 and text[i - 1].isalnum())):
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                if text[j] == "\\":
                    j += 1
                j += 1
            out.append(c + c + "\n" * text.count("\n", i, j))
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def kind_of(head, stack):
    """What a brace opens, from the text since the previous ; { or }."""
    h = " ".join(head.split())
    h = re.sub(r"^(public|private|protected)\s*:\s*", "", h)
    at_scope = all(s[0] == "scope" for s in stack)
    if (re.search(r"\bnamespace\b", h) or h.startswith('extern "')
            or re.match(r"^(template\s*<.*>\s*)?(class|struct|union|enum)\b", h)):
        return "scope", h
    # A variable initialised by a call (`const auto t = make({`) is data; an
    # `operator=` or `operator==` is a function.
    before_paren = re.sub(r"\boperator\s*\S+$", "", h.split("(")[0])
    assigned = re.search(r"(?<![=!<>])=(?!=)", before_paren)
    if at_scope and "(" in h and not assigned:
        return "function", h
    if at_scope:
        return "data", h
    return "inner", h


def functions(text):
    """(lines, first line, head) of every function body of the text."""
    t = strip(text)
    stack, found, line = [], [], 1
    last = -1  # index of the previous ; { or }
    for idx, ch in enumerate(t):
        if ch == "\n":
            line += 1
        elif ch == ";":
            last = idx
        elif ch == "{":
            kind, head = kind_of(t[last + 1:idx], stack)
            stack.append((kind, line, head))
            last = idx
        elif ch == "}":
            if stack:
                kind, first, head = stack.pop()
                if kind == "function":
                    found.append((line - first + 1, first, head))
            last = idx
    return found


def sources(root):
    for folder in FOLDERS:
        for p in sorted((root / folder).rglob("*")):
            if p.is_file() and p.suffix in SUFFIXES and "build" not in p.relative_to(root).parts[1:2]:
                yield p


def main():
    args = sys.argv[1:]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    root = pathlib.Path(args[0])
    listing = int(args[2]) if len(args) > 2 and args[1] == "--list" else None
    files, funcs = [], []
    for p in sources(root):
        rel = p.relative_to(root).as_posix()
        text = p.read_text(errors="replace")
        files.append((text.count("\n") + (0 if text.endswith("\n") or not text else 1), rel))
        if p.suffix in BRACED:
            funcs += [(n, rel, first, head) for n, first, head in functions(text)]
    if listing is not None:
        for n, rel, first, head in sorted(funcs, reverse=True)[:listing]:
            print(f"{n:5}  {rel}:{first}  {head[:80]}")
        for n, rel in sorted(files, reverse=True)[:listing]:
            print(f"{n:5}  {rel}")
        return 0
    problems = []
    for n, rel in files:
        if n > MAX_FILE_LINES and rel not in ALLOWED_FILES:
            problems.append(f"{rel}: {n} lines, more than {MAX_FILE_LINES}")
    for n, rel, first, head in funcs:
        allowed = any(rel == path and head.startswith(start) for path, start in ALLOWED_FUNCTIONS)
        if n > MAX_FUNCTION_LINES and not allowed:
            problems.append(f"{rel}:{first}: function `{head[:80]}` has {n} lines, "
                            f"more than {MAX_FUNCTION_LINES}")
    for path, _ in ALLOWED_FUNCTIONS:
        if not (root / path).exists():
            problems.append(f"{path}: in the allowlist of scripts/check-sizes.py, but absent")
    for path in ALLOWED_FILES:
        if not (root / path).exists():
            problems.append(f"{path}: in the allowlist of scripts/check-sizes.py, but absent")
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} over the limits: split them into named steps, or (a table) "
              "add them with the reason to the allowlist in scripts/check-sizes.py")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
