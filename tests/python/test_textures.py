"""Textures in Python: Engine.add_texture (a path, an image file's bytes, or a numpy array of
texels), add_mesh's texcoords and Surface(texture=, wrap_s=, wrap_t=), and load_scene passing a
file's textures on, so that a Scene's render is the CLI's `dynrt render` of the same frame and
camera, bit for bit (both shade through the same FramePipeline and TextureSet; the CLI writes the
frame's floats to an .exr, read back here). An array of texels renders as a PNG file of the same
texels. Bad texcoords, textures, texel arrays and texture ids raise InvalidArgument naming them."""

import base64
import json
import math
import os
import struct
import subprocess
import zlib
from pathlib import Path

import numpy as np
import pytest

import dynrt

from conftest import REPO

WIDTH, HEIGHT = 80, 60
VIEW = dict(eye=(0.4, 0.5, 3.2), target=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0), fov_y_deg=45.0)


def cli_path():
    env = os.environ.get("DYNRT_CLI")
    path = Path(env) if env else REPO / "build" / "release" / "engine" / "dynrt"
    return path if path.is_absolute() else Path.cwd() / path


@pytest.fixture(scope="session")
def cli():
    path = cli_path()
    if not path.exists():
        pytest.skip(f"the CLI {path} is not built (target dynrt; DYNRT_CLI names another)")
    return path


def checker_png(path):
    """A 4x4 image of distinct colours, so that a wrong coordinate or wrap shows."""
    x, y = np.meshgrid(np.arange(4), np.arange(4), indexing="xy")
    rgb = np.stack([0.15 + 0.25 * x, 0.9 - 0.2 * y, ((x + y) % 2).astype(float)], -1).astype(np.float32)
    dynrt.save_image(path, rgb)
    return Path(path).read_bytes()


def quad_mesh(tiles=2.0):
    """A 2x2 quad in the plane z = 0 as 4x4 vertices, with texture coordinates running `tiles`
    times across it (s right, t down), offset so that the wrap modes matter."""
    s = np.linspace(-1.0, 1.0, 4)
    x, y = np.meshgrid(s, s, indexing="xy")
    positions = np.stack([x.ravel(), y.ravel(), np.zeros(16)], 1).astype(np.float32)
    texcoords = np.stack([tiles * (x.ravel() + 1) / 2 - 0.3, tiles * (1 - y.ravel()) / 2], 1).astype(np.float32)
    a = np.array([j * 4 + i for j in range(3) for i in range(3)])
    indices = np.concatenate([np.stack([a, a + 1, a + 4], 1), np.stack([a + 1, a + 5, a + 4], 1)]).astype(np.int32)
    return positions, indices, texcoords


