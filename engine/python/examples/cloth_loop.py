"""A cloth simulated in numpy drapes over a sphere, and dynrt renders it after every step.

What it shows about the Python API:

- The cloth's positions are *borrowed*: ``add_mesh(positions, faces, motion="deformable",
  borrow=True)`` makes the engine read the simulation's own float32 (V, 3) array, with no copy
  per step. The simulation only ever writes into that array in place (``+=``, ``[...] =``, and
  strided views of it), never rebinding it to a new one; each step ``set_positions(cloth,
  positions)`` tells the engine it changed and ``update()`` refits the cloth's tree (or rebuilds
  it when refitting has degraded it; the report says why).
- Static meshes (the ground and the sphere, placed with a 4x4 transform) are added once and
  built once.
- ``update()``'s report dict: refit, rebuild and top-level times and the objects refitted and
  rebuilt, printed beside the simulation's own time.
- ``render(view, w, h, mesh=True, report=True)`` every step: the image, the mesh id of every
  pixel (here: how many pixels show the cloth) and the render's report (trace time, and how
  many pixels were traced again: with reuse_pixels only those the moving cloth may have
  changed). With --out each frame is written with ``dynrt.save_image``.

The simulation is position-based dynamics (Mueller, Heidelberger, Hennix and Ratcliff 2007,
"Position Based Dynamics") in small substeps (Macklin et al. 2019, "Small Steps in Physics
Simulation"): Verlet integration predicts the positions, then distance constraints between grid
neighbours (structural) and across each square's diagonals (shear) are projected, followed by
sphere and ground collisions with friction. The constraints are split into 8 colours, in each of
which no two constraints share a vertex, and each colour is a pair of strided views of the
(rows, columns, 3) grid: one colour is projected with a handful of whole-array numpy operations,
Gauss-Seidel between colours, with no Python loop over particles.

    PYTHONPATH=build/release/python /usr/bin/python3 engine/python/examples/cloth_loop.py
    ... cloth_loop.py --steps 180 --size 640x480 --out cloth   # cloth/frame_0001.png, ...
"""

import argparse
import pathlib
import sys
import time

import numpy as np

import dynrt

STEP_S = 1.0 / 60.0
GRAVITY = -9.81
DAMPING = 0.998        # of the Verlet velocity, per substep
FRICTION = 0.5         # share of a contact's velocity lost per substep
CLOTH_SIZE = 2.0       # metres per side
CLOTH_HEIGHT = 1.4     # starts flat at this height, centred over the sphere
SPHERE_CENTRE = np.array([0.0, 0.55, 0.0], np.float32)
SPHERE_RADIUS = 0.55
# Cloth particles keep this far from the sphere and the ground, so that the flat triangles
# between them do not cut into the curved sphere (no z-fighting in the render).
THICKNESS = 0.012


# ---- Meshes with numpy ---------------------------------------------------------------------

def grid_faces(rows, columns):
    """Two triangles per square of a rows x columns vertex grid numbered row by row: (T, 3)."""
    i, j = np.meshgrid(np.arange(rows - 1), np.arange(columns - 1), indexing="ij")
    v00 = (i * columns + j).ravel()
    v01, v10, v11 = v00 + 1, v00 + columns, v00 + columns + 1
    return np.concatenate([np.stack([v00, v10, v11], 1), np.stack([v00, v11, v01], 1)])


def uv_sphere(radius, rings=32, segments=64):
    """A sphere around the origin: float32 positions, (T, 3) faces and float32 unit normals."""
    theta = np.linspace(0.0, np.pi, rings + 1)[:, None]
    phi = np.linspace(0.0, 2.0 * np.pi, segments + 1)[None, :]
    normals = np.stack(np.broadcast_arrays(np.sin(theta) * np.cos(phi), np.cos(theta),
                                           np.sin(theta) * np.sin(phi)), axis=-1).reshape(-1, 3)
    faces = grid_faces(rings + 1, segments + 1).reshape(2, rings, segments, 3)
    # The triangles of the first and last ring that collapse into the poles are left out.
    faces = np.concatenate([faces[0, 1:].reshape(-1, 3), faces[1, :-1].reshape(-1, 3)])
    normals = normals.astype(np.float32)
    return radius * normals, faces, normals


def translation(offset):
    """A 4x4 transform, rows first, that moves by `offset`."""
    matrix = np.eye(4)
    matrix[:3, 3] = offset
    return matrix


