// TextureSet (texture_set.h): every mapped texture decoded and MIP-mapped at construction,
// textures in parallel (texture_decode.h, mip_pyramid.h); lookups are dynrt's own SIMD
// trilinear filter (texture_filter.h), with no lock, cache or name resolution per call.

#include "dynrt/engine/texture_set.h"

#include "dynrt/packet/simd.h"
#include "dynrt/scene/warnings.h"
#include "textures/mip_pyramid.h"
#include "textures/texture_decode.h"
#include "textures/texture_filter.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace dynrt {

struct TextureSet::Impl {
    /// One scene texture, read (or not).
    struct Entry {
        std::optional<textures::MipPyramid> pyramid;
        bool srgb = true;
        std::string problem;  ///< why it cannot be read
    };
    /// One material's map, when it has a usable one (TextureSet::usable_).
    struct Map {
        std::size_t texture = 0;
        TextureWrap wrap_s = TextureWrap::repeat, wrap_t = TextureWrap::repeat;
    };

    std::vector<Entry> textures;
    std::vector<Map> materials;
    std::vector<std::string> warnings;
    double load_seconds = 0.0;
};

bool TextureSet::needed(const Scene& scene) {
    return std::any_of(scene.materials.begin(), scene.materials.end(),
                       [](const Material& m) { return m.diffuse_map.has_value() || m.emission_map.has_value(); });
}

TextureSet::TextureSet(const Scene& scene, bool print_warnings) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    const auto start = std::chrono::steady_clock::now();
    s.textures.resize(scene.textures.size());
    // Slot k < M: material k's diffuse map; M + k: its emission map.
    material_count_ = scene.materials.size();
    s.materials.resize(2 * material_count_);
    usable_.assign(2 * material_count_, 0);
    const auto map_of = [&](std::size_t k) -> const std::optional<TextureMap>& {
        const Material& material = scene.materials[k % material_count_];
        return k < material_count_ ? material.diffuse_map : material.emission_map;
    };
    // The textures some material maps, each read once, in parallel.
    std::vector<std::size_t> mapped;
    for (std::size_t k = 0; k < 2 * material_count_; ++k) {
        if (map_of(k) && map_of(k)->texture < scene.textures.size()) mapped.push_back(map_of(k)->texture);
    }
    std::sort(mapped.begin(), mapped.end());
    mapped.erase(std::unique(mapped.begin(), mapped.end()), mapped.end());
    tbb::parallel_for(std::size_t(0), mapped.size(), [&](std::size_t k) {
        const Texture& texture = scene.textures[mapped[k]];
        Impl::Entry& entry = s.textures[mapped[k]];
        entry.srgb = texture.srgb;
        const TexelArray texels = textures::decode_texture(texture, entry.problem);
        if (entry.problem.empty()) entry.pyramid.emplace(texels);
    });
    s.load_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (std::size_t m = 0; m < 2 * material_count_; ++m) {
        const Material& material = scene.materials[m % material_count_];
        if (!map_of(m)) continue;
        const TextureMap& map = *map_of(m);
        Warning warning{.source = scene.source,
                        .kind = "texture cannot be read",
                        .kinds = "textures cannot be read",
                        .item = "index " + std::to_string(map.texture),
                        .user = "material '" + material.name + "'",
                        .users = "materials",
                        .detail = "no such texture",
                        .effect = m < material_count_ ? "the diffuse colour is used alone"
                                                      : "the emission factor is used alone"};
        if (map.texture < scene.textures.size()) {
            const Texture& texture = scene.textures[map.texture];
            warning.item = texture.path.empty() ? "'" + texture.name + "'" : texture.path;
            // A missing file is said so in the same words for every one (decode_texture's
            // "no such file"), so that a scene whose texture folder is absent gets one line
            // (WarningLog groups by reason).
            warning.detail = s.textures[map.texture].problem;
        }
        if (!warning.detail.empty()) {
            s.warnings.push_back(warning_line(warning));
            if (print_warnings) warn(std::move(warning));
            continue;
        }
        Impl::Map& out = s.materials[m];
        usable_[m] = 1;
        any_emission_ = any_emission_ || m >= material_count_;
        out.texture = map.texture;
        out.wrap_s = map.wrap_s;
        out.wrap_t = map.wrap_t;
    }
}

