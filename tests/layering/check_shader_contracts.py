#!/usr/bin/env python3
"""Fails, naming file:line, when a file includes a GPU contract of a layer it does not see.

The rule: the GPU contracts (the headers C++ and GLSL share) sit in shaders/shared/<folder>/, one
folder per layer (CONTRACT_LAYER below). A layer sees its own contracts and those of the layers
below it, as check_layers.cmake's table says for C++ headers; sim and render are siblings and see
none of each other's. Checked:
  - every contract header: its includes reach only its own folder's layer and those below;
  - every shader under shaders/<layer>/, through the common/ helpers it includes (the helpers have
    no layer of their own: each is judged for every shader that includes it);
  - every C++ file of a layer folder, for its "shaders/shared/<folder>/..." includes.
Tests are not checked: they see everything.

Usage: check_shader_contracts.py SOURCE_DIR [LAYERS_TABLE]   (table: check_layers.cmake beside this)
"""
import os
import re
import sys

# Contract folder under shaders/shared/ -> the C++ layer it belongs to (cmake/Layers.cmake).
# The solids (static boxes, the tank, the mesh obstacles' maps) and the particles the solver hands
# the renderers (the whitewater pool) sit below both sim and render, so both see them: with gpu,
# the lowest layer that deals in GPU buffers, which both link (geometry, which makes the maps on
# the CPU, is not linked by render).
CONTRACT_LAYER = {
    "core": "core",
    "solids": "gpu",
    "particles": "gpu",
    "grid": "grid",
    "sim": "sim",
    "render": "render",
    "control": "control",
}

INCLUDE = re.compile(r'\s*#\s*include\s+"([^"]+)"')
GLSL = (".comp", ".vert", ".frag", ".glsl")
CPP = (".h", ".hpp", ".cpp")


def layer_table(path):
    """{layer: set of the layers it may include besides itself}, in the table's order."""
    text = open(path, encoding="utf-8").read()
    table = {}
    for layer, allowed in re.findall(r'"(\w+)\|[^|"]*\|([\w,]*)"', text):
        table[layer] = set(a for a in allowed.split(",") if a)
    return table


def cmake_layers(root):
    path = os.path.join(root, "CMakeLists.txt")
    if not os.path.exists(path):
        return []
    return re.findall(r"aquaform_layer\(\s*\S+\s+(\S+)", open(path, encoding="utf-8").read())


def includes(path):
    """(line number, included name) of each quoted include."""
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            m = INCLUDE.match(line)
            if m:
                yield number, m.group(1)


