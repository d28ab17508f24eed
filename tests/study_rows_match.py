#!/usr/bin/python3
"""Whether a merged study's rows equal an unsharded run's: the same cells in the same order in
study.csv and the same passes in study_passes.csv, every text field equal and every number equal
within a tolerance (the software device's results vary in the last digits between runs), times
(ms_total, fps, ms) ignored. Usage: study_rows_match.py UNSHARDED_DIR MERGED_DIR"""
import csv
import math
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


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    full, merged = sys.argv[1], sys.argv[2]
    want, got = rows(f"{full}/study.csv"), rows(f"{merged}/study.csv")
    problems = compare("study.csv", want, got, lambda r: r["cell"])
    problems += compare("study_passes.csv", rows(f"{full}/study_passes.csv"), rows(f"{merged}/study_passes.csv"),
                        lambda r: (r["cell"], r["pass"]))
    if not want:
        problems.append("the unsharded study has no rows")
    if problems:
        print("\n".join(problems))
        sys.exit(1)
    print(f"{len(got)} cells of {merged} equal the unsharded run's (errors within {REL:.0%} or {ABS})")


main()
