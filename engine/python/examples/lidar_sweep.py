"""A spinning lidar on a car driving down a street of moving traffic, cast through dynrt.

What it shows about the Python API:

- Static meshes (the ground and the buildings) and rigid ones (the cars) built with numpy and
  added once; the cars then move only by ``set_transform`` with a 4x4 numpy matrix (rows
  first, as numpy writes it), so ``update()`` refits and rebuilds no mesh's tree, only the
  small top-level tree over the meshes (a few microseconds).
- One sweep per step as one ray batch through ``intersect(origins, directions, tmin, tmax,
  out=hits, stats=True)``: the float32 (N, 3) ray arrays and the ``dynrt.hit_dtype`` result
  array are allocated once and reused, read and written in place by the engine.
- The hits as numpy: a point cloud (``origins + t * directions`` where ``mesh >= 0``), returns
  per mesh with ``np.bincount`` of the ``mesh`` field, and a range image.
- Ray order. The engine cuts a batch into runs of 256 consecutive rays, splits each run by
  the signs of its directions, and traces each part as one 16x16 packet when its directions are
  coherent (all within about 25 degrees of the part's middle ray), else ray by ray. So the
  order of the beams in the batch decides the tracer, and --order picks it:
    horizon  (default) the beams below the horizon first, then those above it, each half in
             firing order: every run is one narrow patch of neighbouring beams, one full packet.
    firing   for each azimuth step every channel, the order a spinning lidar fires in: a run is
             a few azimuth columns of the whole fan, two half-full packets (below and above the
             horizon), a little slower.
    channel  for each channel every azimuth step (a range image row by row): a run sweeps 90
             degrees of azimuth, too wide for a packet, so every ray goes alone.
  The "packets" column is the share of rays traced as packets; the car columns are the share
  of the sweep's rays that hit each car. The azimuths are offset by half
  a step so that no beam lies on an axis plane.

The scene: y is up and the road runs along x. The ego car drives along +x at 10 m/s in lane
z = -1.75 with the lidar 1.9 m above the road (the ego car itself is not in the scene); six cars
drive in four lanes (those at z > 0 oncoming) and wrap around within 60 m of the ego car so the
traffic stays in range. Each step is one revolution at 10 Hz (0.1 s): a real spinning lidar
fires while the scene moves; here each revolution sees one instant.

    PYTHONPATH=build/release/python /usr/bin/python3 engine/python/examples/lidar_sweep.py
    ... lidar_sweep.py --steps 200 --channels 64 --out lidar   # range image + last point cloud
"""

import argparse
import pathlib
import sys
import time

import numpy as np

import dynrt

STEP_S = 0.1                    # one revolution per step (10 Hz)
EGO_SPEED = 10.0                # m/s along +x
EGO_LANE_Z = -1.75
SENSOR_HEIGHT = 1.9             # metres above the road
FAN_DEG = (-25.0, 15.0)         # the channels' elevations, lowest to highest
TRAFFIC_WINDOW = 60.0           # cars wrap around within +-60 m of the ego car

# Two triangles per face of a box whose corner k is at the high end of x if k & 1, of y if
# k & 2 and of z if k & 4, wound counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
BOX_FACES = np.array([[0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5], [0, 1, 5], [0, 5, 4],
                      [2, 6, 7], [2, 7, 3], [0, 2, 3], [0, 3, 1], [4, 5, 7], [4, 7, 6]])
CORNER_BITS = (np.arange(8)[:, None] >> np.arange(3)) & 1      # (8, 3): which corner is high

# name, lane z, x ahead of the ego car at t = 0, speed along x in m/s (< 0: oncoming), kind
TRAFFIC = [
    ("car0", -1.75, 14.0, 8.0, "car"),     # ahead in our lane, slower: we close in on it
    ("car1", -5.25, -6.0, 13.0, "van"),    # overtakes us on the left
    ("car2", -5.25, 25.0, 11.0, "car"),
    ("car3", 1.75, 30.0, -12.0, "car"),    # oncoming
    ("car4", 5.25, -10.0, -9.0, "van"),
    ("car5", 1.75, -35.0, -14.0, "car"),
]


# ---- Geometry with numpy ------------------------------------------------------------------

def box(lo, hi):
    """An axis-aligned box from corner `lo` to corner `hi`: float32 (8, 3) positions and (12, 3)
    triangles."""
    lo, hi = np.asarray(lo, np.float32), np.asarray(hi, np.float32)
    return np.where(CORNER_BITS, hi, lo).astype(np.float32), BOX_FACES


def merge(*meshes):
    """One mesh of several (positions, indices) pairs, the indices offset to match."""
    offsets = np.cumsum([0] + [len(p) for p, _ in meshes[:-1]])
    positions = np.concatenate([p for p, _ in meshes]).astype(np.float32)
    indices = np.concatenate([i + o for (_, i), o in zip(meshes, offsets)])
    return positions, indices


