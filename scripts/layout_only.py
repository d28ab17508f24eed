#!/usr/bin/python3
"""Checks that a change of layout changed only layout: scripts/layout_only.py BASE

Lists the C++ files that differ from revision BASE in more than whitespace and the order of
their #include lines (what clang-format changes); exit 1 when one does. Run after applying
.clang-format to many files, to show that the commit moves no code.
"""
import re
import subprocess
import sys


def content(text):
    """The #include lines as a sorted list and the rest with all whitespace removed."""
    lines = text.split("\n")
    includes = sorted(re.sub(r"\s+", "", line) for line in lines if line.lstrip().startswith("#include"))
    rest = "".join(re.sub(r"\s+", "", line) for line in lines if not line.lstrip().startswith("#include"))
    return includes, rest


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    base = sys.argv[1]
    changed = subprocess.run(["git", "diff", "--name-only", base], capture_output=True, text=True,
                             check=True).stdout.split()
    sources = [f for f in changed if f.endswith((".cpp", ".h"))]
    beyond = []
    for path in sources:
        before = subprocess.run(["git", "show", f"{base}:{path}"], capture_output=True, text=True).stdout
        with open(path) as f:
            if content(before) != content(f.read()):
                beyond.append(path)
    for path in beyond:
        print(f"{path}: changed beyond layout")
    print(f"{len(sources)} C++ files changed since {base}, {len(beyond)} beyond layout")
    return 1 if beyond else 0


if __name__ == "__main__":
    sys.exit(main())
