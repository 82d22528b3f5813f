#include "numpy_args.h"

#include "api/scene_texture.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>

namespace dynrt::python {

void invalid(const std::string& where, const std::string& message) {
    throw Error(Error::Code::invalid_argument, where + ": " + message);
}

py::dtype dtype(const char* name) { return py::dtype(name); }

namespace {

/// How arrays the engine copies anyway are taken: converted when needed to a C-contiguous array
/// of the wanted type with its data aligned (numpy copies an array at an odd byte offset rather
/// than hand it over as it is, which would make every load misaligned).
constexpr int kConverted = py::array::c_style | py::array::forcecast | py::detail::npy_api::NPY_ARRAY_ALIGNED_;

std::string shape_text(const py::array& a) {
    std::ostringstream out;
    out << "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) out << (d ? ", " : "") << a.shape(d);
    out << (a.ndim() == 1 ? ",)" : ")");
    return out.str();
}

std::string type_name(py::handle value) {
    return py::str(py::type::handle_of(value).attr("__name__")).cast<std::string>();
}

}  // namespace

py::array checked_array(py::handle value, const std::string& where, const ArraySpec& spec) {
    const std::string name = spec.name;
    const std::string wanted = spec.columns ? "(N, " + std::to_string(spec.columns) + ")" : "(N,)";
    const std::string dtype_name = spec.dtype.attr("name").cast<std::string>();
    if (!py::isinstance<py::array>(value)) {
        invalid(where, name + " must be a numpy array of " + dtype_name + " with shape " + wanted +
                           ", got " + type_name(value) + " (use np.ascontiguousarray(x, dtype=np.float32))");
    }
    py::array a = py::reinterpret_borrow<py::array>(value);
    if (!a.dtype().equal(spec.dtype)) {
        if (spec.result_dtype) {
            invalid(where, name + " must have dtype " + spec.result_dtype + ": allocate it with np.empty(n, dtype=" +
                               spec.result_dtype + ")");
        }
        // dtype.name drops the byte order: say '>f4' for a big-endian float32.
        std::string got = a.dtype().attr("name").cast<std::string>();
        if (got == dtype_name) got = a.dtype().attr("str").cast<std::string>() + ", not in native byte order";
        invalid(where, name + " must have dtype " + dtype_name + ", got " + got +
                           " (it is read in place, not converted: use np.ascontiguousarray(" + name +
                           ", dtype=np." + dtype_name + "))");
    }
    const bool shape_ok = spec.columns ? (a.ndim() == 2 && a.shape(1) == spec.columns) : a.ndim() == 1;
    if (!shape_ok) invalid(where, name + " must have shape " + wanted + ", got " + shape_text(a));
    if (!(a.flags() & py::array::c_style)) {
        invalid(where, name + " must be C-contiguous (it is read in place): use np.ascontiguousarray(" +
                           name + ")");
    }
    require_aligned(a, where, name);
    if (spec.writeable && !a.writeable()) invalid(where, name + " is read-only; the results are written into it");
    return a;
}

void require_aligned(const py::array& a, const std::string& where, const std::string& name) {
    if (reinterpret_cast<std::uintptr_t>(a.data()) % a.dtype().attr("alignment").cast<std::uintptr_t>() != 0) {
        // A view at an odd byte offset into a buffer (np.frombuffer): not a valid float array.
        invalid(where, name + " is not aligned in memory: pass a copy (" + name + ".copy())");
    }
}

py::array converted_rows(py::handle value, const std::string& where, const char* name, int columns) {
    const std::string wanted = "(N, " + std::to_string(columns) + ")";
    py::array any = py::array::ensure(value);
    if (!any) {
        PyErr_Clear();
        invalid(where, std::string(name) + " must be an array of numbers with shape " + wanted);
    }
    const char kind = any.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        invalid(where, std::string(name) + " must hold real numbers, got dtype " +
                           any.dtype().attr("name").cast<std::string>());
    }
    if (any.ndim() != 2 || any.shape(1) != columns) {
        invalid(where, std::string(name) + " must have shape " + wanted + ", got " + shape_text(any));
    }
    return py::array_t<float, kConverted>::ensure(any);
}