# ---- The cloth -------------------------------------------------------------------------------

class Cloth:
    """An n x n particle grid of unit masses, stepped by position-based dynamics in numpy.

    `positions` is the float32 (n * n, 3) array the engine borrows: it is written in place only,
    never replaced, so the engine's reference to it stays the array the simulation moves."""

    def __init__(self, n):
        u = np.linspace(-CLOTH_SIZE / 2, CLOTH_SIZE / 2, n, dtype=np.float32)
        self.positions = np.empty((n * n, 3), np.float32)
        grid = self.positions.reshape(n, n, 3)           # a view: rows along z, columns along x
        grid[..., 0] = u[None, :]
        grid[..., 1] = CLOTH_HEIGHT
        grid[..., 2] = u[:, None]
        self.previous = self.positions.copy()
        self.faces = grid_faces(n, n)

        # Each colour: (a, b, rest), two equal-shaped views of the grid, a[k] and b[k] being
        # the ends of one constraint; within a colour no vertex appears twice.
        spacing = CLOTH_SIZE / (n - 1)
        diagonal = spacing * np.sqrt(2.0)
        self.colours = []
        for s in (0, 1):   # even, then odd, first ends: neighbouring pairs never share a vertex
            self.colours += [
                (grid[:, s:n - 1:2], grid[:, s + 1:n:2], spacing),               # along x
                (grid[s:n - 1:2, :], grid[s + 1:n:2, :], spacing),               # along z
                (grid[s:n - 1:2, :-1], grid[s + 1:n:2, 1:], diagonal),           # shear \
                (grid[s:n - 1:2, 1:], grid[s + 1:n:2, :-1], diagonal),           # shear /
            ]

    def step(self, dt, substeps):
        """Advances the cloth by `dt` seconds in `substeps` substeps."""
        h = dt / substeps
        for _ in range(substeps):
            self._predict(h)
            for a, b, rest in self.colours:
                self._project(a, b, rest)
            self._collide()

    def _predict(self, h):
        """Verlet: x' = x + damping (x - x_previous) + g h^2."""
        velocity = self.positions - self.previous
        self.previous[:] = self.positions
        self.positions += DAMPING * velocity
        self.positions[:, 1] += GRAVITY * h * h

    @staticmethod
    def _project(a, b, rest):
        """Moves both ends of every constraint of a colour halfway towards being `rest` apart
        (equal masses), in place in the grid."""
        d = b - a
        length = np.sqrt(np.einsum("...i,...i->...", d, d))[..., None]
        d *= 0.5 * (1.0 - rest / np.maximum(length, 1e-9))
        a += d
        b -= d

    def _collide(self):
        """Pushes particles out of the sphere and above the ground; a contact loses part of its
        velocity (its previous position moves towards the current one), which acts as friction."""
        p = self.positions
        offset = p - SPHERE_CENTRE
        distance = np.sqrt(np.einsum("ij,ij->i", offset, offset))
        reach = SPHERE_RADIUS + THICKNESS
        inside = distance < reach
        p[inside] = SPHERE_CENTRE + offset[inside] * (reach / distance[inside])[:, None]
        below = p[:, 1] < THICKNESS
        p[below, 1] = THICKNESS
        contact = inside | below
        self.previous[contact] += FRICTION * (p[contact] - self.previous[contact])


# ---- The loop ---------------------------------------------------------------------------------

