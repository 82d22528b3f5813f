"""What the Python module's tests share: meshes built with numpy (a waving grid, a UV sphere),
ray batches (coherent camera rays, which the engine traces as 16x16 packets, and incoherent
random ones, traced ray by ray), a small world of meshes of every motion class, and where the
C++ oracle program and the shared scene files are.

Run from the repository (scripts/run_tests.sh does):

    DYNRT_API_ORACLE=build/release/tests/python/dynrt_python_api_oracle \
    PYTHONPATH=build/release/python /usr/bin/python3 -m pytest -q -p no:cacheprovider tests/python
"""

import math
import os
from pathlib import Path

import numpy as np
import pytest

import dynrt

REPO = Path(__file__).resolve().parents[2]


# ---- meshes ---------------------------------------------------------------------------------

def grid_indices(n):
    """Two triangles per quad of an n x n vertex grid, (2 (n-1)^2, 3) int32."""
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="xy")
    a = (j * n + i).ravel()
    b, c, d = a + 1, a + n, a + n + 1
    return np.stack([np.stack([a, b, c], 1), np.stack([b, d, c], 1)], 1).reshape(-1, 3).astype(np.int32)


def wave_positions(n, phase=0.0, size=2.0, amplitude=0.15, out=None):
    """An n x n grid in the plane y = 0, `size` wide and centred on the origin, waved:
    y = amplitude sin(3 x + phase) cos(3 z). float32 (n * n, 3); written into `out` if given."""
    s = np.linspace(-size / 2, size / 2, n, dtype=np.float64)
    x, z = np.meshgrid(s, s, indexing="xy")
    y = amplitude * np.sin(3.0 * x + phase) * np.cos(3.0 * z)
    p = np.stack([x.ravel(), y.ravel(), z.ravel()], 1).astype(np.float32)
    if out is None:
        return p
    out[...] = p
    return out


def wave_grid(n, phase=0.0, size=2.0, amplitude=0.15):
    """(positions float32 (n * n, 3), indices int32 (T, 3)) of the waved grid."""
    return wave_positions(n, phase, size, amplitude), grid_indices(n)


def uv_sphere(rings=12, segments=24, radius=0.5, centre=(0.0, 0.0, 0.0)):
    """A closed UV sphere: (positions float32 (V, 3), indices int32 (T, 3))."""
    theta = np.pi * np.arange(1, rings) / rings
    phi = 2 * np.pi * np.arange(segments) / segments
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], -1).reshape(-1, 3)
    v = np.concatenate([[[0, 1, 0]], ring, [[0, -1, 0]]]) * radius + np.asarray(centre)
    south = len(v) - 1
    at = lambda r, s: 1 + (r - 1) * segments + (s % segments)  # noqa: E731
    tris = []
    for s in range(segments):
        tris.append((0, at(1, s + 1), at(1, s)))
        tris.append((south, at(rings - 1, s), at(rings - 1, s + 1)))
    for r in range(1, rings - 1):
        for s in range(segments):
            tris.append((at(r, s), at(r, s + 1), at(r + 1, s)))
            tris.append((at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)))
    return v.astype(np.float32), np.asarray(tris, dtype=np.int32)


def translation(x, y, z):
    m = np.eye(4, dtype=np.float32)
    m[:3, 3] = (x, y, z)
    return m


def rotation_y(radians, offset=(0.0, 0.0, 0.0)):
    """Rotation about +Y, then `offset`: float32 (4, 4), rows first."""
    c, s = math.cos(radians), math.sin(radians)
    m = np.array([[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1]], dtype=np.float64)
    m[:3, 3] = offset
    return m.astype(np.float32)


# ---- rays -----------------------------------------------------------------------------------

