#!/usr/bin/env python3
"""Fails, naming the difference, when a layer's declared links are not the layers it includes.

A layer is a folder CMakeLists.txt makes a library of (aquaform_layer(target folder ...)). Its
declared links are the other layers' libraries named in its target_link_libraries(...) calls; the
layers it includes are the folders named by its files' `#include "folder/..."` lines. The two
must be equal: a link no file uses is a dependency in name only (it widens what the layer can
see), and an include of a layer reached only through another link leans on that link's choice.

Usage: check_links.py SOURCE_DIR
"""
import os
import re
import sys


def layers(cmake):
    """{library target: folder}"""
    return dict(re.findall(r"aquaform_layer\(\s*(\S+)\s+(\S+)", cmake))


def declared_links(cmake, targets):
    """{folder: {folders it links}}"""
    links = {folder: set() for folder in targets.values()}
    for target, args in re.findall(r"target_link_libraries\(\s*(\S+)([^)]*)\)", cmake):
        if target in targets:
            links[targets[target]] |= {targets[a] for a in args.split() if a in targets and a != target}
    return links


def included_layers(root, folder, folders):
    include = re.compile(r'\s*#\s*include\s+"([^"/]+)/')
    found = set()
    for name in sorted(os.listdir(os.path.join(root, folder))):
        if os.path.splitext(name)[1] not in (".h", ".cpp"):
            continue
        with open(os.path.join(root, folder, name), encoding="utf-8", errors="replace") as f:
            for line in f:
                m = include.match(line)
                if m and m.group(1) in folders and m.group(1) != folder:
                    found.add(m.group(1))
    return found


def main():
    root = sys.argv[1]
    cmake = open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8").read()
    targets = layers(cmake)
    folders = set(targets.values())
    failures = []
    for folder, linked in sorted(declared_links(cmake, targets).items()):
        used = included_layers(root, folder, folders)
        unused, unlinked = sorted(linked - used), sorted(used - linked)
        if unused:
            failures.append(f"{folder} links {', '.join(unused)} but includes nothing of "
                            f"{'it: drop the link' if len(unused) == 1 else 'them: drop the links'}")
        if unlinked:
            failures.append(f"{folder} includes {', '.join(unlinked)} but does not link "
                            f"{'it: link it' if len(unlinked) == 1 else 'them: link them'}")
    for line in failures:
        print(line)
    if failures:
        return 1
    print(f"each of {len(folders)} layers links exactly the layers it includes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
