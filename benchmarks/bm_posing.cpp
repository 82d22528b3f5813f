// Posing: the milliseconds ScenePoser::pose spends writing about 1,000,000 world-space vertices
// per frame (issue 20, "posing at memory speed": <= 3 ms per frame, 2 threads). Three inputs:
//   explode: sphere:333333 (333,332 triangles unshared: 999,996 vertices) with `--anim explode`;
//   wave:    sphere:2000000 (1,000,002 shared vertices) with `--anim wave`;
//   skinned: CesiumMan (../shared/scenes/cesiumman/CesiumMan.glb) with its one skinned
//            primitive replicated in place to >= 1,000,000 vertices, playing its walk clip;
//            skipped when the file is missing.
// Every iteration poses the next frame, so every vertex changes. Counters: vertices/s (items)
// and bytes/s, counting 12 bytes read from the source positions and 12 written per vertex (a
// lower bound on the traffic: skin weights, morph deltas and per-triangle offsets come on top).
// Threads: 2 by default (the machine), or DYNRT_BM_THREADS.

#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/scene_loading.h"

#include <benchmark/benchmark.h>
#include <oneapi/tbb/task_arena.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace dynrt::bench {
namespace {

constexpr std::size_t kTargetVertices = 1000000;

int thread_count() {
    const char* text = std::getenv("DYNRT_BM_THREADS");
    const int threads = text ? std::atoi(text) : 2;
    return threads > 0 ? threads : 2;
}

Scene procedural(const std::string& spec, const std::string& motion) {
    Scene scene = make_procedural_scene(spec);
    anim::add_procedural_motions(scene, std::vector<std::string>{motion});
    return scene;
}

/// CesiumMan with its skinned object's vertices (with their influences) copied `copies` times
/// onto themselves, so one skinned object of >= kTargetVertices vertices plays the walk.
bool cesium_man_scaled(Scene& out) {
    const std::filesystem::path path =
        std::filesystem::path(DYNRT_SHARED_SCENES_DIR) / "cesiumman" / "CesiumMan.glb";
    if (!std::filesystem::exists(path)) return false;
    Scene scene = load_gltf(path);
    for (Object& object : scene.objects) {
        if (!object.skin || object.morph) continue;
        const std::size_t n = object.mesh.positions.size();
        const std::size_t copies = (kTargetVertices + n - 1) / n;
        Mesh mesh = object.mesh;
        SkinWeights skin = *object.skin;
        for (std::size_t c = 1; c < copies; ++c) {
            const auto first = static_cast<std::uint32_t>(mesh.positions.size());
            mesh.positions.insert(mesh.positions.end(), object.mesh.positions.begin(), object.mesh.positions.end());
            for (const glm::uvec3& t : object.mesh.triangles) mesh.triangles.push_back(t + first);
            skin.joints.insert(skin.joints.end(), object.skin->joints.begin(), object.skin->joints.end());
            skin.weights.insert(skin.weights.end(), object.skin->weights.begin(), object.skin->weights.end());
        }
        object.mesh = std::move(mesh);
        object.skin = std::move(skin);
        out = std::move(scene);
        return true;
    }
    return false;
}

void pose_frames(benchmark::State& state, const Scene& scene) {
    anim::PoseSettings settings;
    settings.skip_fixed_positions = true;  // as the Renderer poses
    settings.loop = true;
    const anim::ScenePoser poser(scene, settings);
    anim::PosedScene posed;
    std::size_t vertices = 0;
    for (const Object& object : scene.objects) vertices += object.mesh.positions.size();
    tbb::task_arena arena(thread_count());
    int frame = 0;
    arena.execute([&] { poser.pose(frame++, posed); });  // the first call sizes the storage
    for (auto _ : state) {
        arena.execute([&] { poser.pose(frame++, posed); });
        benchmark::DoNotOptimize(posed.objects.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * vertices));
    state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * vertices * 2 * sizeof(glm::vec3)));
    state.counters["vertices"] = static_cast<double>(vertices);
    state.counters["threads"] = thread_count();
}

void BM_PoseExplode(benchmark::State& state) {
    static const Scene scene = procedural("sphere:333333", "explode");
    pose_frames(state, scene);
}

void BM_PoseWave(benchmark::State& state) {
    static const Scene scene = procedural("sphere:2000000", "wave");
    pose_frames(state, scene);
}

void BM_PoseSkinned(benchmark::State& state) {
    static Scene scene;
    static const bool found = cesium_man_scaled(scene);
    if (!found) {
        state.SkipWithError("CesiumMan.glb not found under " DYNRT_SHARED_SCENES_DIR);
        return;
    }
    pose_frames(state, scene);
}

BENCHMARK(BM_PoseExplode)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PoseWave)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_PoseSkinned)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace dynrt::bench

BENCHMARK_MAIN();
