// libFuzzer target: BART's AFF scene files (engine/src/loaders/aff_parser.h, aff_scene.h,
// aff_keyframes.h): arbitrary text parsed, converted to a scene and posed over its frames.
// README.md ("Fuzzing") says how to run it. Crash inputs become regression tests in
// tests/data/fuzz_regressions/aff_scene/.

#include "fuzz_entry_points.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    dynrt::fuzz::feed_aff_scene(std::string_view(reinterpret_cast<const char*>(data), size));
    return 0;
}
