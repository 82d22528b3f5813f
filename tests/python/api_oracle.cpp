// dynrt_python_api_oracle: the C++ library API's answers for the Python tests
// (tests/python/test_matches_cpp_api.py). The Python module must give the same results bit
// for bit on the same meshes and rays; this program computes them through dynrt::Engine as an
// embedding C++ program would, with the rays as dynrt::Ray structs (span<const Ray>), so the
// module's path (numpy arrays read in place as RayArrays) is checked against the Ray path.
//
//   dynrt_python_api_oracle FOLDER
//
// Input, written by the Python test into FOLDER. Every .f32 / .u32 / .i32 file is raw
// little-endian data as numpy's tofile() writes it (C order, no header):
//
//   meshes.txt              one line per mesh, in add_mesh order: NAME MOTION
//                           (MOTION as motion_name(): automatic, static, rigid, deformable,
//                           exploding)
//   NAME.positions0.f32     its vertices, (V, 3) float32
//   NAME.indices.u32        its triangles, (T, 3) uint32
//   NAME.transform0.f32     optional: its object-to-world transform, (4, 4) float32 with rows
//                           first (numpy's M[row, column]); the identity when absent
//   NAME.surface.f32        optional: its Surface, 16 float32: diffuse xyz, specular xyz,
//                           shininess, reflectance xyz, transmittance xyz, ior, 2 unused;
//                           the default Surface when absent
//   NAME.positions1.f32     optional: set_positions(mesh, these) before step 1
//   NAME.transform1.f32     optional: set_transform(mesh, this) before step 1
//   rays.txt                one ray set name per line
//   SET.origins.f32         (N, 3) float32
//   SET.directions.f32      (N, 3) float32
//   SET.tmin.f32            (N,) float32
//   SET.tmax.f32            (N,) float32
//   view.f32                10 float32: eye xyz, target xyz, up xyz, vertical fov in degrees
//   image.i32               2 int32: width, height
//   settings.f32            RenderSettings for a second render: background xyz, ambient,
//                           max_depth, cutoff, smooth_normals (0 or 1), reuse_pixels (0 or 1),
//                           then x, y, z, intensity per light (8 + 4 L float32)
//
// Each mesh is added with Ownership::copy, its motion and surface, name NAME. Step 0
// is update() after adding them all; step 1 is update() after the set_positions and
// set_transform calls above. It writes into FOLDER
//
//   ids.u32                 the MeshId value add_mesh returned for each mesh, in order
//
// and after each step S:
//
//   stepS.SET.hits.bin      intersect(): N dynrt::RayHit structs (20 bytes each: t float32,
//                           mesh uint32, primitive uint32, u float32, v float32)
//   stepS.SET.occluded.u8   occluded(): N bytes, 0 or 1
//   stepS.rgb.f32           render() with default RenderSettings: (height, width, 3) float32
//   stepS.depth.f32         (height, width) float32
//   stepS.mesh.i32          (height, width) int32
//   stepS.rgb2.f32          render() with settings.f32's RenderSettings, rgb only
//
// Exit status 0 on success; 1 with a message on stderr for a missing file or a dynrt::Error.

#include <dynrt/dynrt.h>

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

template <typename T>
std::vector<T> read_raw(const fs::path& path) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) throw std::runtime_error("cannot read " + path.string());
    const std::streamsize bytes = in.tellg();
    if (bytes % std::streamsize(sizeof(T)) != 0) {
        throw std::runtime_error(path.string() + ": " + std::to_string(bytes) + " bytes, not a multiple of " +
                                 std::to_string(sizeof(T)));
    }
    std::vector<T> values(std::size_t(bytes) / sizeof(T));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(values.data()), bytes);
    if (!in) throw std::runtime_error("cannot read " + path.string());
    return values;
}

template <typename T>
void write_raw(const fs::path& path, const std::vector<T>& values) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(T)));
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::vector<std::string> read_lines(const fs::path& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path.string());
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) {
        if (!line.empty()) lines.push_back(line);
    }
    return lines;
}

