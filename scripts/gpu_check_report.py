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


def reconstruction_verdict(meta, render):
    early = not_judged(meta, render, "frames", "bench_render")
    if early:
        return early
    frames = []
    for f in render["frames"]:
        adaptive = next((r for r in f["records"] if r.get("label") == "adaptive"), None)
        if adaptive is None:
            continue
        grid = (f.get("in_place") or {}).get("solver_frame_grid_ms", 0.0)
        total = adaptive["ms_total"] + grid
        passes = adaptive.get("ms_per_pass") or {}
        sprites, march = passes.get("render_splat", 0.0), passes.get("render_march", 0.0)
        frames.append(dict(frame=f["name"], particles=f["particles"], ms_reconstruction=adaptive["ms_total"],
                           ms_frame_grid=grid, ms_total=total, ms_sprites=sprites, ms_march=march,
                           pass_=total <= RECONSTRUCTION_MS and sprites <= SPRITES_MS and march <= MARCH_MS))
    if not frames:
        return verdict("not measured", reason="bench_render drew no adaptive frame")
    passed = all(f.pop("pass_") for f in frames)
    return verdict("pass" if passed else "fail", target_ms=RECONSTRUCTION_MS, target_sprites_ms=SPRITES_MS,
                   target_march_ms=MARCH_MS, frames=frames)


def resolution_verdict(meta, render):
    """Adaptive resolution pays: >= 1.5x faster than full resolution on broad surfaces, never slower."""
    early = not_judged(meta, render, "frames", "bench_render")
    if early:
        return early
    frames = []
    for f in render["frames"]:
        r = (f.get("targets") or {}).get("adaptive_resolution") or {}
        if "full_res_ms_total" not in r:
            continue
        speedup = r["full_res_ms_total"] / r["ms_total"] if r["ms_total"] > 0 else 0.0
        need = RESOLUTION_SPEEDUP if f["name"] in BROAD_FRAMES else 1.0
        frames.append(dict(frame=f["name"], ms_adaptive=r["ms_total"], ms_full_resolution=r["full_res_ms_total"],
                           speedup=speedup, speedup_min=need, used=r.get("used"), pass_=speedup >= need))
    if not frames:
        return verdict("not measured", reason="bench_render drew no adaptive/adaptive_full_res pair")
    passed = all(f.pop("pass_") for f in frames)
    return verdict("pass" if passed else "fail", frames=frames)


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
                      adaptive_resolution=resolution_verdict(meta, render)),
        bench_sim=sim,
        bench_render=render,
        run=dict(frames_written=max(0, stats_text.count("\n") - 1) if stats_text else 0,
                 host_ms_between_frames=host_ms_between_frames(steps), stats_csv=stats_text),
    )
    staged = out + ".partial"
    with open(staged, "w") as f:
        json.dump(report, f, indent=1)
        f.write("\n")
    os.replace(staged, out)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: gpu_check_report.py WORK_DIR OUT_FILE")
    main(sys.argv[1], sys.argv[2])