Texels texel_array(py::handle value, const std::string& where) {
    const py::array any = py::reinterpret_borrow<py::array>(value);
    const py::dtype type = any.dtype();
    const bool floating = type.equal(dtype("float32"));
    if (!floating && !type.equal(dtype("uint8"))) {
        std::string got = type.attr("name").cast<std::string>();
        if (got == "float32") got = type.attr("str").cast<std::string>() + ", not in native byte order";
        invalid(where, "texels must have dtype uint8 (0-255) or float32, got " + got +
                           " (use texels.astype(np.uint8) or texels.astype(np.float32))");
    }
    if (any.ndim() != 2 && any.ndim() != 3) {
        invalid(where, "texels must have shape (H, W) or (H, W, C) with C from 1 to 4, got " + shape_text(any));
    }
    const py::ssize_t channels = any.ndim() == 3 ? any.shape(2) : 1;
    if (channels < 1 || channels > 4) {
        invalid(where, "texels have " + std::to_string(channels) + " channels (shape " + shape_text(any) +
                           "), not 1 to 4 (grey, grey and alpha, RGB, RGBA)");
    }
    if (any.shape(0) == 0 || any.shape(1) == 0) invalid(where, "texels are empty, shape " + shape_text(any));
    if (any.shape(0) > api_detail::kTexelSideMax || any.shape(1) > api_detail::kTexelSideMax) {
        invalid(where, "texels' shape " + shape_text(any) + " is too large: each side must be at most " +
                           std::to_string(api_detail::kTexelSideMax));
    }
    Texels texels;
    // A strided view (a crop, a channel slice) is copied into a contiguous array of its own.
    texels.array = floating ? py::array(py::array_t<float, kConverted>::ensure(any))
                            : py::array(py::array_t<std::uint8_t, kConverted>::ensure(any));
    if (!texels.array) {
        PyErr_Clear();
        invalid(where, "texels could not be copied into a contiguous array");
    }
    texels.height = int(any.shape(0));
    texels.width = int(any.shape(1));
    texels.channels = int(channels);
    texels.floating = floating;
    return texels;
}

std::optional<float> scalar(py::handle value) {
    if (py::isinstance<py::array>(value)) {
        const py::array a = py::reinterpret_borrow<py::array>(value);
        if (a.ndim() != 0) return std::nullopt;
    } else if (!PyNumber_Check(value.ptr()) || PyBool_Check(value.ptr())) {
        return std::nullopt;
    }
    PyObject* f = PyNumber_Float(value.ptr());
    if (!f) {
        PyErr_Clear();
        return std::nullopt;
    }
    const double d = PyFloat_AsDouble(f);
    Py_DECREF(f);
    return float(d);
}

std::span<const float> floats(const py::array& a) {
    return {static_cast<const float*>(a.data()), std::size_t(a.size())};
}

std::span<float> mutable_floats(py::array& a) {
    return {static_cast<float*>(a.mutable_data()), std::size_t(a.size())};
}

std::vector<std::uint32_t> index_list(py::handle value, const std::string& where) {
    py::array any = py::array::ensure(value);
    if (!any) invalid(where, "indices must be an array of integers with shape (T, 3)");
    const char kind = any.dtype().kind();
    if (kind != 'i' && kind != 'u') {
        invalid(where, "indices must have an integer dtype, got " + any.dtype().attr("name").cast<std::string>());
    }
    if (!((any.ndim() == 2 && any.shape(1) == 3) || (any.ndim() == 1 && any.shape(0) % 3 == 0))) {
        invalid(where, "indices must have shape (T, 3) or (3T,), got " + shape_text(any));
    }
    // int64 holds every uint32 and every negative value: check in it, then narrow.
    const auto wide = py::array_t<std::int64_t, kConverted>::ensure(any);
    if (!wide) invalid(where, "indices could not be read as integers");
    if (any.dtype().kind() == 'u' && any.dtype().itemsize() == 8) {
        // uint64 values above int64's range would wrap: check them before the cast.
        const auto big = py::array_t<std::uint64_t, kConverted>::ensure(any);
        for (py::ssize_t i = 0; i < big.size(); ++i) {
            if (big.data()[i] > std::numeric_limits<std::uint32_t>::max()) {
                invalid(where, "index " + std::to_string(i) + " is " + std::to_string(big.data()[i]) +
                                   ", beyond uint32");
            }
        }
    }
    std::vector<std::uint32_t> out(std::size_t(wide.size()));
    const std::int64_t* in = wide.data();
    for (std::size_t i = 0; i < out.size(); ++i) {
        if (in[i] < 0 || in[i] > std::int64_t(std::numeric_limits<std::uint32_t>::max())) {
            invalid(where, "index " + std::to_string(i) + " is " + std::to_string(in[i]) +
                               (in[i] < 0 ? ", negative" : ", beyond uint32"));
        }
        out[i] = std::uint32_t(in[i]);
    }
    return out;
}

