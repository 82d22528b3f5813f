// The assimp loader (engine/src/loaders/assimp_loader.cpp): OBJ and PLY files written here load
// the same triangles as an equivalent glTF (compared triangle by triangle and by the exact
// reference's hits), a Collada node animation and a skinned, animated glTF read through assimp
// pose as dynrt's glTF loader poses the same animation, bad files are refused with one line
// naming the file, and load_scene tells a file's kind by extension and content.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/reference/reference_tracer.h"
#include "dynrt/scene/node.h"
#include "dynrt/scene/scene_error.h"

#include "gltf_test_file.h"
#include "shell_command.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <unistd.h>
#include <vector>

namespace dynrt {
namespace assimp_loader_test {

using json = nlohmann::json;
using test::GltfTestFile;
using WorldTriangle = std::array<glm::dvec3, 3>;

/// Writes `text` to `<TempDir>/dynrt_<pid>_<name>` and returns the path.
std::filesystem::path write_file(const std::string& name, const std::string& text) {
    const std::filesystem::path path =
        std::filesystem::path(::testing::TempDir()) / ("dynrt_" + std::to_string(::getpid()) + "_" + name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

/// Every triangle of `scene` posed at `frame`, in world space.
std::vector<WorldTriangle> world_triangles(const Scene& scene, int frame) {
    anim::PosedScene posed;
    anim::pose_scene(scene, frame, posed);
    std::vector<WorldTriangle> out;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const std::vector<glm::vec3>& p = posed.objects[i].positions;
        for (const glm::uvec3& t : scene.objects[i].mesh.triangles) {
            out.push_back({glm::dvec3(p[t.x]), glm::dvec3(p[t.y]), glm::dvec3(p[t.z])});
        }
    }
    return out;
}

/// The largest distance between a vertex of a triangle of `a` and the same vertex of its
/// closest triangle in `b` (same winding, any first vertex), and the other way round: 0 when
/// both list the same triangles, whatever their order and indexing. The search for the closest
/// goes outward from the nearest centroid x: the matched vertices' largest distance is at
/// least the centroids' distance, so candidates further away in x cannot be closer.
double triangle_set_distance(const std::vector<WorldTriangle>& a, const std::vector<WorldTriangle>& b) {
    const auto centroid_x = [](const WorldTriangle& t) { return (t[0].x + t[1].x + t[2].x) / 3.0; };
    const auto one_way = [&](const std::vector<WorldTriangle>& from, std::vector<WorldTriangle> to) {
        std::sort(to.begin(), to.end(),
                  [&](const WorldTriangle& p, const WorldTriangle& q) { return centroid_x(p) < centroid_x(q); });
        std::vector<double> xs;
        for (const WorldTriangle& u : to) xs.push_back(centroid_x(u));
        double worst = 0.0;
        for (const WorldTriangle& t : from) {
            const double x = centroid_x(t);
            double best = INFINITY;
            const auto distance = [&](const WorldTriangle& u) {
                for (int r = 0; r < 3; ++r) {
                    double d = 0.0;
                    for (int k = 0; k < 3; ++k) d = std::max(d, glm::distance(t[k], u[(k + r) % 3]));
                    best = std::min(best, d);
                }
            };
            const std::size_t start = std::size_t(std::lower_bound(xs.begin(), xs.end(), x) - xs.begin());
            for (std::size_t i = start; i < to.size() && xs[i] - x <= best; ++i) distance(to[i]);
            for (std::size_t i = start; i > 0 && x - xs[i - 1] <= best; --i) distance(to[i - 1]);
            worst = std::max(worst, best);
        }
        return worst;
    };
    return std::max(one_way(a, b), one_way(b, a));
}

/// Rays from `eye` through a 24 x 24 grid 0.4 radians wide around the scene's centre: both scenes must hit at the
/// same distance (the same object when `same_objects`), or both miss, wherever the reference
/// calls the answer determined in both.
void expect_same_hits(const Scene& a, const Scene& b, const glm::dvec3& eye, const glm::dvec3& centre,
                      bool same_objects = true) {
    anim::PosedScene posed_a, posed_b;
    anim::pose_scene(a, 0, posed_a);
    anim::pose_scene(b, 0, posed_b);
    const reference::ReferenceTracer tracer_a(a, posed_a), tracer_b(b, posed_b);
    const glm::dvec3 forward = glm::normalize(centre - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0.0, 1.0, 0.0)));
    const glm::dvec3 up = glm::cross(right, forward);
    int hits = 0, compared = 0;
    for (int y = 0; y < 24; ++y) {
        for (int x = 0; x < 24; ++x) {
            reference::RayD ray;
            ray.org = eye;
            ray.dir = glm::normalize(forward + (x - 11.5) / 60.0 * right + (y - 11.5) / 60.0 * up);
            const reference::ReferenceHit ha = tracer_a.closest(ray), hb = tracer_b.closest(ray);
            if (ha.ambiguity != reference::Ambiguity::kNone || hb.ambiguity != reference::Ambiguity::kNone) continue;
            ++compared;
            ASSERT_EQ(ha.is_hit(), hb.is_hit()) << "ray " << x << ", " << y;
            if (!ha.is_hit()) continue;
            ++hits;
            if (same_objects) {
                EXPECT_EQ(ha.object, hb.object) << "ray " << x << ", " << y;
            }
            EXPECT_NEAR(ha.t, hb.t, 1e-9 * ha.t) << "ray " << x << ", " << y;
        }
    }
    EXPECT_GT(hits, 100);
    EXPECT_GT(compared, 500);
}

/// Expects `load` to throw SceneError whose message contains every one of `parts`.
template <class Load>
void expect_scene_error(Load load, std::initializer_list<std::string> parts) {
    try {
        load();
        FAIL() << "no SceneError";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        for (const std::string& part : parts) EXPECT_NE(what.find(part), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

// A unit cube of six quads (outward winding) and a triangle beside it, as OBJ objects and as
// glTF nodes. assimp fans a convex quad from its first corner: (a, b, c), (a, c, d).
const std::vector<float> kCube = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
const std::vector<std::array<int, 4>> kCubeQuads = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                    {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
const std::vector<float> kWedge = {2, 0, 0, 3, 0, 0.5f, 2.5f, 1.5f, 0.25f};

std::string obj_text() {
    std::string text = "# written by assimp_loader_test\no cube\n";
    for (std::size_t v = 0; v < kCube.size(); v += 3) {
        text += "v " + std::to_string(kCube[v]) + " " + std::to_string(kCube[v + 1]) + " " + std::to_string(kCube[v + 2]) + "\n";
    }
    for (const auto& q : kCubeQuads) {
        text += "f " + std::to_string(q[0] + 1) + " " + std::to_string(q[1] + 1) + " " + std::to_string(q[2] + 1) + " " +
                std::to_string(q[3] + 1) + "\n";
    }
    text += "o wedge\nv 2 0 0\nv 3 0 0.5\nv 2.5 1.5 0.25\nf 9 10 11\n";
    return text;
}

/// The cube as a glTF mesh of indexed triangles (each of kCubeQuads split in two, as the OBJ's
/// faces are): its mesh index in `f`.
int add_indexed_cube(GltfTestFile& f) {
    std::vector<std::uint32_t> indices;
    for (const auto& q : kCubeQuads) {
        for (const int i : {q[0], q[1], q[2], q[0], q[2], q[3]}) indices.push_back(std::uint32_t(i));
    }
    const int cube = f.add_mesh(kCube, json::object(), nullptr, "cube");
    f.doc()["meshes"][cube]["primitives"][0]["indices"] = f.add_accessor(indices, "SCALAR", test::kGltfUnsignedInt);
    return cube;
}

/// The cube and the wedge as a glTF file: two root nodes, indexed triangles.
std::filesystem::path equivalent_gltf(const std::string& name) {
    GltfTestFile f;
    const int cube = add_indexed_cube(f);
    f.add_node({{"name", "cube"}, {"mesh", cube}});
    f.add_node({{"name", "wedge"}, {"mesh", f.add_mesh(kWedge, json::object(), nullptr, "wedge")}});
    return f.write(name);
}

TEST(AssimpLoader, ObjLoadsTheTrianglesOfTheEquivalentGltf) {
    const Scene obj = load_scene(write_file("cube.obj", obj_text()).string());
    const Scene gltf = load_gltf(equivalent_gltf("cube_for_obj.gltf"));
    ASSERT_EQ(obj.objects.size(), 2u);
    EXPECT_EQ(obj.objects[0].mesh.triangles.size(), 12u);
    // JoinIdenticalVertices: the cube's corners are shared, so its normals are smooth as glTF's.
    EXPECT_EQ(obj.objects[0].mesh.positions.size(), 8u);
    EXPECT_EQ(obj.triangle_count(), gltf.triangle_count());
    EXPECT_EQ(triangle_set_distance(world_triangles(obj, 0), world_triangles(gltf, 0)), 0.0);
    expect_same_hits(obj, gltf, {4.0, 3.0, 5.0}, {1.5, 0.5, 0.5});
    expect_same_hits(obj, gltf, {-3.0, -2.0, -4.0}, {1.5, 0.5, 0.5});
}

std::string ply_header(const std::string& format, int vertices, int faces) {
    return "ply\nformat " + format + " 1.0\ncomment written by assimp_loader_test\nelement vertex " +
           std::to_string(vertices) + "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
           std::to_string(faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
}

/// The cube and the wedge as one PLY mesh (PLY has no objects), ASCII or binary.
std::string ply_text(bool binary) {
    const std::size_t vertices = (kCube.size() + kWedge.size()) / 3;
    std::string text = ply_header(binary ? "binary_little_endian" : "ascii", int(vertices), int(kCubeQuads.size() + 1));
    const auto put = [&](auto value) {
        text.append(reinterpret_cast<const char*>(&value), sizeof value);
    };
    for (const std::vector<float>* part : {&kCube, &kWedge}) {
        for (std::size_t v = 0; v < part->size(); v += 3) {
            if (binary) {
                for (int k = 0; k < 3; ++k) put((*part)[v + std::size_t(k)]);
            } else {
                text += std::to_string((*part)[v]) + " " + std::to_string((*part)[v + 1]) + " " +
                        std::to_string((*part)[v + 2]) + "\n";
            }
        }
    }
    std::vector<std::vector<int>> faces;
    for (const auto& q : kCubeQuads) faces.push_back({q.begin(), q.end()});
    faces.push_back({8, 9, 10});
    for (const std::vector<int>& face : faces) {
        if (binary) {
            put(std::uint8_t(face.size()));
            for (const int i : face) put(std::int32_t(i));
        } else {
            text += std::to_string(face.size());
            for (const int i : face) text += " " + std::to_string(i);
            text += "\n";
        }
    }
    return text;
}

TEST(AssimpLoader, PlyAsciiAndBinaryLoadTheTrianglesOfTheEquivalentGltf) {
    const Scene gltf = load_gltf(equivalent_gltf("cube_for_ply.gltf"));
    for (const bool binary : {false, true}) {
        SCOPED_TRACE(binary ? "binary" : "ascii");
        const Scene ply = load_scene(write_file(binary ? "binary.ply" : "ascii.ply", ply_text(binary)).string());
        EXPECT_EQ(ply.triangle_count(), gltf.triangle_count());
        EXPECT_EQ(triangle_set_distance(world_triangles(ply, 0), world_triangles(gltf, 0)), 0.0);
        // PLY has one mesh where the glTF has two objects.
        expect_same_hits(ply, gltf, {4.0, 3.0, 5.0}, {1.5, 0.5, 0.5}, false);
    }
}

// tests/data/cube_and_wedge.fbx is the OBJ above converted by assimp's FBX exporter (ASCII FBX
// 7.5, kept as a text fixture: the command is in its first lines).
TEST(AssimpLoader, FbxLoadsTheTrianglesOfTheEquivalentGltf) {
    const Scene fbx = load_scene(std::string(DYNRT_SOURCE_DIR) + "/tests/data/cube_and_wedge.fbx");
    const Scene gltf = load_gltf(equivalent_gltf("cube_for_fbx.gltf"));
    ASSERT_EQ(fbx.objects.size(), 2u);
    EXPECT_EQ(fbx.triangle_count(), gltf.triangle_count());
    EXPECT_EQ(triangle_set_distance(world_triangles(fbx, 0), world_triangles(gltf, 0)), 0.0);
    expect_same_hits(fbx, gltf, {4.0, 3.0, 5.0}, {1.5, 0.5, 0.5});
}

// ---- Animation ------------------------------------------------------------------------------

/// One key of the test animation: translation, rotation (angle about an axis), scale.
struct TrsKey {
    double time_s;
    glm::dvec3 translation;
    double angle_rad;
    glm::dvec3 axis;
    glm::dvec3 scale;

    glm::dquat rotation() const { return glm::angleAxis(angle_rad, glm::normalize(axis)); }
    glm::dmat4 matrix() const {
        const glm::dquat q = rotation();
        return trs_matrix(translation, glm::dvec4(q.x, q.y, q.z, q.w), scale);
    }
};

const std::vector<TrsKey> kKeys = {
    {0.0, {0.0, 0.0, 0.0}, 0.0, {0.0, 1.0, 0.0}, {1.0, 1.0, 1.0}},
    {1.0, {1.0, 2.0, 0.0}, M_PI / 2.0, {0.0, 1.0, 0.0}, {1.0, 2.0, 1.0}},
    {2.0, {0.0, 0.0, 3.0}, 2.0 * M_PI / 3.0, {1.0, 1.0, 0.0}, {0.5, 0.5, 0.5}},
};

/// The parent's fixed matrix: translation (5, 0, 0), uniform scale 2.
const glm::dmat4 kHolder = trs_matrix({5.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 1.0}, glm::dvec3(2.0));

/// `m` as Collada writes a matrix: 16 numbers, row by row.
std::string collada_matrix(const glm::dmat4& m) {
    std::string out;
    char number[32];
    for (int row = 0; row < 4; ++row) {
        for (int column = 0; column < 4; ++column) {
            std::snprintf(number, sizeof number, "%.17g ", m[column][row]);
            out += number;
        }
    }
    return out;
}

/// The cube hung on node "box" under node "holder" (kHolder), "box" animated by kKeys as a
/// matrix channel, linear, in Collada 1.4.1; a camera "view" at (2, 3, 10) looking down -Z
/// (yfov 45 degrees, aspect 1.5) and a point light "lamp" at (-4, 6, 2), colour (1, 0.5, 0.25).
std::string collada_text() {
    std::string positions, triangles, times, matrices, interpolations;
    for (const float x : kCube) positions += std::to_string(x) + " ";
    for (const auto& q : kCubeQuads) {
        for (const int i : {q[0], q[1], q[2], q[0], q[2], q[3]}) triangles += std::to_string(i) + " ";
    }
    for (const TrsKey& key : kKeys) {
        times += std::to_string(key.time_s) + " ";
        matrices += collada_matrix(key.matrix());
        interpolations += "LINEAR ";
    }
    const std::string keys = std::to_string(kKeys.size());
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="cube-mesh" name="cube">
      <mesh>
        <source id="cube-positions">
          <float_array id="cube-positions-array" count="24">)" + positions + R"(</float_array>
          <technique_common>
            <accessor source="#cube-positions-array" count="8" stride="3">
              <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
            </accessor>
          </technique_common>
        </source>
        <vertices id="cube-vertices"><input semantic="POSITION" source="#cube-positions"/></vertices>
        <triangles count="12">
          <input semantic="VERTEX" source="#cube-vertices" offset="0"/>
          <p>)" + triangles + R"(</p>
        </triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_cameras>
    <camera id="view-camera" name="view">
      <optics><technique_common><perspective>
        <yfov>45</yfov><aspect_ratio>1.5</aspect_ratio><znear>0.1</znear><zfar>100</zfar>
      </perspective></technique_common></optics>
    </camera>
  </library_cameras>
  <library_lights>
    <light id="lamp-light" name="lamp"><technique_common><point><color>1 0.5 0.25</color></point></technique_common></light>
  </library_lights>
  <library_animations>
    <animation id="move" name="move">
      <source id="move-input">
        <float_array id="move-input-array" count=")" + keys + R"(">)" + times + R"(</float_array>
        <technique_common>
          <accessor source="#move-input-array" count=")" + keys + R"(" stride="1"><param name="TIME" type="float"/></accessor>
        </technique_common>
      </source>
      <source id="move-output">
        <float_array id="move-output-array" count=")" + std::to_string(16 * kKeys.size()) + R"(">)" + matrices + R"(</float_array>
        <technique_common>
          <accessor source="#move-output-array" count=")" + keys + R"(" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor>
        </technique_common>
      </source>
      <source id="move-interpolation">
        <Name_array id="move-interpolation-array" count=")" + keys + R"(">)" + interpolations + R"(</Name_array>
        <technique_common>
          <accessor source="#move-interpolation-array" count=")" + keys + R"(" stride="1"><param name="INTERPOLATION" type="name"/></accessor>
        </technique_common>
      </source>
      <sampler id="move-sampler">
        <input semantic="INPUT" source="#move-input"/>
        <input semantic="OUTPUT" source="#move-output"/>
        <input semantic="INTERPOLATION" source="#move-interpolation"/>
      </sampler>
      <channel source="#move-sampler" target="box/transform"/>
    </animation>
  </library_animations>
  <library_visual_scenes>
    <visual_scene id="scene" name="scene">
      <node id="holder" name="holder" type="NODE">
        <matrix sid="transform">)" + collada_matrix(kHolder) + R"(</matrix>
        <node id="box" name="box" type="NODE">
          <matrix sid="transform">)" + collada_matrix(kKeys[0].matrix()) + R"(</matrix>
          <instance_geometry url="#cube-mesh"/>
        </node>
      </node>
      <node id="view" name="view" type="NODE">
        <matrix sid="transform">1 0 0 2 0 1 0 3 0 0 1 10 0 0 0 1</matrix>
        <instance_camera url="#view-camera"/>
      </node>
      <node id="lamp" name="lamp" type="NODE">
        <matrix sid="transform">1 0 0 -4 0 1 0 6 0 0 1 2 0 0 0 1</matrix>
        <instance_light url="#lamp-light"/>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

/// The same scene and animation in glTF: translation, rotation and scale channels, linear.
std::filesystem::path animated_gltf() {
    GltfTestFile f;
    const int cube = add_indexed_cube(f);
    json holder_matrix = json::array();
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) holder_matrix.push_back(kHolder[c][r]);
    }
    const int holder = f.add_node({{"name", "holder"}, {"matrix", holder_matrix}});
    const int box = f.add_node({{"name", "box"}, {"mesh", cube}}, false);
    f.add_child(holder, box);
    GltfTestFile::Channel translation{box, "translation", {}, {}}, rotation{box, "rotation", {}, {}},
        scale{box, "scale", {}, {}};
    for (const TrsKey& key : kKeys) {
        for (GltfTestFile::Channel* c : {&translation, &rotation, &scale}) c->times.push_back(float(key.time_s));
        const glm::dquat q = key.rotation();
        translation.values.insert(translation.values.end(),
                                  {float(key.translation.x), float(key.translation.y), float(key.translation.z)});
        rotation.values.insert(rotation.values.end(), {float(q.x), float(q.y), float(q.z), float(q.w)});
        scale.values.insert(scale.values.end(), {float(key.scale.x), float(key.scale.y), float(key.scale.z)});
    }
    f.add_animation("move", {translation, rotation, scale});
    return f.write("animated_cube.gltf");
}

TEST(AssimpLoader, ColladaNodeAnimationPosesAsTheSameGltfAnimation) {
    const Scene dae = load_scene(write_file("animated_cube.dae", collada_text()).string());
    const Scene gltf = load_gltf(animated_gltf());
    ASSERT_EQ(dae.clips.size(), 1u);
    EXPECT_EQ(dae.clips[0].name, "move");
    EXPECT_NEAR(dae.clips[0].end_time(), 2.0, 1e-9);
    // 24 fps: frames 0, 24 and 48 are the keys; the others between them, and past the end.
    for (const int frame : {0, 6, 12, 24, 30, 41, 48, 60}) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        const std::vector<WorldTriangle> a = world_triangles(dae, frame), b = world_triangles(gltf, frame);
        ASSERT_EQ(a.size(), b.size());
        // glTF keys are floats, Collada's decomposed from float matrices: a few float ulps.
        EXPECT_LT(triangle_set_distance(a, b), 1e-5);
    }
    // The animation moves the box: frame 24 is not frame 0.
    EXPECT_GT(triangle_set_distance(world_triangles(dae, 0), world_triangles(dae, 24)), 1.0);
}

TEST(AssimpLoader, ColladaCameraAndLight) {
    const Scene dae = load_scene(write_file("camera_and_light.dae", collada_text()).string());
    ASSERT_EQ(dae.cameras.size(), 1u);
    EXPECT_EQ(dae.cameras[0].name, "view");
    EXPECT_NEAR(dae.cameras[0].yfov_rad, M_PI / 4.0, 1e-6);
    EXPECT_NEAR(dae.cameras[0].aspect_ratio, 1.5, 1e-6);
    anim::PosedScene posed;
    anim::pose_scene(dae, 0, posed);
    ASSERT_TRUE(posed.camera.has_value());
    EXPECT_LT(glm::distance(posed.camera->eye, glm::dvec3(2.0, 3.0, 10.0)), 1e-6);
    EXPECT_LT(glm::distance(posed.camera->forward, glm::dvec3(0.0, 0.0, -1.0)), 1e-6);
    EXPECT_LT(glm::distance(posed.camera->up, glm::dvec3(0.0, 1.0, 0.0)), 1e-6);
    ASSERT_EQ(dae.lights.size(), 1u);
    // On its node, posed with it: at (-4, 6, 2) in the rest pose; its colour kept.
    const PointLight& lamp = dae.lights[0];
    ASSERT_GE(lamp.node, 0);
    const glm::dvec3 placed(posed.node_world.at(std::size_t(lamp.node)) * glm::dvec4(glm::dvec3(lamp.position), 1.0));
    EXPECT_LT(glm::distance(placed, glm::dvec3(-4.0, 6.0, 2.0)), 1e-6);
    EXPECT_EQ(lamp.kind, PointLight::Kind::point);
    EXPECT_NEAR(lamp.intensity, 1.0f, 1e-6f);
    EXPECT_LT(glm::distance(lamp.color, glm::vec3(1.0f, 0.5f, 0.25f)), 1e-6f);
    EXPECT_FALSE(lamp.inverse_square);
}

/// A chain of joints j0 -> j1 (0, 1, 0) -> j2 (0, 1, 0), inverse bind matrices T(0, -y, 0); j1
/// turns 90 degrees about Z over [0, 1] s and j2 30 degrees about X over [0, 2] s. The mesh
/// node "body", translated by 100 (which skinning ignores), has a strip of 4 triangles whose
/// vertices mix up to three joints. With `mesh_node_name` "j1" the mesh node is named as a
/// joint and comes first in the scene, as glTF exporters' armatures sometimes have it;
/// `bind_x` moves the strip's vertices along x at bind time.
std::filesystem::path skinned_gltf(const std::string& mesh_node_name = "body", float bind_x = 0.0f) {
    GltfTestFile f;
    const int j0 = f.add_node({{"name", "j0"}});
    const int j1 = f.add_node({{"name", "j1"}, {"translation", {0.0, 1.0, 0.0}}}, false);
    const int j2 = f.add_node({{"name", "j2"}, {"translation", {0.0, 1.0, 0.0}}}, false);
    f.add_child(j0, j1);
    f.add_child(j1, j2);
    std::vector<float> ibm;
    for (const float y : {0.0f, -1.0f, -2.0f}) ibm.insert(ibm.end(), {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, y, 0, 1});
    f.doc()["skins"] = json::array({json{{"joints", {j0, j1, j2}}, {"inverseBindMatrices", f.add_floats(ibm, "MAT4")}}});
    std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0, 2, 0, 1, 2, 0};
    for (std::size_t v = 0; v < positions.size(); v += 3) positions[v] += bind_x;
    const int joints = f.add_accessor(
        std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1, 0, 0, 0, 1, 2, 0, 1, 2, 0, 0, 2, 1, 0, 0, 2, 0, 0, 0}, "VEC4",
        test::kGltfUnsignedByte);
    const int weights = f.add_floats({1, 0, 0, 0, 0.7f, 0.3f, 0, 0, 0.2f, 0.5f, 0.3f, 0, 0.5f, 0.5f, 0, 0,
                                      0.75f, 0.25f, 0, 0, 1, 0, 0, 0},
                                     "VEC4");
    const int mesh = f.add_mesh(positions, {{"JOINTS_0", joints}, {"WEIGHTS_0", weights}});
    f.doc()["meshes"][mesh]["primitives"][0]["indices"] = f.add_accessor(
        std::vector<std::uint16_t>{0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5}, "SCALAR", test::kGltfUnsignedShort);
    f.add_node({{"name", mesh_node_name}, {"mesh", mesh}, {"skin", 0}, {"translation", {100.0, 0.0, 0.0}}});
    json& roots = f.doc()["scenes"][0]["nodes"];
    std::reverse(roots.begin(), roots.end());
    const float h = float(std::sqrt(0.5)), s = float(std::sin(M_PI / 12.0)), c = float(std::cos(M_PI / 12.0));
    f.add_animation("Bend", {{j1, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, h, h}},
                             {j2, "rotation", {0, 2}, {0, 0, 0, 1, s, 0, 0, c}}});
    return f.write("skinned_chain_" + mesh_node_name + "_" + std::to_string(bind_x) + ".gltf");
}

// assimp's own glTF reader gives bones, offset matrices, weights and node channels: read
// through load_assimp, the file must pose as dynrt's glTF loader poses it.
TEST(AssimpLoader, SkinnedAnimationThroughAssimpPosesAsTheGltfLoader) {
    const std::filesystem::path file = skinned_gltf();
    const Scene via_assimp = load_assimp(file);
    const Scene gltf = load_gltf(file);
    ASSERT_EQ(via_assimp.objects.size(), 1u);
    ASSERT_TRUE(via_assimp.objects[0].skin.has_value());
    EXPECT_EQ(via_assimp.objects[0].skin->influences, 4u);
    ASSERT_EQ(via_assimp.clips.size(), 1u);
    for (const int frame : {0, 6, 12, 24, 36, 48}) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        EXPECT_LT(triangle_set_distance(world_triangles(via_assimp, frame), world_triangles(gltf, frame)), 1e-5);
    }
    EXPECT_GT(triangle_set_distance(world_triangles(gltf, 0), world_triangles(gltf, 24)), 0.5);
}

