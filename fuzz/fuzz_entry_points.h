#pragma once
// What each fuzz target does with one input, shared by the libFuzzer targets (built with clang)
// and by tests/fuzz_regressions_test.cpp (built with gcc, run optimised and under ASan+UBSan),
// so a crash input kept as a regression test goes through exactly the code the fuzzer ran.
//
// Bad input must end in the engine's documented error, a SceneError with a one-line message;
// anything else that escapes (another exception, a crash, a sanitizer report, a hang) is a bug.

#include "dynrt/anim/motion_class.h"
#include "dynrt/anim/posed_scene.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/scene/scene_error.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace dynrt::fuzz {

/// How an input ended: it loaded (and posed), or the engine rejected it with `error`.
struct FuzzOutcome {
    bool loaded = false;
    /// The SceneError's message when rejected.
    std::string error;
};

/// True when a glTF outcome keeps the loader's promise: loaded, or one non-empty line that
/// names the document first.
inline bool keeps_gltf_error_contract(const FuzzOutcome& outcome) {
    if (outcome.loaded) return true;
    const std::string_view error = outcome.error;
    return error.find('\n') == std::string_view::npos &&
           (error.starts_with("fuzz.glb: ") || error.starts_with("fuzz.gltf: "));
}

/// The largest scene the procedural spec target builds, per part and in total, instead of the
/// engine's 100M: the fuzzer then spends its time in the parser, not in allocating and filling
/// huge meshes (a 10,000-triangle sphere takes well under a millisecond even under ASan). The
/// mesh builders run the same code for any N, and the limit checks are still exercised, at
/// this smaller bound.
inline constexpr std::uint64_t kFuzzMaxProceduralTriangles = 10'000;

/// glTF loader target: `bytes` is a whole document, GLB when it starts with the GLB magic
/// "glTF", else JSON, so one corpus holds both encodings and mutations can cross between them.
/// The document is loaded from memory (no filesystem access at all), and a scene that loads is
/// posed at several times, since animation samplers, skins and morph targets are where indices
/// from the file are used long after loading.
inline FuzzOutcome feed_gltf_loader(std::span<const unsigned char> bytes) {
    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    try {
        const Scene scene = load_gltf_from_memory(bytes, binary ? GltfFormat::binary : GltfFormat::json,
                                                  binary ? "fuzz.glb" : "fuzz.gltf");
        const anim::ScenePoser poser(scene, anim::PoseSettings{});
        anim::PosedScene posed;
        // Before the first key, the first keys (most seeds key at 0, 0.5 and 1 s, 24 frames per
        // second), past every key, and halfway through the clips when that is a sane frame.
        for (const int frame : {-1, 0, 7, 12, 24, 100000}) poser.pose(frame, posed);
        const double middle = 0.5 * poser.end_time() * anim::kDefaultFps;
        if (std::isfinite(middle) && std::abs(middle) < 1e6) poser.pose(static_cast<int>(middle), posed);
    } catch (const SceneError& e) {
        return FuzzOutcome{false, e.what()};
    }
    return FuzzOutcome{true, {}};
}

/// Procedural spec target: `text` is a spec string, built with kFuzzMaxProceduralTriangles.
inline FuzzOutcome feed_procedural_spec(std::string_view text) {
    try {
        make_procedural_scene(std::string(text), kFuzzMaxProceduralTriangles);
    } catch (const SceneError& e) {
        return FuzzOutcome{false, e.what()};
    }
    return FuzzOutcome{true, {}};
}

/// The scene the animation spec target animates: two objects, each with a ':' and a '#' in its
/// name, since `--anim MOTION[:OBJECT]` splits at a ':' and names select by '/' and '#'.
inline constexpr const char* kFuzzAnimationScene = "sphere:20#ff0000+plane:2@0,-1,0";

/// Animation spec target: the command line's `--anim MOTION[:OBJECT]` and `--treat NAME=CLASS`
/// parsers, reachable as anim::add_procedural_motions and anim::parse_class_overrides. `text`
/// holds one spec per line: lines starting with '=' are --treat specs (the '=' dropped), the
/// others --anim specs. The scene is then posed at a few frames with those motions and classes.
/// Their documented errors are std::invalid_argument (bad spec, or a class lowered), besides
/// SceneError.
inline FuzzOutcome feed_animation_specs(std::string_view text) {
    std::vector<std::string> motions, classes;
    for (std::size_t start = 0; start <= text.size();) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        const std::string_view line = text.substr(start, end - start);
        if (!line.empty() && line.front() == '=') {
            classes.emplace_back(line.substr(1));
        } else {
            motions.emplace_back(line);
        }
        start = end + 1;
    }
    try {
        Scene scene = make_procedural_scene(kFuzzAnimationScene);
        anim::add_procedural_motions(scene, motions);
        anim::PoseSettings settings;
        settings.class_overrides = anim::parse_class_overrides(scene, classes);
        const anim::ScenePoser poser(scene, std::move(settings));
        anim::PosedScene posed;
        for (const int frame : {0, 1, 5, -7, 1 << 20}) poser.pose(frame, posed);
    } catch (const SceneError& e) {
        return FuzzOutcome{false, e.what()};
    } catch (const std::invalid_argument& e) {
        return FuzzOutcome{false, e.what()};
    }
    return FuzzOutcome{true, {}};
}

/// BART scene target: `text` is an AFF file named fuzz.aff (its includes resolve in the working
/// folder and mostly fail to open, which is a SceneError too). A scene that loads is posed at
/// its own frame rate before, at, between and past its frames: keyframe tracks, morphing `tpa`
/// objects and the camera are evaluated long after loading.
inline FuzzOutcome feed_aff_scene(std::string_view text) {
    try {
        const Scene scene = load_aff_text(text, "fuzz.aff");
        anim::PoseSettings settings;
        if (scene.setup) settings.fps = scene.setup->fps;
        const anim::ScenePoser poser(scene, std::move(settings));
        anim::PosedScene posed;
        const int last = scene.setup ? scene.setup->frame_count - 1 : 0;
        for (const int frame : {-1, 0, 1, last / 2, last, 1 << 20}) poser.pose(frame, posed);
    } catch (const SceneError& e) {
        return FuzzOutcome{false, e.what()};
    }
    return FuzzOutcome{true, {}};
}

}  // namespace dynrt::fuzz
