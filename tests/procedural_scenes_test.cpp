// Procedural scenes: the exact definitions of scenes/README.md recomputed independently here
// (a second implementation written from scenes/README.md, plus known answers computed in Python),
// spec composition, malformed specs, load_scene dispatch, and check_scene's invariants.

#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace dynrt {
namespace {

// ---- Independent reference implementations (from scenes/README.md) ---------------------------

std::uint64_t reference_stacks(std::uint64_t n) {
    const double s = std::round((1.0 + std::sqrt(1.0 + static_cast<double>(n))) / 2.0);
    return s < 2.0 ? 2 : static_cast<std::uint64_t>(s);
}

Mesh reference_sphere(std::uint64_t n) {
    const std::uint64_t S = reference_stacks(n), L = 2 * S;
    const double pi = 3.141592653589793;
    Mesh m;
    m.positions.push_back({0.0f, 1.0f, 0.0f});
    for (std::uint64_t k = 1; k <= S - 1; ++k) {
        for (std::uint64_t j = 0; j < L; ++j) {
            const double th = pi * static_cast<double>(k) / static_cast<double>(S);
            const double ph = 2.0 * pi * static_cast<double>(j) / static_cast<double>(L);
            m.positions.push_back({static_cast<float>(std::sin(th) * std::cos(ph)),
                                   static_cast<float>(std::cos(th)),
                                   static_cast<float>(std::sin(th) * std::sin(ph))});
        }
    }
    m.positions.push_back({0.0f, -1.0f, 0.0f});
    const auto last = static_cast<std::uint32_t>(m.positions.size() - 1);
    auto r = [&](std::uint64_t k, std::uint64_t j) {
        return static_cast<std::uint32_t>(1 + (k - 1) * L + (j % L));
    };
    for (std::uint64_t j = 0; j < L; ++j) m.triangles.push_back({0u, r(1, j + 1), r(1, j)});
    for (std::uint64_t k = 1; k <= S - 2; ++k) {
        for (std::uint64_t j = 0; j < L; ++j) {
            m.triangles.push_back({r(k, j), r(k, j + 1), r(k + 1, j + 1)});
            m.triangles.push_back({r(k, j), r(k + 1, j + 1), r(k + 1, j)});
        }
    }
    for (std::uint64_t j = 0; j < L; ++j) m.triangles.push_back({r(S - 1, j), r(S - 1, j + 1), last});
    return m;
}

std::uint64_t reference_splitmix(std::uint64_t& state) {
    state += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

Mesh reference_soup(std::uint64_t n) {
    std::uint64_t state = 1;
    auto draw = [&] {
        return static_cast<float>(static_cast<double>(reference_splitmix(state) >> 40) / 16777216.0);
    };
    const float e = 2.0f / std::cbrt(static_cast<float>(n));
    // volatile forces the product to be rounded to float before the sum, whatever FMA
    // contraction the compiler would otherwise apply.
    auto vertex_coordinate = [&](float centre) {
        volatile float offset = e * (draw() - 0.5f);
        return centre + offset;
    };
    Mesh m;
    for (std::uint64_t i = 0; i < n; ++i) {
        const float cx = draw(), cy = draw(), cz = draw();
        for (int v = 0; v < 3; ++v) {
            const float x = vertex_coordinate(cx);
            const float y = vertex_coordinate(cy);
            const float z = vertex_coordinate(cz);
            m.positions.push_back({x, y, z});
        }
        const auto f = static_cast<std::uint32_t>(3 * i);
        m.triangles.push_back({f, f + 1, f + 2});
    }
    return m;
}

void expect_same_mesh(const Mesh& actual, const Mesh& expected) {
    ASSERT_EQ(actual.positions.size(), expected.positions.size());
    ASSERT_EQ(actual.triangles.size(), expected.triangles.size());
    for (std::size_t i = 0; i < expected.positions.size(); ++i) {
        // Bit-exact: the definitions promise the same floats in any implementation.
        ASSERT_EQ(actual.positions[i].x, expected.positions[i].x) << "vertex " << i;
        ASSERT_EQ(actual.positions[i].y, expected.positions[i].y) << "vertex " << i;
        ASSERT_EQ(actual.positions[i].z, expected.positions[i].z) << "vertex " << i;
    }
    for (std::size_t t = 0; t < expected.triangles.size(); ++t) {
        ASSERT_EQ(actual.triangles[t], expected.triangles[t]) << "triangle " << t;
    }
}

/// By value: callers pass a temporary scene.
Mesh only_mesh(const Scene& scene) {
    EXPECT_EQ(scene.objects.size(), 1u);
    return scene.objects.at(0).mesh;
}

glm::vec3 face_normal(const Mesh& m, const glm::uvec3& t) {
    const glm::vec3 a = m.positions[t.x], b = m.positions[t.y], c = m.positions[t.z];
    const glm::vec3 u = b - a, v = c - a;
    return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}

// ---- sphere:N ------------------------------------------------------------------------------

TEST(ProceduralSphere, TriangleAndVertexCountsFollowTheStackFormula) {
    struct Case {
        std::uint64_t n, stacks;
    };
    // S = max(2, round((1 + sqrt(1 + N)) / 2)), worked out by hand.
    for (const Case c : {Case{1, 2}, Case{2, 2}, Case{8, 2}, Case{9, 2}, Case{100, 6}, Case{20000, 71}}) {
        const Scene scene = make_procedural_scene("sphere:" + std::to_string(c.n));
        const Mesh& m = only_mesh(scene);
        const std::uint64_t L = 2 * c.stacks;
        EXPECT_EQ(m.triangles.size(), 2 * L * (c.stacks - 1)) << "sphere:" << c.n;
        EXPECT_EQ(m.positions.size(), 2 + (c.stacks - 1) * L) << "sphere:" << c.n;
        EXPECT_EQ(scene.triangle_count(), m.triangles.size());
    }
}

TEST(ProceduralSphere, MatchesAnIndependentImplementationBitForBit) {
    for (const std::uint64_t n : {1ull, 7ull, 100ull, 3000ull}) {
        SCOPED_TRACE("sphere:" + std::to_string(n));
        expect_same_mesh(only_mesh(make_procedural_scene("sphere:" + std::to_string(n))),
                         reference_sphere(n));
    }
}

TEST(ProceduralSphere, KnownVerticesAndTriangles) {
    const Mesh m = only_mesh(make_procedural_scene("sphere:100"));  // S = 6, L = 12
    EXPECT_EQ(m.positions.front(), glm::vec3(0.0f, 1.0f, 0.0f));
    EXPECT_EQ(m.positions.back(), glm::vec3(0.0f, -1.0f, 0.0f));
    // Ring 1, slice 0 is vertex 1 at theta = pi/6, phi = 0.
    EXPECT_EQ(m.positions[1], glm::vec3(static_cast<float>(std::sin(3.141592653589793 / 6)),
                                        static_cast<float>(std::cos(3.141592653589793 / 6)), 0.0f));
    // Ring 3 (the equator, theta = pi/2), slice 3 (phi = pi/2) is vertex 1 + 2*12 + 3 = 28.
    EXPECT_NEAR(m.positions[28].x, 0.0f, 1e-7f);
    EXPECT_NEAR(m.positions[28].y, 0.0f, 1e-7f);
    EXPECT_EQ(m.positions[28].z, 1.0f);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 2, 1));
    EXPECT_EQ(m.triangles[11], glm::uvec3(0, 1, 12));                            // the fan wraps j + 1 to 0
    EXPECT_EQ(m.triangles[12], glm::uvec3(1, 2, 14));                            // first quad: (a, b, d)
    EXPECT_EQ(m.triangles[13], glm::uvec3(1, 14, 13));                           // then (a, d, c)
    EXPECT_EQ(m.triangles.back(), glm::uvec3(1 + 4 * 12 + 11, 1 + 4 * 12, 61));  // bottom fan, last = 61
}

