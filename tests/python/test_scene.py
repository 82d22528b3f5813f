"""dynrt.load_scene: procedural specs (scenes/README.md "Procedural scenes") and, when the shared scene
folder is there, animated glTF and BART files, played into an Engine: what the scene reports
(names, mesh ids, motions, frames, fps), posing by frame and by time, objects that really
move between frames (hits change), renders of the right shape and type, and meshes of one's
own added to the scene's engine."""

import numpy as np
import pytest

import dynrt

from conftest import camera_rays

SPEC = "sphere:500+plane:4@0,-1,0,4#808080"


def rays_toward(view, n=48):
    """Coherent rays through the view's image, (origins, directions)."""
    return camera_rays(n, n, eye=view.eye, target=view.target, fov_y_deg=view.fov_y_deg)


def shared_file(shared_scenes, relative):
    path = shared_scenes / relative
    if not path.exists():
        pytest.skip(f"{path} is missing")
    return path


# ---- procedural specs ----

def test_procedural_scene_reports_its_objects():
    scene = dynrt.load_scene(SPEC)
    assert scene.names == ["sphere:500", "plane:4@0,-1,0,4#808080"]
    assert scene.mesh_ids == [0, 1]
    assert scene.motions == ["static", "static"]
    assert scene.fps == 24.0 and scene.frame_count == 1 and scene.frame == 0
    assert len(scene.engine) == 2
    assert isinstance(scene.engine, dynrt.Engine)
    assert all(isinstance(light, dynrt.Light) for light in scene.lights) and scene.lights
    assert len(scene.background) == 3
    assert isinstance(scene.view, dynrt.View)


def test_procedural_meshes_are_hit_where_the_spec_puts_them():
    scene = dynrt.load_scene(SPEC)
    scene.pose(frame=0)
    # Straight down through the sphere's centre: its top at y = 1 first, then the floor at y = -1.
    o = np.float32([[0, 3, 0], [2, 3, 2], [5, 3, 5]])
    d = np.float32([[0, -1, 0]] * 3)
    hits = scene.intersect(o, d)
    assert hits["mesh"].tolist() == [0, 1, -1]
    assert hits["t"][0] == pytest.approx(2.0, abs=0.01) and hits["t"][1] == pytest.approx(4.0, abs=1e-5)
    assert scene.occluded(o, d).tolist() == [True, True, False]


def test_queries_need_a_pose_first():
    scene = dynrt.load_scene("sphere:100")
    with pytest.raises(dynrt.InvalidState):
        scene.render(8, 8)
    report = scene.pose(0.0)
    assert isinstance(report, dict) and report["frame"] == 0 and report["triangles"] > 0
    assert scene.render(8, 8).shape == (8, 8, 3)


def test_render_shape_and_types():
    scene = dynrt.load_scene(SPEC)
    scene.pose(frame=0)
    rgb = scene.render(40, 30)
    assert rgb.shape == (30, 40, 3) and rgb.dtype == np.float32 and rgb.flags.c_contiguous
    rgb2, depth, mesh, report = scene.render(40, 30, depth=True, mesh=True, report=True)
    assert rgb2.tobytes() == rgb.tobytes()
    assert depth.shape == (30, 40) and depth.dtype == np.float32
    assert mesh.shape == (30, 40) and mesh.dtype == np.int32
    assert set(np.unique(mesh)) == {-1, 0, 1}
    assert np.isinf(depth[mesh == -1]).all() and np.isfinite(depth[mesh >= 0]).all()
    assert isinstance(report, dict) and report["primary_rays"] == 40 * 30
    # The scene's lights and background are the defaults of its render.
    assert scene.engine.render(scene.view, 40, 30, lights=scene.lights,
                               background=scene.background).tobytes() == rgb.tobytes()


def test_user_meshes_added_to_the_scene_engine_are_hit():
    scene = dynrt.load_scene(SPEC)
    scene.pose(frame=0)
    quad = np.float32([[-0.5, 2, -0.5], [0.5, 2, -0.5], [0.5, 2, 0.5], [-0.5, 2, 0.5]])
    mine = scene.engine.add_mesh(quad, [[0, 1, 2], [0, 2, 3]], name="lid")
    assert mine == 2 and len(scene.engine) == 3
    o, d = np.float32([[0, 3, 0]]), np.float32([[0, -1, 0]])
    assert scene.intersect(o, d)["mesh"][0] == 0  # not traced before the next update
    scene.pose(frame=0)  # pose updates the engine
    hit = scene.intersect(o, d)[0]
    assert hit["mesh"] == mine and hit["t"] == pytest.approx(1.0)
    assert scene.mesh_ids == [0, 1]  # the scene's own objects only


def test_fps_sets_the_frame_times():
    scene = dynrt.load_scene("sphere:100", fps=30)
    assert scene.fps == 30.0
    assert scene.frame_at(0.5) == 15
    scene.pose(0.5)
    assert scene.frame == 15


def test_scene_source_may_be_a_path(tmp_path, shared_scenes):
    path = shared_file(shared_scenes, "animatedmorphcube/AnimatedMorphCube.glb")
    assert dynrt.load_scene(path).names == dynrt.load_scene(str(path)).names


# ---- shared scene files: glTF ----

def hits_at(scene, frame, rays):
    scene.pose(frame=frame)
    return scene.intersect(*rays)


