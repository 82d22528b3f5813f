"""Borrowed positions (add_mesh(..., borrow=True)): the engine holds exactly one reference to
the array it reads in place, from add_mesh until remove_mesh, until set_positions points the
mesh at another array, or until the engine goes away; copied meshes hold none. And the engine
really reads the array in place: new values written into it show after set_positions +
update, exactly as the same values handed over as a copy."""

import gc
import sys

import numpy as np
import pytest

import dynrt

from conftest import camera_rays, wave_grid, wave_positions

N = 24


@pytest.fixture
def grid():
    positions, indices = wave_grid(N)
    return positions, indices


def refs(a):
    # getrefcount's own argument adds one; comparisons between two calls cancel it out.
    return sys.getrefcount(a)


def test_add_mesh_holds_one_reference_and_remove_mesh_drops_it(grid):
    positions, indices = grid
    engine = dynrt.Engine()
    before = refs(positions)
    mesh = engine.add_mesh(positions, indices, borrow=True)
    assert refs(positions) == before + 1
    assert engine.borrows(mesh)
    engine.update()
    assert refs(positions) == before + 1
    engine.remove_mesh(mesh)
    assert refs(positions) == before
    assert not engine.borrows(mesh)


def test_set_positions_moves_the_reference_to_the_new_array(grid):
    positions, indices = grid
    other = wave_positions(N, phase=1.0)
    engine = dynrt.Engine()
    before, before_other = refs(positions), refs(other)
    mesh = engine.add_mesh(positions, indices, motion="deformable", borrow=True)
    engine.set_positions(mesh, other)
    assert refs(positions) == before  # released
    assert refs(other) == before_other + 1  # held
    assert engine.borrows(mesh)
    engine.set_positions(mesh, other)  # the same array again: still one reference
    assert refs(other) == before_other + 1
    engine.set_positions(mesh, positions)
    assert refs(positions) == before + 1 and refs(other) == before_other


def test_deleting_the_engine_releases_its_arrays(grid):
    positions, indices = grid
    second = positions.copy()
    before, before_second = refs(positions), refs(second)
    engine = dynrt.Engine()
    engine.add_mesh(positions, indices, borrow=True)
    engine.add_mesh(second, indices, borrow=True)
    engine.update()
    assert refs(positions) == before + 1 and refs(second) == before_second + 1
    del engine
    gc.collect()
    assert refs(positions) == before and refs(second) == before_second


def test_a_scene_engine_releases_borrowed_arrays_too(grid):
    positions, indices = grid
    before = refs(positions)
    scene = dynrt.load_scene("sphere:100")
    scene.engine.add_mesh(positions, indices, borrow=True)
    assert refs(positions) == before + 1
    del scene
    gc.collect()
    assert refs(positions) == before


def test_copied_meshes_hold_no_reference(grid):
    positions, indices = grid
    normals = np.tile(np.float32([0, 1, 0]), (len(positions), 1))
    other = wave_positions(N, phase=2.0)
    engine = dynrt.Engine()
    before = [refs(a) for a in (positions, indices, normals, other)]
    mesh = engine.add_mesh(positions, indices, normals=normals, motion="deformable")
    engine.set_positions(mesh, other, normals=normals)
    engine.update()
    assert [refs(a) for a in (positions, indices, normals, other)] == before
    assert not engine.borrows(mesh)


def test_normals_of_a_borrowed_mesh_are_copied(grid):
    positions, indices = grid
    normals = np.tile(np.float32([0, 1, 0]), (len(positions), 1))
    before = refs(normals)
    engine = dynrt.Engine()
    mesh = engine.add_mesh(positions, indices, normals=normals, borrow=True, motion="deformable")
    engine.set_positions(mesh, positions, normals=normals)
    assert refs(normals) == before


def test_refused_calls_take_no_reference(grid):
    positions, indices = grid
    engine = dynrt.Engine()
    bad = positions.copy()
    bad[3] = np.nan
    before_bad = refs(bad)
    with pytest.raises(dynrt.InvalidArgument):
        engine.add_mesh(bad, indices, borrow=True)
    assert refs(bad) == before_bad
    mesh = engine.add_mesh(positions, indices, borrow=True, motion="deformable")
    before = refs(positions)
    short = positions[:-1].copy()
    before_short = refs(short)
    with pytest.raises(dynrt.InvalidArgument):
        engine.set_positions(mesh, short)  # wrong vertex count: the mesh keeps its array
    assert refs(short) == before_short and refs(positions) == before
    with pytest.raises(dynrt.InvalidArgument):
        engine.remove_mesh(mesh + 1)
    assert refs(positions) == before


def test_a_borrowed_array_outlives_its_last_python_name(grid):
    """The engine's reference keeps the array alive: dropping every Python name of it does not
    free the memory the engine reads (a freed buffer would give garbage or crash)."""
    positions, indices = grid
    engine = dynrt.Engine()
    mesh = engine.add_mesh(positions.copy(), indices, borrow=True, motion="deformable")
    gc.collect()
    engine.update()
    reference = dynrt.Engine()
    reference.add_mesh(positions, indices)
    reference.update()
    junk = [np.full_like(positions, 7.0) for _ in range(20)]  # would reuse freed memory
    engine.set_positions(mesh, positions.copy())  # the engine's reference is the only one
    gc.collect()
    junk += [np.full_like(positions, 9.0) for _ in range(20)]
    engine.update()
    assert len(junk) == 40
    o, d = camera_rays(32, 32)
    assert engine.intersect(o, d).tobytes() == reference.intersect(o, d).tobytes()
    assert (reference.intersect(o, d)["mesh"] == 0).sum() > 100


def test_new_values_written_in_place_are_read_by_the_next_update(grid):
    positions, indices = grid
    o, d = camera_rays(48, 32)
    engine = dynrt.Engine()
    mesh = engine.add_mesh(positions, indices, motion="deformable", borrow=True)
    engine.update()
    first = engine.intersect(o, d)
    # Written in place, then announced: the engine reads this very array.
    wave_positions(N, phase=1.3, out=positions)
    engine.set_positions(mesh, positions)
    engine.update()
    moved = engine.intersect(o, d)
    assert moved.tobytes() != first.tobytes()
    copied = dynrt.Engine()
    copied.add_mesh(wave_positions(N, phase=1.3), indices, motion="deformable")
    copied.update()
    assert moved.tobytes() == copied.intersect(o, d).tobytes()
    assert (moved["mesh"] == mesh).sum() > 200


def test_queries_see_the_last_update_not_the_array(grid):
    """Between set_positions and update the engine still traces the last update's geometry,
    for borrowed meshes as for copied ones."""
    positions, indices = grid
    o, d = camera_rays(48, 32)
    engine = dynrt.Engine()
    mesh = engine.add_mesh(positions, indices, motion="deformable", borrow=True)
    engine.update()
    first = engine.intersect(o, d)
    other = wave_positions(N, phase=2.1)
    engine.set_positions(mesh, other)
    assert engine.intersect(o, d).tobytes() == first.tobytes()
    engine.update()
    assert engine.intersect(o, d).tobytes() != first.tobytes()


def test_borrows_reports_each_mesh(grid):
    positions, indices = grid
    engine = dynrt.Engine()
    copied = engine.add_mesh(positions, indices)
    borrowed = engine.add_mesh(positions.copy(), indices, borrow=True, motion="deformable")
    assert not engine.borrows(copied) and engine.borrows(borrowed)
    engine.set_positions(borrowed, positions.copy())
    assert engine.borrows(borrowed)  # still borrowing, the new array
    engine.remove_mesh(borrowed)
    assert not engine.borrows(borrowed)
