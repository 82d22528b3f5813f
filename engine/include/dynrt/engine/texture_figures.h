#pragma once
// What a scene's textures cost: the figures of one TextureSet (texture_set.h), taken once when
// it is built, not per frame. They reach the render report's "run" (report.h), `dynrt bench`'s
// start-up line and the library API (Engine::texture_figures).

#include <cstddef>

namespace dynrt {

/// One TextureSet's figures; all 0 when none was built (a scene that maps no texture, or
/// before the first trace).
struct TextureFigures {
    /// Readable textures held, each counted once however many materials map it
    /// (TextureSet::texture_count).
    std::size_t count = 0;
    /// Bytes they hold in memory, every MIP level included (TextureSet::bytes).
    std::size_t bytes = 0;
    /// Wall-clock ms their reading, decoding and MIP-mapping took (TextureSet::load_seconds).
    double load_ms = 0.0;

    bool operator==(const TextureFigures&) const = default;
};

}  // namespace dynrt
