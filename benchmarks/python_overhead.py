#!/usr/bin/env python3
"""What the Python layer adds to a simulation step (issue 23), measured in one script.

The step is bm_api's (benchmarks/bm_api.cpp, BM_StepApi): a 224 x 224-vertex waving grid
(99,458 triangles, deformable) gets new positions, update() refits it, and 1,048,576 camera
rays in 16x16 blocks (rays:0) are intersected. The C++ side is bm_api itself, run as a
subprocess (Google Benchmark's per-iteration real time, the vertex copy into a borrowed buffer
untimed); the Python side is the same step through `dynrt` in this process: the same grid and
rays built with numpy in float32 by the same formulas, set_positions + update() (its report
dict included) + intersect(origins, directions, 0, 100, out=hits), timed with perf_counter,
the borrowed array's copy untimed as in C++. Rounds alternate C++ and Python so that both see
the same machine load; each side's figure is the median over rounds of its per-step mean.

    /usr/bin/python3 benchmarks/python_overhead.py [--rounds 7] [--steps 30] [--bm build/release/benchmarks/bm_api]
"""

import argparse
import json
import pathlib
import statistics
import subprocess
import sys
import time

import numpy as np

import dynrt

GRID = 224
IMAGE = 1024


def wave_frame(phase):
    """bm_api's wave_frame: x, z on the unit square, y a product of sines (float32)."""
    i = np.arange(GRID, dtype=np.float32) / np.float32(GRID - 1)
    x, z = np.meshgrid(i, i)  # x varies along a row, rows are z: vertex j * GRID + i
    y = np.float32(0.05) * np.sin(np.float32(12) * x + np.float32(phase)) * np.cos(np.float32(9) * z - np.float32(phase))
    return np.ascontiguousarray(np.stack([x, y.astype(np.float32), z], axis=-1).reshape(-1, 3), dtype=np.float32)


def grid_indices():
    j, i = np.meshgrid(np.arange(GRID - 1), np.arange(GRID - 1), indexing="ij")
    a = (j * GRID + i).ravel()
    b, c = a + 1, a + GRID
    d = c + 1
    return np.stack([a, c, b, b, c, d], axis=1).reshape(-1, 3).astype(np.uint32)


def tile_rays():
    """bm_api's camera rays, 16x16 blocks in order: from (0.5, 1.2, 0.5) looking down."""
    s = np.float32(np.tan(np.float32(0.5236)))
    ty, tx, y, x = np.meshgrid(np.arange(0, IMAGE, 16), np.arange(0, IMAGE, 16), np.arange(16), np.arange(16),
                               indexing="ij")
    px = (tx + x).ravel().astype(np.float32)
    py = (ty + y).ravel().astype(np.float32)
    u = (np.float32(2) * (px + np.float32(0.5)) / np.float32(IMAGE) - np.float32(1)) * s
    v = (np.float32(2) * (py + np.float32(0.5)) / np.float32(IMAGE) - np.float32(1)) * s
    directions = np.stack([u, np.full_like(u, -1.0), v], axis=1).astype(np.float32)
    origins = np.tile(np.float32([0.5, 1.2, 0.5]), (len(u), 1))
    return np.ascontiguousarray(origins), np.ascontiguousarray(directions)


def cpp_round(bm, borrow, min_time):
    """One run of bm_api's BM_StepApi/rays:0/borrow:B: ms per step (real time)."""
    out = subprocess.run([str(bm), f"--benchmark_filter=^BM_StepApi/rays:0/borrow:{int(borrow)}/",
                          "--benchmark_format=json", f"--benchmark_min_time={min_time}"],
                         check=True, capture_output=True, text=True).stdout
    run = json.loads(out)["benchmarks"][0]
    assert run["time_unit"] == "ms"
    return run["real_time"], int(run["iterations"])


