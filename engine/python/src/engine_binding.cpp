#include "engine_binding.h"

#include "numpy_args.h"

#include "dynrt/engine/report.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

namespace dynrt::python {

// intersect writes RayHit structs straight into the rows of a hit_dtype array.
static_assert(sizeof(RayHit) == 20 && offsetof(RayHit, t) == 0 && offsetof(RayHit, mesh) == 4 &&
              offsetof(RayHit, primitive) == 8 && offsetof(RayHit, u) == 12 && offsetof(RayHit, v) == 16);
static_assert(sizeof(MeshId) == 4);

py::object report_dict(const FrameStats& stats) {
    return py::module_::import("json").attr("loads")(frame_report_json(stats));
}

py::dtype hit_dtype() {
    // Created once and kept for the life of the process (a leaked reference: the interpreter
    // may be finalising when statics are destroyed).
    static py::dtype* dtype = [] {
        py::list fields;
        for (const auto& [name, type] : {std::pair{"t", "<f4"}, std::pair{"mesh", "<i4"},
                                          std::pair{"triangle", "<i4"}, std::pair{"u", "<f4"},
                                          std::pair{"v", "<f4"}}) {
            fields.append(py::make_tuple(name, type));
        }
        return new py::dtype(py::module_::import("numpy").attr("dtype")(fields));
    }();
    return *dtype;
}

namespace {

const std::string kAddMesh = "dynrt.Engine.add_mesh";
const std::string kSetPositions = "dynrt.Engine.set_positions";

/// A positions or normals argument: read in place when the mesh borrows it, so exactly a
/// C-contiguous float32 (N, 3) array; else any (N, 3) array of numbers, converted when needed
/// (the engine copies it during the call anyway).
py::array positions_array(py::handle value, const std::string& where, const char* name, bool borrow) {
    if (borrow) return checked_array(value, where, ArraySpec{name, dtype("float32"), 3, false});
    return converted_rows(value, where, name, 3);
}

}  // namespace

std::uint32_t PyEngine::add_mesh(py::handle positions, py::handle indices, const std::string& motion_text,
                                 py::handle transform_value, const Surface* surface, py::handle normals,
                                 const std::string& name, bool borrow, py::handle texcoords) {
    const py::array p = positions_array(positions, kAddMesh, "positions", borrow);
    const std::vector<std::uint32_t> index_values = index_list(indices, kAddMesh);
    py::array n;
    if (!normals.is_none()) {
        n = positions_array(normals, kAddMesh, "normals", false);
        if (rows(n) != rows(p)) {
            invalid(kAddMesh, std::to_string(rows(p)) + " positions but " + std::to_string(rows(n)) + " normals");
        }
    }
    py::array st;
    if (!texcoords.is_none()) {
        st = converted_rows(texcoords, kAddMesh, "texcoords", 2);
        if (rows(st) != rows(p)) {
            invalid(kAddMesh, std::to_string(rows(p)) + " positions but " + std::to_string(rows(st)) + " texcoords");
        }
    }
    MeshDesc desc;
    desc.name = name;
    desc.positions = floats(p);
    if (st) desc.texcoords = floats(st);
    desc.indices = index_values;
    if (n) desc.normals = floats(n);
    desc.motion = motion(motion_text, kAddMesh);
    desc.ownership = borrow ? Ownership::borrow : Ownership::copy;
    desc.transform = transform(transform_value, kAddMesh);
    if (surface) desc.surface = *surface;
    const MeshId id = engine_.add_mesh(desc);
    if (borrow) borrowed_[id.value] = p;
    return id.value;
}

std::uint32_t PyEngine::add_texture(py::handle source, bool srgb, const std::string& name,
                                    const std::string& mime_type) {
    const std::string where = "dynrt.Engine.add_texture";
    TextureDesc desc;
    desc.name = name;
    desc.mime_type = mime_type;
    desc.srgb = srgb;
    if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__")) {
        desc.path = py::str(py::module_::import("os").attr("fspath")(source)).cast<std::string>();
        if (desc.path.empty()) invalid(where, "the path is empty");
        return engine_.add_texture(desc).value;
    }
    // A numpy array of rows and columns holds texels; a one-dimensional one, like any other
    // buffer, an image file's bytes.
    if (py::isinstance<py::array>(source)) {
        const auto array = py::reinterpret_borrow<py::array>(source);
        if (array.ndim() != 1) {
            const Texels texels = texel_array(array, where);
            desc.width = texels.width;
            desc.height = texels.height;
            desc.channels = texels.channels;
            const std::size_t count = std::size_t(texels.array.size());
            // Copied (and float values checked) by add_texture.
            if (texels.floating) {
                desc.texels_float = {static_cast<const float*>(texels.array.data()), count};
            } else {
                desc.texels8 = {static_cast<const std::uint8_t*>(texels.array.data()), count};
            }
            return engine_.add_texture(desc).value;
        }
        if (!array.dtype().equal(dtype("uint8"))) {
            invalid(where, "a one-dimensional array is taken as an image file's bytes and must have dtype uint8, got " +
                               array.dtype().attr("name").cast<std::string>() +
                               " (texels are an (H, W) or (H, W, C) array)");
        }
    }
    if (!PyObject_CheckBuffer(source.ptr())) {
        invalid(where, "source must be a path (str or os.PathLike), an image file's bytes or a numpy array of "
                       "texels, got " + py::str(py::type::handle_of(source).attr("__name__")).cast<std::string>());
    }
    Py_buffer view;
    if (PyObject_GetBuffer(source.ptr(), &view, PyBUF_C_CONTIGUOUS) != 0) {
        PyErr_Clear();
        invalid(where, "source's bytes must be contiguous");
    }
    struct Release {
        Py_buffer& view;
        ~Release() { PyBuffer_Release(&view); }
    } release{view};
    // Copied by add_texture.
    desc.encoded = {static_cast<const unsigned char*>(view.buf), std::size_t(view.len)};
    return engine_.add_texture(desc).value;
}

