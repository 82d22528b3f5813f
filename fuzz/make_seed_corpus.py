#!/usr/bin/env python3
"""Writes the seed corpus of the fuzz targets: fuzz/corpus/<target>/ for each target.

The glTF seeds are small self-contained documents built the way tests/gltf_test_file.h builds
the tests' files (one bufferView per accessor, the buffer embedded as a base64 data: URI, or the
GLB BIN chunk), each exercising one part of the loader that hostile files attack: index types
and strip/fan assembly, the node tree (TRS, matrix, children), the three interpolations, a
skin, morph targets with animated weights, a camera, and the GLB container. They are a few
hundred bytes to 2 kB, so the fuzzer mutates structure rather than megabytes of buffer data;
the bundled scenes/default.gltf is left out for that reason (its buffer is 550 kB), and its
features (instancing, the three index types, matrix nodes) are in these seeds instead.

Standard library only, deterministic: re-running it reproduces the committed files.
Usage: python3 fuzz/make_seed_corpus.py   (writes under fuzz/corpus/, next to this script)
"""

import base64
import json
import os
import struct

BYTE, UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT, FLOAT = 5120, 5121, 5123, 5125, 5126
COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT4": 16}
FORMATS = {UNSIGNED_BYTE: "B", UNSIGNED_SHORT: "H", UNSIGNED_INT: "I", FLOAT: "f"}

TRIANGLE = [0, 0, 0, 1, 0, 0, 0, 1, 0]
QUAD_STRIP = [0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0]


class Document:
    """A glTF document under construction, mirroring tests/gltf_test_file.h."""

    def __init__(self):
        self.doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": []}], "nodes": [],
                    "meshes": [], "accessors": [], "bufferViews": []}
        self.bin = bytearray()

    def push(self, array, value):
        self.doc.setdefault(array, []).append(value)
        return len(self.doc[array]) - 1

    def accessor(self, values, type_, component_type, normalized=False):
        while len(self.bin) % 4:
            self.bin.append(0)
        data = struct.pack("<%d%s" % (len(values), FORMATS[component_type]), *values)
        view = self.push("bufferViews", {"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        accessor = {"bufferView": view, "componentType": component_type,
                    "count": len(values) // COMPONENTS[type_], "type": type_}
        if normalized:
            accessor["normalized"] = True
        return self.push("accessors", accessor)

    def floats(self, values, type_):
        return self.accessor(values, type_, FLOAT)

    def mesh(self, primitives, name="mesh", weights=None):
        mesh = {"name": name, "primitives": primitives}
        if weights is not None:
            mesh["weights"] = weights
        return self.push("meshes", mesh)

    def node(self, node, root=True):
        index = self.push("nodes", node)
        if root:
            self.doc["scenes"][0]["nodes"].append(index)
        return index

    def animation(self, name, channels):
        """channels: (node, path, times, values, interpolation)."""
        animation = {"name": name, "samplers": [], "channels": []}
        for node, path, times, values, interpolation in channels:
            type_ = {"rotation": "VEC4", "weights": "SCALAR"}.get(path, "VEC3")
            sampler = len(animation["samplers"])
            animation["samplers"].append({"input": self.floats(times, "SCALAR"),
                                          "output": self.floats(values, type_), "interpolation": interpolation})
            animation["channels"].append({"sampler": sampler, "target": {"node": node, "path": path}})
        return self.push("animations", animation)

    def gltf(self):
        doc = dict(self.doc)
        doc["buffers"] = [{"byteLength": len(self.bin),
                           "uri": "data:application/octet-stream;base64," + base64.b64encode(self.bin).decode()}]
        return json.dumps(doc, separators=(",", ":")).encode()

    def glb(self):
        doc = dict(self.doc)
        doc["buffers"] = [{"byteLength": len(self.bin)}]
        text = json.dumps(doc, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        data = bytes(self.bin) + b"\0" * (-len(self.bin) % 4)
        chunks = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(data), 0x004E4942) + data
        return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


def triangle():
    d = Document()
    d.doc["materials"] = [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.1, 1], "roughnessFactor": 0.5}}]
    mesh = d.mesh([{"attributes": {"POSITION": d.floats(TRIANGLE, "VEC3")}, "material": 0}])
    d.node({"name": "tri", "mesh": mesh})
    return d


def indexed_topologies():
    """All three index types, strips and fans, a node tree with TRS, a matrix and an instanced mesh."""
    d = Document()
    position = d.floats(QUAD_STRIP, "VEC3")
    strip = {"attributes": {"POSITION": position}, "indices": d.accessor([0, 1, 2, 3], "SCALAR", UNSIGNED_BYTE),
             "mode": 5}
    fan = {"attributes": {"POSITION": position}, "indices": d.accessor([0, 1, 3, 2], "SCALAR", UNSIGNED_SHORT),
           "mode": 6}
    listed = {"attributes": {"POSITION": position}, "indices": d.accessor([0, 1, 2, 2, 1, 3], "SCALAR", UNSIGNED_INT)}
    lines = {"attributes": {"POSITION": position}, "mode": 1}
    mesh = d.mesh([strip, fan, listed, lines], "quads")
    child = d.node({"name": "child", "mesh": mesh, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1]}, False)
    d.node({"name": "parent", "mesh": mesh, "translation": [0, 1, 0], "rotation": [0, 0.7071068, 0, 0.7071068],
            "scale": [2, 2, 2], "children": [child]})
    return d