def resolution(text):
    """argparse type: 'WxH' as (width, height)."""
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WxH, e.g. 320x240, got {text!r}") from None
    if width < 1 or height < 1:
        raise argparse.ArgumentTypeError(f"width and height must be >= 1, got {text!r}")
    return width, height


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--steps", type=int, default=90, help="simulation steps of 1/60 s")
    parser.add_argument("--size", type=resolution, default="320x240", help="image size WxH")
    parser.add_argument("--grid", type=int, default=64, help="cloth particles per side")
    parser.add_argument("--substeps", type=int, default=8, help="simulation substeps per step")
    parser.add_argument("--threads", type=int, default=0, help="engine threads (0: all cores)")
    parser.add_argument("--out", type=pathlib.Path,
                        help="folder for the frames: frame_0001.png, ...")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.grid < 2 or args.substeps < 1:
        parser.error("--steps and --substeps must be at least 1, --grid at least 2")
    width, height = args.size
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)

    engine = dynrt.Engine(threads=args.threads)
    ground = np.array([[-6, 0, -6], [6, 0, -6], [6, 0, 6], [-6, 0, 6]], np.float32)
    engine.add_mesh(ground, [[0, 2, 1], [0, 3, 2]], motion="static", name="ground",
                    surface=dynrt.Surface(diffuse=(0.55, 0.55, 0.5), specular=(0, 0, 0)))
    sphere_positions, sphere_faces, sphere_normals = uv_sphere(SPHERE_RADIUS)
    engine.add_mesh(sphere_positions, sphere_faces, normals=sphere_normals, motion="static",
                    transform=translation(SPHERE_CENTRE), name="sphere",
                    surface=dynrt.Surface(diffuse=(0.7, 0.2, 0.15), specular=(0.5, 0.5, 0.5),
                                          shininess=64.0))
    cloth = Cloth(args.grid)
    cloth_id = engine.add_mesh(cloth.positions, cloth.faces, motion="deformable", borrow=True,
                               name="cloth", surface=dynrt.Surface(diffuse=(0.2, 0.4, 0.75),
                                                                   specular=(0.1, 0.1, 0.1)))
    view = dynrt.View(eye=(2.6, 2.0, 3.1), target=(0.0, 0.45, 0.0), fov_y_deg=45.0)
    lights = [dynrt.Light((-2.0, 5.0, 3.0), 0.9)]

    first = engine.update()   # builds every tree: reported apart from the steps
    print(f"cloth {args.grid}x{args.grid} particles, {first['triangles']} triangles in the scene; "
          f"first build {first['total_ms']:.2f} ms; rendering {width}x{height} every step")
    # Columns: the simulation's own time; update()'s report under its keys (total_ms is the
    # whole update; the report's update_ms is only its first stage, checking the vertices);
    # objects refitted/rebuilt; the render's wall time, the share of pixels it traced again
    # and the pixels showing the cloth (from the mesh id image).
    print(f"{'step':>4} {'sim_ms':>7} {'refit_ms':>8} {'rebuild_ms':>10} {'top_level_ms':>12} "
          f"{'total_ms':>8} {'ref/reb':>7} {'render_ms':>9} {'traced':>6} {'cloth_px':>8}")
    sim_ms, update_ms, render_ms, rebuilds = [], [], [], 0
    for step in range(1, args.steps + 1):
        started = time.perf_counter()
        cloth.step(STEP_S, args.substeps)
        sim_ms.append(1e3 * (time.perf_counter() - started))
        if not np.isfinite(cloth.positions).all():
            sys.exit(f"cloth_loop: the simulation diverged at step {step}")

        engine.set_positions(cloth_id, cloth.positions)   # the same array: "it changed"
        report = engine.update()
        update_ms.append(report["total_ms"])
        rebuilds += report["objects_rebuilt"]

        started = time.perf_counter()
        rgb, mesh, frame = engine.render(view, width, height, mesh=True, report=True, lights=lights)
        render_ms.append(1e3 * (time.perf_counter() - started))
        if args.out is not None:
            dynrt.save_image(str(args.out / f"frame_{step:04d}.png"), rgb)

        traced = frame["pixels_traced"] / (width * height)
        cloth_px = np.count_nonzero(mesh == cloth_id)
        line = (f"{step:4d} {sim_ms[-1]:7.2f} {report['refit_ms']:8.3f} "
                f"{report['rebuild_ms']:10.3f} {report['top_level_ms']:12.3f} "
                f"{report['total_ms']:8.3f} {report['objects_refitted']:3d}/"
                f"{report['objects_rebuilt']:<3d} {render_ms[-1]:9.2f} {traced:6.0%} {cloth_px:8d}")
        # Why a tree was rebuilt: for the cloth, its refitted tree's SAH cost had grown past
        # (1 + rebuild_threshold) times its cost at the last build.
        for rebuilt in report["rebuilds"]:
            line += f"  rebuilt {rebuilt['name']}: {rebuilt['reason']}"
            if "sah_at_last_build" in rebuilt:
                line += (f" (SAH {rebuilt['sah_at_last_build']:.1f} -> "
                         f"{rebuilt['sah_refitted']:.1f})")
        print(line)

    written = f"; frames in {args.out}" if args.out is not None else ""
    print(f"median over {args.steps} steps: sim {np.median(sim_ms):.2f} ms, update "
          f"{np.median(update_ms):.3f} ms, render {np.median(render_ms):.2f} ms at "
          f"{width}x{height}; {rebuilds} rebuilds{written}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