dynrt::Motion motion_named(const std::string& name) {
    for (const dynrt::Motion m : {dynrt::Motion::automatic, dynrt::Motion::static_, dynrt::Motion::rigid,
                                  dynrt::Motion::deformable, dynrt::Motion::exploding}) {
        if (name == dynrt::motion_name(m)) return m;
    }
    throw std::runtime_error("unknown motion '" + name + "'");
}

/// A (4, 4) float32 file, rows first, as the API's column-major Transform.
dynrt::Transform read_transform(const fs::path& path) {
    const std::vector<float> rows_first = read_raw<float>(path);
    if (rows_first.size() != 16) throw std::runtime_error(path.string() + ": not 16 floats");
    float column_major[16];
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 4; ++column) {
            column_major[column * 4 + row] = rows_first[std::size_t(row * 4 + column)];
        }
    }
    return dynrt::Transform::from_column_major(column_major);
}

/// A Surface from its 16 floats (see the file format above).
dynrt::Surface read_surface(const fs::path& path) {
    const std::vector<float> v = read_raw<float>(path);
    if (v.size() != 16) throw std::runtime_error(path.string() + ": not 16 floats");
    return dynrt::Surface{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, v[6],
                          {v[7], v[8], v[9]}, {v[10], v[11], v[12]}, v[13]};
}

/// settings.f32 (see the file format above).
dynrt::RenderSettings read_settings(const fs::path& path) {
    const std::vector<float> v = read_raw<float>(path);
    if (v.size() < 8 || (v.size() - 8) % 4 != 0) {
        throw std::runtime_error(path.string() + ": not 8 + 4 L floats");
    }
    dynrt::RenderSettings s;
    s.background = {v[0], v[1], v[2]};
    s.ambient = v[3];
    s.max_depth = int(v[4]);
    s.cutoff = v[5];
    s.smooth_normals = v[6] != 0.0f;
    s.reuse_pixels = v[7] != 0.0f;
    for (std::size_t i = 8; i < v.size(); i += 4) {
        s.lights.push_back(dynrt::Light{{v[i], v[i + 1], v[i + 2]}, v[i + 3]});
    }
    return s;
}

struct MeshFiles {
    std::string name;
    dynrt::Motion motion = dynrt::Motion::automatic;
    std::vector<float> positions0, positions1;
    std::vector<std::uint32_t> indices;
    bool has_transform1 = false;
    dynrt::Transform transform0, transform1;
    dynrt::Surface surface;
};

struct RaySet {
    std::string name;
    std::vector<dynrt::Ray> rays;
};

RaySet read_rays(const fs::path& folder, const std::string& name) {
    const std::vector<float> origins = read_raw<float>(folder / (name + ".origins.f32"));
    const std::vector<float> directions = read_raw<float>(folder / (name + ".directions.f32"));
    const std::vector<float> tmin = read_raw<float>(folder / (name + ".tmin.f32"));
    const std::vector<float> tmax = read_raw<float>(folder / (name + ".tmax.f32"));
    const std::size_t n = origins.size() / 3;
    if (origins.size() != 3 * n || directions.size() != 3 * n || tmin.size() != n || tmax.size() != n) {
        throw std::runtime_error("ray set '" + name + "': array sizes disagree");
    }
    RaySet set{name, std::vector<dynrt::Ray>(n)};
    for (std::size_t i = 0; i < n; ++i) {
        set.rays[i].origin = {origins[3 * i], origins[3 * i + 1], origins[3 * i + 2]};
        set.rays[i].direction = {directions[3 * i], directions[3 * i + 1], directions[3 * i + 2]};
        set.rays[i].tmin = tmin[i];
        set.rays[i].tmax = tmax[i];
    }
    return set;
}

