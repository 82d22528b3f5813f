#!/usr/bin/env python3
"""Peak resident size over a long embedding's add/update/remove cycles (issue 34).

The loop a simulation that spawns and despawns meshes runs: add a deformable grid of about
5,000 triangles, update(), remove it; repeated. Peak RSS (VmHWM) is printed after 300, 1,500
and 3,000 cycles, through the C++ API (the memory_cycles program, run as a subprocess) and
through Python (`dynrt` in a child process of this script, one process per run so that each
peak is its own). The target: the peak after 3,000 cycles within 10% of the peak after 300.

    python3 benchmarks/memory_cycles.py [--bin build/release/benchmarks/memory_cycles]
        [--lib DIR] [--pythonpath DIR] [--checkpoints 300,1500,3000] [--triangles 5000]

--lib runs the C++ program against another build's libdynrt.so (LD_LIBRARY_PATH), and
--pythonpath imports another build's module, to compare builds with one binary and one script.
"""

import argparse
import math
import os
import subprocess
import sys


def status_kb(key):
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


def child(checkpoints, triangles):
    """The loop through Python, printing the C++ program's lines."""
    import numpy as np

    import dynrt

    side = max(1, round(math.sqrt(triangles / 2)))
    n = side + 1
    j, i = np.meshgrid(np.arange(side), np.arange(side), indexing="ij")
    a = (j * n + i).ravel()
    b, c = a + 1, a + n
    indices = np.stack([a, c, b, b, c, c + 1], axis=1).reshape(-1, 3).astype(np.uint32)
    u = np.arange(n, dtype=np.float32) / np.float32(side)
    x, z = np.meshgrid(u, u)
    engine = dynrt.Engine()
    cycle = 0
    for target in checkpoints:
        while cycle < target:
            phase = np.float32(0.01 * cycle)
            y = np.float32(0.05) * np.sin(np.float32(12) * x + phase) * np.cos(np.float32(9) * z - phase)
            positions = np.stack([x, y.astype(np.float32), z], axis=-1).reshape(-1, 3)
            mesh = engine.add_mesh(positions, indices, motion="deformable", name="debris")
            engine.update()
            engine.remove_mesh(mesh)
            cycle += 1
        print(f"cycles {cycle} peak_rss_kb {status_kb('VmHWM')} rss_kb {status_kb('VmRSS')}", flush=True)


def parse(lines):
    rows = {}
    for line in lines.splitlines():
        words = line.split()
        if len(words) == 6 and words[0] == "cycles":
            rows[int(words[1])] = (int(words[3]), int(words[5]))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bin", default="build/release/benchmarks/memory_cycles")
    parser.add_argument("--lib", help="folder of the libdynrt.so to run the C++ program against")
    parser.add_argument("--pythonpath", help="folder holding the dynrt package to import")
    parser.add_argument("--checkpoints", default="300,1500,3000")
    parser.add_argument("--triangles", type=int, default=5000)
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    checkpoints = [int(c) for c in args.checkpoints.split(",")]
    if args.child:
        child(checkpoints, args.triangles)
        return 0
    runs = []
    env = dict(os.environ)
    if args.lib:
        env["LD_LIBRARY_PATH"] = args.lib + os.pathsep + env.get("LD_LIBRARY_PATH", "")
    cpp = subprocess.run([args.bin, "--triangles", str(args.triangles), "--checkpoints", args.checkpoints],
                         env=env, capture_output=True, text=True, check=True)
    runs.append(("C++ API", parse(cpp.stdout)))
    env = dict(os.environ)
    if args.pythonpath:
        env["PYTHONPATH"] = args.pythonpath + os.pathsep + env.get("PYTHONPATH", "")
    py = subprocess.run([sys.executable, __file__, "--child", "--checkpoints", args.checkpoints,
                         "--triangles", str(args.triangles)], env=env, capture_output=True, text=True, check=True)
    runs.append(("Python", parse(py.stdout)))
    print("| front end | " + " | ".join(f"peak MB after {c}" for c in checkpoints) + f" | last / first |")
    print("| --- |" + " ---: |" * (len(checkpoints) + 1))
    for name, rows in runs:
        peaks = [rows[c][0] / 1024 for c in checkpoints]
        print(f"| {name} | " + " | ".join(f"{p:.1f}" for p in peaks) + f" | {peaks[-1] / peaks[0]:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
