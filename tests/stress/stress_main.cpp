// main of dynrt_stress_tests: GoogleTest's own flags, plus --stress for the long mode (see
// benchmarks/README.md, "Stress suite").

#include "stress_mode.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>

namespace dynrt::stress {
namespace {
bool g_stress = false;
}  // namespace

bool stress_mode() { return g_stress; }

}  // namespace dynrt::stress

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    // InitGoogleTest removed its own flags; what remains is ours.
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--stress") == 0) {
            dynrt::stress::g_stress = true;
        } else {
            std::fprintf(stderr, "dynrt_stress_tests: unknown argument '%s' (only --stress and gtest flags)\n",
                         argv[i]);
            return 2;
        }
    }
    std::printf("dynrt_stress_tests: %s mode\n", dynrt::stress::stress_mode() ? "stress (long)" : "fast");
    return RUN_ALL_TESTS();
}
