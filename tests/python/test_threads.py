"""Threads: update, render, intersect, occluded and load_scene release the GIL (another Python
thread makes progress while they run); errors cross threads as the right dynrt exceptions,
whether a Python worker thread called the engine or one of the engine's own worker threads
found the problem; a change attempted while another thread renders raises
dynrt.InvalidState and the render still finishes correctly; and queries from several threads
at once give the single-threaded answers.

The GIL probe: a worker thread makes the call while the main thread counts iterations of a
pure-Python loop until the call returns. With the GIL released the loop runs all along; held,
it runs only for the few milliseconds before the call starts (Python's switch interval), so
its rate drops to almost nothing. The rate is compared with the loop's rate during
time.sleep (which releases the GIL), measured just before, and a control checks that the
probe does see a C call that holds the GIL (sorted() of a long list). Timing-based, so marked
heavy (left out under ASan+UBSan). The engines here run on one thread (threads=1), leaving the
other core to the loop."""

import concurrent.futures
import random
import threading
import time

import numpy as np
import pytest

import dynrt

from conftest import World, camera_rays, random_rays, view, wave_grid, wave_positions

BIG_N = 600  # a 600 x 600 grid: 717,602 triangles, rebuilt in about 0.2 s on one core
MIN_CALL_S = 0.08  # calls shorter than this say little about the GIL
RELEASED_SHARE = 0.2  # the loop keeps at least this share of its free-running rate


def progress_during(call):
    """(loop iterations per second while call() ran in another thread, call's seconds, its
    result)."""
    done = threading.Event()
    box = {}

    def run():
        start = time.perf_counter()
        try:
            box["result"] = call()
        except BaseException as error:  # re-raised below, in the test's thread
            box["error"] = error
        finally:
            box["seconds"] = time.perf_counter() - start
            done.set()

    worker = threading.Thread(target=run)
    count = 0
    worker.start()
    while not done.is_set():
        count += 1
    worker.join()
    if "error" in box:
        raise box["error"]
    return count / box["seconds"], box["seconds"], box.get("result")


def free_rate():
    """The loop's rate while the other thread sleeps (the GIL released all along)."""
    return max(progress_during(lambda: time.sleep(0.1))[0] for _ in range(2))


def assert_gil_released(call):
    baseline = free_rate()
    rate, seconds, result = progress_during(call)
    assert seconds >= MIN_CALL_S, f"the call took {seconds * 1e3:.0f} ms: too short to tell"
    assert rate >= RELEASED_SHARE * baseline, (
        f"the other thread ran at {rate:.0f} iterations/s during the {seconds * 1e3:.0f} ms call, "
        f"{rate / baseline:.1%} of its {baseline:.0f}/s: the call held the GIL")
    return result


@pytest.fixture(scope="module")
def big():
    """One-threaded engine with a big exploding mesh (rebuilt at every update)."""
    positions, indices = wave_grid(BIG_N)
    engine = dynrt.Engine(threads=1)
    mesh = engine.add_mesh(positions, indices, motion="exploding")
    engine.update()
    return engine, mesh


@pytest.mark.heavy
def test_probe_sees_a_call_that_holds_the_gil():
    numbers = [random.random() for _ in range(1_500_000)]
    baseline = free_rate()
    rate, seconds, _ = progress_during(lambda: sorted(numbers))
    assert seconds >= MIN_CALL_S
    assert rate < RELEASED_SHARE * baseline, (rate, baseline)


@pytest.mark.heavy
def test_render_releases_the_gil(big):
    engine, _ = big
    rgb = assert_gil_released(lambda: engine.render(view(), 1024, 1024, reuse_pixels=False))
    assert rgb.shape == (1024, 1024, 3)


@pytest.mark.heavy
@pytest.mark.parametrize("kind", ["intersect", "occluded"])
def test_ray_queries_release_the_gil(big, kind):
    engine, _ = big
    o, d = random_rays(1_200_000, box=1.2)
    result = assert_gil_released(lambda: getattr(engine, kind)(o, d))
    assert len(result) == len(o)


@pytest.mark.heavy
def test_update_releases_the_gil(big):
    engine, mesh = big
    engine.set_positions(mesh, wave_positions(BIG_N, phase=0.8))
    report = assert_gil_released(engine.update)
    assert report["triangles"] == 2 * (BIG_N - 1) ** 2


@pytest.mark.heavy
def test_load_scene_releases_the_gil():
    # Big enough that the call lasts well past MIN_CALL_S (a million triangles took 67 ms on a
    # quiet machine, too short to tell).
    scene = assert_gil_released(lambda: dynrt.load_scene("sphere:4000000", threads=1))
    assert scene.names == ["sphere:4000000"]


# ---- errors crossing threads ----

@pytest.fixture(scope="module")
def small():
    engine, _ = World().build()
    return engine


