#!/usr/bin/env python3
"""Writes scenes/sky.hdr, the bundled environment map: an equirectangular (latitude-longitude)
sky, 256 x 128, in Radiance RGBE (.hdr), made here from a few formulas so that it carries no
third-party licence. A blue zenith fading to a pale horizon, a warm grey ground below it, and
a small bright sun 35 degrees up, a quarter turn to the right of -Z (dynrt's forward), which
casts the lighting a glTF directional light would cast from there.

Mapping (dynrt/engine/environment_map.h): u = 1/2 + atan2(x, -z) / (2 pi) across, v = acos(y)
/ pi down. Run: python3 scenes/make_sky.py (pure Python, no packages)."""

import math
import pathlib

WIDTH, HEIGHT = 256, 128
SUN_ELEVATION, SUN_AZIMUTH = math.radians(35.0), math.radians(90.0)  # azimuth from -Z toward +X
SUN = (math.cos(SUN_ELEVATION) * math.sin(SUN_AZIMUTH), math.sin(SUN_ELEVATION),
       -math.cos(SUN_ELEVATION) * math.cos(SUN_AZIMUTH))
SUN_RADIUS = math.radians(2.5)


def sky(d):
    x, y, z = d
    if y < 0.0:
        # The ground: darker toward the nadir.
        t = min(1.0, -y * 4.0)
        return tuple((1 - t) * h + t * g for h, g in zip((0.55, 0.52, 0.48), (0.22, 0.2, 0.18)))
    t = y ** 0.5
    colour = [(1 - t) * h + t * z_ for h, z_ in zip((0.85, 0.9, 1.0), (0.18, 0.35, 0.8))]
    cos_sun = x * SUN[0] + y * SUN[1] + z * SUN[2]
    angle = math.acos(max(-1.0, min(1.0, cos_sun)))
    glow = 0.6 * math.exp(-angle / 0.25)  # a halo around the sun
    colour = [c + glow * s for c, s in zip(colour, (1.0, 0.85, 0.6))]
    if angle < SUN_RADIUS:
        colour = [c + 60.0 * s for c, s in zip(colour, (1.0, 0.9, 0.75))]
    return tuple(colour)


def rgbe(rgb):
    m = max(rgb)
    if m < 1e-32:
        return bytes((0, 0, 0, 0))
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes([int(c * scale) for c in rgb] + [exponent + 128])


def main():
    rows = []
    for j in range(HEIGHT):
        v = (j + 0.5) / HEIGHT
        theta = v * math.pi
        row = bytearray()
        for i in range(WIDTH):
            u = (i + 0.5) / WIDTH
            phi = (u - 0.5) * 2.0 * math.pi
            d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
            row += rgbe(sky(d))
        rows.append(bytes(row))
    header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n" % (HEIGHT, WIDTH)
    out = pathlib.Path(__file__).with_name("sky.hdr")
    out.write_bytes(header + b"".join(rows))
    print(f"wrote {out} ({WIDTH}x{HEIGHT})")


if __name__ == "__main__":
    main()
