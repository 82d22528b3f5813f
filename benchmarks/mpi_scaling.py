#!/usr/bin/env python3
"""Frames per second of `dynrt render` across processes on one machine (issue 24).

Renders the same frames of a scene (default: BART kitchen at 1024x1024) as
  one process with T threads (the ordinary render),
  mpirun -np 1 and -np N with one thread each (--distribute frames),
  mpirun -np N with one thread each and --distribute tiles,
rounds interleaved, each configuration timed as a whole process (wall clock, images written
included). Prints the median fps (min-max) per configuration and, from the reports, the median
per-frame hand-out and gather times against the median frame time.

  /usr/bin/python3 benchmarks/mpi_scaling.py [--scene S] [--frames 0-23] [--res 1024x1024]
                                             [--ranks 2] [--rounds 3]
"""

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DYNRT = os.path.join(HERE, "..", "build", "release", "engine", "dynrt")
KITCHEN = os.path.join(HERE, "..", "..", "shared", "scenes", "bart", "kitchen", "kitchen.aff")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--scene", default=KITCHEN)
    p.add_argument("--frames", default="0-23")
    p.add_argument("--res", default="1024x1024")
    p.add_argument("--ranks", type=int, default=2)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--keep", help="copy the last round's reports into this folder")
    args = p.parse_args()
    if not os.path.exists(args.scene) and ":" not in args.scene:
        print(f"mpi_scaling: {args.scene} not found; skipped")
        return 0
    if not shutil.which("mpirun"):
        print("mpi_scaling: mpirun not found (bash scripts/install-deps.sh); skipped")
        return 0
    first, last = (int(x) for x in args.frames.split("-"))
    frames = last - first + 1
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    mpirun = ["mpirun", "--oversubscribe", "--bind-to", "none"]
    n = args.ranks
    configs = {
        f"1 process, {n} threads": [DYNRT],
        "mpirun -np 1, 1 thread": mpirun + ["-np", "1", DYNRT],
        f"mpirun -np {n} frames, 1 thread each": mpirun + ["-np", str(n), DYNRT],
        f"mpirun -np {n} tiles, 1 thread each": mpirun + ["-np", str(n), DYNRT],
    }
    extra = {
        f"1 process, {n} threads": ["--threads", str(n)],
        "mpirun -np 1, 1 thread": ["--threads", "1"],
        f"mpirun -np {n} frames, 1 thread each": ["--threads", "1"],
        f"mpirun -np {n} tiles, 1 thread each": ["--threads", "1", "--distribute", "tiles"],
    }
    seconds = {name: [] for name in configs}
    reports = {}
    work = tempfile.mkdtemp(prefix="dynrt_mpi_scaling_")
    try:
        for r in range(args.rounds):
            for name, command in configs.items():
                out = os.path.join(work, f"c{list(configs).index(name)}")
                shutil.rmtree(out, ignore_errors=True)
                os.makedirs(out)
                report = os.path.join(out, "r.json")
                full = command + ["render", args.scene, "--frames", args.frames, "--res", args.res,
                                  "--out", os.path.join(out, "%04d.png"), "--report", report] + extra[name]
                start = time.perf_counter()
                subprocess.run(full, env=env, check=True, stdout=subprocess.DEVNULL)
                seconds[name].append(time.perf_counter() - start)
                with open(report) as f:
                    reports[name] = json.load(f)
                if args.keep:
                    os.makedirs(args.keep, exist_ok=True)
                    shutil.copy(report, os.path.join(args.keep, f"c{list(configs).index(name)}.json"))
                print(f"round {r + 1} {name}: {seconds[name][-1]:.2f} s", file=sys.stderr)
    finally:
        shutil.rmtree(work, ignore_errors=True)

    print(f"{args.scene} frames {args.frames} at {args.res}, {args.rounds} rounds interleaved")
    # frame ms: the median frame's total_ms after the first (the steady state, the tiles' wait
    # and gather included); overhead: the median per-frame hand-out, or the gather (with the
    # wait for the slowest share beside it), from the last round's report.
    print(f"{'configuration':40} {'fps median (min-max)':>22} {'frame ms':>9} {'overhead ms':>12} {'wait ms':>8}")
    for name in configs:
        fps = sorted(frames / s for s in seconds[name])
        frames_json = reports[name]["frames"]
        frame_ms = statistics.median(f["total_ms"] for f in frames_json[1:])
        over, wait = "", ""
        if "gather_ms" in frames_json[0]:
            over = f"{statistics.median(f['gather_ms'] for f in frames_json):.3f}"
            wait = f"{statistics.median(f['wait_ms'] for f in frames_json):.1f}"
        elif "handout_ms" in frames_json[0]:
            over = f"{statistics.median(f['handout_ms'] for f in frames_json):.3f}"
        print(f"{name:40} {statistics.median(fps):6.2f} ({fps[0]:.2f}-{fps[-1]:.2f}) {frame_ms:9.1f} "
              f"{over:>12} {wait:>8}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
