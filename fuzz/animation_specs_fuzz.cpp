// libFuzzer target: the command line's animation spec parsers, `--anim MOTION[:OBJECT]` and
// `--treat NAME=CLASS` (anim::add_procedural_motions, anim::parse_class_overrides), applied to a
// small procedural scene that is then posed, so that the motions (explode unshares triangles)
// and the class overrides run too. Input format in fuzz_entry_points.h; README.md ("Fuzzing")
// says how to run it. Crash inputs become regression tests in tests/data/fuzz_regressions/.

#include "fuzz_entry_points.h"

#include <oneapi/tbb/global_control.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // One thread: posing runs in parallel on oneTBB, and worker threads would only make runs
    // slower on a shared machine and crashes harder to replay.
    static const auto one_thread =
        std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    dynrt::fuzz::feed_animation_specs(std::string_view(reinterpret_cast<const char*>(data), size));
    return 0;
}