TEST(ProceduralSphere, TrianglesFaceOutward) {
    const Mesh m = only_mesh(make_procedural_scene("sphere:500"));
    for (const glm::uvec3& t : m.triangles) {
        const glm::vec3 centroid = (m.positions[t.x] + m.positions[t.y] + m.positions[t.z]) / 3.0f;
        const glm::vec3 n = face_normal(m, t);
        ASSERT_GT(n.x * centroid.x + n.y * centroid.y + n.z * centroid.z, 0.0f);
    }
}

// ---- soup:N --------------------------------------------------------------------------------

TEST(ProceduralSoup, MatchesAnIndependentSplitMix64BitForBit) {
    for (const std::uint64_t n : {1ull, 2ull, 8ull, 1000ull, 12345ull}) {
        SCOPED_TRACE("soup:" + std::to_string(n));
        const Mesh m = only_mesh(make_procedural_scene("soup:" + std::to_string(n)));
        EXPECT_EQ(m.triangles.size(), n);
        expect_same_mesh(m, reference_soup(n));
    }
}

TEST(ProceduralSoup, KnownAnswerFromPython) {
    // Computed with a Python splitmix64 (first output of seed 1 is 0x910a2dec89025cc1) and
    // float32 rounding by struct; soup:8 has e = 2 / cbrt(8) = 1 exactly.
    const Mesh m = only_mesh(make_procedural_scene("soup:8"));
    EXPECT_EQ(m.positions[0], glm::vec3(0x1.059766p-1f, 0x1.614dc2p-1f, 0x1.3be0acp+0f));
    EXPECT_EQ(m.positions[1], glm::vec3(0x1.e34832p-1f, 0x1.89a69p-1f, 0x1.835574p-1f));
    EXPECT_EQ(m.positions[2], glm::vec3(0x1.b89b12p-1f, 0x1.4cc2d2p-1f, 0x1.139076p+0f));
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(m.triangles[7], glm::uvec3(21, 22, 23));

    // soup:2 has e = 2 / cbrtf(2) = 0x1.965feap+0, whose products are inexact in float: the
    // case where fusing multiply and add (FMA) would change the bits.
    const Mesh two = only_mesh(make_procedural_scene("soup:2"));
    EXPECT_EQ(two.positions[0], glm::vec3(0x1.e9b704p-2f, 0x1.508a98p-1f, 0x1.636908p+0f));
    EXPECT_EQ(two.positions[1], glm::vec3(0x1.2a627cp+0f, 0x1.90968cp-1f, 0x1.42d36p-1f));
    EXPECT_EQ(two.positions[2], glm::vec3(0x1.088334p+0f, 0x1.2fee8cp-1f, 0x1.236ab6p+0f));
}

