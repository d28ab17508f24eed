#!/usr/bin/env python3
"""Fails, naming each cycle, when the modules of a layer include each other in a circle.

A module is foo.h with foo.cpp (either may be alone) in one layer folder; module A depends on B
when one of A's files includes B's header from the same folder ("gpu/b.h" or "b.h"). Layers are
the folders CMakeLists.txt makes libraries of (aquaform_layer(target folder ...)); includes
between layers are check_layers.cmake's business.

Usage: check_cycles.py SOURCE_DIR [LAYER...]   (layers: CMakeLists.txt's, unless given)
"""
import collections
import os
import re
import sys


def layer_folders(root):
    cmake = open(os.path.join(root, "CMakeLists.txt"), encoding="utf-8").read()
    return re.findall(r"aquaform_layer\(\s*\S+\s+(\S+)", cmake)


def module_graph(folder, layer):
    """{module: {module it includes: file that includes it}}"""
    include = re.compile(r'\s*#\s*include\s+"(?:%s/)?([^"/]+)\.h"' % re.escape(layer))
    graph = collections.defaultdict(dict)
    for name in sorted(os.listdir(folder)):
        module, ext = os.path.splitext(name)
        if ext not in (".h", ".cpp"):
            continue
        graph[module]  # a module that includes nothing is still one
        with open(os.path.join(folder, name), encoding="utf-8", errors="replace") as f:
            for line in f:
                m = include.match(line)
                if m and m.group(1) != module and os.path.exists(os.path.join(folder, m.group(1) + ".h")):
                    graph[module].setdefault(m.group(1), name)
    return graph


def strongly_connected(graph):
    """Tarjan's components of more than one module (a cycle runs through each)."""
    index, low, stack, on_stack, found = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def one_cycle(graph, component):
    """The shortest path from the component's first module back to itself."""
    start, inside = component[0], set(component)
    came_from, queue = {start: None}, collections.deque([start])
    while queue:
        v = queue.popleft()
        for w in sorted(graph[v]):
            if w == start:
                path = [v]
                while path[-1] != start:
                    path.append(came_from[path[-1]])
                return path[::-1] + [start]
            if w in inside and w not in came_from:
                came_from[w] = v
                queue.append(w)
    raise AssertionError("no way back to %s in its own component" % start)


def main():
    root = sys.argv[1]
    layers = sys.argv[2:] or layer_folders(root)
    if not layers:
        print("no layer folders found in %s/CMakeLists.txt (aquaform_layer(target folder ...))" % root)
        return 1
    problems, modules = [], 0
    for layer in layers:
        folder = os.path.join(root, layer)
        if not os.path.isdir(folder):
            problems.append("%s/: a layer folder that is not there" % layer)
            continue
        graph = module_graph(folder, layer)
        modules += len(graph)
        for component in strongly_connected(graph):
            cycle = one_cycle(graph, component)
            hops = ", ".join("%s includes %s.h" % (graph[a][b], b) for a, b in zip(cycle, cycle[1:]))
            problems.append("%s: %s (%s); all of %s are tied together. Break it with a forward declaration, "
                            "a type in a leaf header of its own, or a split"
                            % (layer, " -> ".join(cycle), hops, ", ".join(component)))
    if problems:
        print("include cycles inside a layer:\n" + "\n".join(problems))
        return 1
    print("no include cycles inside a layer (%d layers, %d modules)" % (len(layers), modules))
    return 0


if __name__ == "__main__":
    sys.exit(main())
