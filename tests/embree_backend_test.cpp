// Embree behind the trace seam (dynrt/embree/embree_backend.h): the same frames rendered with
// Embree's hits must agree with dynrt's on all but edge pixels, in every mode the seam serves
// (full frames, exact reuse, adaptive sampling, reflection and refraction rays, animated
// frames whose geometry each update reloads), and the check itself must catch a backend that
// answers wrongly. A backend that is not bit-identical is checked this way: the counts of
// pixels whose hit object differs, against a bound.

#include <gtest/gtest.h>

#if DYNRT_HAVE_EMBREE

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/bench/hit_agreement.h"
#include "dynrt/embree/embree_backend.h"
#include "dynrt/embree/embree_tracer.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace dynrt::embree {
namespace {

/// Pixels whose object or colour differ between two renders of the same frame.
struct FrameDifference {
    std::size_t object = 0;  ///< hit/miss or object differs
    std::size_t color = 0;   ///< a channel differs by more than 2/255
};

FrameDifference difference(const RenderedFrame& a, const RenderedFrame& b) {
    FrameDifference d;
    d.object = compare_hits(a.object, a.prim, b.object, b.prim).object_differs;
    for (std::size_t p = 0; p < a.color.size(); ++p) {
        const glm::vec3 delta = glm::abs(a.color[p] - b.color[p]);
        d.color += std::max(delta.x, std::max(delta.y, delta.z)) > 2.0f / 255.0f;
    }
    return d;
}

/// Renders frames first..last of `scene` with dynrt and with `backend`, and checks every
/// frame's differences against `max_fraction` of the pixels. Returns the last frame's figures
/// (dynrt's).
FrameStats expect_agreement(const Scene& scene, const Camera& camera, RenderOptions options, int first,
                      int last, const std::function<std::shared_ptr<FrameBackend>()>& backend,
                      double max_fraction, const std::string& what) {
    SCOPED_TRACE(what);
    options.hit_buffers = true;
    Renderer dynrt_renderer(options);
    options.backend = backend;
    Renderer other_renderer(options);
    const std::size_t pixels = std::size_t(options.width) * std::size_t(options.height);
    FrameStats last_stats;
    for (int f = first; f <= last; ++f) {
        RenderedFrame ours, theirs;
        dynrt_renderer.render(scene, camera, f, ours);
        other_renderer.render(scene, camera, f, theirs);
        EXPECT_EQ(theirs.stats.backend, backend()->name());
        EXPECT_GT(theirs.stats.backend_load_ms, 0.0);
        EXPECT_EQ(ours.stats.backend, "dynrt");
        EXPECT_EQ(theirs.stats.primary_rays, ours.stats.primary_rays);
        const FrameDifference d = difference(ours, theirs);
        EXPECT_LE(double(d.object), max_fraction * double(pixels)) << "frame " << f;
        EXPECT_LE(double(d.color), max_fraction * double(pixels)) << "frame " << f;
        EXPECT_NEAR(double(theirs.stats.reflection_rays), double(ours.stats.reflection_rays),
                    max_fraction * double(pixels)) << "frame " << f;
        last_stats = ours.stats;
    }
    return last_stats;
}

Scene whitted_scene() {
    Scene scene = load_scene("plane:4@0,-1,0,4+sphere:2000@0.9,-0.2,0,0.8+sphere:800@-1.2,-0.4,-1,0.6");
    scene.materials.resize(3);
    scene.materials[0].reflectance = glm::vec3(0.6f);
    scene.materials[1].diffuse = glm::vec3(0.02f);
    scene.materials[1].transmittance = glm::vec3(0.9f);
    scene.materials[1].ior = 1.5f;
    scene.materials[2].diffuse = glm::vec3(0.8f, 0.2f, 0.1f);
    for (std::size_t i = 0; i < scene.objects.size(); ++i) scene.objects[i].material = std::uint32_t(i);
    return scene;
}

Camera looking_at(const Scene& scene) { return default_camera(scene_bounds(scene)); }

RenderOptions small_options() {
    RenderOptions options;
    options.width = 120;
    options.height = 90;
    return options;
}

const auto kMedium = [] { return make_embree_backend(BuildQuality::medium); };

TEST(EmbreeBackend, FullFramesAgreeOnAllButEdgePixels) {
    const Scene scene = load_scene("sphere:20000");
    expect_agreement(scene, looking_at(scene), small_options(), 0, 0, kMedium, 0.005, "sphere");
}

TEST(EmbreeBackend, ReflectionsAndRefractionsAgree) {
    const Scene scene = whitted_scene();
    RenderOptions options = small_options();
    options.secondary.max_depth = 4;
    // A miss here and there in a reflection changes its pixel's colour: a looser bound.
    const FrameStats stats = expect_agreement(scene, looking_at(scene), options, 0, 0, kMedium, 0.02, "whitted");
    EXPECT_GT(stats.reflection_rays, 1000u);
    EXPECT_GT(stats.refraction_rays, 100u);
}

TEST(EmbreeBackend, AnimatedFramesReloadTheirGeometry) {
    Scene scene = load_scene("sphere:20000");
    const std::vector<std::string> wave = {"wave"};
    anim::add_procedural_motions(scene, wave);
    RenderOptions options = small_options();
    options.reuse.mode = PixelReuse::exact;
    for (const BuildQuality q : {BuildQuality::refit, BuildQuality::low}) {
        expect_agreement(scene, looking_at(scene), options, 0, 3, [q] { return make_embree_backend(q); },
                         0.005, embree_backend_name(q) + ", exact reuse");
    }
    options.reuse.mode = PixelReuse::off;
    options.adaptive_tolerance = 0.02f;
    expect_agreement(scene, looking_at(scene), options, 0, 1, kMedium, 0.02, "adaptive");
}

/// A backend that answers wrongly: Embree's hits with every other lane's lost.
class LosingBackend final : public FrameBackend {
public:
    std::string name() const override { return "losing"; }
    double load(const Scene& scene, const FrameGeometry& geometry) override {
        return inner_->load(scene, geometry);
    }
    void forget() override { inner_->forget(); }
    int closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                TraceWork* work) const override {
        const int packed = inner_->closest(rays, coherence, hits, work);
        rays.active.for_each([&](int lane) {
            if (lane % 2 == 1) hits[lane] = bvh::InstanceHit{};
        });
        return packed;
    }
    packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence,
                              TraceWork* work) const override {
        return inner_->occluded(rays, coherence, work);
    }