TextureSet::~TextureSet() = default;


glm::vec3 TextureSet::diffuse(std::uint32_t material, glm::vec2 st, float width) const {
    return one(index(material, TextureSlot::diffuse), st, width);
}

glm::vec3 TextureSet::emission(std::uint32_t material, glm::vec2 st, float width) const {
    return one(index(material, TextureSlot::emission), st, width);
}

glm::vec3 TextureSet::one(std::size_t k, glm::vec2 st, float width) const {
    // One lane: the same operations as every lane of the batch's vectors, so the same bits
    // (texture_filter_test.cpp checks it).
    const Impl::Map& map = impl_->materials[k];
    const Impl::Entry& entry = impl_->textures[map.texture];
    glm::vec3 rgb;
    float* const out[3] = {&rgb.x, &rgb.y, &rgb.z};
    textures::trilinear_lookup<1>(*entry.pyramid, map.wrap_s, map.wrap_t, entry.srgb, &st.x, &st.y, &width, out);
    return rgb;
}

float TextureSet::alpha(std::uint32_t material, glm::vec2 st) const {
    const Impl::Map& map = impl_->materials[index(material, TextureSlot::diffuse)];
    const textures::MipPyramid& pyramid = *impl_->textures[map.texture].pyramid;
    using Filter = textures::TrilinearFilter<1>;
    float value;
    Filter::L::store(&value, Filter::alpha(pyramid, map.wrap_s, map.wrap_t, Filter::L::load(&st.x),
                                           Filter::L::load(&st.y)));
    return value;
}

void TextureSet::lookup(TextureSlot slot, std::uint32_t material, std::size_t count, const float* s, const float* t,
                        const float* width, float* const rgb[3]) const {
    const Impl::Map& map = impl_->materials[index(material, slot)];
    const Impl::Entry& entry = impl_->textures[map.texture];
    const textures::MipPyramid& pyramid = *entry.pyramid;
    constexpr int W = packet::simd::kNativeLanes;
    using Batch = textures::TrilinearBatch<W>;
    thread_local Batch batch;
    std::size_t i = 0;
    // Whole batches, then what is left in whole vectors.
    while (i + W <= count) {
        const int n = int(std::min<std::size_t>(Batch::kMax, (count - i) / W * W));
        float* const out[3] = {rgb[0] + i, rgb[1] + i, rgb[2] + i};
        batch.run(pyramid, map.wrap_s, map.wrap_t, entry.srgb, n, s + i, t + i, width + i, out);
        i += std::size_t(n);
    }
    if (i == count) return;
    // The last lookups, padded to a full vector with copies of the last of them.
    alignas(64) float pad[3][W], result[3][W];
    for (int lane = 0; lane < W; ++lane) {
        const std::size_t from = i + std::min<std::size_t>(std::size_t(lane), count - i - 1);
        pad[0][lane] = s[from];
        pad[1][lane] = t[from];
        pad[2][lane] = width[from];
    }
    float* const out[3] = {result[0], result[1], result[2]};
    batch.run(pyramid, map.wrap_s, map.wrap_t, entry.srgb, W, pad[0], pad[1], pad[2], out);
    for (std::size_t k = i; k < count; ++k) {
        for (int c = 0; c < 3; ++c) rgb[c][k] = result[c][k - i];
    }
}

std::size_t TextureSet::bytes() const {
    std::size_t bytes = 0;
    for (const Impl::Entry& entry : impl_->textures) {
        if (entry.pyramid) bytes += entry.pyramid->bytes();
    }
    return bytes;
}

std::size_t TextureSet::texture_count() const {
    return std::size_t(std::count_if(impl_->textures.begin(), impl_->textures.end(),
                                     [](const Impl::Entry& entry) { return entry.pyramid.has_value(); }));
}

double TextureSet::load_seconds() const { return impl_->load_seconds; }

const std::vector<std::string>& TextureSet::warnings() const { return impl_->warnings; }

}  // namespace dynrt
