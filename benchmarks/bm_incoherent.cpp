// Incoherent rays through the library API (issue 17's single-ray target): 1M rays from random
// points inside the scene's bounds in random directions, as a lidar in a crowded scene or a
// diffuse bounce would cast them, traced by dynrt::Engine::intersect and ::occluded (the
// public API, all cores) and by Embree 3's rtcIntersect1 and rtcOccluded1 over the very same
// rays, in parallel chunks of 256 on the same oneTBB arena. Embree builds at
// RTC_BUILD_QUALITY_HIGH (its best trees; the build is not timed) and traces with an incoherent
// context, its recommended setup for such rays. Closest-hit rays are unbounded; occlusion rays
// are segments of a quarter of the scene's diagonal, so that some are occluded and some not.
// Items are rays; the counters hit_fraction (closest) and occluded_fraction let the two sides
// be checked for the same answers.

#include "bm_scenes.h"

#include "dynrt/api/engine.h"

#if DYNRT_HAVE_EMBREE
#include "bm_embree.h"
#include "dynrt/embree/embree_rays.h"
#endif

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

constexpr std::size_t kRays = 1u << 20;
constexpr std::size_t kChunk = 256;

/// The batch for one scene: origins uniform in the scene's box, directions uniform on the
/// sphere, a fixed seed so every run and both tracers see the same rays.
const std::vector<dynrt::Ray>& incoherent_rays(const SceneInput& input, bool segments) {
    static std::map<std::pair<std::string, bool>, std::vector<dynrt::Ray>> cache;
    std::vector<dynrt::Ray>& rays = cache[{input.spec, segments}];
    if (!rays.empty()) return rays;
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    const glm::vec3 lo = input.bounds.lo, hi = input.bounds.hi;
    const float length = 0.25f * glm::length(hi - lo);
    rays.resize(kRays);
    for (dynrt::Ray& r : rays) {
        const glm::vec3 o = lo + glm::vec3(unit(rng), unit(rng), unit(rng)) * (hi - lo);
        // Uniform on the sphere: z uniform in [-1, 1], the angle around it uniform.
        const float z = 2.0f * unit(rng) - 1.0f, phi = 6.2831853f * unit(rng);
        const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        r.origin = {o.x, o.y, o.z};
        r.direction = {s * std::cos(phi), s * std::sin(phi), z};
        r.tmin = 0.0f;
        r.tmax = segments ? length : std::numeric_limits<float>::infinity();
    }
    return rays;
}

/// An engine holding the scene's objects as static meshes, updated once.
dynrt::Engine& engine_for(const SceneInput& input) {
    static std::map<std::string, std::unique_ptr<dynrt::Engine>> cache;
    std::unique_ptr<dynrt::Engine>& engine = cache[input.spec];
    if (engine) return *engine;
    engine = std::make_unique<dynrt::Engine>();
    for (std::size_t o = 0; o < input.positions.size(); ++o) {
        if (input.indices[o].empty()) continue;
        dynrt::MeshDesc mesh;
        mesh.name = "object " + std::to_string(o);
        // input.positions carries one float of padding for Embree's 16-byte vertex loads.
        mesh.positions = std::span<const float>(input.positions[o].data(),
                                                input.positions[o].size() - 1);
        mesh.indices = input.indices[o];
        mesh.motion = dynrt::Motion::static_;
        engine->add_mesh(mesh);
    }
    engine->update();
    return *engine;
}

