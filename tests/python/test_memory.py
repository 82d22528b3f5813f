"""Memory over a long embedding through Python (issue 34): a loop that adds a mesh, updates and
removes it gives the memory back, as Engine.memory_bytes() and the ids show."""

import numpy as np
import pytest

import dynrt

from conftest import grid_indices, view, wave_positions


def test_add_update_remove_cycles_give_the_bytes_back():
    engine = dynrt.Engine()
    ground = engine.add_mesh(wave_positions(8, size=6.0) - np.float32([0, 1, 0]), grid_indices(8))
    positions, indices = wave_positions(24), grid_indices(24)

    def cycle(phase, update=True):
        mesh = engine.add_mesh(positions, indices, motion="deformable", name="debris")
        if update:
            engine.update()
            engine.set_positions(mesh, wave_positions(24, phase=phase))
            engine.update()
        engine.remove_mesh(mesh)
        return mesh

    def cycles(count):
        ids = [cycle(0.1 * k) for k in range(count)] + [cycle(0.0, update=False) for _ in range(count)]
        engine.update()
        return ids

    # A mesh removed is freed at the next update, so a loop that adds the next mesh before it
    # holds two places: the baseline is taken after a few rounds of the same loop.
    cycles(3)
    baseline = engine.memory_bytes()
    assert baseline > positions.nbytes
    ids = cycles(150)
    assert engine.memory_bytes() == baseline
    # Ids are never reused; the removed ones are refused.
    assert len(set(ids)) == len(ids) and len(engine) == 1
    with pytest.raises(dynrt.InvalidArgument, match=f"id {ids[0]} \\(it was removed\\)"):
        engine.motion(ids[0])
    assert engine.motion(ground) == "static"


@pytest.mark.parametrize("layout", [{"compact_leaves": True}, {"quantized_nodes": True},
                                    {"compact_leaves": True, "quantized_nodes": True}])
def test_compact_layouts_draw_the_same_frame_in_fewer_bytes(layout):
    """Engine(compact_leaves=True): the static meshes' leaves read their vertices;
    Engine(quantized_nodes=True): their tree's boxes are 8-bit planes (issue 43). The frame is
    the default engine's bit for bit, and the engine holds fewer bytes."""
    engines = [dynrt.Engine(), dynrt.Engine(**layout)]
    for engine in engines:
        engine.add_mesh(wave_positions(32, size=6.0) - np.float32([0, 1, 0]), grid_indices(32), name="ground")
        engine.add_mesh(wave_positions(16, phase=0.3), grid_indices(16), motion="deformable", name="cloth")
        engine.update()
    frames = [engine.render(view(), 48, 32, reuse_pixels=False) for engine in engines]
    assert frames[0].shape == (32, 48, 3)
    assert np.array_equal(frames[0].view(np.uint32), frames[1].view(np.uint32))
    assert engines[1].memory_bytes() < engines[0].memory_bytes()


def test_a_memory_budget_chooses_the_static_layout_and_reports_it():
    """Engine(memory_budget=BYTES): the static meshes' tree gets the fastest layout whose build
    is predicted to stay within the budget; update() reports the choice. A budget below what
    the process holds already gets the smallest layout (an engine asked for it holds the same
    bytes); the frame is the default engine's bit for bit."""
    engines = [dynrt.Engine(), dynrt.Engine(compact_leaves=True, quantized_nodes=True),
               dynrt.Engine(memory_budget=1_000_000)]
    reports = []
    for engine in engines:
        engine.add_mesh(wave_positions(32, size=6.0) - np.float32([0, 1, 0]), grid_indices(32), name="ground")
        reports.append(engine.update())
    assert "static_layout" not in reports[0]
    chosen = reports[2]["static_layout"]
    assert chosen["chosen"] == "compact leaves, quantized nodes"
    assert "over the budget" in chosen["why"]
    assert chosen["predicted_peak_bytes"] > 1_000_000
    assert engines[2].memory_bytes() == engines[1].memory_bytes() < engines[0].memory_bytes()
    frames = [engine.render(view(), 48, 32, reuse_pixels=False) for engine in (engines[0], engines[2])]
    assert np.array_equal(frames[0].view(np.uint32), frames[1].view(np.uint32))
    with pytest.raises(TypeError):
        dynrt.Engine(memory_budget=-1)