def test_engine_errors_reach_future_result(small):
    o, d = camera_rays(32, 32)
    bad = d.copy()
    bad[700] = np.nan
    with concurrent.futures.ThreadPoolExecutor(max_workers=3) as pool:
        bad_ray = pool.submit(small.intersect, o, bad)
        bad_shape = pool.submit(small.occluded, o, d[:, :2].copy())
        bad_view = pool.submit(small.render, dynrt.View(eye=(0, 0, 0), target=(0, 0, 0)), 8, 8)
        fine = pool.submit(small.intersect, o, d)
        with pytest.raises(dynrt.InvalidArgument) as raised:
            bad_ray.result()
        assert str(raised.value) == "dynrt::Engine: ray 700: direction is not finite"
        with pytest.raises(dynrt.InvalidArgument, match="directions must have shape"):
            bad_shape.result()
        with pytest.raises(dynrt.InvalidArgument, match="camera eye equals target"):
            bad_view.result()
        assert (fine.result()["mesh"] >= 0).any()


def test_invalid_state_and_geometry_reach_future_result():
    positions, indices = wave_grid(32)
    engine = dynrt.Engine()
    mesh = engine.add_mesh(positions, indices, motion="deformable", borrow=True)
    o, d = camera_rays(16, 16)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        with pytest.raises(dynrt.InvalidState, match="intersect before the first update"):
            pool.submit(engine.intersect, o, d).result()
        pool.submit(engine.update).result()
        positions[100] = np.inf
        engine.set_positions(mesh, positions)
        with pytest.raises(dynrt.InvalidGeometry, match="borrowed vertex 100 is not finite"):
            pool.submit(engine.update).result()


def test_a_bad_ray_deep_in_a_big_batch_found_by_the_engines_threads():
    """The batch is checked in parallel, run by run, on the engine's worker threads; the error
    still names the ray, from the caller's thread or a pool's."""
    engine, _ = World().build(engine=dynrt.Engine(threads=2))
    o, d = random_rays(400_000)
    d[312_345] = (0.0, 0.0, 0.0)
    with pytest.raises(dynrt.InvalidArgument) as raised:
        engine.intersect(o, d)
    assert str(raised.value) == "dynrt::Engine: ray 312345: direction is zero"
    o[398_765] = (np.nan, 0, 0)
    d[312_345] = (0.0, 0.0, 1.0)
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        with pytest.raises(dynrt.InvalidArgument) as raised:
            pool.submit(engine.occluded, o, d).result()
    assert str(raised.value) == "dynrt::Engine: ray 398765: origin is not finite"


def test_a_non_finite_vertex_of_a_big_mesh_found_by_the_engines_threads():
    positions, indices = wave_grid(300)
    engine = dynrt.Engine(threads=2)
    mesh = engine.add_mesh(positions, indices, motion="deformable", borrow=True)
    engine.update()
    positions[77_777] = (1.0, np.nan, 0.0)
    engine.set_positions(mesh, positions)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        with pytest.raises(dynrt.InvalidGeometry) as raised:
            pool.submit(engine.update).result()
    assert str(raised.value) == ("dynrt::Engine: mesh 'mesh 0' (id 0), step 1: borrowed vertex 77777 "
                                 "is not finite (1, nan, 0)")


# ---- changes while another thread renders ----

def render_seen_running(pool, render, probe):
    """Submits render() to `pool` until probe(), a change to the engine, is refused while the
    render runs; returns the render's future. A render that starts while the probe is inside
    the engine is refused itself (InvalidState, the other side of the same check): then it is
    submitted again."""
    for _ in range(20):
        future = pool.submit(render)
        while not future.done():
            try:
                probe()
            except dynrt.InvalidState:
                return future
        future.exception()  # ended, or refused, before the probe saw it running
    pytest.fail("the render was never seen running")


def test_changes_while_rendering_raise_invalid_state_and_the_render_finishes(big):
    engine, mesh = big
    reference = engine.render(view(), 640, 480, reuse_pixels=False)
    moved = wave_positions(BIG_N, phase=2.0)
    extra_p, extra_i = wave_grid(4)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        # Until the render starts a change goes through (it shows at the next update only).
        render = render_seen_running(pool, lambda: engine.render(view(), 640, 480, reuse_pixels=False),
                                     lambda: engine.set_transform(mesh, np.eye(4)))
        with pytest.raises(dynrt.InvalidState) as refused:
            engine.set_transform(mesh, np.eye(4))
        assert str(refused.value) == ("dynrt::Engine: a change or update while another thread was tracing or "
                                      "rendering the engine (see the thread-safety contract in dynrt/api/engine.h)")
        # Every other change is refused too while the render runs (it takes well over 50 ms).
        attempts = [
            lambda: engine.set_positions(mesh, moved),
            lambda: engine.add_mesh(extra_p, extra_i),
            lambda: engine.remove_mesh(mesh),
            lambda: engine.set_surface(mesh, dynrt.Surface()),
            engine.update,
        ]
        outcomes = []
        for attempt in attempts:
            try:
                attempt()
                outcomes.append("done")
            except dynrt.InvalidState:
                outcomes.append("refused")
        rendering = not render.done()
        image = render.result()
    assert rendering, "the render ended during the attempts: make it longer"
    assert outcomes == ["refused"] * len(attempts)
    assert image.tobytes() == reference.tobytes()
    assert len(engine) == 1
    engine.update()  # nothing half done: the engine still works and traces what it did
    assert engine.render(view(), 640, 480, reuse_pixels=False).tobytes() == reference.tobytes()