// assimp names a bone's node by name alone: when a mesh node shares a joint's name, the bone is
// the node without meshes.
TEST(AssimpLoader, BonesFindTheirJointWhenAMeshNodeSharesItsName) {
    const std::filesystem::path file = skinned_gltf("j1");
    const Scene via_assimp = load_assimp(file);
    const Scene gltf = load_gltf(file);
    for (const int frame : {0, 12, 24, 48}) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        EXPECT_LT(triangle_set_distance(world_triangles(via_assimp, frame), world_triangles(gltf, frame)), 1e-5);
    }
}

// The shared glTF models with skins and node animation, read through assimp, pose as dynrt's
// glTF loader poses them. Left out: models with morph targets (assimp's are not read) and
// InterpolationTest (assimp 5.2.5's keys have no STEP or CUBICSPLINE: it differs from frame 1).
TEST(AssimpLoader, SharedAnimatedGltfModelsThroughAssimpPoseAsTheGltfLoader) {
    const std::filesystem::path root(DYNRT_SHARED_SCENES_DIR);
    if (!std::filesystem::is_directory(root)) GTEST_SKIP() << root << " does not exist";
    for (const char* model : {"riggedsimple/RiggedSimple.glb", "riggedfigure/RiggedFigure.glb",
                              "simpleskin/SimpleSkin.gltf", "boxanimated/BoxAnimated.glb",
                              "animatedcube/AnimatedCube.gltf", "fox/Fox.glb", "robot/robot.glb",
                              "cesiummilktruck/CesiumMilkTruck.glb"}) {
        SCOPED_TRACE(model);
        const std::filesystem::path file = root / model;
        if (!std::filesystem::exists(file)) continue;
        const Scene gltf = load_gltf(file);
        const Scene via_assimp = load_assimp(file);
        EXPECT_EQ(via_assimp.triangle_count(), gltf.triangle_count());
        EXPECT_EQ(via_assimp.clips.size(), gltf.clips.size());
        // The base colour images, embedded ones (CesiumMilkTruck's JPEG) read from memory.
        ASSERT_EQ(via_assimp.textures.size(), gltf.textures.size());
        for (std::size_t t = 0; t < gltf.textures.size(); ++t) {
            EXPECT_EQ(via_assimp.textures[t].encoded, gltf.textures[t].encoded);
            EXPECT_EQ(via_assimp.textures[t].path, gltf.textures[t].path);
        }
        for (const int frame : {0, 10, 30}) {
            SCOPED_TRACE("frame " + std::to_string(frame));
            const std::vector<WorldTriangle> a = world_triangles(via_assimp, frame), b = world_triangles(gltf, frame);
            double extent = 1.0;
            for (const WorldTriangle& t : b) {
                for (const glm::dvec3& p : t) extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
            }
            // Float keys and matrices decomposed by assimp: a few float ulps of the model's size.
            EXPECT_LT(triangle_set_distance(a, b), 2e-6 * extent);
        }
    }
}