Vec3 vec3(py::handle value, const std::string& where, const char* name) {
    const auto numbers = py::array_t<double, kConverted>::ensure(value);
    if (!numbers || numbers.size() != 3 || numbers.ndim() != 1) {
        PyErr_Clear();
        invalid(where, std::string(name) + " must be three numbers (x, y, z)");
    }
    const double* v = numbers.data();
    return Vec3{float(v[0]), float(v[1]), float(v[2])};
}

py::tuple to_tuple(const Vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

Transform transform(py::handle value, const std::string& where) {
    if (value.is_none()) return Transform::identity();
    const auto m = py::array_t<double, kConverted>::ensure(value);
    if (!m || m.ndim() != 2 || m.shape(0) != 4 || m.shape(1) != 4) {
        PyErr_Clear();
        invalid(where, "transform must be a 4x4 matrix (rows first, as numpy writes it)");
    }
    Transform t;
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 4; ++column) t.m[std::size_t(column * 4 + row)] = float(m.at(row, column));
    }
    return t;
}

py::array_t<double> transform_array(const Transform& t) {
    py::array_t<double> m({4, 4});
    auto out = m.mutable_unchecked<2>();
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 4; ++column) out(row, column) = t.m[std::size_t(column * 4 + row)];
    }
    return m;
}

MeshId mesh_id(py::handle value, const std::string& where) {
    if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr())) {
        invalid(where, "mesh must be an integer id (what add_mesh returned), got " + type_name(value));
    }
    const py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    const long long id = PyLong_AsLongLong(index.ptr());
    if (PyErr_Occurred() || id < 0 || id >= (long long)(std::numeric_limits<std::uint32_t>::max())) {
        PyErr_Clear();
        invalid(where, "mesh " + py::str(value).cast<std::string>() + " is not a mesh id");
    }
    return MeshId{std::uint32_t(id)};
}

TextureId texture_id(py::handle value, const std::string& where) {
    if (value.is_none()) return TextureId{};
    if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr())) {
        invalid(where, "texture must be an integer id (what add_texture returned) or None, got " + type_name(value));
    }
    const py::int_ index = py::reinterpret_steal<py::int_>(PyNumber_Index(value.ptr()));
    const long long id = PyLong_AsLongLong(index.ptr());
    if (PyErr_Occurred() || id < 0 || id >= (long long)(std::numeric_limits<std::uint32_t>::max())) {
        PyErr_Clear();
        invalid(where, "texture " + py::str(value).cast<std::string>() + " is not a texture id");
    }
    return TextureId{std::uint32_t(id)};
}

const char* wrap_name(Wrap wrap) {
    switch (wrap) {
        case Wrap::repeat: return "repeat";
        case Wrap::clamp: return "clamp";
        case Wrap::mirror: return "mirror";
    }
    return "repeat";
}

Wrap wrap(const std::string& name, const std::string& where, const char* argument) {
    for (const Wrap w : {Wrap::repeat, Wrap::clamp, Wrap::mirror}) {
        if (name == wrap_name(w)) return w;
    }
    invalid(where, std::string(argument) + " must be \"repeat\", \"clamp\" or \"mirror\", got \"" + name + "\"");
}

Motion motion(const std::string& name, const std::string& where) {
    for (const Motion m : {Motion::automatic, Motion::static_, Motion::rigid, Motion::deformable,
                           Motion::exploding}) {
        if (name == motion_name(m)) return m;
    }
    invalid(where, "motion must be \"automatic\", \"static\", \"rigid\", \"deformable\" or "
                   "\"exploding\", got \"" + name + "\"");
}

}  // namespace dynrt::python
