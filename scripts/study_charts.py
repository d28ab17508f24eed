#!/usr/bin/env python3
"""Charts of an `aquaform study` run.

Usage: study_charts.py OUT_DIR

Reads whichever of study.csv, study_passes.csv and solver_map.csv exist in OUT_DIR and writes
each chart as PNG and SVG into OUT_DIR/charts/, printing one written path per line on stdout
(notes go to stderr). Needs matplotlib (Debian: apt-get install python3-matplotlib); run it with
/usr/bin/python3 where a pyenv or venv python3 without matplotlib comes first on PATH.

Exit status, as the aquaform command's: 0 charts written; 2 bad input (usage, an unknown flag, no
CSV, a missing column, nothing to chart), one line naming the fix, before any chart is drawn;
1 a failure at run time (no matplotlib, the charts folder cannot be written); 130 Ctrl-C.
"""

import csv
import math
import os
import sys
from collections import defaultdict

EXIT_RUNTIME, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 1, 2, 130

STUDY_COLUMNS = ["case", "scene", "method", "width", "height", "particles", "metaball_scale", "recursion_depth",
                 "bisection_steps", "visual", "ms_total", "fps", "depth_err_mean", "depth_err_p95",
                 "normal_err_deg_mean", "coverage_mismatch", "psnr_db", "overflow", "status"]
PASSES_COLUMNS = ["case", "scene", "method", "width", "height", "particles", "pass", "ms"]
SOLVER_MAP_COLUMNS = ["scene", "dt", "iterations", "control_pressure", "density_err_max", "density_err_mean",
                      "stable", "blowup_time_s"]

MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "<", ">", "h", "p"]


class InputError(Exception):
    pass


def fail(message, status):
    print("study_charts.py: " + message, file=sys.stderr)
    sys.exit(status)


def note(message):
    print("study_charts.py: " + message, file=sys.stderr)


def read_csv(path, required):
    """Rows of a CSV as dicts; an InputError names the file and the first missing column."""
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        header = [h.strip() for h in (reader.fieldnames or [])]
        for column in required:
            if column not in header:
                raise InputError("%s lacks the column \"%s\" (its header: %s); write it with the columns %s"
                                 % (path, column, ",".join(header) or "empty", ",".join(required)))
        reader.fieldnames = header
        return [{k: (v or "").strip() for k, v in row.items() if k is not None} for row in reader]


def number(text):
    """A finite float, or None for an empty, unparsable or non-finite field (reference and failed rows)."""
    try:
        value = float(text)
    except (TypeError, ValueError):
        return None
    return value if math.isfinite(value) else None


def integer(text):
    value = number(text)
    return int(round(value)) if value is not None else None


def method_styles(methods):
    """One colour and marker per method, the same in every chart."""
    import matplotlib.pyplot as plt
    colours = plt.get_cmap("tab10").colors
    return {m: (colours[i % len(colours)], MARKERS[i % len(MARKERS)]) for i, m in enumerate(sorted(methods))}


def subplot_grid(count, width=5.5, height=4.2):
    import matplotlib.pyplot as plt
    cols = min(count, 3)
    rows = (count + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False, layout="constrained")
    flat = [ax for row in axes for ax in row]
    for ax in flat[count:]:
        ax.set_visible(False)
    return fig, flat[:count]


def log_axis(ax, which):
    """Log scale labelled 2, 3, 10 rather than 2x10^0 (the default for spans under a decade)."""
    import matplotlib.ticker as ticker
    axis = ax.xaxis if which == "x" else ax.yaxis
    (ax.set_xscale if which == "x" else ax.set_yscale)("log")
    axis.set_major_formatter(ticker.LogFormatter(labelOnlyBase=False))
    axis.set_minor_formatter(ticker.LogFormatter(labelOnlyBase=False, minor_thresholds=(2, 0.5)))