// ---- plane:N -------------------------------------------------------------------------------

TEST(ProceduralPlane, OneQuad) {
    const Mesh m = only_mesh(make_procedural_scene("plane:1"));
    const std::vector<glm::vec3> expected = {{-1, 0, -1}, {1, 0, -1}, {-1, 0, 1}, {1, 0, 1}};
    EXPECT_EQ(m.positions, expected);
    ASSERT_EQ(m.triangles.size(), 2u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 2, 3));
    EXPECT_EQ(m.triangles[1], glm::uvec3(0, 3, 1));
}

TEST(ProceduralPlane, GridIsExactAndFacesUp) {
    const Mesh m = only_mesh(make_procedural_scene("plane:3"));
    ASSERT_EQ(m.positions.size(), 16u);
    ASSERT_EQ(m.triangles.size(), 18u);
    const float third = 1.0f / 3.0f;
    // Vertex r*(N+1)+c at x = float(2c-N)/float(N), z = float(2r-N)/float(N).
    EXPECT_EQ(m.positions[0], glm::vec3(-1.0f, 0.0f, -1.0f));
    EXPECT_EQ(m.positions[1], glm::vec3(-third, 0.0f, -1.0f));
    EXPECT_EQ(m.positions[6], glm::vec3(third, 0.0f, -third));
    EXPECT_EQ(m.positions[15], glm::vec3(1.0f, 0.0f, 1.0f));
    // Quad (r=1, c=2) is quad r*N + c = 5: a=6, b=7, c=10, d=11 -> (a,c,d), (a,d,b).
    EXPECT_EQ(m.triangles[2 * 5], glm::uvec3(6, 10, 11));
    EXPECT_EQ(m.triangles[2 * 5 + 1], glm::uvec3(6, 11, 7));
    for (const glm::uvec3& t : m.triangles) {
        const glm::vec3 n = face_normal(m, t);
        EXPECT_GT(n.y, 0.0f);
        EXPECT_EQ(n.x, 0.0f);
        EXPECT_EQ(n.z, 0.0f);
    }
}