def test_queries_from_several_threads_give_the_single_threaded_answers():
    engine, _ = World().build(engine=dynrt.Engine(threads=2))
    batches = [camera_rays(96, 64), random_rays(30_000, seed=3), random_rays(5_000, seed=4)]
    single = [(engine.intersect(o, d).tobytes(), engine.occluded(o, d).tobytes()) for o, d in batches]
    single_image = engine.render(view(), 160, 120, reuse_pixels=False).tobytes()

    def work(i):
        o, d = batches[i % len(batches)]
        if i % 4 == 3:
            return "render", engine.render(view(), 160, 120, reuse_pixels=False).tobytes()
        return i % len(batches), (engine.intersect(o, d).tobytes(), engine.occluded(o, d).tobytes())

    with concurrent.futures.ThreadPoolExecutor(max_workers=6) as pool:
        results = list(pool.map(work, range(48)))
    for key, value in results:
        assert value == (single_image if key == "render" else single[key]), key
    assert sum(key == "render" for key, _ in results) == 12


def test_scene_pose_while_rendering_is_refused_then_catches_up(shared_scenes):
    """Scene.pose hands the engine its changes, then updates; refused (another thread renders)
    after the poser has moved on, the next pose must still give the engine the whole frame:
    the same images as a scene posed there directly."""
    path = shared_scenes / "cesiumman" / "CesiumMan.glb"
    if not path.exists():
        pytest.skip(f"{path} is missing")
    floor_p, floor_i = wave_grid(400)  # a big floor under the man makes renders long
    floor = np.diag([4.0, 1.0, 4.0, 1.0])
    floor[1, 3] = -0.01

    def load():
        scene = dynrt.load_scene(path, threads=1)
        scene.engine.add_mesh(floor_p, floor_i, transform=floor, motion="static")
        return scene

    scene = load()
    scene.pose(frame=0)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        # Until the render has started an update with nothing to do goes through.
        render = render_seen_running(pool, lambda: scene.render(800, 800, reuse_pixels=False), scene.engine.update)
        with pytest.raises(dynrt.InvalidState):
            scene.pose(frame=12)
        rendering = not render.done()
        render.result()
    assert rendering, "the render ended during pose: make it longer"
    scene.pose(frame=12)
    fresh = load()
    fresh.pose(frame=12)
    assert scene.frame == fresh.frame == 12
    images = [s.render(96, 96, view=fresh.view, depth=True, mesh=True, reuse_pixels=False) for s in (scene, fresh)]
    for a, b in zip(*images):
        assert a.tobytes() == b.tobytes()
    # Not a vacuous comparison: the man moved between frames 0 and 12.
    still = load()
    still.pose(frame=0)
    assert still.render(96, 96, view=fresh.view, reuse_pixels=False).tobytes() != images[1][0].tobytes()


def test_progress_and_cancel_from_another_thread(big):
    """render_progress() polled while a render runs in another thread only grows; after it,
    every tile pass is done. cancel_render() stops a long render, which raises InvalidState
    (its arrays hold no whole image), and the next render is whole."""
    engine, _ = big
    assert engine.render_progress()["tracing"] is False
    reference = engine.render(view(), 320, 240, reuse_pixels=False, samples_per_pixel=4)
    done = engine.render_progress()
    assert done["tiles_total"] == 20 * 15 * 4 and done["tiles_done"] == done["tiles_total"]
    assert done["fraction"] == 1.0
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as pool:
        render = pool.submit(lambda: engine.render(view(), 320, 240, reuse_pixels=False, samples_per_pixel=4))
        last = 0
        while not render.done():
            p = engine.render_progress()
            if p["tracing"]:
                assert last <= p["tiles_done"] <= p["tiles_total"] == 20 * 15 * 4
                last = p["tiles_done"]
        assert render.result().tobytes() == reference.tobytes()
        # Stopped as soon as it is seen tracing (64 samples per pixel take seconds on one thread).
        long = pool.submit(lambda: engine.render(view(), 320, 240, reuse_pixels=False, samples_per_pixel=64))
        while not long.done() and not engine.render_progress()["tracing"]:
            time.sleep(0.001)
        engine.cancel_render()
        with pytest.raises(dynrt.InvalidState, match="stopped by cancel_render"):
            long.result()
    assert engine.render(view(), 320, 240, reuse_pixels=False, samples_per_pixel=4).tobytes() == reference.tobytes()
