#!/usr/bin/env python3
"""Cache misses per ray of dynrt's trace, simulated by Valgrind's cachegrind (issue 43,
"memory-coherent layouts").

This machine's virtual CPUs expose no cache counters to `perf`, so the caches are simulated:
cachegrind counts the first-level data cache's (D1) and the last level's (LL) read and write
misses of every instruction the process runs, with the host's cache sizes. To keep only the
trace's, each case is rendered twice on one thread, at --res and at 1x1: the loading, the
build and the bookkeeping are the same in both, so the difference of the misses over the
difference of the rays (camera and shadow rays, from the reports) is the misses of a ray.

Cachegrind cannot run AVX-512 code: give it a build without it (-march=haswell: the AVX2
kernels, 8 lanes), e.g.

    bash scripts/build.sh avx2 -DCMAKE_BUILD_TYPE=Release -DDYNRT_NATIVE=OFF \\
        -DCMAKE_CXX_FLAGS=-march=haswell -- dynrt
    /usr/bin/python3 scripts/cache_misses.py --dynrt build/avx2/engine/dynrt sphere:200000 \\
        --flags "" --flags "--leaves compact" --flags "--leaves compact --nodes quantized"

It installs Valgrind (Debian's `valgrind`) when it is missing. Each run is 20-50 times slower
than natively: keep the scenes to a few hundred thousand triangles.
"""

import argparse
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

COUNTS = re.compile(r"==\d+== (D1  misses|LLd misses|D   refs):\s+([\d,]+)")


def ensure_valgrind():
    if shutil.which("valgrind"):
        return
    print("installing valgrind (apt-get)", file=sys.stderr)
    subprocess.run(["apt-get", "update", "-q"], check=True)
    subprocess.run(["apt-get", "install", "-y", "-q", "valgrind"], check=True)


def run(dynrt, scene, flags, res, last_level, workdir):
    """Cachegrind's data-cache totals and the report's rays of one render."""
    report = os.path.join(workdir, "report.json")
    command = ["valgrind", "--tool=cachegrind", "--cache-sim=yes", "--cachegrind-out-file=/dev/null",
               f"--LL={last_level}", dynrt, "render", scene, "--res", res, "--threads", "1", "--reuse", "off",
               "--out", os.path.join(workdir, "image.png"), "--report", report] + flags
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed: {shlex.join(command)}\n{done.stderr[-2000:]}")
    counts = {name: int(value.replace(",", "")) for name, value in COUNTS.findall(done.stderr)}
    with open(report) as f:
        frame = json.load(f)["frames"][0]
    counts["rays"] = frame["primary_rays"] + frame["shadow_rays"]
    return counts


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dynrt", required=True, help="a dynrt binary built without AVX-512")
    parser.add_argument("scene", nargs="+", help="scene specs or files")
    parser.add_argument("--flags", action="append", default=None,
                        help="render flags of one configuration (repeatable; default: none)")
    parser.add_argument("--res", default="256x256")
    parser.add_argument("--ll", default="8388608,16,64",
                        help="the simulated last-level cache: size,associativity,line bytes (default "
                             "8 MB, a core's share of a desktop L3; cachegrind would take the whole "
                             "host socket's, 272 MB on this virtual machine)")
    args = parser.parse_args()
    ensure_valgrind()
    configurations = args.flags or [""]
    print(f"simulated last level: {args.ll} (size,ways,line); D1 as the host's")
    print(f"{'scene':34} {'flags':38} {'rays':>8} {'D refs/ray':>11} {'D1 miss/ray':>12} {'LLd miss/ray':>13}")
    with tempfile.TemporaryDirectory() as workdir:
        for scene in args.scene:
            for flags in configurations:
                split = shlex.split(flags)
                full = run(args.dynrt, scene, split, args.res, args.ll, workdir)
                empty = run(args.dynrt, scene, split, "1x1", args.ll, workdir)
                rays = full["rays"] - empty["rays"]
                per = {k: (full[k] - empty[k]) / rays for k in ("D   refs", "D1  misses", "LLd misses")}
                print(f"{scene:34} {flags or '(default)':38} {rays:8d} {per['D   refs']:11.1f} "
                      f"{per['D1  misses']:12.2f} {per['LLd misses']:13.3f}", flush=True)


if __name__ == "__main__":
    main()