// ---- Composition ---------------------------------------------------------------------------

TEST(ProceduralComposition, PlacementColourAndNames) {
    const std::string spec = "plane:1@0,-1,0,4#808080+sphere:20000#d04030+soup:10";
    const Scene scene = make_procedural_scene(spec);
    EXPECT_EQ(scene.source, spec);
    ASSERT_EQ(scene.objects.size(), 3u);
    EXPECT_EQ(scene.objects[0].name, "plane:1@0,-1,0,4#808080");
    EXPECT_EQ(scene.objects[1].name, "sphere:20000#d04030");
    EXPECT_EQ(scene.objects[2].name, "soup:10");

    glm::mat4 expected(4.0f);
    expected[3] = glm::vec4(0.0f, -1.0f, 0.0f, 1.0f);
    EXPECT_EQ(scene.objects[0].transform, expected);
    EXPECT_EQ(scene.objects[1].transform, glm::mat4(1.0f));
    // The mesh stays in its own space; the placement is only the transform.
    EXPECT_EQ(scene.objects[0].mesh.positions[3], glm::vec3(1.0f, 0.0f, 1.0f));

    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[0].diffuse, glm::vec3(0.8f));
    EXPECT_EQ(scene.objects[0].material, 1u);
    EXPECT_EQ(scene.materials[1].diffuse, glm::vec3(128.0f / 255.0f));
    EXPECT_EQ(scene.objects[1].material, 2u);
    EXPECT_EQ(scene.materials[2].diffuse, glm::vec3(208.0f / 255.0f, 64.0f / 255.0f, 48.0f / 255.0f));
    EXPECT_EQ(scene.objects[2].material, 0u);
    EXPECT_EQ(scene.triangle_count(), 2u + 19880u + 10u);
}

TEST(ProceduralComposition, SuffixesInEitherOrderAndNumberForms) {
    const Scene scene = make_procedural_scene("sphere:10#FF00aa@1.5,-2e-1,.25+soup:3@-0,1e1,3,0.5");
    ASSERT_EQ(scene.objects.size(), 2u);
    EXPECT_EQ(scene.objects[0].transform[3], glm::vec4(1.5f, -0.2f, 0.25f, 1.0f));
    EXPECT_EQ(scene.objects[0].transform[0][0], 1.0f);
    EXPECT_EQ(scene.materials[scene.objects[0].material].diffuse, glm::vec3(1.0f, 0.0f, 170.0f / 255.0f));
    EXPECT_EQ(scene.objects[1].transform[3], glm::vec4(0.0f, 10.0f, 3.0f, 1.0f));
    EXPECT_EQ(scene.objects[1].transform[1][1], 0.5f);
    EXPECT_EQ(scene.objects[1].transform[2][2], 0.5f);
    EXPECT_EQ(scene.objects[1].transform[3][3], 1.0f);
}