void PyEngine::set_positions(py::handle mesh_value, py::handle positions, py::handle normals) {
    const std::uint32_t mesh = mesh_id(mesh_value, kSetPositions).value;
    const bool borrow = borrowed_.count(mesh) != 0;
    const py::array p = positions_array(positions, kSetPositions, "positions", borrow);
    py::array n;
    if (!normals.is_none()) n = positions_array(normals, kSetPositions, "normals", false);
    engine_.set_positions(MeshId{mesh}, floats(p), n ? floats(n) : std::span<const float>{});
    // The engine took the call: a borrowed mesh now reads this array (the old one is released).
    if (borrow) borrowed_[mesh] = p;
}

bool PyEngine::borrows(py::handle mesh_value) const {
    return borrowed_.count(mesh_id(mesh_value, "dynrt.Engine.borrows").value) != 0;
}

void PyEngine::remove_mesh(py::handle mesh_value) {
    const std::uint32_t mesh = mesh_id(mesh_value, "dynrt.Engine.remove_mesh").value;
    engine_.remove_mesh(MeshId{mesh});
    borrowed_.erase(mesh);
}

namespace {

/// The keyword arguments every render takes, as the API's RenderSettings.
RenderSettings render_settings(py::handle lights, py::handle background, float ambient, bool reuse_pixels,
                               int max_depth, float cutoff, bool smooth_normals, int samples_per_pixel,
                               const std::string& filter, float aa_contrast, py::handle environment,
                               float environment_scale, int environment_lights, const std::string& where) {
    RenderSettings s;
    if (!lights.is_none()) {
        for (py::handle light : lights) {
            if (!py::isinstance<Light>(light)) invalid(where, "lights must be dynrt.Light values");
            s.lights.push_back(light.cast<Light>());
        }
    }
    s.background = vec3(background, where, "background");
    s.ambient = ambient;
    s.reuse_pixels = reuse_pixels;
    s.max_depth = max_depth;
    s.cutoff = cutoff;
    s.smooth_normals = smooth_normals;
    s.samples_per_pixel = samples_per_pixel;
    s.filter = filter;
    s.aa_contrast = aa_contrast;
    if (!environment.is_none()) {
        if (!py::isinstance<py::str>(environment) && !py::hasattr(environment, "__fspath__")) {
            invalid(where, "environment must be a path (str or os.PathLike) or None");
        }
        s.environment = py::str(py::module_::import("os").attr("fspath")(environment)).cast<std::string>();
    }
    s.environment_scale = environment_scale;
    s.environment_lights = environment_lights;
    return s;
}

/// Renders into checked arrays with the GIL released; returns the frame's figures.
FrameStats render_arrays(const PyEngine& self, const View& view, py::array& rgb, py::array* depth,
                         py::array* mesh, const RenderSettings& settings) {
    ImageView image;
    image.height = int(rgb.shape(0));
    image.width = int(rgb.shape(1));
    image.rgb = mutable_floats(rgb);
    if (depth) image.depth = mutable_floats(*depth);
    if (mesh) image.mesh = {static_cast<std::int32_t*>(mesh->mutable_data()), std::size_t(mesh->size())};
    FrameStats stats;
    {
        const py::gil_scoped_release nogil;
        stats = self.engine().render(view, image, settings);
    }
    // A render stopped by cancel_render() from another thread: its arrays are not an image.
    if (stats.cancelled) {
        throw Error(Error::Code::invalid_state, "dynrt.Engine.render: stopped by cancel_render() before it finished; "
                                                "the arrays hold no whole image");
    }
    return stats;
}

/// An image array of shape (height, width[, 3]) checked for render_into.
py::array image_array(py::handle value, const std::string& where, const char* name, const char* type,
                      int channels, int height, int width, bool writeable = true) {
    if (!py::isinstance<py::array>(value)) invalid(where, std::string(name) + " must be a numpy array");
    py::array a = py::reinterpret_borrow<py::array>(value);
    if (!a.dtype().equal(dtype(type))) {
        invalid(where, std::string(name) + " must have dtype " + type + ", got " + a.dtype().attr("name").cast<std::string>());
    }
    const bool shape_ok = channels ? (a.ndim() == 3 && a.shape(2) == channels) : a.ndim() == 2;
    if (!shape_ok || (height >= 0 && (a.shape(0) != height || a.shape(1) != width))) {
        invalid(where, std::string(name) + " must have shape " +
                           (height >= 0 ? "(" + std::to_string(height) + ", " + std::to_string(width)
                                        : std::string("(H, W")) +
                           (channels ? ", 3)" : ")"));
    }
    if (!(a.flags() & py::array::c_style)) invalid(where, std::string(name) + " must be C-contiguous");
    require_aligned(a, where, name);
    if (writeable && !a.writeable()) invalid(where, std::string(name) + " is read-only");
    return a;
}

/// A ray batch's arrays, checked and read in place.
struct RayBatch {
    py::array origins, directions, tmin, tmax;
    RayArrays arrays;
};

RayBatch ray_batch(py::handle origins, py::handle directions, py::handle tmin, py::handle tmax,
                   const std::string& where) {
    RayBatch b;
    b.origins = checked_array(origins, where, ArraySpec{"origins", dtype("float32"), 3, false});
    b.directions = checked_array(directions, where, ArraySpec{"directions", dtype("float32"), 3, false});
    if (rows(b.directions) != rows(b.origins)) {
        invalid(where, std::to_string(rows(b.origins)) + " origins but " + std::to_string(rows(b.directions)) +
                           " directions");
    }
    b.arrays.origins = floats(b.origins);
    b.arrays.directions = floats(b.directions);
    const auto limit = [&](py::handle value, const char* name, py::array& keep, std::span<const float>& per_ray,
                           float& all) {
        if (const std::optional<float> number = scalar(value)) {
            all = *number;
            return;
        }
        if (!py::isinstance<py::array>(value) && PyNumber_Check(value.ptr()) && !PyBool_Check(value.ptr())) {
            invalid(where, std::string(name) + " must be a number or a float32 (N,) array; " +
                               py::str(value).cast<std::string>().substr(0, 40) + " is not representable as a float");
        }
        keep = checked_array(value, where, ArraySpec{name, dtype("float32"), 0, false});
        if (rows(keep) != rows(b.origins)) {
            invalid(where, std::to_string(rows(b.origins)) + " rays but " + std::to_string(rows(keep)) + " " + name +
                               " values");
        }
        per_ray = floats(keep);
    };
    limit(tmin, "tmin", b.tmin, b.arrays.tmin, b.arrays.tmin_all);
    limit(tmax, "tmax", b.tmax, b.arrays.tmax, b.arrays.tmax_all);
    return b;
}

py::dict query_dict(const QueryStats& q) {
    py::dict d;
    d["rays"] = q.rays;
    d["hits"] = q.hits;
    d["packet_rays"] = q.packet_rays;
    d["single_rays"] = q.single_rays;
    d["ms"] = q.ms;
    d["mrays_per_s"] = q.mrays_per_s;
    return d;
}

/// `out` checked as a result array of `dtype` with `n` rows, or a new one.
py::array result_array(py::handle out, const py::dtype& type, const char* type_name, std::size_t n,
                       const char* name, const std::string& where) {
    if (out.is_none()) return py::array(type, std::vector<py::ssize_t>{py::ssize_t(n)});
    py::array a = checked_array(out, where, ArraySpec{name, type, 0, true, type_name});
    if (rows(a) != n) invalid(where, std::string(name) + " has " + std::to_string(rows(a)) + " rows for " + std::to_string(n) + " rays");
    return a;
}

/// intersect and occluded: the batch checked, the result array (of `Result` rows) made or
/// checked, `query` run with the GIL released; the results, with the batch's figures when
/// `stats`.
template <typename Result, typename Query>
py::object run_query(const PyEngine& self, const std::string& where, py::handle origins, py::handle directions,
                     py::handle tmin, py::handle tmax, py::handle out, bool stats, const py::dtype& type,
                     const char* type_name, Query&& query) {
    const RayBatch batch = ray_batch(origins, directions, tmin, tmax, where);
    py::array results = result_array(out, type, type_name, batch.arrays.size(), "out", where);
    const std::span<Result> rows(static_cast<Result*>(results.mutable_data()), batch.arrays.size());
    QueryStats q;
    {
        const py::gil_scoped_release nogil;
        q = query(self.engine(), batch.arrays, rows);
    }
    if (stats) return py::make_tuple(results, query_dict(q));
    return results;
}

constexpr float kInf = std::numeric_limits<float>::infinity();

}  // namespace

