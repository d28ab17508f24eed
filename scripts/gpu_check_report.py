#!/usr/bin/env python3
"""Assembles scripts/gpu_check.sh's JSON from its work folder, after every step, so that a run cut
short still reports what it did. Standard library only: the GPU machine's python3 is not Debian's.

Usage: gpu_check_report.py WORK_DIR OUT_FILE   (WORK_DIR/meta.json and steps.jsonl, see gpu_check.sh)
"""
import json
import os
import re
import sys

# Issue 36's targets on the H200.
SOLVER_MS_PER_STEP = 1.2     # a 1M-particle step, violent mid-run state, the scene's iterations
RECONSTRUCTION_MS = 4.0      # the adaptive reconstruction of 1M particles at 1920x1080, with the frame grid
SPRITES_MS = 0.6             # of which all depth sprites (render_splat)
MARCH_MS = 2.0               # and the march (render_march)
RESOLUTION_SPEEDUP = 1.5     # adaptive against its full-resolution twin on broad surfaces
BROAD_FRAMES = ("calm", "violent_wall", "double_collision")
# Real time (issue 36): the real-time factor (simulated s / wall s) of a displayed frame, per size.
FRAME_TARGETS = ((500000, 1.0, "frame_500k"), (1000000, 0.8, "frame_1m"))
VIEWER_TARGET = (1000000, 0.8)  # the viewer's own loop (view --headless) at 1M


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def tail(path, chars=4000):
    try:
        with open(path, errors="replace") as f:
            return f.read()[-chars:]
    except OSError:
        return None


def device_of(info_output):
    """The device `aquaform info` chose, or None."""
    for line in (info_output or "").splitlines():
        if line.startswith("aquaform will use device"):
            return line.split(":", 1)[1].strip()
    return None


def verdict(status, **fields):
    return dict(status=status, **fields)


def not_judged(meta, bench, key, step):
    """The verdict when a benchmark's figures cannot be judged against a GPU target, else None."""
    if meta["quick"]:
        return verdict("not applicable", reason="--quick: small sizes on any device")
    if not bench or not bench.get(key):
        return verdict("not measured", reason=step + " wrote no figures (see its step)")
    if bench.get("device_type") == "software (CPU)":
        return verdict("not applicable", reason="ran on a software device: " + bench.get("device", "?"))
    return None


def solver_verdict(meta, sim):
    early = not_judged(meta, sim, "records", "bench_sim")
    if early:
        return early
    record = sim["records"][0]
    ms = record["ms_per_step"]
    return verdict("pass" if ms <= SOLVER_MS_PER_STEP else "fail", ms_per_step=ms, particles=record["particles"],
                   iterations=record["iterations"], target_ms=SOLVER_MS_PER_STEP)


def per_frame_verdict(meta, render, judge, missing, **targets):
    """A verdict over bench_render's frames: judge(frame) gives a frame's figures with `pass_`, or
    None where the frame lacks what it needs; `missing` says why when no frame had it."""
    early = not_judged(meta, render, "frames", "bench_render")
    if early:
        return early
    frames = [j for j in (judge(f) for f in render["frames"]) if j is not None]
    if not frames:
        return verdict("not measured", reason=missing)
    passed = all(f.pop("pass_") for f in frames)
    return verdict("pass" if passed else "fail", frames=frames, **targets)


def reconstruction_figures(f):
    adaptive = next((r for r in f["records"] if r.get("label") == "adaptive"), None)
    if adaptive is None:
        return None
    grid = (f.get("in_place") or {}).get("solver_frame_grid_ms", 0.0)
    total = adaptive["ms_total"] + grid
    passes = adaptive.get("ms_per_pass") or {}
    sprites, march = passes.get("render_splat", 0.0), passes.get("render_march", 0.0)
    return dict(frame=f["name"], particles=f["particles"], ms_reconstruction=adaptive["ms_total"], ms_frame_grid=grid,
                ms_total=total, ms_sprites=sprites, ms_march=march,
                pass_=total <= RECONSTRUCTION_MS and sprites <= SPRITES_MS and march <= MARCH_MS)


def resolution_figures(f):
    """Adaptive resolution pays: >= 1.5x faster than full resolution on broad surfaces, never slower."""
    r = (f.get("targets") or {}).get("adaptive_resolution") or {}
    if "full_res_ms_total" not in r:
        return None
    speedup = r["full_res_ms_total"] / r["ms_total"] if r["ms_total"] > 0 else 0.0
    need = RESOLUTION_SPEEDUP if f["name"] in BROAD_FRAMES else 1.0
    return dict(frame=f["name"], ms_adaptive=r["ms_total"], ms_full_resolution=r["full_res_ms_total"], speedup=speedup,
                speedup_min=need, used=r.get("used"), pass_=speedup >= need)


def reconstruction_verdict(meta, render):
    return per_frame_verdict(meta, render, reconstruction_figures, "bench_render drew no adaptive frame",
                             target_ms=RECONSTRUCTION_MS, target_sprites_ms=SPRITES_MS, target_march_ms=MARCH_MS)


def resolution_verdict(meta, render):
    return per_frame_verdict(meta, render, resolution_figures, "bench_render drew no adaptive/adaptive_full_res pair")


def frame_not_judged(meta, bench, step):
    """Why a real-time factor cannot be judged against the H200's targets, else None. As
    `bench frame` says it: judged on a discrete GPU only."""
    if meta["quick"]:
        return verdict("not judged", reason="--quick: small sizes on any device")
    if not bench:
        return verdict("not measured", reason=step + " wrote no figures (see its step)")
    kind = bench.get("device_type")
    if kind == "software (CPU)":
        return verdict("not judged", reason="software device: " + bench.get("device", "?"))
    if kind != "discrete GPU":
        return verdict("not judged", reason="not a discrete GPU: %s (%s)" % (bench.get("device", "?"), kind))
    return None