def animated():
    """The three interpolations on one node, and an animated perspective camera."""
    d = Document()
    mesh = d.mesh([{"attributes": {"POSITION": d.floats(TRIANGLE, "VEC3")}}])
    body = d.node({"name": "body", "mesh": mesh})
    d.doc["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}}]
    eye = d.node({"name": "eye", "camera": 0, "translation": [0, 0, 5]})
    d.animation("move", [
        (body, "translation", [0, 0.5, 1], [0, 0, 0, 1, 0, 0, 1, 1, 0], "LINEAR"),
        (body, "scale", [0, 1], [1, 1, 1, 2, 2, 2], "STEP"),
        # CUBICSPLINE: (in-tangent, value, out-tangent) per key.
        (body, "rotation", [0, 1], [0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0,
                                    0, 0, 0, 0, 0, 0.7071068, 0, 0.7071068, 0, 0, 0, 0], "CUBICSPLINE"),
        (eye, "translation", [0, 1], [0, 0, 5, 0, 1, 5], "LINEAR"),
    ])
    return d


def skinned():
    """Two joints in a chain, four influences with normalized UNSIGNED_BYTE weights, an animated joint."""
    d = Document()
    j0 = d.node({"name": "j0", "children": [1]})
    j1 = d.node({"name": "j1", "translation": [0, 1, 0]}, False)
    ibm = [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
           1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1]
    d.doc["skins"] = [{"joints": [j0, j1], "inverseBindMatrices": d.floats(ibm, "MAT4"), "skeleton": j0}]
    joints = d.accessor([0, 1, 0, 0] * 3, "VEC4", UNSIGNED_BYTE)
    weights = d.accessor([255, 0, 0, 0, 128, 127, 0, 0, 0, 255, 0, 0], "VEC4", UNSIGNED_BYTE, normalized=True)
    positions = [0, 0, 0, 1, 0.5, 0, 0, 1, 0]
    mesh = d.mesh([{"attributes": {"POSITION": d.floats(positions, "VEC3"), "JOINTS_0": joints,
                                   "WEIGHTS_0": weights}}], "skinned")
    d.node({"name": "body", "mesh": mesh, "skin": 0})
    d.animation("bend", [(j1, "rotation", [0, 1], [0, 0, 0, 1, 0, 0, 0.3826834, 0.9238795], "LINEAR")])
    return d


def morphed():
    """Two position morph targets with mesh default weights and animated weights."""
    d = Document()
    target0 = {"POSITION": d.floats([0, 0, 1, 0, 0, 1, 0, 0, 1], "VEC3")}
    target1 = {"POSITION": d.floats([1, 0, 0, 0, 0, 0, 0, 0, 0], "VEC3")}
    mesh = d.mesh([{"attributes": {"POSITION": d.floats(TRIANGLE, "VEC3")}, "targets": [target0, target1]}],
                  "morph", weights=[0.5, 0])
    body = d.node({"name": "body", "mesh": mesh})
    d.animation("breathe", [(body, "weights", [0, 1, 2], [0, 0, 1, 0.5, 0, 1], "LINEAR")])
    return d


SPECS = {
    "sphere": "sphere:100",
    "soup": "soup:27",
    "plane": "plane:2",
    "placed_coloured": "sphere:10#FF00aa@1.5,-2e-1,.25+soup:3@-0,1e1,3,0.5",
    "composition": "plane:1@0,-1,0,4#808080+sphere:200#d04030",
    "bad_placement": "sphere:10@1,2",
}


# One spec per line: --anim specs, and --treat specs after a '=' (fuzz/fuzz_entry_points.h),
# for the scene "sphere:20#ff0000+plane:2@0,-1,0".
ANIMATION_SPECS = {
    "rigid_all": "rigid",
    "explode_treat": "explode:sphere:20#ff0000\n=sphere:20#ff0000=exploding",
    "wave_rigid_treat": "wave:plane:2@0,-1,0\nrigid:sphere:20\n=plane:2=deformable",
    "unknown_motion": "spin:plane:2",
}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    gltf_dir = os.path.join(here, "corpus", "gltf_loader")
    spec_dir = os.path.join(here, "corpus", "procedural_spec")
    animation_dir = os.path.join(here, "corpus", "animation_specs")
    for folder in (gltf_dir, spec_dir, animation_dir):
        os.makedirs(folder, exist_ok=True)
    documents = {"triangle": triangle, "indexed_topologies": indexed_topologies, "animated": animated,
                 "skinned": skinned, "morphed": morphed}
    for name, make in documents.items():
        d = make()
        with open(os.path.join(gltf_dir, name + ".gltf"), "wb") as f:
            f.write(d.gltf())
        with open(os.path.join(gltf_dir, name + ".glb"), "wb") as f:
            f.write(d.glb())
    for folder, specs in ((spec_dir, SPECS), (animation_dir, ANIMATION_SPECS)):
        for name, spec in specs.items():
            with open(os.path.join(folder, name + ".txt"), "w") as f:
                f.write(spec)


if __name__ == "__main__":
    main()
