// TextureSet over OpenImageIO's TextureSystem (texture_set.h). Files are opened by name;
// embedded images (glTF data: URIs and bufferViews) through an in-memory IOProxy registered
// with the texture system's image cache under a name of their own, whose extension tells
// OpenImageIO the format.

#include "dynrt/engine/texture_set.h"

#include "dynrt/scene/warnings.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <string>
#include <system_error>
#include <vector>

namespace dynrt {

namespace {

OIIO::TextureOpt::Wrap wrap_of(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::clamp: return OIIO::TextureOpt::WrapClamp;
        case TextureWrap::mirror: return OIIO::TextureOpt::WrapMirror;
        case TextureWrap::repeat: break;
    }
    return OIIO::TextureOpt::WrapPeriodic;
}

/// The file extension OpenImageIO picks a reader by, for an embedded image's MIME type.
std::string extension_of(const std::string& mime_type) {
    if (mime_type == "image/png") return ".png";
    if (mime_type == "image/jpeg" || mime_type == "image/jpg") return ".jpg";
    if (mime_type == "image/bmp") return ".bmp";
    if (mime_type == "image/gif") return ".gif";
    if (mime_type == "image/webp") return ".webp";
    if (mime_type == "image/ktx2") return ".ktx2";
    return ".png";  // glTF allows PNG and JPEG; a wrong guess fails to read and is reported
}

/// IEC 61966-2-1's decoding: sRGB-encoded value -> linear.
float srgb_decode(float encoded) {
    const float c = std::clamp(encoded, 0.0f, 1.0f);
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

std::string one_line(std::string text) {
    std::replace(text.begin(), text.end(), '\n', ' ');
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? std::string("no reason given") : text;
}

/// Texture systems are pooled, never destroyed: Debian's OpenImageIO 2.4 frees one in
/// TextureSystem::destroy with a sized delete of the wrong size (AddressSanitizer's
/// new-delete-type-mismatch, inside the library). A set takes a system from the pool and gives
/// it back emptied (every file closed and forgotten), so the pool holds as many systems as
/// sets were ever alive at once, reachable from here to the end of the process.
class SystemPool {
public:
    static OIIO::TextureSystem* take() {
        SystemPool& pool = instance();
        {
            const std::lock_guard<std::mutex> lock(pool.mutex_);
            if (!pool.free_.empty()) {
                OIIO::TextureSystem* system = pool.free_.back();
                pool.free_.pop_back();
                return system;
            }
        }
        OIIO::TextureSystem* system = OIIO::TextureSystem::create(false);
        // Images without MIP levels (PNG, JPEG) get them made on first use, in tiles.
        system->attribute("automip", 1);
        system->attribute("autotile", 64);
        system->attribute("gray_to_rgb", 1);
        const std::lock_guard<std::mutex> lock(pool.mutex_);
        pool.all_.push_back(system);
        return system;
    }

    static void give_back(OIIO::TextureSystem* system) {
        // Closes and forgets every file, so a later set reads files afresh and no embedded
        // image's proxy (freed with its set) is touched again.
        system->invalidate_all(true);
        SystemPool& pool = instance();
        const std::lock_guard<std::mutex> lock(pool.mutex_);
        pool.free_.push_back(system);
    }

private:
    static SystemPool& instance() {
        // Never destroyed either: the systems stay reachable (no leak report) to the end.
        static SystemPool* const pool = new SystemPool;
        return *pool;
    }
    std::mutex mutex_;
    std::vector<OIIO::TextureSystem*> all_, free_;
};

}  // namespace

struct TextureSet::Impl {
    /// One scene texture, opened.
    struct Entry {
        OIIO::TextureSystem::TextureHandle* handle = nullptr;
        bool srgb = true;
        bool usable = false;
        std::string problem;  ///< why it cannot be read
        /// An embedded image: its bytes and the proxy OpenImageIO reads them through (both
        /// outlive their use: the set empties its texture system before they go).
        std::vector<unsigned char> bytes;
        std::unique_ptr<OIIO::Filesystem::IOMemReader> proxy;
    };
    /// One material's map, when it has a usable one.
    struct Map {
        bool usable = false;
        std::size_t texture = 0;
        OIIO::TextureOpt::Wrap swrap = OIIO::TextureOpt::WrapPeriodic, twrap = OIIO::TextureOpt::WrapPeriodic;
    };

    std::vector<Entry> textures;
    std::vector<Map> materials;
    std::vector<std::string> warnings;
    OIIO::TextureSystem* system = nullptr;

    ~Impl() {
        if (system != nullptr) SystemPool::give_back(system);
    }

