#!/usr/bin/env python3
"""Writes dynrt's bundled default scene: default.gltf (JSON) + default.bin (buffer).

A ground plane with spheres, a torus, an icosphere, a stack of boxes, a cone and a two-part
pedestal, lit by the renderer's default light so that objects shadow the ground and each other.
The file is also a small loader test: a node hierarchy (parents with TRS and a matrix, children,
one mesh instanced six times), all three index types (UNSIGNED_BYTE, UNSIGNED_SHORT,
UNSIGNED_INT), non-indexed primitives and a mesh with two primitives and two materials.

Y is up, units are metres-ish, triangles wind counter-clockwise seen from outside (glTF's front
face). Standard library only; the output is deterministic, so re-running it reproduces the
committed files byte for byte.

Usage: python3 scenes/make_default_scene.py [output_dir]   (default: this script's folder)
"""

import json
import math
import os
import struct
import sys

GENERATOR = "dynrt default scene (scenes/make_default_scene.py)"

UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT, FLOAT = 5121, 5123, 5125, 5126
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


# ---- Small vector helpers --------------------------------------------------------------------

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def normalize(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def orient_outward(positions, triangles, outward_of):
    """Flips every triangle whose normal points against outward_of(centroid), so each generator
    need not get its winding right by hand; degenerate (pole) triangles are left alone."""
    result = []
    for t in triangles:
        a, b, c = (positions[i] for i in t)
        normal = cross(sub(b, a), sub(c, a))
        centroid = tuple((a[k] + b[k] + c[k]) / 3 for k in range(3))
        if dot(normal, normal) > 0 and dot(normal, outward_of(centroid)) < 0:
            t = (t[0], t[2], t[1])
        result.append(t)
    return result


def away_from(point):
    return lambda p: sub(p, point)


# ---- Meshes (positions, triangles as index triples or None for non-indexed) ------------------

def uv_sphere(radius, slices, stacks):
    positions = [(0.0, radius, 0.0)]
    for k in range(1, stacks):
        theta = math.pi * k / stacks
        for j in range(slices):
            phi = 2 * math.pi * j / slices
            positions.append((radius * math.sin(theta) * math.cos(phi), radius * math.cos(theta),
                              radius * math.sin(theta) * math.sin(phi)))
    positions.append((0.0, -radius, 0.0))
    last = len(positions) - 1

    def ring(k, j):
        return 1 + (k - 1) * slices + j % slices

    triangles = [(0, ring(1, j + 1), ring(1, j)) for j in range(slices)]
    for k in range(1, stacks - 1):
        for j in range(slices):
            a, b, c, d = ring(k, j), ring(k, j + 1), ring(k + 1, j), ring(k + 1, j + 1)
            triangles += [(a, b, d), (a, d, c)]
    triangles += [(ring(stacks - 1, j), ring(stacks - 1, j + 1), last) for j in range(slices)]
    return positions, orient_outward(positions, triangles, away_from((0, 0, 0)))


def torus(major, minor, major_segments, minor_segments):
    """Ring around the Y axis."""
    positions = []
    for i in range(major_segments):
        u = 2 * math.pi * i / major_segments
        for j in range(minor_segments):
            v = 2 * math.pi * j / minor_segments
            r = major + minor * math.cos(v)
            positions.append((r * math.cos(u), minor * math.sin(v), r * math.sin(u)))

    def vertex(i, j):
        return (i % major_segments) * minor_segments + j % minor_segments

    triangles = []
    for i in range(major_segments):
        for j in range(minor_segments):
            a, b, c, d = vertex(i, j), vertex(i + 1, j), vertex(i, j + 1), vertex(i + 1, j + 1)
            triangles += [(a, b, d), (a, d, c)]

    def outward(p):
        tube_centre = normalize((p[0], 0.0, p[2]))
        return sub(p, (major * tube_centre[0], 0.0, major * tube_centre[2]))

    return positions, orient_outward(positions, triangles, outward)


def icosphere(radius, subdivisions):
    t = (1 + math.sqrt(5)) / 2
    corners = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
               (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    unit = [normalize(c) for c in corners]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                midpoints[key] = len(unit)
                unit.append(normalize(tuple((unit[a][k] + unit[b][k]) / 2 for k in range(3))))
            return midpoints[key]

        refined = []
        for a, b, c in faces:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            refined += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = refined
    positions = [tuple(radius * x for x in p) for p in unit]
    return positions, orient_outward(positions, faces, away_from((0, 0, 0)))


def box(sx, sy, sz):
    """Non-indexed: every triangle has its own three vertices."""
    hx, hy, hz = sx / 2, sy / 2, sz / 2
    corners = [(x, y, z) for x in (-hx, hx) for y in (-hy, hy) for z in (-hz, hz)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indexed = []
    for a, b, c, d in quads:
        indexed += [(a, b, c), (a, c, d)]
    indexed = orient_outward(corners, indexed, away_from((0, 0, 0)))
    return [corners[i] for t in indexed for i in t], None


def cone(radius, height, segments):
    """Base on y = 0, apex at y = height."""
    positions = [(0.0, height, 0.0), (0.0, 0.0, 0.0)]
    for j in range(segments):
        phi = 2 * math.pi * j / segments
        positions.append((radius * math.cos(phi), 0.0, radius * math.sin(phi)))
    triangles = []
    for j in range(segments):
        a, b = 2 + j, 2 + (j + 1) % segments
        triangles += [(0, a, b), (1, b, a)]
    return positions, orient_outward(positions, triangles, away_from((0.0, height / 3, 0.0)))


def cylinder(radius, height, segments):
    """Base on y = 0, closed at both ends."""
    positions = [(0.0, 0.0, 0.0), (0.0, height, 0.0)]
    for y in (0.0, height):
        for j in range(segments):
            phi = 2 * math.pi * j / segments
            positions.append((radius * math.cos(phi), y, radius * math.sin(phi)))
    triangles = []
    for j in range(segments):
        a, b = 2 + j, 2 + (j + 1) % segments
        c, d = a + segments, b + segments
        triangles += [(0, b, a), (1, c, d), (a, b, d), (a, d, c)]
    return positions, orient_outward(positions, triangles, away_from((0.0, height / 2, 0.0)))


def grid_plane(size, n):
    """Square of side `size` in XZ at y = 0, n x n quads, facing +Y."""
    positions = [(size * (c / n - 0.5), 0.0, size * (r / n - 0.5)) for r in range(n + 1) for c in range(n + 1)]
    triangles = []
    for r in range(n):
        for c in range(n):
            a, b = r * (n + 1) + c, r * (n + 1) + c + 1
            cc, d = a + n + 1, b + n + 1
            triangles += [(a, cc, d), (a, d, b)]
    return positions, orient_outward(positions, triangles, lambda p: (0.0, 1.0, 0.0))


# ---- Transforms ------------------------------------------------------------------------------

def quaternion_y(degrees):
    half = math.radians(degrees) / 2
    return [0.0, math.sin(half), 0.0, math.cos(half)]


def matrix_translate_rotate(translation, y_degrees, x_degrees):
    """Column-major translate * rotate_y * rotate_x, for the one node given as a matrix."""
    cy, sy = math.cos(math.radians(y_degrees)), math.sin(math.radians(y_degrees))
    cx, sx = math.cos(math.radians(x_degrees)), math.sin(math.radians(x_degrees))
    ry = [[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]]
    rx = [[1, 0, 0], [0, cx, -sx], [0, sx, cx]]
    r = [[sum(ry[i][k] * rx[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    columns = [[r[0][j], r[1][j], r[2][j], 0.0] for j in range(3)] + [list(translation) + [1.0]]
    return [round(v, 9) + 0.0 for column in columns for v in column]


# ---- glTF writer -----------------------------------------------------------------------------

class GltfWriter:
    def __init__(self):
        self.binary = bytearray()
        self.doc = {
            "asset": {"version": "2.0", "generator": GENERATOR},
            "scene": 0,
            "scenes": [],
            "nodes": [],
            "meshes": [],
            "materials": [],
            "accessors": [],
            "bufferViews": [],
            "buffers": [],
        }

    def _view(self, data, target):
        while len(self.binary) % 4:
            self.binary.append(0)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": len(self.binary),
                                        "byteLength": len(data), "target": target})
        self.binary += data
        return len(self.doc["bufferViews"]) - 1

    def _accessor(self, accessor):
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def positions(self, points):
        data = b"".join(struct.pack("<3f", *p) for p in points)
        # min/max of the stored float32 values, as the spec requires.
        stored = [struct.unpack_from("<3f", data, 12 * i) for i in range(len(points))]
        view = self._view(data, ARRAY_BUFFER)
        return self._accessor({"bufferView": view, "componentType": FLOAT, "count": len(points), "type": "VEC3",
                               "min": [min(p[k] for p in stored) for k in range(3)],
                               "max": [max(p[k] for p in stored) for k in range(3)]})

    def indices(self, triangles, component_type):
        fmt = {UNSIGNED_BYTE: "<B", UNSIGNED_SHORT: "<H", UNSIGNED_INT: "<I"}[component_type]
        flat = [i for t in triangles for i in t]
        data = b"".join(struct.pack(fmt, i) for i in flat)
        view = self._view(data, ELEMENT_ARRAY_BUFFER)
        return self._accessor({"bufferView": view, "componentType": component_type, "count": len(flat),
                               "type": "SCALAR"})

    def material(self, name, rgb, roughness, metallic=0.0):
        self.doc["materials"].append({"name": name, "pbrMetallicRoughness": {
            "baseColorFactor": list(rgb) + [1.0], "metallicFactor": metallic, "roughnessFactor": roughness}})
        return len(self.doc["materials"]) - 1

    def mesh(self, name, primitives):
        """primitives: list of (position accessor, index accessor or None, material)."""
        prims = []
        for position, index, material in primitives:
            prim = {"attributes": {"POSITION": position}, "material": material, "mode": 4}
            if index is not None:
                prim["indices"] = index
            prims.append(prim)
        self.doc["meshes"].append({"name": name, "primitives": prims})
        return len(self.doc["meshes"]) - 1

    def node(self, name, mesh=None, children=None, **transform):
        node = {"name": name}
        if mesh is not None:
            node["mesh"] = mesh
        if children:
            node["children"] = children
        node.update(transform)
        self.doc["nodes"].append(node)
        return len(self.doc["nodes"]) - 1

    def write(self, directory, stem, roots):
        self.doc["scenes"].append({"name": "dynrt default scene", "nodes": roots})
        while len(self.binary) % 4:
            self.binary.append(0)
        self.doc["buffers"].append({"uri": stem + ".bin", "byteLength": len(self.binary)})
        with open(os.path.join(directory, stem + ".bin"), "wb") as f:
            f.write(self.binary)
        # One line per top-level entry and per array element: readable and diff-friendly.
        lines = []
        for key, value in self.doc.items():
            if isinstance(value, list):
                items = ",\n".join("  " + json.dumps(v, separators=(", ", ": ")) for v in value)
                lines.append(' "%s": [\n%s\n ]' % (key, items))
            else:
                lines.append(' "%s": %s' % (key, json.dumps(value, separators=(", ", ": "))))
        with open(os.path.join(directory, stem + ".gltf"), "w", encoding="utf-8") as f:
            f.write("{\n" + ",\n".join(lines) + "\n}\n")


def build(directory):
    w = GltfWriter()

    ground = w.material("ground", (0.55, 0.55, 0.5), roughness=0.9)
    red = w.material("red", (0.8, 0.1, 0.07), roughness=0.3)
    blue = w.material("blue", (0.1, 0.25, 0.85), roughness=0.4)
    green = w.material("green", (0.15, 0.6, 0.2), roughness=0.6)
    gold = w.material("gold", (0.9, 0.65, 0.15), roughness=0.35, metallic=1.0)
    orange = w.material("orange", (0.95, 0.4, 0.05), roughness=0.5)
    white = w.material("white", (0.85, 0.85, 0.82), roughness=0.7)
    purple = w.material("purple", (0.5, 0.15, 0.7), roughness=0.3)
    teal = w.material("teal", (0.1, 0.6, 0.6), roughness=0.3)
    yellow = w.material("yellow", (0.9, 0.85, 0.2), roughness=0.3)

    # Index types: UNSIGNED_INT for the big sphere, UNSIGNED_BYTE for the cone, UNSIGNED_SHORT
    # for the rest; the boxes are non-indexed.
    points, tris = grid_plane(13.0, 48)
    ground_mesh = w.mesh("ground", [(w.positions(points), w.indices(tris, UNSIGNED_SHORT), ground)])

    points, tris = uv_sphere(1.0, 128, 64)
    sphere_mesh = w.mesh("big_sphere", [(w.positions(points), w.indices(tris, UNSIGNED_INT), red)])

    points, tris = torus(1.0, 0.35, 96, 48)
    torus_mesh = w.mesh("torus", [(w.positions(points), w.indices(tris, UNSIGNED_SHORT), blue)])

    points, tris = icosphere(0.9, 4)
    ico_mesh = w.mesh("icosphere", [(w.positions(points), w.indices(tris, UNSIGNED_SHORT), green)])

    points, _ = box(1.0, 1.0, 1.0)
    box_positions = w.positions(points)
    box_mesh = w.mesh("box", [(box_positions, None, gold)])

    points, tris = cone(0.75, 1.8, 48)
    cone_mesh = w.mesh("cone", [(w.positions(points), w.indices(tris, UNSIGNED_BYTE), orange)])

    points, tris = cylinder(0.45, 1.0, 64)
    column = (w.positions(points), w.indices(tris, UNSIGNED_SHORT), white)
    points, _ = box(1.1, 0.2, 1.1)
    cap_positions = w.positions([(x, y + 1.1, z) for x, y, z in points])
    pedestal_mesh = w.mesh("pedestal", [column, (cap_positions, None, gold)])

    # Three coloured small spheres share one position and one index accessor.
    points, tris = uv_sphere(0.45, 48, 24)
    small_positions, small_indices = w.positions(points), w.indices(tris, UNSIGNED_SHORT)
    small_meshes = [w.mesh("small_sphere_" + name, [(small_positions, small_indices, material)])
                    for name, material in (("purple", purple), ("teal", teal), ("yellow", yellow))]

    roots = [
        w.node("ground", ground_mesh),
        w.node("red_sphere", sphere_mesh, translation=[0.0, 1.5, 0.0], scale=[1.5, 1.5, 1.5]),
        w.node("blue_torus", torus_mesh, matrix=matrix_translate_rotate((3.3, 1.35, 1.7), 30.0, 90.0)),
        w.node("green_icosphere", ico_mesh, translation=[-3.3, 0.9, 1.5]),
        w.node("orange_cone", cone_mesh, translation=[2.8, 0.0, -2.4]),
    ]
    bottom = w.node("box_bottom", box_mesh, translation=[0.0, 0.6, 0.0], scale=[1.2, 1.2, 1.2])
    top = w.node("box_top", box_mesh, translation=[0.1, 1.55, 0.05], rotation=quaternion_y(35.0),
                 scale=[0.7, 0.7, 0.7])
    roots.append(w.node("box_stack", children=[bottom, top], translation=[-2.7, 0.0, -2.4],
                        rotation=quaternion_y(25.0)))
    ball = w.node("pedestal_ball", small_meshes[2], translation=[0.0, 1.65, 0.0])
    roots.append(w.node("pedestal", pedestal_mesh, children=[ball], translation=[0.0, 0.0, -4.3]))
    moons = []
    for k in range(6):
        angle = 2 * math.pi * k / 6
        moons.append(w.node("moon%d" % k, small_meshes[k % 3],
                            translation=[round(5.4 * math.cos(angle), 6) + 0.0, 0.45,
                                         round(5.4 * math.sin(angle), 6) + 0.0]))
    roots.append(w.node("carousel", children=moons, rotation=quaternion_y(10.0)))

    w.write(directory, "default", roots)


if __name__ == "__main__":
    build(sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__)))