def save(fig, charts_dir, name, written):
    for ext in ("png", "svg"):
        path = os.path.join(charts_dir, name + "." + ext)
        # Drawn beside the chart and renamed over it once whole: a full disk leaves no cut file.
        staged = os.path.join(charts_dir, ".%s.%d.%s" % (name, os.getpid(), ext))
        try:
            fig.savefig(staged, dpi=120, format=ext)
            os.replace(staged, path)
        except OSError as e:
            try:
                os.remove(staged)
            except OSError:
                pass
            fail("cannot write %s: %s; free some space or choose another folder with --out" % (path, e.strerror or e),
                 EXIT_RUNTIME)
        written.append(path)
    import matplotlib.pyplot as plt
    plt.close(fig)


def pareto_front(points):
    """Non-dominated (time, error) points, fastest first: each is more accurate than every faster one."""
    front, best = [], math.inf
    for t, e in sorted(points):
        if e < best:
            front.append((t, e))
            best = e
    return front


def resolution(row):
    return "%sx%s" % (row["width"], row["height"])


# The trade-off charts: time per frame against one error column of study.csv, per resolution and
# particle count, with the Pareto front. Every method row is a point, so a method drawn on both
# surfaces (the " iso" rows) shows both.
TRADE_OFFS = [
    # (column, axis label, chart name, title)
    ("depth_err_mean", "mean depth error [particle radii]", "pareto", "speed against accuracy"),
    ("roughness_deg", "roughness on flat regions [deg]", "roughness", "speed against smoothness"),
]


def chart_pareto(rows, styles, charts_dir, written, column, ylabel, name, title):
    groups = defaultdict(list)
    for r in rows:
        t, e = number(r["ms_total"]), number(r.get(column, ""))
        # Only successful rows are trade-offs; the reference has no depth error against itself (its
        # roughness is the field's own: the floor of the methods').
        if r["status"] != "ok" or t is None or e is None or t <= 0:
            continue
        groups[(integer(r["width"]) or 0, integer(r["height"]) or 0, integer(r["particles"]) or 0)].append(
            (t, e, r["method"]))
    if not groups:
        return note("study.csv has no ok row with ms_total and %s: no %s chart" % (column, name))
    keys = sorted(groups)
    fig, axes = subplot_grid(len(keys))
    for ax, key in zip(axes, keys):
        pts = groups[key]
        for method in sorted({m for _, _, m in pts}):
            colour, marker = styles[method]
            xs = [t for t, _, m in pts if m == method]
            ys = [e for _, e, m in pts if m == method]
            ax.scatter(xs, ys, color=colour, marker=marker, label=method, zorder=3)
        front = pareto_front([(t, e) for t, e, _ in pts])
        ax.step([t for t, _ in front], [e for _, e in front], where="post", color="0.3", linestyle="--",
                linewidth=1, label="Pareto front", zorder=2)
        log_axis(ax, "x")
        ax.set_xlabel("time per frame [ms] (log)")
        ax.set_ylabel(ylabel)
        ax.set_title("%dx%d, %d particles" % key)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
    fig.suptitle(title)
    save(fig, charts_dir, name, written)


def chart_time_vs_particles(rows, styles, charts_dir, written):
    # (resolution) -> method -> particles -> [ms]; failed rows have no meaningful time.
    groups = defaultdict(lambda: defaultdict(lambda: defaultdict(list)))
    for r in rows:
        t, n = number(r["ms_total"]), integer(r["particles"])
        if r["status"].startswith("failed") or t is None or t <= 0 or not n or n <= 0:
            continue
        groups[(integer(r["width"]) or 0, integer(r["height"]) or 0)][r["method"]][n].append(t)
    if not groups:
        return note("study.csv has no row with ms_total and particles: no time_vs_particles chart")
    keys = sorted(groups)
    fig, axes = subplot_grid(len(keys))
    for ax, key in zip(axes, keys):
        for method, by_n in sorted(groups[key].items()):
            colour, marker = styles[method]
            ns = sorted(by_n)
            ax.plot(ns, [sum(by_n[n]) / len(by_n[n]) for n in ns], color=colour, marker=marker, label=method)
        log_axis(ax, "x")
        log_axis(ax, "y")
        ax.set_xlabel("particles (log)")
        ax.set_ylabel("time per frame [ms] (log)")
        ax.set_title("%dx%d" % key)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize="small")
    fig.suptitle("time against particle count")
    save(fig, charts_dir, "time_vs_particles", written)


