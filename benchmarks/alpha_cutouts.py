"""What cut-out materials (glTF alphaMode MASK, docs/rendering.md "Alpha") cost a frame that
has them: a 512x512 frame of a 180,000-triangle backdrop behind 0, 1 or 4 quads with a
checkered alpha texture (half their area cut out), each rendered with the quads opaque
(alpha_cutoff 0) and cut out (0.5). A ray crossing k cut layers is traversed k + 1 times
(engine/src/rendering/alpha_cutouts.h), so the cut-out frames cost the backdrop's frame plus
the traversals their holes add. Median of 7 renders each, pixel reuse off.

    bash scripts/install-python.sh build/release && python3 benchmarks/alpha_cutouts.py
"""

import statistics
import time

import numpy as np

import dynrt

SIZE = 512
VIEW = dynrt.View(eye=(0, 0, 4), target=(0, 0, 0), up=(0, 1, 0), fov_y_deg=50)


def checker():
    texels = np.full((64, 64, 4), 180, np.uint8)
    y, x = np.mgrid[0:64, 0:64]
    texels[..., 3] = np.where(((x // 8) + (y // 8)) % 2 == 0, 255, 0)
    return texels


def backdrop(n=300):
    s = np.linspace(-3, 3, n)
    x, y = np.meshgrid(s, s)
    positions = np.stack([x.ravel(), y.ravel(), -3 + 0.2 * np.sin(3 * x.ravel()) * np.cos(3 * y.ravel())], 1)
    a = np.array([j * n + i for j in range(n - 1) for i in range(n - 1)])
    indices = np.concatenate([np.stack([a, a + 1, a + n], 1), np.stack([a + 1, a + n + 1, a + n], 1)])
    return positions.astype(np.float32), indices.astype(np.int32)


def engine_with(layers, cutoff):
    engine = dynrt.Engine()
    texture = engine.add_texture(checker())
    engine.add_mesh(*backdrop())
    for k in range(layers):
        z, shift = 1.0 - 0.5 * k, 0.13 * k
        positions = np.array([[-2 + shift, -2, z], [2 + shift, -2, z], [2 + shift, 2, z], [-2 + shift, 2, z]], np.float32)
        texcoords = np.array([[0, 2], [2, 2], [2, 0], [0, 0]], np.float32)
        engine.add_mesh(positions, np.array([[0, 1, 2], [0, 2, 3]], np.int32), texcoords=texcoords,
                        surface=dynrt.Surface(texture=texture, alpha_cutoff=cutoff))
    engine.update()
    return engine


def median_ms(engine, runs=7):
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        engine.render(VIEW, SIZE, SIZE, reuse_pixels=False)
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def main():
    for layers in (0, 1, 4):
        for cutoff in (0.0, 0.5) if layers else (0.0,):
            kind = "cut out" if cutoff else "opaque"
            print(f"{layers} layer(s), {kind:7s}: {median_ms(engine_with(layers, cutoff)):7.2f} ms")


if __name__ == "__main__":
    main()