@pytest.mark.parametrize("relative, motion", [
    ("cesiumman/CesiumMan.glb", "deformable"),  # a skin
    ("animatedmorphcube/AnimatedMorphCube.glb", "deformable"),  # morph targets
    ("animatedcube/AnimatedCube.gltf", "rigid"),  # a node rotation
])
def test_gltf_animation_moves_the_meshes(shared_scenes, relative, motion):
    path = shared_file(shared_scenes, relative)
    scene = dynrt.load_scene(path)
    assert scene.motions == [motion] and scene.mesh_ids == [0] and len(scene.names) == 1
    assert scene.fps == 24.0 and scene.frame_count > 12
    assert scene.engine.motion(0) == motion
    scene.pose(frame=0)
    rays = rays_toward(scene.view)
    first = scene.intersect(*rays)
    assert (first["mesh"] == 0).sum() > 50
    later = hits_at(scene, 12, rays)
    assert (later["mesh"] == 0).sum() > 50
    assert later.tobytes() != first.tobytes()
    # Back at frame 0: the very same hits.
    assert hits_at(scene, 0, rays).tobytes() == first.tobytes()


def test_pose_by_time_is_pose_by_frame(shared_scenes):
    path = shared_file(shared_scenes, "cesiumman/CesiumMan.glb")
    by_time, by_frame = dynrt.load_scene(path), dynrt.load_scene(path)
    rays = rays_toward(by_frame.view)
    for frame in (0, 7, 30):
        by_time.pose(frame / 24)
        by_frame.pose(frame=frame)
        assert by_time.frame == by_frame.frame == frame
        assert by_time.intersect(*rays).tobytes() == by_frame.intersect(*rays).tobytes()
    # Another fps: frame 15 at 30 fps is frame 12 at 24 fps (both at 0.5 s).
    at30 = dynrt.load_scene(path, fps=30)
    at30.pose(0.5)
    by_frame.pose(frame=12)
    assert at30.frame == 15
    assert at30.intersect(*rays).tobytes() == by_frame.intersect(*rays).tobytes()


def test_static_and_rigid_objects_of_one_file(shared_scenes):
    path = shared_file(shared_scenes, "boxanimated/BoxAnimated.glb")
    scene = dynrt.load_scene(path)
    assert sorted(scene.motions) == ["rigid", "static"]
    rigid = scene.mesh_ids[scene.motions.index("rigid")]
    static = scene.mesh_ids[scene.motions.index("static")]
    with pytest.raises(dynrt.InvalidArgument, match="was added as static"):
        scene.engine.set_transform(static, np.eye(4))
    # Only the rigid inner box moves: every pixel that changes between frames shows it at one
    # of them.
    scene.pose(frame=0)
    rays = rays_toward(scene.view, n=64)
    frames = [hits_at(scene, f, rays)["mesh"] for f in (0, 20, 40, 60)]
    changed = 0
    for before, after in zip(frames, frames[1:]):
        moved = before != after
        changed += moved.sum()
        assert ((before[moved] == rigid) | (after[moved] == rigid)).all()
        assert (after == static).sum() > 50
    assert changed > 20
    assert any((f == rigid).any() for f in frames)


# ---- shared scene files: BART ----

def test_bart_robots(shared_scenes):
    path = shared_file(shared_scenes, "bart/robots/Robot.aff")
    scene = dynrt.load_scene(path)
    n = len(scene.names)
    assert n > 100 and scene.mesh_ids == list(range(n)) and len(scene.engine) == n
    assert set(scene.motions) <= {"static", "rigid", "deformable", "exploding"} and "rigid" in scene.motions
    assert scene.frame_count > 100 and 0 < scene.fps < 100
    scene.pose(frame=0)
    start_view = scene.view  # the file's camera follows its own path: keep frame 0's
    rays = rays_toward(start_view, n=64)
    first = scene.intersect(*rays)
    assert (first["mesh"] >= 0).mean() > 0.5
    later = hits_at(scene, 40, rays)
    assert later.tobytes() != first.tobytes()
    moved = set(np.unique(first["mesh"][first["mesh"] != later["mesh"]])) - {-1}
    motions = {scene.motions[scene.mesh_ids.index(m)] for m in moved}
    assert "rigid" in motions, motions
    rgb = scene.render(64, 48)
    assert rgb.shape == (48, 64, 3) and np.isfinite(rgb).all() and rgb.max() > 0


def test_a_gltf_light_on_a_node_is_where_its_node_puts_it(tmp_path):
    """KHR_lights_punctual on a moved and turned node: Scene.lights (which Scene.render lights
    with) gives it in world space at the posed frame, as dynrt render poses it."""
    import base64
    import json
    import struct
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    doc = {
        "asset": {"version": "2.0"}, "scene": 0,
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "spot", "intensity": 3.14159265, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.4}}]}},
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0},
                  {"translation": [1, 2, 3], "rotation": [0.70710678, 0, 0, 0.70710678],
                   "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]}],
        "bufferViews": [{"buffer": 0, "byteLength": len(positions)}],
        "buffers": [{"byteLength": len(positions),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(positions).decode()}],
    }
    path = tmp_path / "lamp.gltf"
    path.write_text(json.dumps(doc))
    scene = dynrt.load_scene(str(path))
    (light,) = scene.lights
    assert light.kind == "spot"
    assert np.allclose(light.position, (1, 2, 3), atol=1e-6)
    # -Z turned 90 degrees about +X points along +Y.
    assert np.allclose(light.direction, (0, 1, 0), atol=1e-6)
