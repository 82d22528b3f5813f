// The compiled part of the Python package `dynrt` (engine/python/dynrt/__init__.py wraps it):
// the library API's Engine, its value types, load_scene's scene player, and the exceptions
// every C++ error becomes.

#include "engine_binding.h"
#include "scene_binding.h"
#include "value_types.h"

#include "dynrt/dynrt.h"
#include "dynrt/scene/scene_error.h"

#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace {

/// The exception classes, created once and kept for the life of the process.
struct Exceptions {
    PyObject* error;             ///< dynrt.Error, a RuntimeError: the base of them all
    PyObject* invalid_argument;  ///< also a ValueError
    PyObject* invalid_geometry;  ///< also a ValueError
    PyObject* invalid_state;     ///< a RuntimeError
    PyObject* scene_error;       ///< also a ValueError: a scene file or spec that cannot be read
};

Exceptions& exceptions() {
    static Exceptions e{};
    return e;
}

PyObject* new_exception(py::module_& m, const char* name, py::tuple bases, const char* doc) {
    const std::string qualified = std::string("dynrt.") + name;
    PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
    if (!type) throw py::error_already_set();
    m.add_object(name, py::handle(type));
    return type;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "dynrt's engine for Python: see help(dynrt) and README \"Python\".";
    Exceptions& e = exceptions();
    e.error = new_exception(m, "Error", py::make_tuple(py::handle(PyExc_RuntimeError)),
                            "Every error the engine raises (dynrt::Error in C++).");
    const py::handle error(e.error), value_error(PyExc_ValueError);
    e.invalid_argument = new_exception(m, "InvalidArgument", py::make_tuple(error, value_error),
                                       "A bad argument: wrong dtype or shape, unknown mesh, non-finite value, "
                                       "bad option. Nothing was changed.");
    e.invalid_geometry = new_exception(m, "InvalidGeometry", py::make_tuple(error, value_error),
                                       "Geometry that became unusable in update() (a vertex not finite); the "
                                       "message names the mesh, the step and the vertex.");
    e.invalid_state = new_exception(m, "InvalidState", py::make_tuple(error),
                                    "A call at the wrong time: tracing before the first update(), or a change "
                                    "while another thread renders or traces.");
    e.scene_error = new_exception(m, "SceneError", py::make_tuple(error, value_error),
                                  "A scene file or spec that cannot be read; the message names the file, the "
                                  "object and the problem.");
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const dynrt::Error& error) {
            const Exceptions& x = exceptions();
            PyObject* type = x.error;
            switch (error.code()) {
                case dynrt::Error::Code::invalid_argument: type = x.invalid_argument; break;
                case dynrt::Error::Code::invalid_geometry: type = x.invalid_geometry; break;
                case dynrt::Error::Code::invalid_state: type = x.invalid_state; break;
            }
            PyErr_SetString(type, error.what());
        } catch (const dynrt::SceneError& error) {
            PyErr_SetString(exceptions().scene_error, error.what());
        }
    });

    dynrt::python::bind_value_types(m);
    dynrt::python::bind_engine(m);
    dynrt::python::bind_scene(m);
}