def chart_passes(rows, charts_dir, written):
    import matplotlib.pyplot as plt
    # (method, particles, width, height) -> pass -> [ms over cases]
    bars = defaultdict(lambda: defaultdict(list))
    order = []  # passes in the order they first appear: execution order
    for r in rows:
        ms = number(r["ms"])
        if ms is None:
            continue
        key = (r["method"], integer(r["particles"]) or 0, integer(r["width"]) or 0, integer(r["height"]) or 0)
        bars[key][r["pass"]].append(ms)
        if r["pass"] not in order:
            order.append(r["pass"])
    if not bars:
        return note("study_passes.csv has no row with ms: no passes chart")
    keys = sorted(bars)
    fig, ax = plt.subplots(figsize=(9, 1.2 + 0.45 * len(keys)), layout="constrained")
    colours = plt.get_cmap("tab20").colors
    left = [0.0] * len(keys)
    for i, name in enumerate(order):
        widths = [sum(bars[k][name]) / len(bars[k][name]) if bars[k][name] else 0.0 for k in keys]
        ax.barh(range(len(keys)), widths, left=left, color=colours[i % len(colours)], label=name)
        left = [a + b for a, b in zip(left, widths)]
    ax.set_yticks(range(len(keys)))
    ax.set_yticklabels(["%s  %d p  %dx%d" % k for k in keys], fontsize="small")
    ax.invert_yaxis()
    ax.set_xlabel("GPU time per frame [ms]")
    ax.set_title("time per pass")
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize="small", loc="center left", bbox_to_anchor=(1.0, 0.5))
    save(fig, charts_dir, "passes", written)


def chart_solver_map(rows, charts_dir, written):
    import matplotlib.colors as mcolors
    import matplotlib.patches as mpatches
    panels = defaultdict(list)
    for r in rows:
        dt, it = number(r["dt"]), integer(r["iterations"])
        if dt is None or it is None:
            continue
        panels[(r["scene"], number(r["control_pressure"]))].append(
            (dt, it, number(r["density_err_max"]), integer(r["stable"]) == 1, number(r["blowup_time_s"])))
    if not panels:
        return note("solver_map.csv has no row with dt and iterations: no solver_map chart")
    keys = sorted(panels, key=lambda k: (k[0], -1.0 if k[1] is None else k[1]))
    values = [e for cells in panels.values() for _, _, e, _, _ in cells if e is not None and e > 0]
    # Errors span decades between a quiet and an exploding cell: a log scale shows both.
    if values and max(values) > 10 * min(values):
        norm = mcolors.LogNorm(vmin=min(values), vmax=max(values))
    else:
        norm = mcolors.Normalize(vmin=0.0, vmax=max(values) if values else 1.0)
    fig, axes = subplot_grid(len(keys), width=6.0, height=4.6)
    image = None
    for ax, key in zip(axes, keys):
        cells = panels[key]
        dts = sorted({c[0] for c in cells})
        its = sorted({c[1] for c in cells})
        grid = [[math.nan] * len(dts) for _ in its]
        for dt, it, err, stable, blowup in cells:
            x, y = dts.index(dt), its.index(it)
            if err is not None:
                grid[y][x] = err
            text = "-" if err is None else "%.3g" % err
            if not stable:
                # Hatched and crossed, so that an unstable cell reads as one in grey print too.
                ax.add_patch(mpatches.Rectangle((x - 0.5, y - 0.5), 1, 1, fill=False, hatch="xx", edgecolor="black",
                                                linewidth=0))
                ax.plot([x - 0.5, x + 0.5], [y - 0.5, y + 0.5], color="black", linewidth=1.2)
                ax.plot([x - 0.5, x + 0.5], [y + 0.5, y - 0.5], color="black", linewidth=1.2)
                text += "\nblow-up" + ("" if blowup is None else " %.3g s" % blowup)
            ax.text(x, y, text, ha="center", va="center", fontsize="x-small",
                    bbox=dict(boxstyle="round,pad=0.15", facecolor="white", alpha=0.75, linewidth=0))
        image = ax.imshow(grid, origin="lower", aspect="auto", cmap="viridis", norm=norm,
                          extent=(-0.5, len(dts) - 0.5, -0.5, len(its) - 0.5))
        ax.set_xticks(range(len(dts)))
        ax.set_xticklabels(["%.3g" % d for d in dts], rotation=30)
        ax.set_yticks(range(len(its)))
        ax.set_yticklabels([str(i) for i in its])
        ax.set_xlim(-0.5, len(dts) - 0.5)
        ax.set_ylim(-0.5, len(its) - 0.5)
        ax.set_xlabel("solver time step dt [s]")
        ax.set_ylabel("constraint iterations")
        scene, pressure = key
        ax.set_title(scene + ("" if pressure is None else ", control %.4g Pa" % pressure))
    fig.colorbar(image, ax=axes, label="max density error (rho/rho0 - 1)")
    fig.suptitle("solver stability: max density error; crossed cells blew up")
    save(fig, charts_dir, "solver_map", written)