/// skinned_gltf()'s chain, strip and animation in Collada 1.4.1: joint nodes j0 -> j1 -> j2, a
/// skin controller (inverse bind matrices, weights per vertex) instanced on node "body"
/// (translated by 100, which skinning ignores), j1's and j2's turns as linear matrix channels.
std::string collada_skin_text() {
    const auto key = [](double y, double angle, const glm::dvec3& axis) {
        const glm::dquat q = glm::angleAxis(angle, axis);
        return collada_matrix(trs_matrix({0.0, y, 0.0}, glm::dvec4(q.x, q.y, q.z, q.w), glm::dvec3(1.0)));
    };
    const auto animation = [](const std::string& joint, const std::string& times, const std::string& matrices) {
        const std::string id = joint + "-turn";
        return R"(    <animation id=")" + id + R"(">
      <source id=")" + id + R"(-input"><float_array id=")" + id + R"(-input-array" count="2">)" + times + R"(</float_array>
        <technique_common><accessor source="#)" + id + R"(-input-array" count="2" stride="1"><param name="TIME" type="float"/></accessor></technique_common></source>
      <source id=")" + id + R"(-output"><float_array id=")" + id + R"(-output-array" count="32">)" + matrices + R"(</float_array>
        <technique_common><accessor source="#)" + id + R"(-output-array" count="2" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
      <source id=")" + id + R"(-interpolation"><Name_array id=")" + id + R"(-interpolation-array" count="2">LINEAR LINEAR</Name_array>
        <technique_common><accessor source="#)" + id + R"(-interpolation-array" count="2" stride="1"><param name="INTERPOLATION" type="name"/></accessor></technique_common></source>
      <sampler id=")" + id + R"(-sampler"><input semantic="INPUT" source="#)" + id + R"(-input"/><input semantic="OUTPUT" source="#)" + id +
               R"(-output"/><input semantic="INTERPOLATION" source="#)" + id + R"(-interpolation"/></sampler>
      <channel source="#)" + id + R"(-sampler" target=")" + joint + R"(/transform"/>
    </animation>
)";
    };
    const glm::dvec3 z(0.0, 0.0, 1.0), x(1.0, 0.0, 0.0);
    std::string inverse_binds;
    for (const double y : {0.0, -1.0, -2.0}) inverse_binds += key(y, 0.0, z);
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="meter" meter="1"/><up_axis>Y_UP</up_axis></asset>
  <library_geometries>
    <geometry id="strip-mesh" name="strip">
      <mesh>
        <source id="strip-positions">
          <float_array id="strip-positions-array" count="18">0 0 0 1 0 0 0 1 0 1 1 0 0 2 0 1 2 0</float_array>
          <technique_common><accessor source="#strip-positions-array" count="6" stride="3">
            <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
          </accessor></technique_common>
        </source>
        <vertices id="strip-vertices"><input semantic="POSITION" source="#strip-positions"/></vertices>
        <triangles count="4"><input semantic="VERTEX" source="#strip-vertices" offset="0"/><p>0 1 2 2 1 3 2 3 4 4 3 5</p></triangles>
      </mesh>
    </geometry>
  </library_geometries>
  <library_controllers>
    <controller id="skin" name="skin">
      <skin source="#strip-mesh">
        <bind_shape_matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</bind_shape_matrix>
        <source id="skin-joints"><Name_array id="skin-joints-array" count="3">j0 j1 j2</Name_array>
          <technique_common><accessor source="#skin-joints-array" count="3" stride="1"><param name="JOINT" type="name"/></accessor></technique_common></source>
        <source id="skin-binds"><float_array id="skin-binds-array" count="48">)" + inverse_binds + R"(</float_array>
          <technique_common><accessor source="#skin-binds-array" count="3" stride="16"><param name="TRANSFORM" type="float4x4"/></accessor></technique_common></source>
        <source id="skin-weights"><float_array id="skin-weights-array" count="11">1 0.7 0.3 0.2 0.5 0.3 0.5 0.5 0.75 0.25 1</float_array>
          <technique_common><accessor source="#skin-weights-array" count="11" stride="1"><param name="WEIGHT" type="float"/></accessor></technique_common></source>
        <joints><input semantic="JOINT" source="#skin-joints"/><input semantic="INV_BIND_MATRIX" source="#skin-binds"/></joints>
        <vertex_weights count="6">
          <input semantic="JOINT" source="#skin-joints" offset="0"/><input semantic="WEIGHT" source="#skin-weights" offset="1"/>
          <vcount>1 2 3 2 2 1</vcount>
          <v>0 0  0 1 1 2  0 3 1 4 2 5  1 6 2 7  2 8 1 9  2 10</v>
        </vertex_weights>
      </skin>
    </controller>
  </library_controllers>
  <library_animations>
)" + animation("j1", "0 1", key(1.0, 0.0, z) + key(1.0, M_PI / 2.0, z)) +
           animation("j2", "0 2", key(1.0, 0.0, x) + key(1.0, M_PI / 6.0, x)) + R"(  </library_animations>
  <library_visual_scenes>
    <visual_scene id="scene" name="scene">
      <node id="j0" name="j0" sid="j0" type="JOINT"><matrix sid="transform">)" + key(0.0, 0.0, z) + R"(</matrix>
        <node id="j1" name="j1" sid="j1" type="JOINT"><matrix sid="transform">)" + key(1.0, 0.0, z) + R"(</matrix>
          <node id="j2" name="j2" sid="j2" type="JOINT"><matrix sid="transform">)" + key(1.0, 0.0, x) + R"(</matrix></node>
        </node>
      </node>
      <node id="body" name="body" type="NODE"><matrix sid="transform">1 0 0 100 0 1 0 0 0 0 1 0 0 0 0 1</matrix>
        <instance_controller url="#skin"><skeleton>#j0</skeleton></instance_controller>
      </node>
    </visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

TEST(AssimpLoader, ColladaSkinnedAnimationPosesAsTheSameGltf) {
    const Scene dae = load_scene(write_file("skinned_chain.dae", collada_skin_text()).string());
    const Scene gltf = load_gltf(skinned_gltf());
    ASSERT_EQ(dae.objects.size(), 1u);
    ASSERT_TRUE(dae.objects[0].skin.has_value());
    EXPECT_FALSE(dae.clips.empty());
    EXPECT_GT(triangle_set_distance(world_triangles(dae, 0), world_triangles(dae, 48)), 0.5);
    for (const int frame : {0, 6, 12, 24, 36, 48, 60}) {
        SCOPED_TRACE("frame " + std::to_string(frame));
        EXPECT_LT(triangle_set_distance(world_triangles(dae, frame), world_triangles(gltf, frame)), 1e-5);
    }
}

// tests/data/animated_cube.fbx and skinned_chain.fbx are the two Collada files above converted
// by assimp's FBX exporter (its key times and scale property corrected by hand: the command and
// the corrections are in their first lines). What FBX says differs from the glTF in two ways:
// - FBX animates Euler angles. assimp turns them into quaternion keys at the file's key times,
//   and dynrt slerps between those, so the cube poses as the glTF at its keys and while it
//   turns about one axis (to frame 24), not between the last two keys (where FBX would
//   interpolate the Euler angles, not the rotation).
// - A skin cluster's Transform is the mesh's world matrix at bind time, which the exporter took
//   from the mesh node "body" (translation 100, which glTF's skinning ignores): in the FBX file
//   the strip's vertices sit at x + 100 when bound, and swing around the joints from there, as
//   skinned_gltf's strip with bind_x = 100 does.
// Euler keys are written with 6 digits: the cube agrees to 1e-4.
TEST(AssimpLoader, FbxNodeAndSkinnedAnimationsPoseAsTheSameGltf) {
    const std::string data = std::string(DYNRT_SOURCE_DIR) + "/tests/data/";
    const Scene cube_fbx = load_scene(data + "animated_cube.fbx");
    const Scene cube_gltf = load_gltf(animated_gltf());
    ASSERT_EQ(cube_fbx.clips.size(), 1u);
    for (const int frame : {0, 6, 12, 18, 24, 48, 60}) {
        SCOPED_TRACE("cube, frame " + std::to_string(frame));
        EXPECT_LT(triangle_set_distance(world_triangles(cube_fbx, frame), world_triangles(cube_gltf, frame)), 1e-4);
    }
    const Scene chain_fbx = load_scene(data + "skinned_chain.fbx");
    const Scene chain_gltf = load_gltf(skinned_gltf("body", 100.0f));
    ASSERT_EQ(chain_fbx.objects.size(), 1u);
    ASSERT_TRUE(chain_fbx.objects[0].skin.has_value());
    for (const int frame : {0, 6, 12, 24, 30, 41, 48, 60}) {
        SCOPED_TRACE("chain, frame " + std::to_string(frame));
        EXPECT_LT(triangle_set_distance(world_triangles(chain_fbx, frame), world_triangles(chain_gltf, frame)), 1e-4);
    }
}

// ---- Materials and `dynrt info` -------------------------------------------------------------

/// The cube (material "red", a texture that exists) and the wedge (material "glass", 40%
/// opaque, ior 1.3, a texture that does not), with their MTL file and one of the textures.
std::filesystem::path obj_with_materials() {
    write_file("present.png", "not really a PNG: only its existence is looked at");
    const std::string prefix = "dynrt_" + std::to_string(::getpid()) + "_";
    write_file("materials.mtl", "newmtl red\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 64\nmap_Kd " + prefix +
                                    "present.png\n\nnewmtl glass\nKd 0 0 1\nd 0.4\nNi 1.3\nmap_Kd " + prefix +
                                    "missing.png\n");
    std::string text = obj_text();
    text.insert(0, "mtllib " + prefix + "materials.mtl\n");
    text.insert(text.find("o cube\n") + 7, "usemtl red\n");
    text.insert(text.find("f 9 10 11"), "usemtl glass\n");
    return write_file("with_materials.obj", text);
}

TEST(AssimpLoader, ObjMaterialsAndTextures) {
    const std::filesystem::path obj = obj_with_materials();
    const Scene scene = load_scene(obj.string());
    ASSERT_EQ(scene.objects.size(), 2u);
    const Material& red = scene.materials[scene.objects[0].material];
    const Material& glass = scene.materials[scene.objects[1].material];
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.diffuse, glm::vec3(1.0f, 0.0f, 0.0f));
    EXPECT_EQ(red.specular, glm::vec3(0.5f));
    EXPECT_EQ(red.shininess, 64.0f);
    EXPECT_FALSE(red.traces_secondary());
    EXPECT_EQ(glass.name, "glass");
    EXPECT_NEAR(glass.diffuse.z, 0.4f, 1e-6f);
    EXPECT_NEAR(glass.transmittance.x, 0.6f, 1e-6f);
    EXPECT_NEAR(glass.ior, 1.3f, 1e-6f);
    ASSERT_TRUE(red.diffuse_map.has_value());
    ASSERT_TRUE(glass.diffuse_map.has_value());
    ASSERT_EQ(scene.textures.size(), 2u);
    EXPECT_EQ(std::filesystem::path(scene.textures[red.diffuse_map->texture].path),
              obj.parent_path() / ("dynrt_" + std::to_string(::getpid()) + "_present.png"));
}

