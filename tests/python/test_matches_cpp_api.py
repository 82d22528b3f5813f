"""The module gives the C++ library API's results bit for bit: the same meshes and rays go to
dynrt.Engine and to the C++ program api_oracle.cpp (dynrt::Engine with dynrt::Ray structs),
and every closest hit, occlusion flag and rendered pixel (colour, depth, mesh id) must be the
same bytes, at step 0 and after a step that moves a deformable mesh, a rigid one and two
automatic ones. The rays come as coherent camera rays (traced as packets) and incoherent random
ones (traced ray by ray), with per-ray tmin/tmax arrays and with scalar limits; the positions
as copies and as borrowed arrays written in place."""

import subprocess

import numpy as np
import pytest

import dynrt

from conftest import VIEW, camera_rays, random_rays, ray_limits, view

WIDTH, HEIGHT = 96, 64
STEPS = (0, 1)
IMAGES = ("rgb.f32", "depth.f32", "mesh.i32", "rgb2.f32")


def _ray_sets():
    """name -> (origins, directions, tmin, tmax) as Python passes them (arrays or numbers)."""
    cam_o, cam_d = camera_rays(64, 48, eye=VIEW["eye"], target=VIEW["target"], fov_y_deg=30.0)
    rnd_o, rnd_d = random_rays(2001)  # not a multiple of 256: the last run is partial
    cam_tmin, cam_tmax = ray_limits(len(cam_o), seed=3)
    rnd_tmin, rnd_tmax = ray_limits(len(rnd_o), seed=4)
    return {
        "camera": (cam_o, cam_d, cam_tmin, cam_tmax),
        "camera_default": (cam_o, cam_d, 0.0, np.inf),
        "camera_scalar": (cam_o, cam_d, 0.3, 4.25),
        "random": (rnd_o, rnd_d, rnd_tmin, rnd_tmax),
        "random_default": (rnd_o, rnd_d, 0.0, np.inf),
        "random_scalar": (rnd_o, rnd_d, 0.125, 2.5),
    }


RAY_SETS = _ray_sets()

# A second render's settings: everything but the defaults.
SETTINGS = dict(lights=[(1.5, 3.0, 2.0, 0.75), (-2.0, 1.0, 0.5, 0.5)], background=(0.1, 0.2, 0.3), ambient=0.125,
                max_depth=3, cutoff=0.0625, smooth_normals=False, reuse_pixels=False)


def _render_settings():
    s = dict(SETTINGS)
    s["lights"] = [dynrt.Light(position=light[:3], intensity=light[3]) for light in SETTINGS["lights"]]
    return s


def _as_array(limit, n):
    return limit if isinstance(limit, np.ndarray) else np.full(n, limit, np.float32)


def _write_inputs(folder, world):
    """The oracle's input files (format: api_oracle.cpp's header)."""
    lines = []
    for m in world.meshes:
        name = m["name"]
        lines.append(f"{name} {m['motion']}")
        m["positions0"].astype("<f4").tofile(folder / f"{name}.positions0.f32")
        m["indices"].astype("<u4").tofile(folder / f"{name}.indices.u32")
        for key, suffix in (("transform0", "transform0.f32"), ("positions1", "positions1.f32"),
                            ("transform1", "transform1.f32")):
            if m[key] is not None:
                m[key].astype("<f4").tofile(folder / f"{name}.{suffix}")
        if m["surface"] is not None:
            np.array(m["surface"], "<f4").tofile(folder / f"{name}.surface.f32")
    (folder / "meshes.txt").write_text("\n".join(lines) + "\n")
    for name, (o, d, tmin, tmax) in RAY_SETS.items():
        o.astype("<f4").tofile(folder / f"{name}.origins.f32")
        d.astype("<f4").tofile(folder / f"{name}.directions.f32")
        _as_array(tmin, len(o)).astype("<f4").tofile(folder / f"{name}.tmin.f32")
        _as_array(tmax, len(o)).astype("<f4").tofile(folder / f"{name}.tmax.f32")
    (folder / "rays.txt").write_text("\n".join(RAY_SETS) + "\n")
    np.array([*VIEW["eye"], *VIEW["target"], *VIEW["up"], VIEW["fov_y_deg"]], "<f4").tofile(folder / "view.f32")
    np.array([WIDTH, HEIGHT], "<i4").tofile(folder / "image.i32")
    settings = [*SETTINGS["background"], SETTINGS["ambient"], SETTINGS["max_depth"], SETTINGS["cutoff"],
                float(SETTINGS["smooth_normals"]), float(SETTINGS["reuse_pixels"])]
    for light in SETTINGS["lights"]:
        settings += light
    np.array(settings, "<f4").tofile(folder / "settings.f32")


