#!/usr/bin/env python3
"""Lists the C functions longer than a limit (default 150 lines, signature to closing brace).

Usage: scripts/long_functions.py [--max N] [DIR...]   (default DIRs: src cli)

It relies on the house style (STYLE.md): a function's body opens with a '{' alone at column 0
on the line after its signature and closes with a '}' alone at column 0. Prints one line per
long function, longest first: lines, file:line, name; exits 0 either way.
"""
import os
import re
import sys

NAME = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*\(")


def functions(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().split("\n")
    i = 0
    while i < len(lines):
        if lines[i] == "{" and i > 0:
            # the signature: back to the line that starts at column 0 and names the function
            s = i - 1
            while s > 0 and (lines[s][:1].isspace() or lines[s] == ""):
                s -= 1
            m = NAME.search(lines[s])
            e = i + 1
            while e < len(lines) and lines[e] != "}":
                e += 1
            if m:
                yield m.group(1), s + 1, e - s + 1
            i = e
        i += 1


def main(argv):
    limit, dirs = 150, []
    args = iter(argv)
    for a in args:
        if a == "--max":
            limit = int(next(args))
        else:
            dirs.append(a)
    rows = []
    for d in dirs or ["src", "cli"]:
        for root, _, files in os.walk(d):
            for name in files:
                if name.endswith((".c", ".h")):
                    path = os.path.join(root, name)
                    rows += [(n, path, line, name_)
                             for name_, line, n in functions(path) if n > limit]
    for n, path, line, name in sorted(rows, reverse=True):
        print(f"{n:5d}  {path}:{line}  {name}")
    if not rows:
        print(f"no function over {limit} lines")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