void BM_IncoherentDynrt(benchmark::State& state, const std::string& spec, bool any_hit) {
    const SceneInput& input = scene_input(spec);
    const std::vector<dynrt::Ray>& rays = incoherent_rays(input, any_hit);
    dynrt::Engine& engine = engine_for(input);
    std::vector<dynrt::RayHit> hits(rays.size());
    std::vector<std::uint8_t> occluded(rays.size());
    std::size_t answered = 0;
    for (auto _ : state) {
        const dynrt::QueryStats stats =
            any_hit ? engine.occluded(rays, occluded) : engine.intersect(rays, hits);
        answered = stats.hits;
        benchmark::DoNotOptimize(hits.data());
        benchmark::DoNotOptimize(occluded.data());
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
    state.counters[any_hit ? "occluded_fraction" : "hit_fraction"] =
        double(answered) / double(rays.size());
}

#if DYNRT_HAVE_EMBREE
void BM_IncoherentEmbree(benchmark::State& state, const std::string& spec, bool any_hit) {
    const SceneInput& input = scene_input(spec);
    const std::vector<dynrt::Ray>& rays = incoherent_rays(input, any_hit);
    RTCScene scene = make_embree_scene(input, false, nullptr, RTC_BUILD_QUALITY_HIGH);
    {
        const embree::EmbreeFloatMode mode;
        rtcCommitScene(scene);
    }
    std::vector<std::uint8_t> answer(rays.size());
    for (auto _ : state) {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, rays.size(), kChunk),
            [&](const tbb::blocked_range<std::size_t>& range) {
                const embree::EmbreeFloatMode mode;
                RTCIntersectContext context;
                rtcInitIntersectContext(&context);  // incoherent, Embree's default
                for (std::size_t i = range.begin(); i < range.end(); ++i) {
                    const dynrt::Ray& r = rays[i];
                    RTCRayHit rh;
                    rh.ray.org_x = r.origin.x;
                    rh.ray.org_y = r.origin.y;
                    rh.ray.org_z = r.origin.z;
                    rh.ray.dir_x = r.direction.x;
                    rh.ray.dir_y = r.direction.y;
                    rh.ray.dir_z = r.direction.z;
                    rh.ray.tnear = r.tmin;
                    rh.ray.tfar = r.tmax;
                    rh.ray.time = 0.0f;
                    rh.ray.mask = ~0u;
                    rh.ray.id = 0;
                    rh.ray.flags = 0;
                    if (any_hit) {
                        rtcOccluded1(scene, &context, &rh.ray);
                        answer[i] = rh.ray.tfar < 0.0f ? 1 : 0;
                    } else {
                        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                        rtcIntersect1(scene, &context, &rh);
                        answer[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? 1 : 0;
                    }
                }
            });
        benchmark::DoNotOptimize(answer.data());
    }
    std::size_t answered = 0;
    for (std::uint8_t a : answer) answered += a;
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(rays.size()));
    state.counters[any_hit ? "occluded_fraction" : "hit_fraction"] =
        double(answered) / double(rays.size());
    rtcReleaseScene(scene);
}
#endif

void register_all() {
    std::vector<std::string> specs = {"sphere:1000000", "soup:1000000", "scenes/default.gltf"};
    const std::string metal_rough =
        DYNRT_SHARED_SCENES_DIR "/metalroughspheresnotextures/MetalRoughSpheresNoTextures.glb";
    if (std::FILE* f = std::fopen(metal_rough.c_str(), "rb")) {
        std::fclose(f);
        specs.push_back(metal_rough);
    }
    for (const std::string& spec : specs) {
        const std::string name = spec.substr(spec.find_last_of('/') + 1);
        for (bool any_hit : {false, true}) {
            const std::string kind = any_hit ? "Occluded" : "Closest";
            benchmark::RegisterBenchmark(("BM_Incoherent" + kind + "Dynrt/" + name).c_str(),
                                         BM_IncoherentDynrt, spec, any_hit)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
#if DYNRT_HAVE_EMBREE
            benchmark::RegisterBenchmark(("BM_Incoherent" + kind + "Embree/" + name).c_str(),
                                         BM_IncoherentEmbree, spec, any_hit)
                ->Unit(benchmark::kMillisecond)
                ->UseRealTime();
#endif
        }
    }
}

}  // namespace
}  // namespace dynrt::bench

int main(int argc, char** argv) {
    dynrt::bench::register_all();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