/// Every query of one step, written as stepS.*.
void run_queries(const dynrt::Engine& engine, const std::vector<RaySet>& sets, const dynrt::View& view,
                 int width, int height, const dynrt::RenderSettings& settings, const fs::path& folder, int step) {
    const std::string prefix = "step" + std::to_string(step) + ".";
    for (const RaySet& set : sets) {
        std::vector<dynrt::RayHit> hits(set.rays.size());
        engine.intersect(std::span<const dynrt::Ray>(set.rays), std::span<dynrt::RayHit>(hits));
        write_raw(folder / (prefix + set.name + ".hits.bin"), hits);
        std::vector<std::uint8_t> occluded(set.rays.size());
        engine.occluded(std::span<const dynrt::Ray>(set.rays), std::span<std::uint8_t>(occluded));
        write_raw(folder / (prefix + set.name + ".occluded.u8"), occluded);
    }
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    std::vector<float> rgb(3 * pixels), depth(pixels);
    std::vector<std::int32_t> mesh(pixels);
    engine.render(view, dynrt::ImageView{width, height, rgb, depth, mesh});
    write_raw(folder / (prefix + "rgb.f32"), rgb);
    write_raw(folder / (prefix + "depth.f32"), depth);
    write_raw(folder / (prefix + "mesh.i32"), mesh);
    engine.render(view, dynrt::ImageView{width, height, rgb}, settings);
    write_raw(folder / (prefix + "rgb2.f32"), rgb);
}

int run(const fs::path& folder) {
    std::vector<MeshFiles> meshes;
    for (const std::string& line : read_lines(folder / "meshes.txt")) {
        MeshFiles m;
        const std::size_t space = line.find(' ');
        if (space == std::string::npos) throw std::runtime_error("meshes.txt: '" + line + "' is not NAME MOTION");
        m.name = line.substr(0, space);
        m.motion = motion_named(line.substr(space + 1));
        m.positions0 = read_raw<float>(folder / (m.name + ".positions0.f32"));
        m.indices = read_raw<std::uint32_t>(folder / (m.name + ".indices.u32"));
        if (fs::exists(folder / (m.name + ".positions1.f32"))) {
            m.positions1 = read_raw<float>(folder / (m.name + ".positions1.f32"));
        }
        if (fs::exists(folder / (m.name + ".transform0.f32"))) {
            m.transform0 = read_transform(folder / (m.name + ".transform0.f32"));
        }
        if (fs::exists(folder / (m.name + ".surface.f32"))) {
            m.surface = read_surface(folder / (m.name + ".surface.f32"));
        }
        if (fs::exists(folder / (m.name + ".transform1.f32"))) {
            m.transform1 = read_transform(folder / (m.name + ".transform1.f32"));
            m.has_transform1 = true;
        }
        meshes.push_back(std::move(m));
    }
    std::vector<RaySet> sets;
    for (const std::string& name : read_lines(folder / "rays.txt")) sets.push_back(read_rays(folder, name));
    const std::vector<float> v = read_raw<float>(folder / "view.f32");
    const std::vector<std::int32_t> size = read_raw<std::int32_t>(folder / "image.i32");
    if (v.size() != 10 || size.size() != 2) throw std::runtime_error("view.f32 or image.i32 has the wrong size");
    const dynrt::View view{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}, v[9]};
    const dynrt::RenderSettings settings = read_settings(folder / "settings.f32");

    dynrt::Engine engine;
    std::vector<dynrt::MeshId> ids;
    std::vector<std::uint32_t> id_values;
    for (const MeshFiles& m : meshes) {
        dynrt::MeshDesc desc;
        desc.name = m.name;
        desc.positions = m.positions0;
        desc.indices = m.indices;
        desc.motion = m.motion;
        desc.transform = m.transform0;
        desc.surface = m.surface;
        ids.push_back(engine.add_mesh(desc));
        id_values.push_back(ids.back().value);
    }
    write_raw(folder / "ids.u32", id_values);
    engine.update();
    run_queries(engine, sets, view, size[0], size[1], settings, folder, 0);

    for (std::size_t i = 0; i < meshes.size(); ++i) {
        if (!meshes[i].positions1.empty()) engine.set_positions(ids[i], meshes[i].positions1);
        if (meshes[i].has_transform1) engine.set_transform(ids[i], meshes[i].transform1);
    }
    engine.update();
    run_queries(engine, sets, view, size[0], size[1], settings, folder, 1);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: dynrt_python_api_oracle FOLDER (see tests/python/api_oracle.cpp)\n");
        return 2;
    }
    try {
        return run(argv[1]);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dynrt_python_api_oracle: %s\n", e.what());
        return 1;
    }
}