class PythonStep:
    def __init__(self, borrow, per_ray_limits=False):
        self.frames = [wave_frame(0.0), wave_frame(1.0)]
        self.borrow = borrow
        self.buffer = self.frames[0].copy()
        self.engine = dynrt.Engine()  # all cores, as bm_api's Engine
        self.mesh = self.engine.add_mesh(self.buffer if borrow else self.frames[0], grid_indices(),
                                         motion="deformable", borrow=borrow, name="wave")
        self.engine.update()
        self.origins, self.directions = tile_rays()
        self.hits = np.empty(len(self.origins), dtype=dynrt.hit_dtype)
        # Scalar limits read 24 bytes per ray (origin, direction); per-ray limit arrays 32, as
        # the C++ side's dynrt::Ray structs.
        n = len(self.origins)
        self.tmin, self.tmax = ((np.zeros(n, np.float32), np.full(n, 100.0, np.float32)) if per_ray_limits
                                else (0.0, 100.0))
        self.step = 0

    def run(self, steps):
        """Mean ms per step over `steps` steps, the borrowed buffer's copy untimed."""
        total = 0.0
        for _ in range(steps):
            self.step += 1
            frame = self.frames[self.step % 2]
            if self.borrow:
                np.copyto(self.buffer, frame)  # the simulation's own write: not timed (as in C++)
                positions = self.buffer
            else:
                positions = frame
            start = time.perf_counter()
            self.engine.set_positions(self.mesh, positions)
            report = self.engine.update()
            self.engine.intersect(self.origins, self.directions, self.tmin, self.tmax, out=self.hits)
            total += time.perf_counter() - start
            assert report["triangles_refitted"] == 99458
        return 1e3 * total / steps


def fixed_costs(calls=2000):
    """Each call's cost on a one-triangle mesh and one ray: the Python layer's per-call floor
    (argument checks, the report dict, result arrays) plus the engine's least work, in us."""
    engine = dynrt.Engine(threads=1)
    positions = np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    mesh = engine.add_mesh(positions, np.uint32([[0, 1, 2]]), motion="deformable", borrow=True)
    engine.update()
    origins, directions = np.float32([[0.2, 0.2, 1]]), np.float32([[0, 0, -1]])
    hits = np.empty(1, dtype=dynrt.hit_dtype)
    calls_to_time = {
        "set_positions": lambda: engine.set_positions(mesh, positions),
        "update (a refit, report dict)": lambda: (engine.set_positions(mesh, positions), engine.update()),
        "intersect 1 ray (out=)": lambda: engine.intersect(origins, directions, out=hits),
    }
    out = {}
    for name, call in calls_to_time.items():
        times = []
        for _ in range(5):
            start = time.perf_counter()
            for _ in range(calls):
                call()
            times.append((time.perf_counter() - start) / calls * 1e6)
        out[name] = statistics.median(times)
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--steps", type=int, default=30, help="Python steps per round")
    parser.add_argument("--min-time", type=float, default=2.0, help="bm_api's --benchmark_min_time per round (s)")
    parser.add_argument("--per-ray-limits", action="store_true",
                        help="pass tmin and tmax as float32 (N,) arrays (32 bytes per ray, as a dynrt::Ray)")
    parser.add_argument("--bm", default=str(pathlib.Path(__file__).resolve().parents[1] / "build/release/benchmarks/bm_api"))
    args = parser.parse_args()

    print(f"python {sys.version.split()[0]}, numpy {np.__version__}, dynrt from {pathlib.Path(dynrt.__file__).parent}")
    print("per-call floor on a one-triangle mesh (us, median of 5 x 2000 calls): " +
          ", ".join(f"{name} {us:.1f}" for name, us in fixed_costs().items()))
    for borrow in (True, False):
        py = PythonStep(borrow, args.per_ray_limits)
        py.run(3)  # warm up: trees, caches, first-touch of the hit array
        cpp_ms, py_ms, iterations = [], [], []
        for _ in range(args.rounds):
            ms, n = cpp_round(args.bm, borrow, args.min_time)
            cpp_ms.append(ms)
            iterations.append(n)
            py_ms.append(py.run(args.steps))
        c, p = statistics.median(cpp_ms), statistics.median(py_ms)
        limits = "per-ray tmin/tmax arrays" if args.per_ray_limits else "scalar tmin/tmax"
        print(f"\n{'borrow' if borrow else 'copy'} ({limits}): {args.rounds} rounds, C++ {min(iterations)}-{max(iterations)} "
              f"steps per round, Python {args.steps}")
        print(f"  C++ API    ms/step: median {c:8.2f}  (min {min(cpp_ms):.2f}, max {max(cpp_ms):.2f})")
        print(f"  Python     ms/step: median {p:8.2f}  (min {min(py_ms):.2f}, max {max(py_ms):.2f})")
        print(f"  Python over C++: {100 * (p / c - 1):+.1f}% (medians); {100 * (min(py_ms) / min(cpp_ms) - 1):+.1f}% (minima)")
        print("  per round (C++, Python): " + ", ".join(f"{a:.1f}/{b:.1f}" for a, b in zip(cpp_ms, py_ms)))


if __name__ == "__main__":
    main()
