"""dynrt.load_scene and Scene.pose refuse what the CLI refuses, in its words (issue 34): frames
outside 0..9,999,999 or not whole, fps that is not a positive number, clips the file does not
have; the report names the frame posed; queries before the first pose say to pose first; and
clips are chosen by name or index as --clip chooses them."""

import math

import numpy as np
import pytest

import dynrt

from test_scene import rays_toward, shared_file

IA = dynrt.InvalidArgument


@pytest.mark.parametrize("frame, message", [
    (-1, "dynrt.Scene.pose: frame -1: frames are numbered from 0"),
    (10**9, "dynrt.Scene.pose: frame 1000000000: frame numbers above 9999999 are not supported"),
    (2**31, f"dynrt.Scene.pose: frame {2**31}: frame numbers above 9999999 are not supported"),
    (10**30, f"dynrt.Scene.pose: frame {10**30}: frame numbers above 9999999 are not supported"),
    (-2**70, f"dynrt.Scene.pose: frame {-2**70}: frames are numbered from 0"),
    (2.5, "dynrt.Scene.pose: frame 2.5 is not a whole number"),
    ("3", "dynrt.Scene.pose: frame '3' is not a whole number"),
])
def test_pose_refuses_frames_the_cli_refuses(frame, message):
    scene = dynrt.load_scene("sphere:100")
    scene.pose(frame=4)
    with pytest.raises(IA) as caught:
        scene.pose(frame=frame)
    assert str(caught.value) == message
    assert scene.frame == 4  # nothing changed


def test_pose_takes_every_whole_frame_in_range():
    scene = dynrt.load_scene("sphere:100")
    for frame in (0, np.int64(7), 3.0, dynrt._SceneAnimation.frame_max):
        assert scene.pose(frame=frame)["frame"] == int(frame)
        assert scene.frame == int(frame)
    with pytest.raises(IA, match="frames are numbered from 0"):
        scene.pose(-1 / 24)  # a time before 0 s is frame -1


def test_the_report_names_the_frame_posed():
    scene = dynrt.load_scene("sphere:100", fps=10)
    assert scene.pose(frame=10)["frame"] == 10
    assert scene.pose(frame=3)["frame"] == 3
    assert scene.pose(2.0)["frame"] == 20
    assert scene.render(8, 8, report=True)[-1]["frame"] == 20


@pytest.mark.parametrize("fps, shown", [(0, "0"), (-5, "-5"), (math.nan, "nan"), (math.inf, "inf"),
                                        (-math.inf, "-inf"), ("fast", "fast")])
def test_load_scene_refuses_an_fps_that_is_not_a_positive_number(fps, shown):
    with pytest.raises(IA) as caught:
        dynrt.load_scene("sphere:100", fps=fps)
    assert str(caught.value) == f"dynrt.load_scene: fps '{shown}' is not a positive number"


def test_queries_before_the_first_pose_say_to_pose():
    scene = dynrt.load_scene("sphere:100")
    o, d = np.float32([[0, 3, 0]]), np.float32([[0, -1, 0]])
    for call, run in [("render", lambda: scene.render(8, 8)), ("intersect", lambda: scene.intersect(o, d)),
                      ("occluded", lambda: scene.occluded(o, d))]:
        with pytest.raises(dynrt.InvalidState) as caught:
            run()
        assert str(caught.value) == f"dynrt.Scene.{call}: call Scene.pose() first (no frame is posed yet)"
    scene.pose(frame=0)
    assert scene.intersect(o, d)["mesh"][0] == 0


# ---- clips (Fox.glb: Survey, Walk, Run, which animate the same nodes) ----

def test_clips_by_name_or_index_as_the_cli_picks_them(shared_scenes):
    path = shared_file(shared_scenes, "fox/Fox.glb")
    default = dynrt.load_scene(path)
    assert default.clips == ["Survey"]  # the CLI's default: the first of clips that conflict
    run_by_name = dynrt.load_scene(path, clips=["Run"])
    run_by_index = dynrt.load_scene(path, clips=[2])
    assert run_by_name.clips == run_by_index.clips == ["Run"]
    assert dynrt.load_scene(path, clips="Walk").clips == ["Walk"]
    rays = rays_toward(default.view)
    hits = {}
    for name, scene in [("survey", default), ("run", run_by_name), ("run2", run_by_index)]:
        scene.pose(frame=10)
        hits[name] = scene.intersect(*rays).tobytes()
    assert hits["run"] == hits["run2"] and hits["run"] != hits["survey"]


@pytest.mark.parametrize("clip", ["Jump", "7", -1])
def test_an_unknown_clip_is_refused_naming_it_and_the_clips(shared_scenes, clip):
    path = shared_file(shared_scenes, "fox/Fox.glb")
    with pytest.raises(IA) as caught:
        dynrt.load_scene(path, clips=["Walk", clip])
    message = str(caught.value)
    assert message.startswith("dynrt.load_scene: ") and str(clip) in message
    assert "Survey" in message and "Run" in message
