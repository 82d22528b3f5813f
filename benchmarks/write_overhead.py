#!/usr/bin/env python3
"""What writing the frames costs a whole `dynrt render` (issue 34).

Renders a sequence to numbered PNGs (default: CesiumMan's frames 0-23 at 1024x1024) several
times, each timed as a whole process (wall clock), and reads its report: the ratio printed is

    whole process / (sum of the frames' total_ms + the scene's start-up)

1.0 would be a render whose writing costs nothing beside the frames. The start-up is taken two
ways: the wall time of `dynrt info SCENE` (the same scene load, and the process's own start:
libraries loaded, which run.startup_ms does not see), which every dynrt has, and the report's
run.startup_ms (from the command's start to its first frame) when the dynrt writes it. Prints the medians (min-max) over the runs, the writer's
median ms per frame (write_ms) and how long the render waited for it when the report has them.

  /usr/bin/python3 benchmarks/write_overhead.py [--dynrt PATH] [--scene S] [--frames 0-23]
                                                [--res 1024x1024] [--runs 5] [--ext png]
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DYNRT = os.path.join(HERE, "..", "build", "release", "engine", "dynrt")
CESIUM = os.path.join(HERE, "..", "..", "shared", "scenes", "cesiumman", "CesiumMan.glb")


def spread(values):
    return f"{statistics.median(values):.3f} ({min(values):.3f}-{max(values):.3f})"


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dynrt", default=DYNRT)
    p.add_argument("--scene", default=CESIUM)
    p.add_argument("--frames", default="0-23")
    p.add_argument("--res", default="1024x1024")
    p.add_argument("--runs", type=int, default=5)
    p.add_argument("--ext", default="png", help="image format of the frames (png, bmp, exr, ...)")
    args = p.parse_args()
    if not os.path.exists(args.scene) and ":" not in args.scene:
        print(f"write_overhead: {args.scene} not found; skipped")
        return 0
    work = tempfile.mkdtemp(prefix="dynrt_write_overhead_")
    walls, frame_sums, startups, ratios, write_ms, waits = [], [], [], [], [], []
    report_startups, report_ratios = [], []
    try:
        for _ in range(args.runs):
            out = os.path.join(work, "frames")
            shutil.rmtree(out, ignore_errors=True)
            report = os.path.join(work, "r.json")
            command = [args.dynrt, "render", args.scene, "--frames", args.frames, "--res", args.res,
                       "--out", os.path.join(out, "%04d." + args.ext), "--report", report]
            start = time.perf_counter()
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
            wall = time.perf_counter() - start
            with open(report) as f:
                doc = json.load(f)
            frames_s = sum(frame["total_ms"] for frame in doc["frames"]) / 1000.0
            start = time.perf_counter()
            subprocess.run([args.dynrt, "info", args.scene], check=True, stdout=subprocess.DEVNULL)
            startup_s = time.perf_counter() - start
            walls.append(wall)
            frame_sums.append(frames_s)
            startups.append(startup_s)
            ratios.append(wall / (frames_s + startup_s))
            if "startup_ms" in doc["run"]:
                report_startups.append(doc["run"]["startup_ms"] / 1000.0)
                report_ratios.append(wall / (frames_s + report_startups[-1]))
            if "write_ms" in doc["frames"][0]:
                write_ms.append(statistics.median(frame["write_ms"] for frame in doc["frames"]))
                waits.append(doc["run"].get("writer_wait_ms", 0.0))
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print(f"{args.dynrt}: {args.scene} frames {args.frames} at {args.res} to .{args.ext}, "
          f"{args.runs} runs, median (min-max)")
    print(f"  whole process s       {spread(walls)}")
    print(f"  sum of total_ms, s    {spread(frame_sums)}")
    print(f"  dynrt info s          {spread(startups)}")
    print(f"  ratio (dynrt info)    {spread(ratios)}")
    if report_startups:
        print(f"  run.startup_ms, s     {spread(report_startups)}")
        print(f"  ratio (startup_ms)    {spread(report_ratios)}")
    if write_ms:
        print(f"  writer ms/frame       {spread(write_ms)}")
        print(f"  render waited, ms     {spread(waits)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