TEST(AssimpLoader, InfoListsCamerasLightsMaterialsAndMissingTextures) {
    const test::ShellRun obj = test::run_shell(std::string(DYNRT_CLI_PATH) + " info " + obj_with_materials().string());
    ASSERT_EQ(obj.exit_code, 0) << obj.output;
    EXPECT_NE(obj.output.find(" red "), std::string::npos) << obj.output;
    EXPECT_NE(obj.output.find(" glass "), std::string::npos) << obj.output;
    EXPECT_NE(obj.output.find("diffuse [1, 0, 0] x texture"), std::string::npos) << obj.output;
    EXPECT_NE(obj.output.find("textures: 2"), std::string::npos) << obj.output;
    EXPECT_NE(obj.output.find("missing.png  MISSING"), std::string::npos) << obj.output;
    EXPECT_EQ(obj.output.find("present.png  MISSING"), std::string::npos) << obj.output;
    EXPECT_NE(obj.output.find("cameras: 0"), std::string::npos) << obj.output;

    const std::string dae_path = write_file("info.dae", collada_text()).string();
    const test::ShellRun dae = test::run_shell(std::string(DYNRT_CLI_PATH) + " info " + dae_path);
    ASSERT_EQ(dae.exit_code, 0) << dae.output;
    EXPECT_NE(dae.output.find("cameras: 1"), std::string::npos) << dae.output;
    EXPECT_NE(dae.output.find("at [2, 3, 10] looking [0, 0, -1], yfov 45.0 deg, aspect 1.5"), std::string::npos)
        << dae.output;
    EXPECT_NE(dae.output.find("lights: 1"), std::string::npos) << dae.output;
    EXPECT_NE(dae.output.find("point at [-4, 6, 2]"), std::string::npos) << dae.output;

    const test::ShellRun unknown = test::run_shell(std::string(DYNRT_CLI_PATH) + " info " +
                                                   write_file("info_notes.txt", "no scene here\n").string());
    EXPECT_NE(unknown.exit_code, 0);
    EXPECT_NE(unknown.output.find("dynrt: error: "), std::string::npos) << unknown.output;
    EXPECT_NE(unknown.output.find("info_notes.txt: not a scene file dynrt reads"), std::string::npos) << unknown.output;
}