    /// Opens scene texture i (once), reading its header to learn whether it can be read.
    void open(const Scene& scene, std::size_t i) {
        Entry& entry = textures[i];
        if (entry.handle != nullptr || !entry.problem.empty()) return;
        const Texture& texture = scene.textures[i];
        entry.srgb = texture.srgb;
        std::string name = texture.path;
        if (name.empty()) {
            if (texture.encoded.empty()) {
                entry.problem = "the file holds no bytes for it";
                return;
            }
            // A name no file has, numbered per set, so that two sets (a renderer's and the
            // reference's) never share a cache entry.
            static std::atomic<std::uint64_t> sets{0};
            name = "dynrt-embedded-" + std::to_string(++sets) + "-" + std::to_string(i) +
                   extension_of(texture.mime_type);
            entry.bytes = texture.encoded;
            entry.proxy = std::make_unique<OIIO::Filesystem::IOMemReader>(entry.bytes.data(), entry.bytes.size());
            OIIO::ImageSpec config;
            OIIO::Filesystem::IOProxy* proxy = entry.proxy.get();
            config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
            system->imagecache()->add_file(OIIO::ustring(name), nullptr, &config);
        }
        entry.handle = system->get_texture_handle(OIIO::ustring(name));
        int channels = 0;
        if (entry.handle == nullptr ||
            !system->get_texture_info(entry.handle, nullptr, 0, OIIO::ustring("channels"), OIIO::TypeInt, &channels) ||
            channels < 1) {
            entry.problem = one_line(system->geterror());
            return;
        }
        entry.usable = true;
    }
};

bool TextureSet::needed(const Scene& scene) {
    return std::any_of(scene.materials.begin(), scene.materials.end(),
                       [](const Material& m) { return m.diffuse_map.has_value(); });
}

TextureSet::TextureSet(const Scene& scene, bool print_warnings) : impl_(std::make_unique<Impl>()) {
    Impl& s = *impl_;
    s.system = SystemPool::take();
    s.textures.resize(scene.textures.size());
    s.materials.resize(scene.materials.size());
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& material = scene.materials[m];
        if (!material.diffuse_map) continue;
        const TextureMap& map = *material.diffuse_map;
        Warning warning{.source = scene.source,
                        .kind = "texture cannot be read",
                        .kinds = "textures cannot be read",
                        .item = "index " + std::to_string(map.texture),
                        .user = "material '" + material.name + "'",
                        .users = "materials",
                        .detail = "no such texture",
                        .effect = "the diffuse colour is used alone"};
        if (map.texture < scene.textures.size()) {
            s.open(scene, map.texture);
            const Texture& texture = scene.textures[map.texture];
            warning.item = texture.path.empty() ? "'" + texture.name + "'" : texture.path;
            warning.detail.clear();
            if (!s.textures[map.texture].usable) {
                // A missing file is said so, in the same words for every one, so that a scene
                // whose texture folder is absent gets one line (WarningLog groups by reason).
                std::error_code ignored;
                warning.detail = !texture.path.empty() && !std::filesystem::exists(texture.path, ignored)
                                     ? "no such file"
                                     : s.textures[map.texture].problem;
            }
        }
        if (!warning.detail.empty()) {
            s.warnings.push_back(warning_line(warning));
            if (print_warnings) warn(std::move(warning));
            continue;
        }
        Impl::Map& out = s.materials[m];
        out.usable = true;
        out.texture = map.texture;
        out.swrap = wrap_of(map.wrap_s);
        out.twrap = wrap_of(map.wrap_t);
    }
}

TextureSet::~TextureSet() = default;

bool TextureSet::maps(std::uint32_t material) const {
    return material < impl_->materials.size() && impl_->materials[material].usable;
}

glm::vec3 TextureSet::diffuse(std::uint32_t material, glm::vec2 st, float width) const {
    const Impl::Map& map = impl_->materials[material];
    const Impl::Entry& entry = impl_->textures[map.texture];
    OIIO::TextureOpt options;
    options.swrap = map.swrap;
    options.twrap = map.twrap;
    options.mipmode = OIIO::TextureOpt::MipModeTrilinear;
    options.interpmode = OIIO::TextureOpt::InterpBilinear;
    options.fill = 1.0f;
    float rgb[3] = {1.0f, 1.0f, 1.0f};
    // An isotropic footprint: d(s, t)/dx = (width, 0), d(s, t)/dy = (0, width).
    if (!impl_->system->texture(entry.handle, nullptr, options, st.x, st.y, width, 0.0f, 0.0f, width, 3, rgb)) {
        return glm::vec3(1.0f);
    }
    if (!entry.srgb) return glm::vec3(rgb[0], rgb[1], rgb[2]);
    return glm::vec3(srgb_decode(rgb[0]), srgb_decode(rgb[1]), srgb_decode(rgb[2]));
}

// Interim: the lookups are moving off OpenImageIO's TextureSystem (issue 35).
std::size_t TextureSet::bytes() const { return 0; }
std::size_t TextureSet::texture_count() const { return 0; }
double TextureSet::load_seconds() const { return 0.0; }

const std::vector<std::string>& TextureSet::warnings() const { return impl_->warnings; }

}  // namespace dynrt