void bind_engine(py::module_& m) {
    m.attr("hit_dtype") = hit_dtype();

    py::class_<PyEngine, std::shared_ptr<PyEngine>> engine(m, "Engine", R"(The engine of a simulation loop.

Add meshes once, then every step change vertices (set_positions) or transforms (set_transform),
call update(), and render() a view or intersect() / occluded() a batch of rays. The thread-safety
rules of the C++ API hold: between two update() calls the engine is read-only, and render,
intersect and occluded may run from several threads at once (they release the GIL).)");
    engine.def(py::init([](int threads, float cost_ratio, int leaf_size, float cost_ratio_exploding,
                           double rebuild_threshold, bool compact_leaves, bool quantized_nodes,
                           std::size_t memory_budget) {
                   EngineOptions o;
                   o.threads = threads;
                   o.cost_ratio = cost_ratio;
                   o.leaf_size = leaf_size;
                   o.cost_ratio_exploding = cost_ratio_exploding;
                   o.rebuild_threshold = rebuild_threshold;
                   o.compact_leaves = compact_leaves;
                   o.quantized_nodes = quantized_nodes;
                   o.memory_budget = memory_budget;
                   return std::make_shared<PyEngine>(o);
               }),
               py::kw_only(), py::arg("threads") = 0, py::arg("cost_ratio") = 1.0f, py::arg("leaf_size") = 8,
               py::arg("cost_ratio_exploding") = 0.3f, py::arg("rebuild_threshold") = 0.3,
               py::arg("compact_leaves") = false, py::arg("quantized_nodes") = false,
               py::arg("memory_budget") = 0);

    engine.def("add_mesh", &PyEngine::add_mesh, py::arg("positions"), py::arg("indices"), py::kw_only(),
               py::arg("motion") = "automatic", py::arg("transform") = py::none(),
               py::arg("surface") = py::none(), py::arg("normals") = py::none(),
               py::arg("name") = "", py::arg("borrow") = false, py::arg("texcoords") = py::none(),
               R"(Adds a mesh and returns its id (an int). positions: float32 (V, 3); indices: integers
(T, 3). With borrow=True the engine reads `positions` in place from then on and keeps a
reference to it: write new positions into it and call set_positions(mesh, positions).
texcoords: (V, 2) texture coordinates (s right, t down the image), copied; needed by a
surface with a texture.)");
    engine.def("add_texture", &PyEngine::add_texture, py::arg("source"), py::kw_only(), py::arg("srgb") = true,
               py::arg("name") = "", py::arg("mime_type") = "",
               R"(Adds an image for surfaces to map (Surface(texture=id)) and returns its id (an int).
source: a path (str or os.PathLike; read at the first render that shows it, a warning then if it
cannot be read), an image file's bytes (bytes, bytearray, memoryview, a 1-D uint8 array; copied;
their format told from them unless mime_type says), or the texels themselves: a numpy array of
shape (H, W) or (H, W, C), C from 1 to 4 (grey, grey and alpha, RGB, RGBA; alpha unused), rows
from the image's top, dtype uint8 (0-255) or float32 (finite, >= 0; 1 is full), copied.
srgb: the texels are sRGB-encoded; float32 texels are usually linear: pass srgb=False.)");
    engine.def("set_positions", &PyEngine::set_positions, py::arg("mesh"), py::arg("positions"),
               py::arg("normals") = py::none());
    engine.def("set_transform", [](PyEngine& self, py::handle mesh, py::handle t) {
        const std::string where = "dynrt.Engine.set_transform";
        self.engine().set_transform(mesh_id(mesh, where), transform(t, where));
    }, py::arg("mesh"), py::arg("transform"));
    engine.def("set_surface", [](PyEngine& self, py::handle mesh, const Surface& s) {
        self.engine().set_surface(mesh_id(mesh, "dynrt.Engine.set_surface"), s);
    }, py::arg("mesh"), py::arg("surface"));
    engine.def("remove_mesh", &PyEngine::remove_mesh, py::arg("mesh"));
    engine.def("motion", [](const PyEngine& self, py::handle mesh) {
        return std::string(motion_name(self.engine().motion(mesh_id(mesh, "dynrt.Engine.motion"))));
    }, py::arg("mesh"));
    engine.def("borrows", &PyEngine::borrows, py::arg("mesh"),
               "Whether the engine holds the mesh's positions array (added with borrow=True).");
    engine.def_property_readonly("mesh_count", [](const PyEngine& self) { return self.engine().mesh_count(); });
    engine.def("memory_bytes", [](const PyEngine& self) { return self.engine().memory_bytes(); },
               "Heap bytes the engine holds for its meshes (Engine::memory_bytes in C++): back to the live "
               "meshes' share after remove_mesh and update(); the textures' decoded images once a "
               "render has read them.");
    engine.def("texture_figures", [](const PyEngine& self) {
        const TextureFigures t = self.engine().texture_figures();
        py::dict figures;
        figures["count"] = t.count;
        figures["bytes"] = t.bytes;
        figures["load_ms"] = t.load_ms;
        return figures;
    }, "The textures the renders hold, as a dict with the report's keys (README \"Report\", "
       "run.textures): count (readable textures), bytes (every MIP level; part of memory_bytes()) "
       "and load_ms (reading them, at the render that read them); zeros before any render reads "
       "one.");
    engine.def("__len__", [](const PyEngine& self) { return self.engine().mesh_count(); });

    engine.def("update", [](PyEngine& self) {
        FrameStats stats;
        {
            const py::gil_scoped_release nogil;
            stats = self.engine().update();
        }
        return report_dict(stats);
    }, "Brings every tree up to date; returns the step's report as a dict (README \"Report\").");

    engine.def("cancel_render", [](const PyEngine& self) { self.engine().cancel_render(); },
               "Stops the render running now in another thread, if one is: that render raises "
               "dynrt.InvalidState soon, and the next one traces every pixel. Callable from any thread.");
    engine.def("render_progress", [](const PyEngine& self) {
        const RenderProgress p = self.engine().render_progress();
        py::dict d;
        d["tracing"] = p.tracing;
        d["tiles_done"] = p.tiles_done;
        d["tiles_total"] = p.tiles_total;
        d["fraction"] = p.fraction();
        return d;
    }, "How far the render running now (in another thread) has come, as a dict: tracing (a "
       "render is running), tiles_done and tiles_total (each 16x16 tile once per sample per "
       "pixel) and fraction; the last render's between renders.");
    engine.def("render", [](const PyEngine& self, const View& view, int width, int height, bool depth, bool mesh,
                            bool report, py::handle lights, py::handle background, float ambient, bool reuse_pixels,
                            int max_depth, float cutoff, bool smooth_normals, int samples_per_pixel,
                            const std::string& filter, float aa_contrast, py::handle environment,
                            float environment_scale, int environment_lights) -> py::object {
        const std::string where = "dynrt.Engine.render";
        if (width < 1 || height < 1) invalid(where, "width and height must be >= 1");
        const RenderSettings settings =
            render_settings(lights, background, ambient, reuse_pixels, max_depth, cutoff, smooth_normals,
                            samples_per_pixel, filter, aa_contrast, environment, environment_scale,
                            environment_lights, where);
        py::array rgb(dtype("float32"), {py::ssize_t(height), py::ssize_t(width), py::ssize_t(3)});
        py::array depth_image, mesh_image;
        if (depth) depth_image = py::array(dtype("float32"), {py::ssize_t(height), py::ssize_t(width)});
        if (mesh) mesh_image = py::array(dtype("int32"), {py::ssize_t(height), py::ssize_t(width)});
        const FrameStats stats = render_arrays(self, view, rgb, depth ? &depth_image : nullptr,
                                               mesh ? &mesh_image : nullptr, settings);
        if (!depth && !mesh && !report) return rgb;
        py::list out;
        out.append(rgb);
        if (depth) out.append(depth_image);
        if (mesh) out.append(mesh_image);
        if (report) out.append(report_dict(stats));
        return py::tuple(out);
    }, py::arg("view"), py::arg("width"), py::arg("height"), py::kw_only(), py::arg("depth") = false,
       py::arg("mesh") = false, py::arg("report") = false, py::arg("lights") = py::none(),
       py::arg("background") = py::make_tuple(0.05f, 0.06f, 0.08f), py::arg("ambient") = 0.08f,
       py::arg("reuse_pixels") = true, py::arg("max_depth") = 5, py::arg("cutoff") = 1.0f / 256.0f,
       py::arg("smooth_normals") = true, py::arg("samples_per_pixel") = 1, py::arg("filter") = "blackman-harris",
       py::arg("aa_contrast") = 0.0f, py::arg("environment") = py::none(), py::arg("environment_scale") = 1.0f,
       py::arg("environment_lights") = 0,
       R"(Renders `view` at width x height: an (H, W, 3) float32 linear RGB array, or a tuple
(rgb, depth, mesh, report) of the parts asked for: depth (H, W) float32 (+inf on a miss),
mesh (H, W) int32 (the mesh id hit, -1 on a miss), report the frame's dict: the last
update's figures (refit_ms, rebuild_ms, ...) with the render's (primary_ms, shadow_ms,
shade_ms, secondary_ms, rays); its total_ms covers that update and this render.)");

    engine.def("render_into", [](const PyEngine& self, const View& view, py::handle rgb, py::handle depth,
                                 py::handle mesh, py::handle lights, py::handle background, float ambient,
                                 bool reuse_pixels, int max_depth, float cutoff, bool smooth_normals,
                                 int samples_per_pixel, const std::string& filter, float aa_contrast,
                                 py::handle environment, float environment_scale, int environment_lights) {
        const std::string where = "dynrt.Engine.render_into";
        py::array rgb_image = image_array(rgb, where, "rgb", "float32", 3, -1, -1);
        const int height = int(rgb_image.shape(0)), width = int(rgb_image.shape(1));
        py::array depth_image, mesh_image;
        if (!depth.is_none()) depth_image = image_array(depth, where, "depth", "float32", 0, height, width);
        if (!mesh.is_none()) mesh_image = image_array(mesh, where, "mesh", "int32", 0, height, width);
        const RenderSettings settings =
            render_settings(lights, background, ambient, reuse_pixels, max_depth, cutoff, smooth_normals,
                            samples_per_pixel, filter, aa_contrast, environment, environment_scale,
                            environment_lights, where);
        const FrameStats stats = render_arrays(self, view, rgb_image, depth_image ? &depth_image : nullptr,
                                               mesh_image ? &mesh_image : nullptr, settings);
        return report_dict(stats);
    }, py::arg("view"), py::arg("rgb"), py::kw_only(), py::arg("depth") = py::none(), py::arg("mesh") = py::none(),
       py::arg("lights") = py::none(), py::arg("background") = py::make_tuple(0.05f, 0.06f, 0.08f),
       py::arg("ambient") = 0.08f, py::arg("reuse_pixels") = true, py::arg("max_depth") = 5,
       py::arg("cutoff") = 1.0f / 256.0f, py::arg("smooth_normals") = true, py::arg("samples_per_pixel") = 1,
       py::arg("filter") = "blackman-harris", py::arg("aa_contrast") = 0.0f, py::arg("environment") = py::none(),
       py::arg("environment_scale") = 1.0f, py::arg("environment_lights") = 0,
       "Renders into arrays the caller owns (rgb (H, W, 3) float32; depth, mesh (H, W)); returns the report.");

    engine.def("intersect", [](const PyEngine& self, py::handle origins, py::handle directions, py::handle tmin,
                               py::handle tmax, py::handle out, bool stats) {
        return run_query<RayHit>(self, "dynrt.Engine.intersect", origins, directions, tmin, tmax, out, stats,
                                 hit_dtype(), "dynrt.hit_dtype",
                                 [](const Engine& e, const RayArrays& rays, std::span<RayHit> hits) {
                                     return e.intersect(rays, hits);
                                 });
    }, py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f, py::arg("tmax") = kInf, py::kw_only(),
       py::arg("out") = py::none(), py::arg("stats") = false,
       R"(Closest hit of every ray: a structured array of dynrt.hit_dtype (t, mesh, triangle, u, v;
t = inf, mesh = triangle = -1 on a miss). origins, directions: float32 (N, 3), read in place;
tmin, tmax: numbers or float32 (N,). out: a hit_dtype (N,) array to write into. stats=True
also returns the batch's figures.)");

    engine.def("occluded", [](const PyEngine& self, py::handle origins, py::handle directions, py::handle tmin,
                              py::handle tmax, py::handle out, bool stats) {
        return run_query<std::uint8_t>(self, "dynrt.Engine.occluded", origins, directions, tmin, tmax, out, stats,
                                       dtype("bool"), "bool",
                                       [](const Engine& e, const RayArrays& rays, std::span<std::uint8_t> flags) {
                                           return e.occluded(rays, flags);
                                       });
    }, py::arg("origins"), py::arg("directions"), py::arg("tmin") = 0.0f, py::arg("tmax") = kInf, py::kw_only(),
       py::arg("out") = py::none(), py::arg("stats") = false,
       "Whether anything is hit within [tmin, tmax] of every ray: a bool (N,) array (out: one to write into).");

    m.def("save_image", [](py::handle path, py::handle rgb) {
        const py::array image = image_array(rgb, "dynrt.save_image", "rgb", "float32", 3, -1, -1, false);
        // Any path-like (str, pathlib.Path), as open() takes.
        const std::string file = py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
        save_image(file, int(image.shape(1)), int(image.shape(0)), floats(image));
    }, py::arg("path"), py::arg("rgb"),
       "Writes an (H, W, 3) float32 linear RGB array: .png, .jpg, .bmp, .tga (sRGB, 8-bit) or .hdr.");
}

}  // namespace dynrt::python
