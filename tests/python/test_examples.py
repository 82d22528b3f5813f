"""The Python examples (engine/python/examples) run as a user runs them: each as a program of
this interpreter, with a few steps, checked on its exit code, its per-step table and the files it
writes. Self-contained: the examples find dynrt through PYTHONPATH, set here to wherever this
process imported it from."""

import os
import pathlib
import re
import subprocess
import sys

import numpy as np

import dynrt

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "engine" / "python" / "examples"
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def run_example(name, *args, cwd):
    """Runs examples/<name> with `args`; returns its standard output, failing on a nonzero exit."""
    env = dict(os.environ)
    package_root = str(pathlib.Path(dynrt.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (package_root, env.get("PYTHONPATH")) if p)
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, (
        f"{name} exited with {done.returncode}:\n{done.stdout}\n{done.stderr}")
    return done.stdout


def table(stdout):
    """The per-step table: one dict per step row, keyed by the header line's column names."""
    lines = stdout.splitlines()
    header_at = next(i for i, line in enumerate(lines) if line.split()[:1] == ["step"])
    columns = lines[header_at].split()
    rows = []
    for line in lines[header_at + 1:]:
        words = line.split()
        if not words or not words[0].isdigit():
            break
        rows.append(dict(zip(columns, words)))
    return rows


def test_lidar_sweep_returns_points_on_the_cars(tmp_path):
    out = tmp_path / "lidar"
    stdout = run_example("lidar_sweep.py", "--steps", 3, "--channels", 16, "--azimuth", 256,
                         "--out", out, cwd=tmp_path)
    rows = table(stdout)
    assert [int(row["step"]) for row in rows] == [0, 1, 2]
    rays = 16 * 256
    for row in rows:
        assert 0 < int(row["points"]) <= rays
        # Some of every sweep's returns fall on the cars around the ego car.
        assert sum(float(row[f"car{k}%"]) for k in range(6)) > 0.0, row
    assert int(re.search(r"(\d+) returns on cars in all", stdout).group(1)) > 0, stdout

    assert (out / "range_image.png").read_bytes().startswith(PNG_SIGNATURE)
    with np.load(out / "points.npz") as cloud:
        points, mesh, names = cloud["points"], cloud["mesh"], list(cloud["names"])
    assert points.dtype == np.float32 and points.shape == (len(mesh), 3)
    assert int(rows[-1]["points"]) == len(points)
    assert np.isfinite(points).all()
    # The points lie on what they hit: the ground at y = 0, the cars' bodies between 0.3 m and
    # the vans' roofs at 2.3 m.
    np.testing.assert_allclose(points[mesh == names.index("ground"), 1], 0.0, atol=1e-3)
    on_cars = np.isin(mesh, [names.index(f"car{k}") for k in range(6)])
    assert on_cars.any()
    assert points[on_cars, 1].min() >= 0.3 - 1e-3 and points[on_cars, 1].max() <= 2.3 + 1e-3


def test_lidar_sweep_ray_order_changes_the_tracer_not_the_hits(tmp_path):
    images = {}
    for order in ("horizon", "channel"):
        out = tmp_path / order
        stdout = run_example("lidar_sweep.py", "--steps", 1, "--channels", 16, "--azimuth", 256,
                             "--order", order, "--out", out, cwd=tmp_path)
        packets = float(table(stdout)[0]["packets"].rstrip("%"))
        # Coherent runs go as packets; rows of a range image sweep 90 degrees and go ray by ray.
        assert packets > 0.0 if order == "horizon" else packets == 0.0, stdout
        images[order] = (out / "range_image.png").read_bytes()
    assert images["horizon"] == images["channel"]


def test_cloth_loop_moves_the_borrowed_cloth_and_renders_every_step(tmp_path):
    out = tmp_path / "frames"
    steps = 6
    stdout = run_example("cloth_loop.py", "--steps", steps, "--size", "64x48", "--out", out,
                         cwd=tmp_path)
    rows = table(stdout)
    assert [int(row["step"]) for row in rows] == list(range(1, steps + 1))
    for row in rows:
        # The engine saw the borrowed positions change: the cloth was refitted or rebuilt.
        refitted, rebuilt = (int(n) for n in row["ref/reb"].split("/"))
        assert refitted + rebuilt == 1, row
        assert int(row["cloth_px"]) > 0, row
    assert f"median over {steps} steps" in stdout

    frames = sorted(out.glob("frame_*.png"))
    assert [f.name for f in frames] == [f"frame_{s:04d}.png" for s in range(1, steps + 1)]
    assert all(f.read_bytes().startswith(PNG_SIGNATURE) for f in frames)
    # The cloth falls between the first frame and the last.
    assert frames[0].read_bytes() != frames[-1].read_bytes()