class Checker:
    def __init__(self, root, table):
        self.root = root
        self.shaders = os.path.join(root, "shaders")
        self.shared = os.path.join(self.shaders, "shared")
        self.table = table
        self.problems = set()
        self.counts = {"contract headers": 0, "shaders": 0, "C++ files": 0}

    def rel(self, path):
        return os.path.relpath(path, self.root)

    def sees(self, layer, folder):
        owner = CONTRACT_LAYER[folder]
        return owner == layer or owner in self.table.get(layer, ())

    def seen_folders(self, layer):
        return [f for f in CONTRACT_LAYER if self.sees(layer, f)]

    def contract_folder(self, path):
        """The contract folder of a path under shaders/shared/ ('' directly in it), else None."""
        rel = os.path.relpath(os.path.normpath(path), self.shared)
        if rel.startswith(".."):
            return None
        parts = rel.split(os.sep)
        return parts[0] if len(parts) > 1 else ""

    def judge(self, layer, where, target, name):
        """One include of a contract (`target`, a path) by a file of `layer`; `where`: file:line."""
        folder = self.contract_folder(target)
        if folder is None:
            return
        if folder not in CONTRACT_LAYER:
            self.problems.add("%s: includes %s, which is in no contract folder (%s)"
                              % (where, name, ", ".join(CONTRACT_LAYER)))
        elif not self.sees(layer, folder):
            self.problems.add("%s: %s includes %s, a contract of %s, which %s does not see "
                              "(it sees shared/%s)"
                              % (where, layer, name, CONTRACT_LAYER[folder], layer,
                                 ", shared/".join(self.seen_folders(layer))))

    def resolve_glsl(self, including, name):
        """As glslang does: the including file's folder first, then the shader root."""
        for base in (os.path.dirname(including), self.shaders):
            candidate = os.path.normpath(os.path.join(base, name))
            if os.path.isfile(candidate):
                return candidate
        return os.path.normpath(os.path.join(self.shaders, name))

    def check_contract_headers(self):
        for dirpath, _, names in os.walk(self.shared):
            for name in sorted(names):
                path = os.path.join(dirpath, name)
                self.counts["contract headers"] += 1
                folder = self.contract_folder(path)
                if folder not in CONTRACT_LAYER:
                    self.problems.add("%s: a contract outside the layer folders of shaders/shared/ (%s)"
                                      % (self.rel(path), ", ".join(CONTRACT_LAYER)))
                    continue
                for number, included in includes(path):
                    target = self.resolve_glsl(path, included)
                    self.judge(CONTRACT_LAYER[folder], "%s:%d" % (self.rel(path), number), target,
                               "shared/" + os.path.relpath(target, self.shared))

    def check_shader(self, layer, path, chain, visited):
        for number, included in includes(path):
            where = "%s:%d" % (self.rel(path), number)
            target = self.resolve_glsl(path, included)
            if self.contract_folder(target) is not None:
                # A contract's own includes are check_contract_headers' business.
                self.judge(layer, where + ("" if not chain else " (from %s)" % " <- ".join(chain)),
                           target, os.path.relpath(target, self.shaders))
            elif os.path.isfile(target) and target not in visited:
                visited.add(target)
                self.check_shader(layer, target, [where] + chain, visited)

    def check_shaders(self):
        for folder in sorted(os.listdir(self.shaders)):
            path = os.path.join(self.shaders, folder)
            if not os.path.isdir(path) or folder in ("shared", "common"):
                continue
            if folder not in self.table:
                self.problems.add("shaders/%s/: a shader folder named after no layer (%s)"
                                  % (folder, ", ".join(self.table)))
                continue
            for dirpath, _, names in os.walk(path):
                for name in sorted(names):
                    if name.endswith(GLSL):
                        self.counts["shaders"] += 1
                        file = os.path.join(dirpath, name)
                        self.check_shader(folder, file, [], {file})

    def check_cpp(self):
        for layer in self.table:
            folder = os.path.join(self.root, layer)
            for dirpath, _, names in os.walk(folder):
                for name in sorted(names):
                    if not name.endswith(CPP):
                        continue
                    self.counts["C++ files"] += 1
                    path = os.path.join(dirpath, name)
                    for number, included in includes(path):
                        if included.startswith("shaders/shared/"):
                            self.judge(layer, "%s:%d" % (self.rel(path), number),
                                       os.path.join(self.root, included), included)


def main():
    root = sys.argv[1]
    table_path = sys.argv[2] if len(sys.argv) > 2 else os.path.join(os.path.dirname(__file__), "check_layers.cmake")
    table = layer_table(table_path)
    if not table:
        print("no layers in %s (\"layer|header|layers below\")" % table_path)
        return 1
    checker = Checker(root, table)
    for layer in cmake_layers(root):
        if layer not in table:
            checker.problems.add("%s/: a layer of CMakeLists.txt missing from %s's table, so what its files "
                                 "may include is unknown" % (layer, os.path.basename(table_path)))
    if not os.path.isdir(checker.shared):
        checker.problems.add("shaders/shared/: not there")
    else:
        checker.check_contract_headers()
        checker.check_shaders()
        checker.check_cpp()
    if checker.problems:
        print("GPU contracts included from a layer that does not see them "
              "(tests/layering/check_shader_contracts.py says the rule):")
        print("\n".join(sorted(checker.problems)))
        return 1
    print("every GPU contract is included only from its own layer or above (%s)"
          % ", ".join("%d %s" % (n, what) for what, n in checker.counts.items()))
    for layer in table:
        print("  %-9s sees shared/%s" % (layer, ", shared/".join(checker.seen_folders(layer))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
