// Texture lookups per second (issue 35): dynrt's TextureSet (its own MIP pyramid and SIMD
// trilinear filter, textures/texture_filter.h) against OpenImageIO's TextureSystem, which it
// replaced, on the same 1024x1024 8-bit image and the same lookups: tiles of 16x16 lookups on
// a grid `footprint` texels apart, each over a footprint that wide (0.5: magnified; 1.5, 3 and
// 6: minified, blending two MIP levels), as a tile of camera-ray hits on a textured surface
// asks for them. The TextureSystem is timed at its fastest single-lookup call (a texture
// handle and this thread's Perthread, no name resolution) and as dynrt called it before
// (handle only).

#include "dynrt/engine/texture_set.h"

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

constexpr int kSide = 1024;
constexpr int kTile = 256;

const std::string& texture_file() {
    static const std::string path = [] {
        const std::string p = (std::filesystem::temp_directory_path() /
                               ("dynrt_bm_textures_" + std::to_string(::getpid()) + ".png"))
                                  .string();
        std::vector<std::uint8_t> texels(std::size_t(kSide) * kSide * 3);
        std::mt19937 random(1);
        for (std::uint8_t& v : texels) v = std::uint8_t(random() & 0xff);
        auto out = OIIO::ImageOutput::create(p);
        out->open(p, OIIO::ImageSpec(kSide, kSide, 3, OIIO::TypeDesc::UINT8));
        out->write_image(OIIO::TypeDesc::UINT8, texels.data());
        out->close();
        return p;
    }();
    return path;
}

/// Tiles of lookups: 16x16 on a grid `footprint` texels apart, each tile somewhere else.
struct Lookups {
    std::vector<float> s, t, width;
    explicit Lookups(float footprint) {
        std::mt19937 random(2);
        std::uniform_real_distribution<float> corner(0.0f, 1.0f);
        const float step = footprint / float(kSide);
        for (int tile = 0; tile < 64; ++tile) {
            const float s0 = corner(random), t0 = corner(random);
            for (int y = 0; y < 16; ++y) {
                for (int x = 0; x < 16; ++x) {
                    s.push_back(s0 + float(x) * step);
                    t.push_back(t0 + float(y) * step);
                    width.push_back(step);
                }
            }
        }
    }
};

dynrt::Scene textured_scene() {
    dynrt::Scene scene;
    dynrt::Material m;
    m.diffuse_map = dynrt::TextureMap{0, dynrt::TextureWrap::repeat, dynrt::TextureWrap::repeat};
    scene.materials.push_back(m);
    dynrt::Texture texture;
    texture.name = texture.path = texture_file();
    scene.textures.push_back(texture);
    return scene;
}

float footprint_of(const benchmark::State& state) { return float(state.range(0)) / 2.0f; }

void BM_DynrtTiles(benchmark::State& state) {
    const dynrt::TextureSet set(textured_scene());
    const Lookups lookups(footprint_of(state));
    std::vector<float> rgb[3];
    for (auto& c : rgb) c.resize(kTile);
    float* const out[3] = {rgb[0].data(), rgb[1].data(), rgb[2].data()};
    std::size_t done = 0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < lookups.s.size(); i += kTile) {
            set.diffuse(0, kTile, &lookups.s[i], &lookups.t[i], &lookups.width[i], out);
            benchmark::DoNotOptimize(rgb[0][0]);
        }
        done += lookups.s.size();
    }
    state.SetItemsProcessed(std::int64_t(done));
}

void BM_DynrtOneAtATime(benchmark::State& state) {
    const dynrt::TextureSet set(textured_scene());
    const Lookups lookups(footprint_of(state));
    std::size_t done = 0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < lookups.s.size(); ++i) {
            benchmark::DoNotOptimize(set.diffuse(0, {lookups.s[i], lookups.t[i]}, lookups.width[i]));
        }
        done += lookups.s.size();
    }
    state.SetItemsProcessed(std::int64_t(done));
}

void oiio_lookups(benchmark::State& state, bool perthread) {
    OIIO::TextureSystem* system = OIIO::TextureSystem::create(false);
    system->attribute("automip", 1);
    system->attribute("autotile", 64);
    system->attribute("gray_to_rgb", 1);
    OIIO::TextureSystem::TextureHandle* handle = system->get_texture_handle(OIIO::ustring(texture_file()));
    OIIO::TextureSystem::Perthread* thread = perthread ? system->get_perthread_info() : nullptr;
    OIIO::TextureOpt options;
    options.swrap = options.twrap = OIIO::TextureOpt::WrapPeriodic;
    options.mipmode = OIIO::TextureOpt::MipModeTrilinear;
    options.interpmode = OIIO::TextureOpt::InterpBilinear;
    const Lookups lookups(footprint_of(state));
    std::size_t done = 0;
    float rgb[3];
    for (auto _ : state) {
        for (std::size_t i = 0; i < lookups.s.size(); ++i) {
            const float w = lookups.width[i];
            system->texture(handle, thread, options, lookups.s[i], lookups.t[i], w, 0.0f, 0.0f, w, 3, rgb);
            benchmark::DoNotOptimize(rgb[0]);
        }
        done += lookups.s.size();
    }
    state.SetItemsProcessed(std::int64_t(done));
    // Never destroyed: Debian's OpenImageIO 2.4 frees a system with a mismatched sized delete.
}

void BM_OiioHandleAndPerthread(benchmark::State& state) { oiio_lookups(state, true); }
void BM_OiioHandleAsDynrtDid(benchmark::State& state) { oiio_lookups(state, false); }

// Footprints in half texels: 1 (0.5 texel), 3, 6, 12.
#define FOOTPRINTS ->Arg(1)->Arg(3)->Arg(6)->Arg(12)->Unit(benchmark::kMicrosecond)
BENCHMARK(BM_DynrtTiles) FOOTPRINTS;
BENCHMARK(BM_DynrtOneAtATime) FOOTPRINTS;
BENCHMARK(BM_OiioHandleAndPerthread) FOOTPRINTS;
BENCHMARK(BM_OiioHandleAsDynrtDid) FOOTPRINTS;

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::filesystem::remove(texture_file());
    return 0;
}
