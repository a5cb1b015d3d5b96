#!/usr/bin/env python3
"""The longest C++ function bodies of the tree, in lines (issue 55: none over 100).

A brace scanner, not a parser: comments, strings and raw strings are blanked, and a body is a
`{` at namespace or class level whose head ends like a function's (`) {`, `) const {`, a
constructor's initializer list); lambdas and blocks inside a function count as its lines.
Prints the N longest as `lines path:line`; --max L exits 1 when one is over L lines, and
--max-command L when a file of apps/ (the commands: flags and calls) is over L lines.
"""
import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SKIP = {".git", "build", "build-asan"}


def blank(text):
    """Comments and literals replaced by nothing, their newlines kept."""
    out, i, n = [], 0, len(text)
    while i < n:
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"(', i):
            j = text.find(')"', i + 3)
            j = n if j < 0 else j + 2
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif text[i] in "\"'":
            quote, j = text[i], i + 1
            while j < n and text[j] != quote:
                j += 2 if text[j] == "\\" else 1
            out.append(quote * 2)
            i = j + 1
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


FUNCTION_HEAD = re.compile(r"\)\s*(const)?\s*(noexcept)?\s*(override|final)?\s*(->\s*[\w:<>, ]+)?\s*$")
CONTROL_HEAD = re.compile(r"\b(if|for|while|switch|catch)\s*\([^;{}]*\)\s*$")
INIT_LIST = re.compile(r"\)\s*:\s*[\w:]+[({][^;{}]*[)}]\s*$", re.S)


def bodies(path):
    """(lines, first line) of every function body in the file."""
    text = blank(open(path, errors="replace").read())
    stack, line, found = [], 1, []
    for i, c in enumerate(text):
        if c == "\n":
            line += 1
        elif c == "{":
            head = text[max(0, i - 300):i].rstrip()
            inside = any(kind == "fn" for kind, _ in stack)
            is_fn = not inside and (bool(FUNCTION_HEAD.search(head)) and not CONTROL_HEAD.search(head)
                                    or bool(INIT_LIST.search(head)))
            stack.append(("fn" if is_fn else "block", line))
        elif c == "}" and stack:
            kind, first = stack.pop()
            if kind == "fn":
                found.append((line - first + 1, first))
    return found


def sources():
    """The C++ files of the tree: git's tracked ones, or every one outside build folders."""
    if os.path.isdir(os.path.join(ROOT, ".git")):
        listed = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True).stdout.split()
        return [f for f in listed if f.endswith((".cpp", ".hpp", ".h")) and os.path.exists(os.path.join(ROOT, f))]
    found = []
    for dirpath, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in SKIP and not d.startswith("build")]
        found += [os.path.relpath(os.path.join(dirpath, n), ROOT) for n in files if n.endswith((".cpp", ".hpp", ".h"))]
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--top", type=int, default=20, help="how many to print (default 20)")
    ap.add_argument("--max", type=int, help="exit 1 when a function is longer than this many lines")
    ap.add_argument("--max-command", type=int, help="exit 1 when a file of apps/ is longer than this many lines")
    a = ap.parse_args()
    found, long_commands = [], []
    for path in sorted(sources()):
        found += [(n, path, first) for n, first in bodies(os.path.join(ROOT, path))]
        if a.max_command is not None and path.startswith("apps/"):
            lines = open(os.path.join(ROOT, path), errors="replace").read().count("\n")
            if lines > a.max_command:
                long_commands.append(f"{path}: {lines} lines, over {a.max_command}")
    found.sort(key=lambda f: (-f[0], f[1], f[2]))
    for n, path, first in found[:a.top]:
        print(f"{n:5d} {path}:{first}")
    over = [f for f in found if a.max is not None and f[0] > a.max]
    if over:
        print(f"{len(over)} function(s) over {a.max} lines", file=sys.stderr)
    for line in long_commands:
        print(line, file=sys.stderr)
    return 1 if over or long_commands else 0


if __name__ == "__main__":
    sys.exit(main())
