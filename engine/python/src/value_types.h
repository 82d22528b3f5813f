#pragma once
// The library API's small value types as Python classes: dynrt.View, dynrt.Surface and
// dynrt.Light, built with keywords and holding tuples (docs/python.md "Python").

#include <pybind11/pybind11.h>

namespace dynrt::python {

void bind_value_types(pybind11::module_& m);

}  // namespace dynrt::python