def factor_verdict(particles, factor, minimum, **fields):
    return verdict("pass" if factor >= minimum else "fail", real_time_factor=factor, min_real_time_factor=minimum,
                   particles=particles, **fields)


def frame_verdicts(meta, frame, view):
    """Real time per size from bench frame, and the headless viewer's at 1M."""
    out = {}
    for requested, minimum, key in FRAME_TARGETS:
        early = frame_not_judged(meta, frame, "bench_frame")
        record = next((r for r in (frame or {}).get("records", []) if r.get("requested") == requested), None)
        if early:
            out[key] = early
        elif record is None:
            out[key] = verdict("not measured", reason="bench_frame measured no %d-particle frame" % requested)
        else:
            out[key] = factor_verdict(record["particles"], record["real_time_factor"], minimum,
                                      resolution=record["resolution"], fps=record["frames_per_s"],
                                      gpu_ms_per_frame=record["gpu_ms_per_frame"], steps_per_frame=record["steps_per_frame"])
    early = frame_not_judged(meta, view, "view_headless")
    if early:
        out["viewer_1m"] = early
    elif view["particles"] < 0.9 * VIEWER_TARGET[0]:
        out["viewer_1m"] = verdict("not measured", reason="the headless viewer ran %d particles" % view["particles"])
    else:
        out["viewer_1m"] = factor_verdict(view["particles"], view["real_time_factor"], VIEWER_TARGET[1],
                                          resolution=view["resolution"], fps=view["frames_per_s"])
    return out


def study_summary(meta):
    """What the study step left in its folder: rows measured, study.md whole, the charts' names."""
    folder = meta.get("study_dir")
    if not folder or not os.path.isdir(folder):
        return None
    rows = tail(os.path.join(folder, "study.csv"), chars=1 << 24)
    charts = os.path.join(folder, "charts")
    return dict(folder=folder, rows=max(0, rows.count("\n") - 1) if rows else 0,
                study_md=tail(os.path.join(folder, "study.md"), chars=1 << 18),
                charts=sorted(os.listdir(charts)) if os.path.isdir(charts) else [])


def march_lanes_summary(work, render):
    """ms of the adaptive reconstruction and of its march per frame, by lanes a ray."""
    runs = [render] + [load(os.path.join(work, "bench_render_lanes%d.json" % lanes)) for lanes in (1, 8)]
    rows = []
    for run in runs:
        for f in (run or {}).get("frames", []):
            r = next((r for r in f["records"] if r.get("label") == "adaptive"), None)
            if r:
                rows.append(dict(frame=f["name"], lanes=r.get("march_lanes"), ms_total=r["ms_total"],
                                 ms_march=(r.get("ms_per_pass") or {}).get("render_march")))
    return rows


def host_ms_between_frames(steps):
    """What `run` said the device waited for the host between frames (None if it did not say)."""
    run = next((s for s in steps if s["name"] == "run"), None)
    found = re.search(r"host time between frames: ([0-9.]+) ms", run.get("output") or "") if run else None
    return float(found.group(1)) if found else None


def main(work, out):
    meta = load(os.path.join(work, "meta.json"))
    steps = []
    try:
        with open(os.path.join(work, "steps.jsonl")) as f:
            for line in f:
                step = json.loads(line)
                step["output"] = tail(os.path.join(work, step["name"] + ".log"))
                steps.append(step)
    except OSError:
        pass
    info = next((s for s in steps if s["name"] == "info"), None)
    device = device_of(info["output"]) if info else None
    sim = load(os.path.join(work, "bench_sim.json"))
    render = load(os.path.join(work, "bench_render.json"))
    frame = load(os.path.join(work, "bench_frame.json"))
    view = load(os.path.join(work, "view_headless.json"))
    stats = os.path.join(work, "run", "stats.csv")
    stats_text = tail(stats, chars=1 << 24)  # the whole file: a few hundred rows
    report = dict(meta)
    report.update(
        device=device,
        # Why no device was used: what `info` said, and where the Vulkan drivers were looked for.
        device_error=None if device or not info else dict(info_output=info["output"], vulkan=meta.get("vulkan")),
        budget_used_s=round(sum(s.get("seconds", 0.0) for s in steps), 2),
        steps=steps,
        verdicts=dict(solver=solver_verdict(meta, sim), reconstruction=reconstruction_verdict(meta, render),
                      adaptive_resolution=resolution_verdict(meta, render), **frame_verdicts(meta, frame, view)),
        bench_sim=sim,
        bench_render=render,
        # The adaptive reconstruction per frame at each lane count (bench_render's is the default).
        march_lanes=march_lanes_summary(work, render),
        bench_frame=frame,
        view_headless=view,
        study=study_summary(meta),
        run=dict(frames_written=max(0, stats_text.count("\n") - 1) if stats_text else 0,
                 host_ms_between_frames=host_ms_between_frames(steps), stats_csv=stats_text),
    )
    staged = out + ".partial"
    with open(staged, "w") as f:
        json.dump(report, f, indent=1)
        f.write("\n")
    os.replace(staged, out)


if __name__ == "__main__":
    if len(sys.argv) != 3 or not os.path.isdir(sys.argv[1]):  # bad input: 2, as every script
        print("gpu_check_report.py: usage: gpu_check_report.py WORK_DIR OUT_FILE (WORK_DIR: gpu_check.sh's step files)",
              file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1], sys.argv[2])