@pytest.fixture(scope="module")
def cpp(oracle, world, tmp_path_factory):
    """The oracle's results: {(step, what): bytes}."""
    folder = tmp_path_factory.mktemp("oracle")
    _write_inputs(folder, world)
    run = subprocess.run([str(oracle), str(folder)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, f"{oracle} failed: {run.stderr}"
    out = {"ids": (folder / "ids.u32").read_bytes()}
    for step in STEPS:
        for name in RAY_SETS:
            out[step, name, "hits"] = (folder / f"step{step}.{name}.hits.bin").read_bytes()
            out[step, name, "occluded"] = (folder / f"step{step}.{name}.occluded.u8").read_bytes()
        for image in IMAGES:
            out[step, image] = (folder / f"step{step}.{image}").read_bytes()
    return out


def _queries(engine, step, out):
    for name, (o, d, tmin, tmax) in RAY_SETS.items():
        hits, hit_stats = engine.intersect(o, d, tmin, tmax, stats=True)
        flags, flag_stats = engine.occluded(o, d, tmin, tmax, stats=True)
        out[step, name, "hits"] = hits
        out[step, name, "occluded"] = flags
        out[step, name, "stats"] = (hit_stats, flag_stats)
    rgb, depth, mesh = engine.render(view(), WIDTH, HEIGHT, depth=True, mesh=True)
    out[step, "rgb.f32"], out[step, "depth.f32"], out[step, "mesh.i32"] = rgb, depth, mesh
    out[step, "rgb2.f32"] = engine.render(view(), WIDTH, HEIGHT, **_render_settings())


def _python_results(world, borrow):
    engine, arrays = world.build(borrow=borrow)
    out = {}
    _queries(engine, 0, out)
    world.step(engine, arrays, in_place=borrow)
    _queries(engine, 1, out)
    return out


@pytest.fixture(scope="module", params=["copy", "borrow"])
def py(request, world):
    """The module's results for the same world, positions copied or borrowed."""
    return _python_results(world, borrow=request.param == "borrow")


def _first_difference(a, b, what):
    """A readable account of where two byte strings differ."""
    if len(a) != len(b):
        return f"{what}: {len(a)} bytes from Python, {len(b)} from C++"
    i = next(k for k in range(len(a)) if a[k] != b[k])
    return f"{what}: first difference at byte {i}"


@pytest.mark.parametrize("step", STEPS)
@pytest.mark.parametrize("name", list(RAY_SETS))
def test_hits_match_cpp_bit_for_bit(cpp, py, step, name):
    hits = py[step, name, "hits"]
    assert hits.dtype == dynrt.hit_dtype and hits.shape == (len(RAY_SETS[name][0]),)
    got, want = hits.tobytes(), cpp[step, name, "hits"]
    assert got == want, _first_difference(got, want, f"step {step} {name} hits")
    # Not an empty comparison: the batch hits several meshes and misses too.
    assert 2 <= len(np.unique(hits["mesh"])) and (hits["mesh"] == -1).any()


@pytest.mark.parametrize("step", STEPS)
@pytest.mark.parametrize("name", list(RAY_SETS))
def test_occluded_matches_cpp_bit_for_bit(cpp, py, step, name):
    flags = py[step, name, "occluded"]
    assert flags.dtype == np.bool_ and flags.shape == (len(RAY_SETS[name][0]),)
    assert flags.tobytes() == cpp[step, name, "occluded"]
    assert flags.any() and not flags.all()
    # Occluded exactly where the closest hit found something.
    assert np.array_equal(flags, py[step, name, "hits"]["mesh"] >= 0)


@pytest.mark.parametrize("step", STEPS)
@pytest.mark.parametrize("image", IMAGES)
def test_render_matches_cpp_bit_for_bit(cpp, py, step, image):
    """rgb, depth and mesh of a render with the default settings; rgb2 of one with lights,
    background, ambient, depth, cutoff and flat normals given (and a mirror and a glass
    mesh)."""
    got = py[step, image]
    dtype = np.int32 if image == "mesh.i32" else np.float32
    shape = (HEIGHT, WIDTH, 3) if image.startswith("rgb") else (HEIGHT, WIDTH)
    assert got.dtype == dtype and got.shape == shape and got.flags.c_contiguous
    assert got.tobytes() == cpp[step, image], _first_difference(got.tobytes(), cpp[step, image], image)


def test_mesh_ids_match_cpp(cpp, world):
    engine, _ = world.build()
    assert np.frombuffer(cpp["ids"], "<u4").tolist() == list(range(len(world.meshes))) == list(range(len(engine)))


def test_the_step_changes_every_result(py):
    """Step 1 moves things: equal results at both steps would make the step-1 comparisons
    repeat step 0's."""
    for name in RAY_SETS:
        assert py[0, name, "hits"].tobytes() != py[1, name, "hits"].tobytes(), name
    for image in IMAGES:
        assert not np.array_equal(py[0, image], py[1, image]), image


def test_the_settings_change_the_render(py):
    assert not np.array_equal(py[0, "rgb.f32"], py[0, "rgb2.f32"])


def test_samples_and_area_lights_reach_the_engine(world):
    """Several samples per pixel and a sphere light: the same image twice, another than one
    sample's, each pixel the mean of samples (so between one sample's extremes)."""
    engine, _ = world.build(borrow=False)
    light = [dynrt.Light((0.5, 4.0, 2.0), 0.9, radius=0.8)]
    assert light[0].shape == "sphere"
    one = engine.render(view(), 48, 32, lights=light)
    many = engine.render(view(), 48, 32, lights=light, samples_per_pixel=8, filter="tent")
    again = engine.render(view(), 48, 32, lights=light, samples_per_pixel=8, filter="tent")
    assert np.array_equal(many, again)
    assert not np.array_equal(one, many)
    rgb, report = engine.render(view(), 48, 32, lights=light, samples_per_pixel=8, aa_contrast=0.05, report=True)
    assert 0 < report["pixels_refined"] < 48 * 32
    assert report["samples_per_pixel"] == 8


def test_light_kinds_reach_the_engine(world):
    """A spot, a coloured sun and a point light with falloff each give their own image; a
    spot's cone one degree wider changes it."""
    engine, _ = world.build(borrow=False)
    spot = dynrt.Light((0.5, 4.0, 2.0), 0.9, kind="spot", direction=(-0.1, -1.0, -0.4), inner_cone=10, outer_cone=20)
    wider = dynrt.Light((0.5, 4.0, 2.0), 0.9, kind="spot", direction=(-0.1, -1.0, -0.4), inner_cone=10, outer_cone=21)
    sun = dynrt.Light((0, 0, 0), 0.8, kind="directional", direction=(0.3, -1.0, -0.2), color=(1.0, 0.8, 0.6))
    bulb = dynrt.Light((0.5, 2.0, 1.0), 3.0, falloff=True, range=6.0)
    assert (spot.kind, sun.kind, bulb.kind) == ("spot", "directional", "point")
    assert "falloff=True" in repr(bulb) and "kind='spot'" in repr(spot)
    images = [engine.render(view(), 48, 32, lights=[light]) for light in (spot, wider, sun, bulb)]
    for i in range(len(images)):
        for j in range(i + 1, len(images)):
            assert not np.array_equal(images[i], images[j]), (i, j)
    # The sun's colour scales its light per channel: red as under a white sun, blue darker
    # wherever the sun reaches.
    white = engine.render(view(), 48, 32, lights=[
        dynrt.Light((0, 0, 0), 0.8, kind="directional", direction=(0.3, -1.0, -0.2))])
    assert np.array_equal(images[2][..., 0], white[..., 0])
    assert (images[2][..., 2] <= white[..., 2]).all()
    assert (images[2][..., 2] < white[..., 2]).sum() > 48 * 32 // 4


def test_an_environment_shows_where_rays_miss(world):
    """The bundled sky (scenes/sky.hdr) instead of the background: pixels that hit nothing
    change, the others do not (without secondary rays, which would see it in mirrors), and a
    path object works."""
    import pathlib
    sky = pathlib.Path(__file__).resolve().parents[2] / "scenes" / "sky.hdr"
    engine, _ = world.build(borrow=False)
    plain, mesh = engine.render(view(), 48, 32, mesh=True, reuse_pixels=False, max_depth=0)
    lit = engine.render(view(), 48, 32, environment=sky, reuse_pixels=False, max_depth=0)
    brighter = engine.render(view(), 48, 32, environment=str(sky), environment_scale=2.0, reuse_pixels=False,
                             max_depth=0)
    missed = mesh < 0
    assert missed.sum() > 48 * 32 // 10
    assert (np.abs(lit - plain).sum(axis=2)[missed] > 1e-3).all()
    assert np.array_equal(lit[~missed], plain[~missed])
    assert np.allclose(brighter[missed], 2.0 * lit[missed], rtol=1e-5)
    # As 16 suns it lights the meshes instead of the default light: their pixels change.
    sky_lit = engine.render(view(), 48, 32, environment=sky, environment_lights=16, reuse_pixels=False, max_depth=0)
    assert (np.abs(sky_lit - lit).sum(axis=2)[~missed] > 1e-3).mean() > 0.9
    assert np.array_equal(sky_lit[missed], lit[missed])
    with pytest.raises(dynrt.InvalidArgument, match="environment lights need an environment map"):
        engine.render(view(), 48, 32, environment_lights=16)


def test_coherent_rays_go_as_packets_and_incoherent_ones_alone(py):
    """The comparison covers both of the engine's tracers."""
    for step in STEPS:
        for name in ("camera", "camera_default", "camera_scalar"):
            for stats in py[step, name, "stats"]:
                assert stats["packet_rays"] == stats["rays"] == len(RAY_SETS[name][0]), (name, stats)
        for name in ("random", "random_default", "random_scalar"):
            for stats in py[step, name, "stats"]:
                assert stats["single_rays"] > 0.9 * stats["rays"], (name, stats)


def test_limits_change_the_results(py):
    """Per-ray and scalar limits really reach the engine."""
    for kind in ("camera", "random"):
        default = py[0, f"{kind}_default", "hits"]
        for name in (kind, f"{kind}_scalar"):
            hits = py[0, name, "hits"]
            assert not np.array_equal(hits["mesh"], default["mesh"]), name
            tmin, tmax = RAY_SETS[name][2], RAY_SETS[name][3]
            hit = hits["mesh"] >= 0
            assert (hits["t"][hit] >= np.broadcast_to(tmin, hits.shape)[hit]).all()
            assert (hits["t"][hit] <= np.broadcast_to(tmax, hits.shape)[hit]).all()


def test_borrowed_and_copied_positions_give_identical_results(world):
    copied, borrowed = _python_results(world, borrow=False), _python_results(world, borrow=True)
    assert copied.keys() == borrowed.keys()
    for key in copied:
        if key[-1] == "stats":
            continue
        assert copied[key].tobytes() == borrowed[key].tobytes(), key


def test_out_arrays_receive_the_same_results(world):
    engine, _ = world.build()
    o, d, tmin, tmax = RAY_SETS["camera"]
    hits = np.zeros(len(o), dynrt.hit_dtype)
    flags = np.zeros(len(o), np.bool_)
    returned_hits = engine.intersect(o, d, tmin, tmax, out=hits)
    returned_flags = engine.occluded(o, d, tmin, tmax, out=flags)
    assert returned_hits is hits and returned_flags is flags
    assert hits.tobytes() == engine.intersect(o, d, tmin, tmax).tobytes()
    assert flags.tobytes() == engine.occluded(o, d, tmin, tmax).tobytes()
    assert (hits["mesh"] >= 0).any()


def test_render_into_gives_the_render(world):
    engine, _ = world.build()
    rgb, depth, mesh = engine.render(view(), WIDTH, HEIGHT, depth=True, mesh=True)
    rgb2 = np.full((HEIGHT, WIDTH, 3), np.nan, np.float32)
    depth2 = np.full((HEIGHT, WIDTH), np.nan, np.float32)
    mesh2 = np.full((HEIGHT, WIDTH), 12345, np.int32)
    report = engine.render_into(view(), rgb2, depth=depth2, mesh=mesh2)
    assert isinstance(report, dict)
    assert rgb.tobytes() == rgb2.tobytes() and depth.tobytes() == depth2.tobytes()
    assert mesh.tobytes() == mesh2.tobytes()


def test_hit_fields_describe_the_hit(world):
    """t, triangle, u and v give the hit point: origin + t d is on triangle `triangle` at
    barycentrics (u, v) (float32 rounding apart)."""
    engine, _ = world.build()
    o, d, _, _ = RAY_SETS["camera_default"]
    hits = engine.intersect(o, d)
    cloth = hits["mesh"] == 0
    assert cloth.sum() > 100
    m = world.meshes[0]
    tri = m["indices"][hits["triangle"][cloth]]
    p = m["positions0"].astype(np.float64)
    u, v = hits["u"][cloth, None], hits["v"][cloth, None]
    on_triangle = (1 - u - v) * p[tri[:, 0]] + u * p[tri[:, 1]] + v * p[tri[:, 2]]
    along_ray = o[cloth] + hits["t"][cloth, None].astype(np.float64) * d[cloth]
    assert np.abs(on_triangle - along_ray).max() < 1e-4
    assert (hits["triangle"][~(hits["mesh"] >= 0)] == -1).all()
    assert np.isinf(hits["t"][hits["mesh"] == -1]).all()


def _converted(kind, p):
    return {
        "float64": lambda: p.astype(np.float64),
        "list": lambda: p.tolist(),
        "transposed": lambda: np.ascontiguousarray(p.T).T,
        "sliced": lambda: np.repeat(p, 2, axis=0)[::2],
        "big_endian": lambda: p.astype(">f4"),
    }[kind]()


@pytest.mark.parametrize("kind", ["float64", "list", "transposed", "sliced", "big_endian"])
def test_copied_positions_may_be_any_real_array_like(world, kind):
    """Copied positions (and normals) are converted to float32 once: the same results as the
    float32 array itself, at add_mesh and at set_positions."""
    o, d, tmin, tmax = RAY_SETS["camera"]
    want, arrays = world.build()
    want_hits = [want.intersect(o, d, tmin, tmax)]
    world.step(want, arrays, in_place=False)
    want_hits.append(want.intersect(o, d, tmin, tmax))

    engine = dynrt.Engine()
    for m in world.meshes:
        engine.add_mesh(_converted(kind, m["positions0"]), m["indices"], motion=m["motion"],
                        transform=m["transform0"], name=m["name"])
    engine.update()
    assert engine.intersect(o, d, tmin, tmax).tobytes() == want_hits[0].tobytes()
    for mesh, m in enumerate(world.meshes):
        if m["positions1"] is not None:
            engine.set_positions(mesh, _converted(kind, m["positions1"]))
        if m["transform1"] is not None:
            engine.set_transform(mesh, m["transform1"])
    engine.update()
    assert engine.intersect(o, d, tmin, tmax).tobytes() == want_hits[1].tobytes()


def test_integer_positions_are_converted():
    grid = np.array([[0, 0, 0], [4, 0, 0], [0, 4, 0], [4, 4, 0]])
    faces = [[0, 1, 2], [1, 3, 2]]
    as_int, as_float = dynrt.Engine(), dynrt.Engine()
    as_int.add_mesh(grid.astype(np.int16), faces)
    as_float.add_mesh(grid.astype(np.float32), faces)
    as_int.update(), as_float.update()
    o, d = camera_rays(16, 16, eye=(2, 2, 5), target=(2, 2, 0))
    assert as_int.intersect(o, d).tobytes() == as_float.intersect(o, d).tobytes()
    assert (as_int.intersect(o, d)["mesh"] == 0).all()


@pytest.mark.parametrize("tmin, tmax", [
    (np.float32(0.3), np.float32(4.25)),
    (np.float64(0.3), np.float16(4.25)),
    (np.array(0.3, np.float32), np.array(4.25)),
    (np.int64(0), np.int32(4)),
], ids=["float32", "float64_float16", "0d_arrays", "integers"])
def test_numpy_scalar_limits_are_numbers(world, tmin, tmax):
    engine, _ = world.build()
    o, d, _, _ = RAY_SETS["camera_scalar"]
    want = engine.intersect(o, d, float(np.float32(tmin)), float(np.float32(tmax)))
    assert engine.intersect(o, d, tmin, tmax).tobytes() == want.tobytes()
    assert engine.occluded(o, d, tmin, tmax).tobytes() == engine.occluded(o, d, float(tmin), float(tmax)).tobytes()
