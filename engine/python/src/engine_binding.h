#pragma once
// dynrt.Engine: the library API's dynrt::Engine for Python (docs/python.md "Python"). Positions may be
// borrowed (the engine keeps a reference to the numpy array, so it stays alive while the
// engine may read it), ray batches are read in place (Engine::intersect on RayArrays), results
// are written into numpy arrays the caller may pass in, and the GIL is released while the
// engine updates, renders or traces.

#include "dynrt/dynrt.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <unordered_map>

namespace dynrt::python {

namespace py = pybind11;

class PyEngine {
public:
    explicit PyEngine(const EngineOptions& options) : engine_(options) {}

    std::uint32_t add_mesh(py::handle positions, py::handle indices, const std::string& motion,
                           py::handle transform, const Surface* surface, py::handle normals,
                           const std::string& name, bool borrow, py::handle texcoords);
    /// `source`: a path (str or os.PathLike), an image file's bytes (any contiguous buffer of
    /// bytes: bytes, bytearray, memoryview, a 1-D uint8 array), copied, or texels: a numpy
    /// array of shape (H, W) or (H, W, C), uint8 or float32 (texel_array), copied.
    std::uint32_t add_texture(py::handle source, bool srgb, const std::string& name,
                              const std::string& mime_type);
    void set_positions(py::handle mesh, py::handle positions, py::handle normals);
    void remove_mesh(py::handle mesh);
    /// Whether the engine holds a reference to the mesh's positions array: false for a mesh
    /// added without borrowing, removed, or never added.
    bool borrows(py::handle mesh) const;

    Engine& engine() { return engine_; }
    const Engine& engine() const { return engine_; }

private:
    /// The arrays of meshes added with borrow=True, kept alive while the engine may read them
    /// (set_positions replaces a mesh's entry). Declared before engine_ so that the engine is
    /// destroyed first.
    std::unordered_map<std::uint32_t, py::object> borrowed_;
    Engine engine_;
};

/// A frame's figures (FrameStats) as the report's dict (docs/report.md "Report": the keys of a frame).
py::object report_dict(const FrameStats& stats);

/// The structured dtype of intersect's results: t, mesh, triangle, u, v (dynrt::RayHit's
/// layout, so hits are written in place).
py::dtype hit_dtype();

void bind_engine(py::module_& m);

}  // namespace dynrt::python