TEST(ProceduralComposition, MalformedSpecsNameTheSpecAndThePart) {
    struct Case {
        std::string spec, part;
    };
    const std::vector<Case> cases = {
        {"", ""},
        {"cube:5", "cube:5"},
        {"sphere", "sphere"},
        {"sphere:", "sphere:"},
        {"sphere:0", "sphere:0"},
        {"sphere:-3", "sphere:-3"},
        {"sphere:1.5", "sphere:1.5"},
        {"sphere:10x", "sphere:10x"},
        {"sphere:+10", "sphere:"},  // '+' separates parts, so N has no sign
        {"sphere:99999999999999999999999", "sphere:99999999999999999999999"},
        {"soup:100000001", "soup:100000001"},
        {"plane:8000", "plane:8000"},
        {"sphere:100000000", "sphere:100000000"},
        {"sphere:10@1,2", "sphere:10@1,2"},
        {"sphere:10@1,2,3,4,5", "sphere:10@1,2,3,4,5"},
        {"sphere:10@a,b,c", "sphere:10@a,b,c"},
        {"sphere:10@1,,3", "sphere:10@1,,3"},
        {"sphere:10@nan,0,0", "sphere:10@nan,0,0"},
        {"sphere:10@inf,0,0", "sphere:10@inf,0,0"},
        {"sphere:10@1e999,0,0", "sphere:10@1e999,0,0"},
        {"sphere:10@1,2,3,0", "sphere:10@1,2,3,0"},
        {"sphere:10@1,2,3,-1", "sphere:10@1,2,3,-1"},
        {"sphere:10@1,2,3@4,5,6", "sphere:10@1,2,3@4,5,6"},
        {"sphere:10#12345", "sphere:10#12345"},
        {"sphere:10#1234567", "sphere:10#1234567"},
        {"sphere:10#gggggg", "sphere:10#gggggg"},
        {"sphere:10#ff0000#00ff00", "sphere:10#ff0000#00ff00"},
        {"sphere:10#ff0000junk", "sphere:10#ff0000junk"},
        {"sphere:10 ", "sphere:10 "},
        {" sphere:10", " sphere:10"},
        {"sphere:10+", ""},
        {"+sphere:10", ""},
        {"sphere:10++plane:1", ""},
        {"plane:1+sphere:0", "sphere:0"},
        {"scene.obj", "scene.obj"},
        // Each part is under the cap, the sum is not.
        {"soup:60000000+soup:60000000", ""},
    };
    for (const Case& c : cases) {
        try {
            make_procedural_scene(c.spec);
            ADD_FAILURE() << "no error for '" << c.spec << "'";
        } catch (const SceneError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("'" + c.spec + "'"), std::string::npos) << what;
            if (!c.part.empty()) {
                EXPECT_NE(what.find("part '" + c.part + "'"), std::string::npos) << what;
            }
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
}

TEST(ProceduralScene, ACallerCanLowerTheTriangleLimit) {
    // sphere:100 makes 120 triangles; the fuzz target lowers the limit the same way.
    EXPECT_EQ(make_procedural_scene("sphere:100", 120).triangle_count(), 120u);
    try {
        make_procedural_scene("sphere:100", 119);
        ADD_FAILURE() << "no error above the limit";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("makes 120 triangles, more than the limit of 119"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW(make_procedural_scene("plane:5+plane:5", 99), SceneError);  // 50 + 50 in total
}

// ---- load_scene dispatch -------------------------------------------------------------------

TEST(LoadScene, SpecsAreProceduralAndGltfExtensionsAreFiles) {
    EXPECT_EQ(load_scene("sphere:10").objects.size(), 1u);
    for (const std::string path :
         {"/nonexistent/dynrt/a.gltf", "/nonexistent/dynrt/b.GLB", "/nonexistent/c.GlTf"}) {
        try {
            load_scene(path);
            ADD_FAILURE() << "no error for " << path;
        } catch (const SceneError& e) {
            EXPECT_NE(std::string(e.what()).find(path + ": no such file"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(load_scene("model.obj"), SceneError);
}

// ---- check_scene ---------------------------------------------------------------------------

Scene one_triangle_scene() {
    Scene scene;
    scene.source = "hand-made";
    scene.materials.push_back(Material{});
    Object object;
    object.name = "tri";
    object.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    object.mesh.triangles = {{0, 1, 2}};
    scene.objects.push_back(object);
    return scene;
}

void expect_check_error(const Scene& scene, const std::string& fragment) {
    try {
        check_scene(scene);
        ADD_FAILURE() << "no error, expected " << fragment;
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("hand-made: "), std::string::npos) << e.what();
    }
}

TEST(CheckScene, AcceptsAValidScene) { EXPECT_NO_THROW(check_scene(one_triangle_scene())); }

TEST(CheckScene, RejectsBrokenScenesNamingTheObject) {
    Scene scene = one_triangle_scene();
    scene.objects[0].mesh.triangles.edit()[0].z = 3;
    expect_check_error(scene, "object 'tri': triangle 0 index 3 out of range");

    scene = one_triangle_scene();
    scene.objects[0].mesh.positions.edit()[1].y = std::numeric_limits<float>::quiet_NaN();
    expect_check_error(scene, "object 'tri': vertex 1 position");

    scene = one_triangle_scene();
    scene.objects[0].mesh.positions.edit()[2].x = std::numeric_limits<float>::infinity();
    expect_check_error(scene, "object 'tri': vertex 2 position");

    scene = one_triangle_scene();
    scene.objects[0].material = 1;
    expect_check_error(scene, "object 'tri': material index 1 out of range");

    scene = one_triangle_scene();
    scene.objects[0].transform[3].x = std::numeric_limits<float>::infinity();
    expect_check_error(scene, "object 'tri': transform is not finite");

    scene = one_triangle_scene();
    scene.materials.clear();
    expect_check_error(scene, "no materials");

    scene = one_triangle_scene();
    scene.objects[0].mesh.triangles.clear();
    expect_check_error(scene, "no triangles");

    scene = one_triangle_scene();
    scene.objects.clear();
    expect_check_error(scene, "no triangles");
}

TEST(CheckScene, RejectsBadWhittedTermsNamingMaterialAndObject) {
    constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
    constexpr float kInf = std::numeric_limits<float>::infinity();
    const auto with = [](auto change) {
        Scene scene = one_triangle_scene();
        scene.materials[0].name = "glass";
        change(scene.materials[0]);
        return scene;
    };
    // The limits themselves are fine: zero weights, any positive ior (also below 1).
    EXPECT_NO_THROW(check_scene(with([](Material& m) { m.ior = 0.5f; })));
    EXPECT_NO_THROW(check_scene(with([](Material& m) {
        m.reflectance = glm::vec3(0.0f, 0.5f, 1.0f);
        m.transmittance = glm::vec3(1.0f);
        m.ior = 2.4f;
    })));

    expect_check_error(with([&](Material& m) { m.reflectance.y = kNaN; }),
                       "object 'tri': material 'glass' (index 0): reflectance (0, nan, 0) must be finite and >= 0");
    expect_check_error(with([&](Material& m) { m.reflectance.z = -0.25f; }),
                       "object 'tri': material 'glass' (index 0): reflectance (0, 0, -0.25) must be finite and >= 0");
    expect_check_error(with([&](Material& m) { m.transmittance.x = kInf; }),
                       "object 'tri': material 'glass' (index 0): transmittance (inf, 0, 0) must be finite and >= 0");
    expect_check_error(with([&](Material& m) { m.transmittance = glm::vec3(-1.0f); }),
                       "object 'tri': material 'glass' (index 0): transmittance (-1, -1, -1) must be finite and >= 0");
    expect_check_error(with([&](Material& m) { m.ior = 0.0f; }),
                       "object 'tri': material 'glass' (index 0): ior 0 must be finite and > 0");
    expect_check_error(with([&](Material& m) { m.ior = -1.5f; }),
                       "object 'tri': material 'glass' (index 0): ior -1.5 must be finite and > 0");
    expect_check_error(with([&](Material& m) { m.ior = kNaN; }),
                       "object 'tri': material 'glass' (index 0): ior nan must be finite and > 0");
    expect_check_error(with([&](Material& m) { m.ior = kInf; }),
                       "object 'tri': material 'glass' (index 0): ior inf must be finite and > 0");

    // A material no object uses yet is checked too, named without an object.
    Scene unused = one_triangle_scene();
    Material spare;
    spare.name = "spare";
    spare.ior = 0.0f;
    unused.materials.push_back(spare);
    try {
        check_scene(unused);
        ADD_FAILURE() << "an unused material with ior 0 passed";
    } catch (const SceneError& e) {
        EXPECT_EQ(std::string(e.what()), "hand-made: material 'spare' (index 1): ior 0 must be finite and > 0");
    }
}

}  // namespace
}  // namespace dynrt