private:
    std::shared_ptr<FrameBackend> inner_ = make_embree_backend(BuildQuality::medium);
};

TEST(EmbreeBackend, TheCheckCatchesABackendThatLosesHits) {
    const Scene scene = load_scene("sphere:20000");
    RenderOptions options = small_options();
    options.hit_buffers = true;
    RenderedFrame ours, theirs;
    Renderer(options).render(scene, looking_at(scene), 0, ours);
    options.backend = [] { return std::make_shared<LosingBackend>(); };
    Renderer(options).render(scene, looking_at(scene), 0, theirs);
    const std::size_t pixels = std::size_t(options.width) * std::size_t(options.height);
    EXPECT_GT(difference(ours, theirs).object, pixels / 20);  // ten times any bound above
}

// Copies share one mesh in dynrt, but Embree would hold each in full: a scene of a hundred
// billion instanced triangles is refused by name before anything is posed, and a small one
// passes the same check.
TEST(EmbreeBackend, AScenePastTheMemoryItWouldFlattenToIsRefusedByName) {
    Scene scene = load_scene("sphere:200");
    scene.source = "huge forest";
    std::vector<glm::uvec3> corners(1'000'000, scene.objects[0].mesh.triangles[0]);
    scene.objects[0].mesh.triangles = std::move(corners);
    const Object copy = scene.objects[0];
    scene.objects.resize(100'000, copy);
    try {
        check_embree_fits(scene);
        ADD_FAILURE() << "accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("huge forest"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("100000000000 triangles"), std::string::npos) << e.what();
    }
    EXPECT_NO_THROW(check_embree_fits(load_scene("sphere:200*4")));
}

}  // namespace
}  // namespace dynrt::embree

#endif  // DYNRT_HAVE_EMBREE
