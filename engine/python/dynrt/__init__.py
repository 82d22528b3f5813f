"""dynrt: ray tracing of animated triangle meshes for simulation loops.

The library API of dynrt (C++ ``dynrt/dynrt.h``) for Python, with numpy in and numpy out::

    import numpy as np, dynrt

    engine = dynrt.Engine(threads=2)
    cloth = engine.add_mesh(positions, faces, motion="deformable", borrow=True)
    for step in range(steps):
        simulate(positions)                      # writes the borrowed float32 (V, 3) array
        engine.set_positions(cloth, positions)   # "it changed"; no copy
        report = engine.update()                 # refit or rebuild, as a dict
        image = engine.render(view, 640, 480)    # (480, 640, 3) float32
        hits = engine.intersect(origins, directions)  # structured array: t, mesh, triangle, u, v

Bulk arrays (positions, normals, ray origins and directions, result arrays) are read or
written in place: they must be C-contiguous float32 arrays of shape (N, 3) (results: the
documented dtype); anything else raises dynrt.InvalidArgument (a ValueError) naming the
argument, rather than being converted behind your back. Data the engine copies anyway is
converted when needed (indices, texcoords) or copied (a texture's texels: a uint8 or float32
array of shape (H, W) or (H, W, C), a strided view too). update, render, intersect and
occluded release the GIL. docs/python.md "Python" has the details.
"""

import math as _math
import operator as _operator

from ._core import (  # noqa: F401  (re-exported)
    Engine,
    Error,
    InvalidArgument,
    InvalidGeometry,
    InvalidState,
    Light,
    SceneAnimation as _SceneAnimation,
    SceneError,
    Surface,
    View,
    hit_dtype,
    save_image,
)

__all__ = [
    "Engine", "Error", "InvalidArgument", "InvalidGeometry", "InvalidState", "Light", "Scene",
    "SceneError", "Surface", "View", "hit_dtype", "load_scene", "save_image",
]


class Scene:
    """A scene file (glTF, BART, or OBJ, PLY, FBX, Collada... through assimp) or procedural spec
    played into a dynrt.Engine.

    Its objects are the engine's meshes (``mesh_ids``, in the order of ``names``); ``pose``
    moves them to a frame and updates the engine. The engine is an ordinary dynrt.Engine:
    add meshes of your own to it, or query it directly. Frame f is at time f / fps.
    Materials come from the file (Phong terms, reflectance, transmittance, ior, the diffuse
    texture with its objects' texture coordinates), so a render shows what ``dynrt render``
    shows of the same frame from the same camera.
    """

    def __init__(self, source, fps=None, threads=0, cost_ratio=1.0, clips=None):
        engine = Engine(threads=threads, cost_ratio=cost_ratio)
        if fps is not None:
            try:
                fps = float(fps)
            except (TypeError, ValueError):
                raise InvalidArgument(f"dynrt.load_scene: fps '{fps}' is not a positive number") from None
        if clips is not None:
            # Names or indices, as the CLI's repeatable --clip takes them; one alone is a list of one.
            clips = [str(c) for c in ([clips] if isinstance(clips, (str, int)) else clips)]
        self._animation = _SceneAnimation(str(source), fps, clips, engine)
        self.engine = engine

    # ---- what the file holds -------------------------------------------------------------
    @property
    def names(self):
        """The objects' names, in the file's order."""
        return self._animation.names

    @property
    def mesh_ids(self):
        """The engine's mesh id of each object, in the order of names."""
        return self._animation.mesh_ids

    @property
    def motions(self):
        """Each object's motion class: "static", "rigid", "deformable" or "exploding"."""
        return self._animation.motions

    @property
    def fps(self):
        return self._animation.fps

    @property
    def clips(self):
        """The names of the clips that play (load_scene's clips, else the CLI's default)."""
        return self._animation.clips

    @property
    def frame_count(self):
        """The file's own sequence length (BART), or the frames the animation spans."""
        return self._animation.frame_count

    @property
    def frame(self):
        """The frame posed last (0 before any pose)."""
        return self._animation.frame

    @property
    def lights(self):
        """The scene's lights, or the default light a render of it gets."""
        return self._animation.lights

    @property
    def background(self):
        return self._animation.background

    @property
    def view(self):
        """The scene's first camera at the posed frame, or a view framing the whole scene."""
        camera = self._animation.camera
        return camera if camera is not None else self._animation.default_view

    # ---- playing it ----------------------------------------------------------------------
    def frame_at(self, time):
        """The frame at `time` seconds; raises ValueError unless it falls on a frame."""
        exact = float(time) * self.fps
        if not _math.isfinite(exact) or abs(exact - round(exact)) > 1e-6 * max(1.0, abs(exact)):
            raise InvalidArgument(
                f"dynrt.Scene: time {time} s is not on a frame at {self.fps} fps; "
                f"load the scene with another fps, or pose a frame")
        return round(exact)

    def pose(self, time=None, *, frame=None):
        """Poses the scene at `time` seconds (or at `frame`, a whole number from 0 to 9,999,999
        as the CLI's --frames takes), hands what moved to the engine and updates it; returns the
        step's report (a dict, whose "frame" is the frame posed)."""
        if (time is None) == (frame is None):
            raise InvalidArgument("dynrt.Scene.pose: give either a time or a frame")
        if frame is None:
            frame = self.frame_at(time)
        try:
            number = _operator.index(frame)
        except TypeError:
            if not (isinstance(frame, float) and frame.is_integer()):
                raise InvalidArgument(f"dynrt.Scene.pose: frame {frame!r} is not a whole number") from None
            number = int(frame)
        return self._animation.pose(number)

    def _check_posed(self, call):
        if not self._animation.posed:
            raise InvalidState(f"dynrt.Scene.{call}: call Scene.pose() first (no frame is posed yet)")

    def render(self, width, height, *, view=None, **settings):
        """Renders the posed frame with the scene's lights and background (see
        Engine.render for the keywords), from `view` or the scene's own view."""
        self._check_posed("render")
        settings.setdefault("lights", self.lights)
        settings.setdefault("background", self.background)
        result = self.engine.render(self.view if view is None else view, width, height, **settings)
        if settings.get("report"):
            result[-1]["frame"] = self.frame  # the frame posed, as pose()'s report says
        return result

    def intersect(self, origins, directions, tmin=0.0, tmax=_math.inf, **kwargs):
        self._check_posed("intersect")
        return self.engine.intersect(origins, directions, tmin, tmax, **kwargs)

    def occluded(self, origins, directions, tmin=0.0, tmax=_math.inf, **kwargs):
        self._check_posed("occluded")
        return self.engine.occluded(origins, directions, tmin, tmax, **kwargs)


def load_scene(source, *, fps=None, threads=0, cost_ratio=1.0, clips=None):
    """Loads a glTF (.gltf, .glb) or BART (.aff) file, or builds a procedural spec
    ("sphere:2000+plane:10"), into a Scene with its own Engine. fps: frames per second, finite
    and positive (default: the file's, else 24). clips: the glTF animations to play, by name or
    index, as the CLI's --clip (default: all together, or only the first when they animate the
    same nodes). Raises dynrt.SceneError naming the file and the problem, InvalidArgument for a
    bad fps or clip."""
    return Scene(source, fps=fps, threads=threads, cost_ratio=cost_ratio, clips=clips)
