// libFuzzer target: the procedural scene spec parser (`sphere:N`, `soup:N`, `plane:N`,
// compositions with placement and colour) on arbitrary strings, building what parses, with
// scenes capped at kFuzzMaxProceduralTriangles (fuzz_entry_points.h). README.md ("Fuzzing")
// says how to run it. Crash inputs become regression tests in tests/data/fuzz_regressions/.

#include "fuzz_entry_points.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // Any bytes, NULs included: a spec comes from the command line, but the parser takes a
    // std::string and must not assume more about it than its grammar says.
    dynrt::fuzz::feed_procedural_spec(std::string_view(reinterpret_cast<const char*>(data), size));
    return 0;
}
