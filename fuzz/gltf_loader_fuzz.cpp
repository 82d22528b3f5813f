// libFuzzer target: the glTF loader (JSON and GLB) on arbitrary bytes, then the animation of
// whatever loads. See fuzz_entry_points.h for what one input does, and README.md ("Fuzzing")
// for running it. Crash inputs become regression tests in tests/data/fuzz_regressions/.

#include "fuzz_entry_points.h"

#include <oneapi/tbb/global_control.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <memory>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // One thread: posing runs in parallel on oneTBB, and worker threads would only make runs
    // slower on a shared machine and crashes harder to replay.
    static const auto one_thread =
        std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, 1);
    // The loader prints warnings (skipped primitives, unused attributes) to std::cerr; at
    // thousands of inputs a second they would drown libFuzzer's own output. Crashes and
    // sanitizer reports do not go through std::cerr.
    std::cerr.setstate(std::ios::badbit);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const dynrt::fuzz::FuzzOutcome outcome = dynrt::fuzz::feed_gltf_loader({data, size});
    // A rejection must be the documented one-line error naming the document.
    if (!dynrt::fuzz::keeps_gltf_error_contract(outcome)) std::abort();
    return 0;
}
