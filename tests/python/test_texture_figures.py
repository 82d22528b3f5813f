"""Engine.texture_figures() in Python: the textures the renders hold as a dict with the report's
keys (docs/report.md "Report", run.textures), zeros before a render reads one."""

import numpy as np
import pytest

import dynrt

from conftest import VIEW

SIZE = 128


def _textured_engine(path):
    engine = dynrt.Engine(threads=1)
    x, y = np.meshgrid(np.linspace(0.0, 1.0, SIZE), np.linspace(0.0, 1.0, SIZE), indexing="xy")
    dynrt.save_image(path, np.stack([x, y, np.full_like(x, 0.5)], -1).astype(np.float32))
    texture = engine.add_texture(str(path))
    positions = np.float32([[-1, 1, 0], [-1, -1, 0], [1, -1, 0], [1, 1, 0]])
    indices = np.int32([[0, 1, 2], [0, 2, 3]])
    texcoords = np.float32([[0, 0], [0, 1], [1, 1], [1, 0]])
    engine.add_mesh(positions, indices, texcoords=texcoords, surface=dynrt.Surface(texture=texture))
    engine.update()
    return engine


def test_no_figures_before_a_render_reads_the_textures(tmp_path):
    engine = _textured_engine(tmp_path / "before.png")
    assert engine.texture_figures() == {"count": 0, "bytes": 0, "load_ms": 0.0}


def test_the_texture_read_is_counted_and_in_memory_bytes(tmp_path):
    engine = _textured_engine(tmp_path / "read.png")
    engine.render(dynrt.View(**VIEW), 32, 24)
    figures = engine.texture_figures()
    assert set(figures) == {"count", "bytes", "load_ms"}
    assert figures["count"] == 1
    assert figures["bytes"] >= SIZE * SIZE * 3
    assert figures["load_ms"] > 0.0
    assert engine.memory_bytes() > figures["bytes"]