def vehicle(kind):
    """A car-like mesh around its own origin, facing +x over the road at y = 0: a body raised
    by the wheels' clearance and a cabin on top of it, set back."""
    if kind == "van":
        body = box((-2.6, 0.35, -1.0), (2.6, 1.3, 1.0))
        cabin = box((-2.5, 1.3, -0.95), (1.6, 2.3, 0.95))
    else:
        body = box((-2.25, 0.3, -0.9), (2.25, 1.05, 0.9))
        cabin = box((-1.3, 1.05, -0.8), (0.9, 1.55, 0.8))
    return merge(body, cabin)


def street(rng):
    """The static scenery: a ground plane and two rows of buildings of random size along the
    road, from 100 m behind the start to 400 m ahead."""
    ground = (np.array([[-200, 0, -100], [800, 0, -100], [800, 0, 100], [-200, 0, 100]],
                       np.float32),
              np.array([[0, 2, 1], [0, 3, 2]]))
    blocks = []
    for side in (-1.0, 1.0):
        x = np.arange(-100.0, 400.0, 18.0)
        length = rng.uniform(8.0, 16.0, len(x))
        depth = rng.uniform(6.0, 12.0, len(x))
        height = rng.uniform(5.0, 20.0, len(x))
        near = side * 13.0                               # the pavement's edge
        for x0, l, d, h in zip(x, length, depth, height):
            z0, z1 = sorted((near, near + side * d))
            blocks.append(box((x0, 0.0, z0), (x0 + l, h, z1)))
    return ground, merge(*blocks)


def pose(x, z, heading):
    """A 4x4 transform, rows first: a turn of `heading` radians about +y, then a move to
    (x, 0, z). A turn of phi takes +x (the car's forward axis) to (cos phi, 0, -sin phi)."""
    c, s = np.cos(heading), np.sin(heading)
    return np.array([[c, 0.0, s, x],
                     [0.0, 1.0, 0.0, 0.0],
                     [-s, 0.0, c, z],
                     [0.0, 0.0, 0.0, 1.0]])


# ---- The sensor ---------------------------------------------------------------------------

def sweep_directions(channels, azimuths, order="horizon"):
    """The unit directions of one revolution as a float32 (N, 3) array in the batch's `order`
    (see the top of the file), with each ray's channel and azimuth step (its range-image pixel)."""
    elevation = np.radians(np.linspace(*FAN_DEG, channels))
    azimuth = 2.0 * np.pi * (np.arange(azimuths) + 0.5) / azimuths

    def firing(fan):   # for each azimuth step, every channel of `fan`
        return np.tile(fan, azimuths), np.repeat(np.arange(azimuths), len(fan))

    if order == "firing":
        channel, step = firing(np.arange(channels))
    elif order == "channel":
        channel = np.repeat(np.arange(channels), azimuths)
        step = np.tile(np.arange(azimuths), channels)
    else:
        below = firing(np.flatnonzero(elevation < 0.0))
        above = firing(np.flatnonzero(elevation >= 0.0))
        channel, step = (np.concatenate(halves) for halves in zip(below, above))
    el, az = elevation[channel], azimuth[step]
    directions = np.stack([np.cos(el) * np.cos(az), np.sin(el), np.cos(el) * np.sin(az)], axis=1)
    return np.ascontiguousarray(directions, dtype=np.float32), channel, step


PALETTE = np.array([[0.45, 0.45, 0.45], [0.85, 0.75, 0.55], [0.95, 0.3, 0.2], [0.3, 0.8, 0.3],
                    [0.3, 0.5, 1.0], [0.9, 0.5, 0.9], [0.2, 0.9, 0.9], [1.0, 0.65, 0.2]],
                   np.float32)


