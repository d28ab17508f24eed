#!/usr/bin/python3
"""Functions that grew since a base revision: scripts/function_growth.py BASE [NEW]

Refactoring issues ask that no function grow past what it was. This lists every C++ function of
the layer folders that is longer in NEW (a revision; default: the work tree) than in BASE, both
laid out with the repository's .clang-format first, so that a change of layout is not counted as
growth. Functions are found by Universal Ctags (start and end lines) and matched by scope, name
and signature; a function that moved between files still matches. Exit 1 when one grew.
"""
import os
import re
import subprocess
import sys
import tempfile

LAYERS = ["core", "pictures", "gpu", "grid", "geometry", "sim", "render", "control", "session", "exports",
          "bench", "study", "viewer", "runner", "apps"]
REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def export_tree(revision, into):
    """The layer folders of `revision` (None: the work tree) in `into`, laid out by clang-format."""
    if revision is None:
        subprocess.run(["cp", "-r"] + [os.path.join(REPO, d) for d in LAYERS if os.path.isdir(os.path.join(REPO, d))]
                       + [into], check=True)
    else:
        archive = subprocess.run(["git", "-C", REPO, "archive", revision], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", into], input=archive, check=True)
    with open(os.path.join(REPO, ".clang-format")) as style, open(os.path.join(into, ".clang-format"), "w") as out:
        out.write(style.read())
    sources = [os.path.join(root, f) for d in LAYERS for root, _, files in os.walk(os.path.join(into, d))
               for f in files if f.endswith((".cpp", ".h"))]
    for start in range(0, len(sources), 200):
        subprocess.run(["clang-format", "-i", "--style=file"] + sources[start:start + 200], check=True)


def function_lengths(root):
    """{(scope, name, signature): lines} over the layer folders under `root`."""
    folders = [d for d in LAYERS if os.path.isdir(os.path.join(root, d))]
    tags = subprocess.run(["ctags", "-R", "--languages=C++", "--c++-kinds=f", "--fields=+neS", "--extras=-q",
                           "-f", "-"] + folders, cwd=root, check=True, capture_output=True, text=True).stdout
    lengths = {}
    for line in tags.splitlines():
        parts = line.split("\t")
        if parts[0].startswith("__anon"):  # lambdas belong to their function
            continue
        fields = dict(p.split(":", 1) for p in parts[3:] if ":" in p)
        if "line" not in fields or "end" not in fields:
            continue
        scope = fields.get("class", fields.get("namespace", fields.get("function", "")))
        key = (re.sub(r"^aquaform(::)?", "", scope), parts[0], re.sub(r"\s+", "", fields.get("signature", "")))
        lengths[key] = max(lengths.get(key, 0), int(fields["end"]) - int(fields["line"]) + 1)
    return lengths


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    with tempfile.TemporaryDirectory() as base_dir, tempfile.TemporaryDirectory() as new_dir:
        export_tree(sys.argv[1], base_dir)
        export_tree(sys.argv[2] if len(sys.argv) == 3 else None, new_dir)
        before, after = function_lengths(base_dir), function_lengths(new_dir)
    grown = [(key, before[key], n) for key, n in sorted(after.items()) if key in before and n > before[key]]
    for (scope, name, signature), was, now in grown:
        print(f"{scope + '::' if scope else ''}{name}{signature[:70]}: {was} -> {now} lines")
    print(f"{len(grown)} of {len(after)} functions grew since {sys.argv[1]}")
    return 1 if grown else 0


if __name__ == "__main__":
    sys.exit(main())
