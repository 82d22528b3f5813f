#pragma once
// dynrt.load_scene for Python: any scene dynrt reads (glTF, BART, assimp's formats such as OBJ,
// PLY, FBX and Collada, or a procedural spec) played into a dynrt.Engine. The
// scene's objects become the engine's meshes (static ones static, rigid ones with their
// transform, deformable and exploding ones with their posed vertices), and posing a frame sets
// what moved and updates the engine, so renders and ray queries go through the library API as
// a simulation's own meshes do, and a caller may add meshes of its own to the same engine.

#include <pybind11/pybind11.h>

namespace dynrt::python {

void bind_scene(pybind11::module_& m);

}  // namespace dynrt::python