def range_image(hits, channel, step, channels, azimuths, max_range, row_px=4):
    """An (H, W, 3) float32 image of one sweep: azimuth across (straight ahead in the middle,
    the car's right to the right of it), channels down (highest on top), coloured by mesh and
    darker with range; black where nothing was hit."""
    image = np.zeros((channels, azimuths, 3), np.float32)
    hit = hits["mesh"] >= 0
    shade = 1.0 - 0.8 * np.minimum(hits["t"][hit] / max_range, 1.0)
    colour = PALETTE[hits["mesh"][hit] % len(PALETTE)] * shade[:, None]
    image[channels - 1 - channel[hit], step[hit]] = colour
    return np.repeat(np.roll(image, azimuths // 2, axis=1), row_px, axis=0)


# ---- The loop -------------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("--steps", type=int, default=60, help="revolutions, 0.1 s apart")
    parser.add_argument("--channels", type=int, default=32, help="lasers in the vertical fan")
    parser.add_argument("--azimuth", type=int, default=1024, help="azimuth steps per revolution")
    parser.add_argument("--order", choices=("horizon", "firing", "channel"), default="horizon",
                        help="the beams' order in the batch (see the top of the file)")
    parser.add_argument("--range", type=float, default=100.0, help="maximum range in metres")
    parser.add_argument("--threads", type=int, default=0, help="engine threads (0: all cores)")
    parser.add_argument("--out", type=pathlib.Path,
                        help="folder for the last sweep's range image (range_image.png) and "
                             "labelled point cloud (points.npz)")
    args = parser.parse_args(argv)
    if args.steps < 1 or args.channels < 1 or args.azimuth < 1:
        parser.error("--steps, --channels and --azimuth must be at least 1")

    engine = dynrt.Engine(threads=args.threads)
    ground, buildings = street(np.random.default_rng(7))
    names = ["ground", "buildings"]
    engine.add_mesh(*ground, motion="static", name="ground",
                    surface=dynrt.Surface(diffuse=PALETTE[0]))
    engine.add_mesh(*buildings, motion="static", name="buildings",
                    surface=dynrt.Surface(diffuse=PALETTE[1]))
    shapes = {kind: vehicle(kind) for kind in ("car", "van")}
    cars = []      # (mesh id, lane z, x ahead of ego at t = 0, speed)
    for k, (name, lane, ahead, speed, kind) in enumerate(TRAFFIC):
        mesh = engine.add_mesh(*shapes[kind], motion="rigid", name=name,
                               surface=dynrt.Surface(diffuse=PALETTE[2 + k % (len(PALETTE) - 2)]))
        cars.append((mesh, lane, ahead, speed))
        names.append(name)
    car_ids = np.array([mesh for mesh, *_ in cars])

    # The batch's arrays, allocated once: the engine reads and writes them in place.
    directions, channel, step_of_ray = sweep_directions(args.channels, args.azimuth, args.order)
    rays = len(directions)
    origins = np.empty_like(directions)
    hits = np.empty(rays, dtype=dynrt.hit_dtype)

    print(f"lidar: {args.channels} channels x {args.azimuth} azimuth steps = {rays} rays per "
          f"revolution in {args.order} order, range {args.range:g} m; meshes: "
          + " ".join(f"{m}={n}" for m, n in enumerate(names)))
    print("step  points  hit%  " + " ".join(f"{n + '%':>5}" for n in names[2:])
          + "  update_total_ms  cast_ms  Mrays/s  packets  step_ms")
    update_ms, cast_ms, mrays, packets, car_points = [], [], [], [], 0
    for step in range(args.steps):
        started = time.perf_counter()
        seconds = step * STEP_S
        ego_x = EGO_SPEED * seconds

        # ---- Move the cars (rigid: a transform each), then bring the engine up to date ----
        for mesh, lane, ahead, speed in cars:
            # Its distance ahead of the ego car, wrapped into [-TRAFFIC_WINDOW, TRAFFIC_WINDOW).
            ahead_now = ahead + (speed - EGO_SPEED) * seconds
            ahead_now = (ahead_now + TRAFFIC_WINDOW) % (2 * TRAFFIC_WINDOW) - TRAFFIC_WINDOW
            heading = 0.0 if speed > 0 else np.pi
            engine.set_transform(mesh, pose(ego_x + ahead_now, lane, heading))
        report = engine.update()   # its "total_ms" is the whole update ("update_ms" a first stage)

        # ---- One revolution: every beam from the sensor, closest hits into `hits` ----
        origins[:] = (ego_x, SENSOR_HEIGHT, EGO_LANE_Z)
        # With out= the hits are written into `hits` (and it is returned, as the tuple's first).
        _, query = engine.intersect(origins, directions, 0.0, args.range, out=hits, stats=True)

        # ---- The returns as a point cloud, and how many fell on each mesh ----
        hit = hits["mesh"] >= 0
        points = origins[hit] + hits["t"][hit, None] * directions[hit]
        per_mesh = np.bincount(hits["mesh"][hit], minlength=len(names))
        car_points += int(per_mesh[car_ids].sum())
        step_ms = 1e3 * (time.perf_counter() - started)   # the whole step, numpy included

        update_ms.append(report["total_ms"])
        cast_ms.append(query["ms"])
        mrays.append(query["mrays_per_s"])
        packets.append(query["packet_rays"] / rays)
        car_share = " ".join(f"{100.0 * n / rays:5.1f}" for n in per_mesh[car_ids])
        print(f"{step:4d} {len(points):7d} {100.0 * hit.mean():5.1f}  {car_share}  "
              f"{report['total_ms']:15.3f} {query['ms']:8.2f} {query['mrays_per_s']:8.1f} "
              f"{packets[-1]:8.0%} {step_ms:8.2f}")

    print(f"median over {args.steps} steps: update {np.median(update_ms):.3f} ms, cast "
          f"{np.median(cast_ms):.2f} ms at {np.median(mrays):.1f} Mrays/s, "
          f"{np.median(packets):.0%} as packets; "
          f"{car_points} returns on cars in all")

    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        image = range_image(hits, channel, step_of_ray, args.channels, args.azimuth, args.range)
        dynrt.save_image(str(args.out / "range_image.png"), image)
        np.savez(args.out / "points.npz", points=points,
                 mesh=hits["mesh"][hit], names=np.array(names))
        print(f"wrote {args.out / 'range_image.png'} and {args.out / 'points.npz'} "
              f"({len(points)} points of the last sweep)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
