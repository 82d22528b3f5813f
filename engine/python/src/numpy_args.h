#pragma once
// Turning Python arguments into the library API's values, checked: numpy arrays read in place
// (float32, C-contiguous, the right shape), vectors, transforms, surfaces and motions. Every
// problem throws dynrt::Error (invalid_argument) with a message naming the call and the
// argument, which the module raises as dynrt.InvalidArgument (a ValueError); nothing reaches
// the engine unchecked and nothing crashes the interpreter.

#include "dynrt/dynrt.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dynrt::python {

namespace py = pybind11;

/// Throws dynrt::Error(invalid_argument, "<where>: <message>").
[[noreturn]] void invalid(const std::string& where, const std::string& message);

/// What an array argument must be: its dtype, its trailing dimension (0: one-dimensional)
/// and whether the engine writes into it.
struct ArraySpec {
    const char* name;     ///< the argument's name, for errors ("positions")
    py::dtype dtype;      ///< exactly this dtype
    int columns = 3;      ///< shape (N, columns), or (N,) when 0
    bool writeable = false;
    /// For result arrays: how the dtype is named in errors and passed to np.empty in the
    /// hint ("dynrt.hit_dtype", "bool"); null for plain input arrays.
    const char* result_dtype = nullptr;
};

/// `value` as an ndarray meeting `spec`, to be read or written in place (no copy is made, so
/// no conversion either: a float64 array is refused with a hint, not silently converted).
py::array checked_array(py::handle value, const std::string& where, const ArraySpec& spec);

/// `value` (any array-like of real numbers) as a C-contiguous float32 array of shape (N,
/// columns), converted when it is not one already: for data the engine copies anyway.
py::array converted_rows(py::handle value, const std::string& where, const char* name, int columns);

/// A number (a Python or numpy scalar, or a 0-d array) as a float, or nullopt for anything else.
std::optional<float> scalar(py::handle value);

/// Throws unless the array's data is aligned for its dtype (a view at an odd byte offset into a
/// buffer is not), as the engine reads and writes it as C++ values.
void require_aligned(const py::array& a, const std::string& where, const std::string& name);

/// Its rows: shape[0].
inline std::size_t rows(const py::array& a) { return a.ndim() == 0 ? 0 : std::size_t(a.shape(0)); }

/// The floats of a checked float32 array, read in place.
std::span<const float> floats(const py::array& a);
std::span<float> mutable_floats(py::array& a);

/// Triangle indices from any integer array-like of shape (T, 3) or (3T,), copied to uint32
/// (the engine copies indices anyway); negative or too large values are refused.
std::vector<std::uint32_t> index_list(py::handle value, const std::string& where);

/// A texture's texels given as a numpy array (Engine.add_texture): shape (H, W) or (H, W, C)
/// with C from 1 to 4, dtype uint8 (0-255) or float32, neither empty. `array` is C-contiguous
/// and aligned: the caller's, or a copy of a strided view (the engine copies the texels anyway).
struct Texels {
    py::array array;
    int width = 0;
    int height = 0;
    int channels = 0;
    bool floating = false;
};

/// `value` (a numpy array that is not one-dimensional) as Texels; other dtypes, shapes and
/// empty arrays are refused naming what is accepted. Sides longer than TextureDesc's limit are
/// refused here, before they are narrowed to int; the engine checks the rest (float values).
Texels texel_array(py::handle value, const std::string& where);

/// Three numbers (a tuple, list or array).
Vec3 vec3(py::handle value, const std::string& where, const char* name);
py::tuple to_tuple(const Vec3& v);

/// A 4x4 array-like, rows first as numpy writes matrices (M[row, column], acting on column
/// vectors), to the API's column-major Transform. None is the identity.
Transform transform(py::handle value, const std::string& where);
/// The API's Transform as a (4, 4) float64 array, rows first.
py::array_t<double> transform_array(const Transform& t);

/// A mesh id: a Python or numpy integer (hits' `mesh` field) in the range of MeshId values;
/// whether the engine knows it is the engine's to say.
MeshId mesh_id(py::handle value, const std::string& where);

/// A texture id (what add_texture returned): a Python or numpy integer, or None for no
/// texture; whether the engine has it is the engine's to say.
TextureId texture_id(py::handle value, const std::string& where);

/// "repeat", "clamp" or "mirror", and back.
Wrap wrap(const std::string& name, const std::string& where, const char* argument);
const char* wrap_name(Wrap wrap);

/// "automatic", "static", "rigid", "deformable" or "exploding".
Motion motion(const std::string& name, const std::string& where);

/// numpy's dtypes, by name ("float32", "int32", ...).
py::dtype dtype(const char* name);

}  // namespace dynrt::python