// ---- Bad input -------------------------------------------------------------------------------

TEST(AssimpLoader, BadFilesAreOneLineErrorsNamingTheFile) {
    const auto load = [](const std::string& name, const std::string& text) {
        const std::string path = write_file(name, text).string();
        return [path] { load_scene(path); };
    };
    expect_scene_error(load("empty.obj", ""), {"empty.obj", "empty file"});
    expect_scene_error(load("empty.ply", ""), {"empty.ply", "empty file"});
    expect_scene_error(load("no_faces.obj", "# only vertices\nv 0 0 0\nv 1 0 0\n"), {"no_faces.obj"});
    expect_scene_error(load("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), {"nan.obj", "not finite"});
    expect_scene_error(load("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"), {"range.obj"});
    expect_scene_error(load("truncated.ply", ply_header("ascii", 4, 2) + "0 0 0\n1 0 0\n"), {"truncated.ply"});
    expect_scene_error(load("range.ply", ply_header("ascii", 3, 1) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), {"range.ply"});
    std::string binary = ply_text(true);
    binary.resize(binary.size() / 2);
    expect_scene_error(load("truncated_binary.ply", binary), {"truncated_binary.ply"});
    expect_scene_error(load("notes.txt", "hello, this is no scene\n"),
                       {"notes.txt: not a scene file dynrt reads (glTF .gltf/.glb, BART .aff, OBJ, PLY, FBX, Collada .dae"});
    expect_scene_error(load("broken.dae", collada_text().substr(0, 900)), {"broken.dae"});
}

TEST(AssimpLoader, LoadSceneTellsFilesFromSpecsAndKindsByContent) {
    const std::string missing = (std::filesystem::path(::testing::TempDir()) / "dynrt_no_such_mesh.obj").string();
    expect_scene_error([&] { load_scene(missing); }, {missing + ": no such file"});
    expect_scene_error([] { load_scene("bunny.obj"); }, {"bunny.obj: no such file"});
    expect_scene_error([] { load_scene("no/such/folder/scene"); }, {"no/such/folder/scene: no such file"});
    expect_scene_error([] { load_scene(::testing::TempDir()); }, {"is a folder"});
    // Specs still are specs: their numbers and colours are no extensions.
    EXPECT_EQ(load_scene("sphere:2@1.5,0,0#a0a0ff").objects.size(), 1u);
    // An OBJ and a PLY under names that say nothing are read by their content.
    EXPECT_EQ(load_scene(write_file("cube_obj.data", obj_text()).string()).triangle_count(), 13u);
    EXPECT_EQ(load_scene(write_file("cube_ply.txt", ply_text(false)).string()).triangle_count(), 13u);
}

// ---- Shared scenes ---------------------------------------------------------------------------

TEST(AssimpLoader, StanfordBunnyObjLoads) {
    const std::filesystem::path path = std::filesystem::path(DYNRT_SHARED_SCENES_DIR) / "stanfordbunny/stanford-bunny.obj";
    if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " does not exist";
    std::size_t faces = 0, vertices = 0;
    std::ifstream in(path);
    for (std::string line; std::getline(in, line);) {
        faces += line.rfind("f ", 0) == 0;
        vertices += line.rfind("v ", 0) == 0;
    }
    const Scene scene = load_scene(path.string());
    EXPECT_EQ(scene.triangle_count(), faces);
    std::size_t positions = 0;
    for (const Object& object : scene.objects) {
        positions += object.mesh.positions.size();
        EXPECT_EQ(object.mesh.normals.size(), object.mesh.positions.size()) << object.name;
    }
    // Corners shared in the file stay shared: the mesh is smooth, not a triangle soup.
    EXPECT_LE(positions, vertices);
}

}  // namespace assimp_loader_test
}  // namespace dynrt
