// The textures' figures through the library API (Engine::texture_figures): none before a render
// reads textures or without textured meshes; once read, the count, bytes and load time of the
// textures the engine's renders hold, their bytes counted in Engine::memory_bytes.

#include "api_test_world.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace dynrt::api_test {
namespace {

constexpr int kFiguresWidth = 32, kFiguresHeight = 24;
const View kFiguresView{{0.0f, 0.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, 50.0f};

/// A `size` x `size` gradient written as a PNG in the test's temporary folder; its path.
std::string write_gradient(const std::string& name, int size) {
    std::vector<float> rgb;
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) rgb.insert(rgb.end(), {float(x) / float(size), float(y) / float(size), 0.5f});
    }
    const std::string path = (std::filesystem::path(testing::TempDir()) / name).string();
    save_image(path, size, size, rgb);
    return path;
}

/// An engine with two sheets, both mapping `texture` when it is valid, updated and rendered.
struct SheetsEngine {
    Engine engine;
    MeshData left = sheet(-1.1f, 0.0f, 0.0f, 2.0f, 4), right = sheet(1.1f, 0.0f, 0.0f, 2.0f, 4);

    explicit SheetsEngine(const std::string& texture_path) {
        TextureId texture;
        if (!texture_path.empty()) texture = engine.add_texture(TextureDesc{.path = texture_path});
        for (const MeshData* mesh : {&left, &right}) {
            std::vector<float> st;
            for (std::size_t v = 0; v < mesh->vertices(); ++v) {
                st.insert(st.end(), {mesh->positions[3 * v], mesh->positions[3 * v + 1]});
            }
            MeshDesc desc;
            desc.positions = mesh->positions;
            desc.indices = mesh->indices;
            desc.texcoords = st;
            desc.motion = Motion::static_;
            desc.surface.diffuse_texture = texture;
            engine.add_mesh(desc);
        }
        engine.update();
    }

    void render() {
        std::vector<float> rgb(std::size_t(kFiguresWidth * kFiguresHeight * 3));
        engine.render(kFiguresView, ImageView{kFiguresWidth, kFiguresHeight, rgb});
    }
};

TEST(ApiTextureFigures, NoneBeforeARenderReadsThemOrWithoutTextures) {
    SheetsEngine textured(write_gradient("api_figures_before.png", 8));
    EXPECT_EQ(textured.engine.texture_figures(), TextureFigures{}) << "textures are read at the first render";
    SheetsEngine plain("");
    plain.render();
    EXPECT_EQ(plain.engine.texture_figures(), TextureFigures{});
}

// One texture (mapped by both sheets) read by the first render, its
// bytes in memory_bytes: the textured engine holds at least them more than the same engine
// with untextured sheets (the rest of the difference is a few small records).
TEST(ApiTextureFigures, TheTextureReadIsCountedOnceAndItsBytesAreInMemoryBytes) {
    constexpr int kSize = 256;
    SheetsEngine textured(write_gradient("api_figures_read.png", kSize));
    SheetsEngine plain("");
    textured.render();
    plain.render();
    const TextureFigures figures = textured.engine.texture_figures();
    EXPECT_EQ(figures.count, 1u);
    EXPECT_GE(figures.bytes, std::size_t(kSize) * kSize * 3);
    EXPECT_GT(figures.load_ms, 0.0);
    const std::size_t with = textured.engine.memory_bytes(), without = plain.engine.memory_bytes();
    ASSERT_GT(with, without);
    EXPECT_GE(with - without, figures.bytes);
    textured.render();
    EXPECT_EQ(textured.engine.texture_figures(), figures) << "read once, not per render";
}

}  // namespace
}  // namespace dynrt::api_test
