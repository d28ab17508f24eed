#!/usr/bin/python3
"""Whether a merged study's rows equal an unsharded run's: the same cells in the same order in
study.csv, the same passes in study_passes.csv, the same headings and table rows in study.md
(method, particles, size and status: cell for cell), every text field equal and every number equal
within a tolerance (the software device's results vary in the last digits between runs), times
(ms_total, fps, ms) ignored. Usage: study_rows_match.py UNSHARDED_DIR MERGED_DIR"""
import csv
import math
import re
import sys

TIMES = {"ms_total", "fps", "ms"}
REL, ABS = 0.02, 1e-4


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def same(a, b):
    if a == b:
        return True
    try:
        x, y = float(a), float(b)
    except ValueError:
        return False
    return math.isclose(x, y, rel_tol=REL, abs_tol=ABS)


def compare(name, want, got, key):
    problems = []
    wk, gk = [key(r) for r in want], [key(r) for r in got]
    if wk != gk:
        if sorted(wk) == sorted(gk):
            problems.append(f"{name}: the same rows in a different order")
        else:
            problems.append(f"{name}: the rows differ: unsharded {len(wk)}, merged {len(gk)}; "
                            f"missing {sorted(set(wk) - set(gk))}, extra {sorted(set(gk) - set(wk))}")
        return problems
    for w, g in zip(want, got):
        if set(w) != set(g):
            problems.append(f"{name}: columns differ: {sorted(set(w) ^ set(g))}")
            break
        for col in w:
            if col not in TIMES and not same(w[col], g[col]):
                problems.append(f"{name} {key(w)}: {col} unsharded {w[col]!r}, merged {g[col]!r}")
    return problems


def report(path):
    """study.md's headings and its table rows without the numbers: (method, particles, size, status)."""
    out = []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                out.append(line.strip())
            elif line.startswith("| ") and not line.startswith("| -"):
                cells = [c.strip() for c in line.strip().strip("|").split("|")]
                last = cells[-1:] if not re.fullmatch(r"[-+0-9.e%x ]*", cells[-1]) else []  # a status, not a time
                out.append(" | ".join(cells[:3] + last))
    return out


def compare_reports(full, merged):
    want, got = report(full), report(merged)
    if want == got:
        return []
    diff = [f"  unsharded {w!r}\n  merged    {g!r}" for w, g in zip(want, got) if w != g][:5]
    return [f"study.md: {len(want)} headings and rows unsharded, {len(got)} merged; first differences:"] + diff


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    full, merged = sys.argv[1], sys.argv[2]
    want, got = rows(f"{full}/study.csv"), rows(f"{merged}/study.csv")
    problems = compare("study.csv", want, got, lambda r: r["cell"])
    problems += compare("study_passes.csv", rows(f"{full}/study_passes.csv"), rows(f"{merged}/study_passes.csv"),
                        lambda r: (r["cell"], r["pass"]))
    problems += compare_reports(f"{full}/study.md", f"{merged}/study.md")
    if not want:
        problems.append("the unsharded study has no rows")
    if problems:
        print("\n".join(problems))
        sys.exit(1)
    print(f"{len(got)} cells of {merged} equal the unsharded run's, study.md row for row (errors within {REL:.0%} or {ABS})")


main()