def read_exr(path):
    """The floats of an OpenEXR file as the CLI writes them (OpenImageIO: scanlines, channels
    B, G, R of 32-bit floats, ZIP compression in blocks of 16 lines) as (H, W, 3) RGB, top row
    first. Just enough of the format (openexr.com, "OpenEXR File Layout") to read them back
    exactly, with no library the tests would need."""
    data = Path(path).read_bytes()
    assert data[:4] == b"\x76\x2f\x31\x01", "not an OpenEXR file"
    pos, attributes = 8, {}
    while data[pos] != 0:
        end = data.index(b"\0", pos)
        name = data[pos:end].decode()
        end2 = data.index(b"\0", end + 1)
        (size,) = struct.unpack_from("<i", data, end2 + 1)
        attributes[name] = data[end2 + 5:end2 + 5 + size]
        pos = end2 + 5 + size
    pos += 1
    channels, chlist = [], attributes["channels"]
    while chlist[0] != 0:  # name, then pixel type, linear flag, 3 reserved bytes, x and y sampling
        end = chlist.index(b"\0")
        channels.append((chlist[:end].decode(), struct.unpack_from("<i", chlist, end + 1)[0]))
        chlist = chlist[end + 17:]
    assert channels == [("B", 2), ("G", 2), ("R", 2)], channels  # 2: FLOAT
    assert attributes["compression"] in (b"\x00", b"\x03"), "only no compression or ZIP"
    x0, y0, x1, y1 = struct.unpack("<4i", attributes["dataWindow"])
    width, height = x1 - x0 + 1, y1 - y0 + 1
    lines = 16 if attributes["compression"] == b"\x03" else 1
    chunks = -(-height // lines)
    offsets = struct.unpack_from(f"<{chunks}Q", data, pos)
    image = np.empty((height, 3, width), np.float32)
    for offset in offsets:
        y, size = struct.unpack_from("<ii", data, offset)
        block = data[offset + 8:offset + 8 + size]
        rows = min(lines, y1 + 1 - y)
        if size < rows * 3 * width * 4:
            # ZIP: zlib, then a byte-wise delta predictor, then the two halves interleaved.
            t = np.frombuffer(zlib.decompress(block), np.uint8).astype(np.int64)
            t[1:] -= 128
            t = np.cumsum(t) & 0xFF
            half = (len(t) + 1) // 2
            raw = np.empty(len(t), np.uint8)
            raw[0::2], raw[1::2] = t[:half], t[half:]
            block = raw.tobytes()
        image[y - y0:y - y0 + rows] = np.frombuffer(block, "<f4").reshape(rows, 3, width)
    return np.ascontiguousarray(image.transpose(0, 2, 1)[:, :, ::-1])


def cli_render(cli, scene, frame, view, tmp_path, extra=()):
    out = tmp_path / f"cli_{frame}.exr"
    camera = "eye={},{},{},target={},{},{},up={},{},{},fov={}".format(*view.eye, *view.target, *view.up,
                                                                      view.fov_y_deg)
    run = subprocess.run([str(cli), "render", str(scene), "--res", f"{WIDTH}x{HEIGHT}", "--frames", str(frame),
                          "--camera", camera, "--out", str(out), "--quiet", *extra],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    return read_exr(out)


def textured_gltf(folder):
    """A glTF written here: a textured quad (embedded PNG as a data: URI, MIRRORED_REPEAT in s,
    CLAMP_TO_EDGE in t) and, with the same material, a triangle without texture coordinates
    (which shades its colour alone, in the CLI and in Python)."""
    png = checker_png(folder / "checker.png")
    positions, indices, texcoords = quad_mesh()
    tri = np.array([[1.2, -0.8, 0.2], [1.9, -0.8, 0.2], [1.5, 0.4, 0.2]], np.float32)
    tri_indices = np.array([0, 1, 2], np.uint16)
    chunks = [positions.tobytes(), texcoords.tobytes(), indices.astype(np.uint16).tobytes(), tri.tobytes(),
              tri_indices.tobytes()]
    offsets, blob = [], b""
    for c in chunks:
        blob += b"\0" * (-len(blob) % 4)
        offsets.append(len(blob))
        blob += c
    views = [{"buffer": 0, "byteOffset": o, "byteLength": len(c)} for o, c in zip(offsets, chunks)]
    accessors = [
        {"bufferView": 0, "componentType": 5126, "count": 16, "type": "VEC3",
         "min": positions.min(0).tolist(), "max": positions.max(0).tolist()},
        {"bufferView": 1, "componentType": 5126, "count": 16, "type": "VEC2"},
        {"bufferView": 2, "componentType": 5123, "count": indices.size, "type": "SCALAR"},
        {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3",
         "min": tri.min(0).tolist(), "max": tri.max(0).tolist()},
        {"bufferView": 4, "componentType": 5123, "count": 3, "type": "SCALAR"},
    ]
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "name": "quad", "rotation": [0.0, math.sin(0.15), 0.0, math.cos(0.15)]},
                  {"mesh": 1, "name": "triangle"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]},
                   {"primitives": [{"attributes": {"POSITION": 3}, "indices": 4, "material": 0}]}],
        "materials": [{"name": "checker", "pbrMetallicRoughness": {
            "baseColorFactor": [1.0, 0.9, 0.8, 1.0], "baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"wrapS": 33648, "wrapT": 33071}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png).decode()}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    path = folder / "textured.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_load_scene_of_a_textured_gltf_is_the_clis_frame(cli, tmp_path):
    path = textured_gltf(tmp_path)
    scene = dynrt.load_scene(path)
    scene.pose(frame=0)
    view = dynrt.View(**VIEW)
    got = scene.render(WIDTH, HEIGHT, view=view)
    want = cli_render(cli, path, 0, view, tmp_path)
    assert got.shape == want.shape
    assert np.array_equal(got, want), f"{np.count_nonzero((got != want).any(-1))} pixels differ"
    # The texture shows: the quad without it is another image.
    quad = scene.mesh_ids[[n.startswith("quad") for n in scene.names].index(True)]
    scene.engine.set_surface(quad, dynrt.Surface(diffuse=(1.0, 0.9, 0.8), specular=(0.0, 0.0, 0.0)))
    plain = scene.render(WIDTH, HEIGHT, view=view)
    assert np.count_nonzero((plain != got).any(-1)) > WIDTH * HEIGHT // 10


def test_load_scene_of_cesium_man_is_the_clis_frame(cli, shared_scenes, tmp_path):
    # A skinned figure with an embedded JPEG texture, at a posed frame. Flat-shaded, the frame
    # is the CLI's bit for bit. Smooth-shaded, a few pixels differ in the last bit: the poser's
    # vertex normals, unit length to rounding, are normalised once more by the library API
    # (MeshDesc::normals, "normalised on use"), not by the CLI's renderer; textures play no
    # part in it (the flat frame shows the same texels).
    path = shared_scenes / "cesiumman" / "CesiumMan.glb"
    if not path.exists():
        pytest.skip(f"no {path}")
    scene = dynrt.load_scene(path)
    scene.pose(frame=7)
    view = dynrt.View(eye=(0.0, 1.2, 2.6), target=(0.0, 0.8, 0.0), up=(0.0, 1.0, 0.0), fov_y_deg=40.0)
    flat = scene.render(WIDTH, HEIGHT, view=view, smooth_normals=False)
    want_flat = cli_render(cli, path, 7, view, tmp_path, extra=("--normals", "flat"))
    assert np.array_equal(flat, want_flat), f"{np.count_nonzero((flat != want_flat).any(-1))} pixels differ"
    # The figure is in view, in many colours (its texture's).
    assert len(np.unique(flat.reshape(-1, 3), axis=0)) > 300
    smooth = scene.render(WIDTH, HEIGHT, view=view)
    want_smooth = cli_render(cli, path, 7, view, tmp_path)
    np.testing.assert_allclose(smooth, want_smooth, rtol=0, atol=1e-6)


def _engine_with_quad(source, **surface):
    engine = dynrt.Engine(threads=1)
    texture = engine.add_texture(source)
    positions, indices, texcoords = quad_mesh()
    engine.add_mesh(positions, indices, texcoords=texcoords,
                    surface=dynrt.Surface(texture=texture, **surface))
    engine.update()
    return engine


def test_a_texture_from_a_path_or_from_bytes_is_the_same_image(tmp_path):
    png = checker_png(tmp_path / "checker.png")
    view = dynrt.View(**VIEW)
    images = [_engine_with_quad(s, wrap_s="mirror", wrap_t="clamp").render(view, WIDTH, HEIGHT)
              for s in (str(tmp_path / "checker.png"), tmp_path / "checker.png", png, bytearray(png),
                        memoryview(png))]
    for image in images[1:]:
        assert np.array_equal(image, images[0])
    # Each wrap mode is its own image, and the texture shows.
    repeat = _engine_with_quad(png).render(view, WIDTH, HEIGHT)
    assert not np.array_equal(repeat, images[0])
    engine = dynrt.Engine(threads=1)
    positions, indices, _ = quad_mesh()
    engine.add_mesh(positions, indices)
    engine.update()
    assert np.count_nonzero((engine.render(view, WIDTH, HEIGHT) != repeat).any(-1)) > WIDTH * HEIGHT // 10


def test_surface_texture_fields():
    s = dynrt.Surface(texture=3, wrap_s="clamp", wrap_t="mirror")
    assert (s.texture, s.wrap_s, s.wrap_t) == (3, "clamp", "mirror")
    assert "texture=3" in repr(s)
    s.texture = None
    assert s.texture is None and dynrt.Surface().texture is None
    assert (dynrt.Surface().wrap_s, dynrt.Surface().wrap_t) == ("repeat", "repeat")


def test_bad_textures_and_texcoords_raise_naming_them(tmp_path):
    png = checker_png(tmp_path / "checker.png")
    engine = dynrt.Engine(threads=1)
    with pytest.raises(dynrt.InvalidArgument, match="add_texture 'texture 0': no path and no bytes"):
        engine.add_texture(b"")
    with pytest.raises(dynrt.InvalidArgument, match="add_texture 'empty': no path and no bytes"):
        engine.add_texture(bytearray(), name="empty")
    with pytest.raises(dynrt.InvalidArgument, match="source must be a path .* got int"):
        engine.add_texture(12)
    with pytest.raises(dynrt.InvalidArgument, match="the path is empty"):
        engine.add_texture("")
    assert engine.add_texture(png) == 0  # refused calls took no id

    positions, indices, texcoords = quad_mesh()
    with pytest.raises(dynrt.InvalidArgument, match=r"texcoords must have shape \(N, 2\), got \(16, 3\)"):
        engine.add_mesh(positions, indices, texcoords=positions)
    with pytest.raises(dynrt.InvalidArgument, match="16 positions but 15 texcoords"):
        engine.add_mesh(positions, indices, texcoords=texcoords[:15])
    with pytest.raises(dynrt.InvalidArgument, match="texcoords must hold real numbers, got dtype complex64"):
        engine.add_mesh(positions, indices, texcoords=texcoords.astype(np.complex64))
    with pytest.raises(dynrt.InvalidArgument, match="texcoords must hold real numbers, got dtype str"):
        engine.add_mesh(positions, indices, texcoords=[["a", "b"]] * 16)
    with pytest.raises(dynrt.InvalidArgument, match="texcoords must be an array of numbers"):
        engine.add_mesh(positions, indices, texcoords=[[0.0, 0.0], [1.0]])
    bad = texcoords.copy()
    bad[5, 1] = np.nan
    with pytest.raises(dynrt.InvalidArgument, match="'sheet': texcoord 5 is not finite"):
        engine.add_mesh(positions, indices, texcoords=bad, name="sheet")
    with pytest.raises(dynrt.InvalidArgument, match="'sheet': surface maps no texture with id 4"):
        engine.add_mesh(positions, indices, texcoords=texcoords, name="sheet", surface=dynrt.Surface(texture=4))
    with pytest.raises(dynrt.InvalidArgument, match="'sheet': surface maps texture 0 .* no texcoords"):
        engine.add_mesh(positions, indices, name="sheet", surface=dynrt.Surface(texture=0))
    with pytest.raises(dynrt.InvalidArgument, match="texture -1 is not a texture id"):
        dynrt.Surface(texture=-1)
    with pytest.raises(dynrt.InvalidArgument, match="texture must be an integer id"):
        dynrt.Surface(texture="0")
    with pytest.raises(dynrt.InvalidArgument, match='wrap_s must be "repeat", "clamp" or "mirror", got "wrap"'):
        dynrt.Surface(wrap_s="wrap")
    assert engine.mesh_count == 0

    mesh = engine.add_mesh(positions, indices, texcoords=texcoords, name="sheet", surface=dynrt.Surface(texture=0))
    with pytest.raises(dynrt.InvalidArgument, match="set_surface: mesh 'sheet' .* no texture with id 9"):
        engine.set_surface(mesh, dynrt.Surface(texture=9))


def texel_image(channels):
    """A 4x4 uint8 image of distinct values with `channels` channels ((4, 4, C)). Alpha, when
    there is one, is opaque: OpenImageIO multiplies a PNG's colours by its alpha, while texels
    are taken as they are (alpha unused)."""
    x, y = np.meshgrid(np.arange(4), np.arange(4), indexing="xy")
    grey, opaque = 20 + 14 * (x + 4 * y), np.full((4, 4), 255)
    rgb = [40 + 60 * x, 230 - 50 * y, np.where((x + y) % 2, 250, 10)]
    planes = {1: [grey], 2: [grey, opaque], 3: rgb, 4: rgb + [opaque]}[channels]
    return np.stack(planes, -1).astype(np.uint8)


def png_of(texels):
    """The bytes of an 8-bit PNG file holding `texels` ((H, W) or (H, W, C) uint8) as they are."""
    t = texels if texels.ndim == 3 else texels[..., None]
    height, width, channels = t.shape
    colour_type = {1: 0, 2: 4, 3: 2, 4: 6}[channels]  # grey, grey and alpha, RGB, RGBA

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    rows = b"".join(b"\0" + t[row].tobytes() for row in range(height))  # filter 0 on each row
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def _quad_render(source, **texture):
    engine = dynrt.Engine(threads=1)
    positions, indices, texcoords = quad_mesh()
    engine.add_mesh(positions, indices, texcoords=texcoords,
                    surface=dynrt.Surface(texture=engine.add_texture(source, **texture), wrap_s="mirror"))
    engine.update()
    return engine.render(dynrt.View(**VIEW), WIDTH, HEIGHT)


@pytest.mark.parametrize("channels", [1, 2, 3, 4])
def test_a_texel_array_renders_as_the_png_file_of_the_same_texels(channels, capfd):
    # The end-to-end check of texels given directly.
    texels = texel_image(channels)
    want = _quad_render(png_of(texels))
    engine = dynrt.Engine(threads=1)
    positions, indices, _ = quad_mesh()
    engine.add_mesh(positions, indices)
    engine.update()
    assert np.count_nonzero((engine.render(dynrt.View(**VIEW), WIDTH, HEIGHT) != want).any(-1)) > WIDTH * HEIGHT // 10
    capfd.readouterr()
    got = _quad_render(texels, name="array")
    warnings = capfd.readouterr().err
    assert warnings == ""
    assert np.array_equal(got, want)
    # The same texels in a strided view (copied), as (H, W) for grey, and as float32 k / 255
    # (sRGB-encoded as the 8-bit ones are: the same image but for rounding).
    padded = np.zeros((8, 8, channels), np.uint8)
    padded[::2, ::2] = texels
    assert np.array_equal(_quad_render(padded[::2, ::2]), want)
    if channels == 1:
        assert np.array_equal(_quad_render(texels[..., 0]), want)
    floats = _quad_render(texels.astype(np.float32) / 255, srgb=True)
    np.testing.assert_allclose(floats, want, rtol=0, atol=2 / 255)
    assert capfd.readouterr().err == ""


def test_texel_arrays_of_each_shape_and_dtype_are_taken():
    engine = dynrt.Engine(threads=1)
    before = engine.memory_bytes()
    sources = [texel_image(3), texel_image(3)[..., 0], texel_image(1), texel_image(2), texel_image(4),
               np.full((3, 5, 3), 0.5, np.float32), np.zeros((2, 7), np.float32),
               texel_image(4)[:, ::-1, :3],  # not contiguous: copied
               np.asfortranarray(texel_image(3))]
    for i, texels in enumerate(sources):
        assert engine.add_texture(texels, srgb=texels.dtype == np.uint8) == i
    # The engine holds copies of the texels (a float32 RGBA array of 1 MiB here).
    engine.add_texture(np.full((256, 256, 4), 0.25, np.float32), srgb=False, name="linear")
    assert engine.memory_bytes() >= before + 256 * 256 * 4 * 4
    # A 1-D uint8 array is an image file's bytes, as bytes are.
    png = png_of(texel_image(3))
    assert engine.add_texture(np.frombuffer(png, np.uint8)) == len(sources) + 1


def test_bad_texel_arrays_raise_naming_the_problem():
    engine = dynrt.Engine(threads=1)
    rgb = texel_image(3)
    floats = rgb.astype(np.float32) / 255
    dtype = r"texels must have dtype uint8 \(0-255\) or float32, got "
    shape = r"texels must have shape \(H, W\) or \(H, W, C\) with C from 1 to 4, got "
    cases = [
        (rgb.astype(np.int64), dtype + "int64"),
        (rgb.astype(np.float16), dtype + "float16"),
        (rgb.astype(np.float64), dtype + r"float64 \(use texels.astype\(np.uint8\) or texels.astype\(np.float32\)\)"),
        (rgb.astype(bool), dtype + "bool"),
        (floats.astype(">f4"), dtype + ">f4, not in native byte order"),
        (rgb[None], shape + r"\(1, 4, 4, 3\)"),
        (np.array(0.5, np.float32), shape + r"\(\)"),
        (np.zeros((4, 4, 5), np.uint8), r"texels have 5 channels \(shape \(4, 4, 5\)\), not 1 to 4"),
        (np.zeros((4, 4, 0), np.uint8), "texels have 0 channels"),
        (np.zeros((0, 4, 3), np.uint8), r"texels are empty, shape \(0, 4, 3\)"),
        (np.zeros((4, 0), np.float32), r"texels are empty, shape \(4, 0\)"),
        (np.zeros((16385, 1), np.uint8), r"texels' shape \(16385, 1\) is too large: each side must be at most 16384"),
        (np.zeros(12, np.float32), "a one-dimensional array is taken as an image file's bytes and must have "
                                   r"dtype uint8, got float32 \(texels are an \(H, W\) or \(H, W, C\) array\)"),
        (np.zeros(0, np.uint8), "no path and no bytes"),
    ]
    for source, message in cases:
        with pytest.raises(dynrt.InvalidArgument, match="dynrt.Engine.add_texture: " + message
                           if not message.startswith("no path") else message):
            engine.add_texture(source)
    # Float texels must be finite and >= 0; the message names the texture, texel and channel.
    for bad, text in ((np.nan, "nan"), (np.inf, "inf"), (-np.inf, "-inf"), (-0.25, "-0.25")):
        values = floats.copy()
        values[1, 2, 0] = bad
        with pytest.raises(dynrt.InvalidArgument,
                           match=rf"add_texture 'sky': texels_float value 18 \(texel x 2, y 1, channel 0\) is {text}: "
                                 "texels must be finite and >= 0"):
            engine.add_texture(values, name="sky", srgb=False)
    with pytest.raises(ValueError):  # InvalidArgument is a ValueError
        engine.add_texture(np.zeros((4, 4, 5), np.uint8))
    assert engine.add_texture(rgb) == 0  # refused calls took no id


def test_a_cut_out_surface_shows_what_is_behind_its_holes():
    # An RGBA array whose alpha is 0 on the left half: with alpha_cutoff the quad is not there
    # where its texture's alpha is below it, so the background shows through; alpha (the
    # surface's own) multiplies the texture's.
    texels = np.full((4, 4, 4), 200, dtype=np.uint8)
    texels[:, :2, 3] = 0
    view = dynrt.View(**VIEW)
    background = (0.0, 0.0, 1.0)

    def render(**surface):
        engine = dynrt.Engine(threads=1)
        texture = engine.add_texture(texels)
        positions, indices, _ = quad_mesh()
        s = np.linspace(-1.0, 1.0, 4)
        x, y = np.meshgrid(s, s, indexing="xy")
        texcoords = np.stack([(x.ravel() + 1) / 2, (1 - y.ravel()) / 2], 1).astype(np.float32)
        engine.add_mesh(positions, indices, texcoords=texcoords, surface=dynrt.Surface(texture=texture, **surface))
        engine.update()
        return engine.render(view, WIDTH, HEIGHT, background=background)

    def blue(image):
        return np.count_nonzero((image == np.float32(background)).all(-1))

    opaque, cut = render(), render(alpha_cutoff=0.5)
    assert blue(cut) > blue(opaque) + WIDTH * HEIGHT // 8
    assert np.array_equal(render(alpha_cutoff=0.5, alpha=0.4), render(alpha_cutoff=1.0))
    assert blue(render(alpha_cutoff=0.5, alpha=0.4)) > blue(cut)
    assert "alpha_cutoff=0.5" in repr(dynrt.Surface(alpha_cutoff=0.5))
    with pytest.raises(dynrt.InvalidArgument, match="alpha_cutoff 1.5 must be in"):
        engine = dynrt.Engine(threads=1)
        positions, indices, _ = quad_mesh()
        engine.add_mesh(positions, indices, surface=dynrt.Surface(alpha_cutoff=1.5))