def main(argv):
    if len(argv) != 2 or argv[1].startswith("-"):
        fail("usage: study_charts.py OUT_DIR (the directory an `aquaform study` run wrote its CSV files to)%s"
             % ("; unknown argument " + argv[1] if len(argv) == 2 else ""), EXIT_BAD_INPUT)
    out_dir = argv[1]
    if not os.path.isdir(out_dir):
        fail("%s is not a directory; give the directory an `aquaform study` run wrote to" % out_dir, EXIT_BAD_INPUT)
    files = {name: os.path.join(out_dir, name) for name in ("study.csv", "study_passes.csv", "solver_map.csv")}
    present = {name: path for name, path in files.items() if os.path.isfile(path)}
    if not present:
        fail("%s has none of study.csv, study_passes.csv, solver_map.csv; run `aquaform study SPEC.json` first"
             % out_dir, EXIT_BAD_INPUT)
    required = {"study.csv": STUDY_COLUMNS, "study_passes.csv": PASSES_COLUMNS, "solver_map.csv": SOLVER_MAP_COLUMNS}
    try:
        tables = {name: read_csv(path, required[name]) for name, path in present.items()}
    except InputError as e:
        fail(str(e), EXIT_BAD_INPUT)
    except (OSError, csv.Error) as e:
        fail("cannot read %s" % e, EXIT_BAD_INPUT)

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot  # noqa: F401  (fails here rather than mid-chart)
    except ImportError:
        fail("%s has no matplotlib; install it (Debian: apt-get install python3-matplotlib) or run the script "
             "with a python3 that has it (/usr/bin/python3)" % sys.executable, EXIT_RUNTIME)
    matplotlib.rcParams["svg.hashsalt"] = "aquaform"  # reproducible SVG ids

    charts_dir = os.path.join(out_dir, "charts")
    try:
        os.makedirs(charts_dir, exist_ok=True)
    except OSError as e:
        fail("cannot make %s: %s; free some space or choose another folder with --out" % (charts_dir, e.strerror or e),
             EXIT_RUNTIME)
    written = []
    methods = {r["method"] for name in ("study.csv", "study_passes.csv") for r in tables.get(name, [])}
    styles = method_styles(methods)
    if "study.csv" in tables:
        for trade_off in TRADE_OFFS:
            chart_pareto(tables["study.csv"], styles, charts_dir, written, *trade_off)
        chart_time_vs_particles(tables["study.csv"], styles, charts_dir, written)
    if "study_passes.csv" in tables:
        chart_passes(tables["study_passes.csv"], charts_dir, written)
    if "solver_map.csv" in tables:
        chart_solver_map(tables["solver_map.csv"], charts_dir, written)
    if not written:
        fail("no chart drawn: %s in %s have no rows to chart (see the notes above)" % (", ".join(sorted(present)), out_dir),
             EXIT_BAD_INPUT)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv))
    except KeyboardInterrupt:
        fail("stopped by Ctrl-C; the charts written before it stay in OUT_DIR/charts", EXIT_INTERRUPTED)