def camera_rays(width, height, eye=(0.0, 2.5, 3.0), target=(0.0, 0.0, 0.0), fov_y_deg=40.0):
    """Pinhole rays through pixel centres, row by row: neighbours next to each other, so the
    engine traces each run of 256 as a packet. (origins, directions), float32 (N, 3)."""
    eye, target = np.asarray(eye, np.float64), np.asarray(target, np.float64)
    forward = target - eye
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, [0.0, 1.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    half = math.tan(math.radians(fov_y_deg) / 2)
    aspect = width / height
    px = ((np.arange(width) + 0.5) / width * 2 - 1) * half * aspect
    py = (1 - (np.arange(height) + 0.5) / height * 2) * half
    x, y = np.meshgrid(px, py, indexing="xy")
    d = forward + x.reshape(-1, 1) * right + y.reshape(-1, 1) * up
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    origins = np.broadcast_to(eye, d.shape).astype(np.float32)
    return np.ascontiguousarray(origins), d.astype(np.float32)


def random_rays(n, seed=7, box=1.5):
    """Incoherent rays: origins in a box around the world, directions uniform on the sphere
    (traced ray by ray). (origins, directions), float32 (N, 3)."""
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-box, box, (n, 3)).astype(np.float32)
    directions = rng.normal(size=(n, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    return origins, directions.astype(np.float32)


def ray_limits(n, seed=11):
    """Per-ray tmin and tmax, float32 (N,): tmin in [0, 0.5), tmax in [tmin + 0.5, tmin + 6) or
    +inf for a quarter of the rays."""
    rng = np.random.default_rng(seed)
    tmin = rng.uniform(0.0, 0.5, n).astype(np.float32)
    tmax = (tmin + rng.uniform(0.5, 6.0, n)).astype(np.float32)
    tmax[rng.uniform(size=n) < 0.25] = np.inf
    return tmin, tmax


VIEW = dict(eye=(0.0, 2.5, 3.0), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_y_deg=40.0)


def view():
    return dynrt.View(**VIEW)


# ---- a small world of every motion class ----------------------------------------------------

# Surfaces as their 16 floats (api_oracle.cpp's NAME.surface.f32): diffuse, specular, shininess,
# reflectance, transmittance, ior, padding. Values exact in float32.
MIRROR = (0.25, 0.5, 0.75, 0.5, 0.5, 0.5, 64.0, 0.75, 0.75, 0.75, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0)
GLASS = (0.125, 0.125, 0.125, 0.25, 0.25, 0.25, 16.0, 0.0, 0.0, 0.0, 0.875, 0.875, 0.75, 1.5, 0.0, 0.0)


def surface(values):
    """A dynrt.Surface from its 16 floats, or None."""
    if values is None:
        return None
    v = values
    return dynrt.Surface(diffuse=v[0:3], specular=v[3:6], shininess=v[6], reflectance=v[7:10],
                         transmittance=v[10:13], ior=v[13])


class World:
    """The meshes of the oracle comparison, in add_mesh order, with what changes at step 1.
    Each entry: name, motion, positions0, indices, transform0 (or None), positions1 (or None),
    transform1 (or None)."""

    def __init__(self):
        cloth_p0, cloth_i = wave_grid(40, phase=0.0)
        ball_p, ball_i = uv_sphere(rings=10, segments=20, radius=0.35)
        floor_p = np.array([[-3, -0.6, -3], [3, -0.6, -3], [3, -0.6, 3], [-3, -0.6, 3]], np.float32)
        floor_i = np.array([[0, 2, 1], [0, 3, 2]], np.int32)
        flag_p0, flag_i = wave_grid(12, phase=0.5, size=0.6)
        flag_p0 = flag_p0[:, [0, 2, 1]] + np.float32([0.9, 0.3, -0.4])  # upright, to the right
        self.meshes = [
            dict(name="cloth", motion="deformable", positions0=cloth_p0, indices=cloth_i, surface=None,
                 transform0=None, positions1=wave_positions(40, phase=0.9), transform1=None),
            dict(name="ball", motion="rigid", positions0=ball_p, indices=ball_i, surface=MIRROR,
                 transform0=translation(-0.5, 0.45, 0.2), positions1=None,
                 transform1=rotation_y(0.7, offset=(0.4, 0.55, -0.1))),
            dict(name="floor", motion="static", positions0=floor_p, indices=floor_i, surface=None,
                 transform0=None, positions1=None, transform1=None),
            dict(name="flag", motion="automatic", positions0=flag_p0, indices=flag_i, surface=None,
                 transform0=None, positions1=None,
                 transform1=rotation_y(-0.4, offset=(0.1, 0.05, 0.0))),
            dict(name="blob", motion="automatic", positions0=ball_p * np.float32(0.6), indices=ball_i, surface=GLASS,
                 transform0=translation(0.2, 0.6, 0.9),
                 positions1=ball_p * np.float32([0.7, 0.5, 0.7]), transform1=None),
        ]

    def build(self, borrow=False, engine=None):
        """An Engine holding the meshes at step 0 (updated), and the arrays it was given (the
        borrowed ones when borrow=True: step() writes into them)."""
        engine = engine or dynrt.Engine()
        arrays = []
        for m in self.meshes:
            p = m["positions0"].copy()
            mesh = engine.add_mesh(p, m["indices"], motion=m["motion"], transform=m["transform0"],
                                   name=m["name"], borrow=borrow, surface=surface(m["surface"]))
            assert mesh == len(arrays)
            arrays.append(p)
        engine.update()
        return engine, arrays

    def step(self, engine, arrays, in_place):
        """Step 1's changes, then update(). in_place: new positions are written into the arrays
        given before (as a simulation writes its borrowed buffers)."""
        for mesh, m in enumerate(self.meshes):
            if m["positions1"] is not None:
                if in_place:
                    arrays[mesh][...] = m["positions1"]
                    engine.set_positions(mesh, arrays[mesh])
                else:
                    engine.set_positions(mesh, m["positions1"].copy())
            if m["transform1"] is not None:
                engine.set_transform(mesh, m["transform1"])
        engine.update()


@pytest.fixture(scope="session")
def world():
    return World()


# ---- paths ----------------------------------------------------------------------------------

def oracle_path():
    env = os.environ.get("DYNRT_API_ORACLE")
    path = Path(env) if env else REPO / "build" / "release" / "tests" / "python" / "dynrt_python_api_oracle"
    return path if path.is_absolute() else Path.cwd() / path


@pytest.fixture(scope="session")
def oracle():
    path = oracle_path()
    if not path.exists():
        pytest.skip(f"the C++ oracle {path} is not built (target dynrt_python_api_oracle; "
                    f"DYNRT_API_ORACLE names another)")
    return path


def shared_scenes_dir():
    env = os.environ.get("DYNRT_SHARED_SCENES_DIR")
    return Path(env) if env else REPO.parent / "shared" / "scenes"


@pytest.fixture(scope="session")
def shared_scenes():
    path = shared_scenes_dir()
    if not path.is_dir():
        pytest.skip(f"no shared scenes at {path} (DYNRT_SHARED_SCENES_DIR names another folder)")
    return path
