// The memory of a long embedding (issue 34): a simulation that spawns and despawns meshes
// adds a deformable mesh, updates, removes it, again and again. Prints the process's peak
// resident size (VmHWM) after each checkpoint of cycles, through the library API alone, so
// that the same binary can be run against another libdynrt.so (LD_LIBRARY_PATH) to compare
// builds. benchmarks/memory_cycles.py runs it beside the same loop through Python.
//
//   memory_cycles [--triangles 5000] [--checkpoints 300,1500,3000] [--no-update]
//
// One line per checkpoint: "cycles <n> peak_rss_kb <kb> rss_kb <kb>".

#include "dynrt/dynrt.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// "<key>: <n> kB" of /proc/self/status, in kB (0 when absent).
long status_kb(const char* key) {
    std::FILE* status = std::fopen("/proc/self/status", "r");
    if (!status) return 0;
    char line[256];
    long kb = 0;
    const std::size_t n = std::strlen(key);
    while (std::fgets(line, sizeof line, status)) {
        if (std::strncmp(line, key, n) == 0 && line[n] == ':') {
            kb = std::strtol(line + n + 1, nullptr, 10);
            break;
        }
    }
    std::fclose(status);
    return kb;
}

/// A grid of side x side quads (2 side^2 triangles) on the unit square, waved by `phase`.
struct Grid {
    int side = 0;
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;

    explicit Grid(int quads_per_side) : side(quads_per_side) {
        const int n = side + 1;
        positions.resize(std::size_t(3 * n * n));
        for (int j = 0; j < side; ++j) {
            for (int i = 0; i < side; ++i) {
                const std::uint32_t a = std::uint32_t(j * n + i), b = a + 1, c = a + std::uint32_t(n), d = c + 1;
                indices.insert(indices.end(), {a, c, b, b, c, d});
            }
        }
        wave(0.0f);
    }
    void wave(float phase) {
        const int n = side + 1;
        for (int j = 0; j < n; ++j) {
            for (int i = 0; i < n; ++i) {
                const float x = float(i) / float(side), z = float(j) / float(side);
                float* p = &positions[std::size_t(3 * (j * n + i))];
                p[0] = x;
                p[1] = 0.05f * std::sin(12.0f * x + phase) * std::cos(9.0f * z - phase);
                p[2] = z;
            }
        }
    }
};

}  // namespace

int main(int argc, char** argv) {
    int triangles = 5000;
    std::vector<int> checkpoints{300, 1500, 3000};
    bool update = true;
    for (int a = 1; a < argc; ++a) {
        const std::string arg = argv[a];
        if (arg == "--triangles" && a + 1 < argc) {
            triangles = std::atoi(argv[++a]);
        } else if (arg == "--checkpoints" && a + 1 < argc) {
            checkpoints.clear();
            std::stringstream list(argv[++a]);
            for (std::string item; std::getline(list, item, ',');) checkpoints.push_back(std::stoi(item));
        } else if (arg == "--no-update") {
            update = false;
        } else {
            std::fprintf(stderr, "memory_cycles: error: unknown argument '%s'\n", arg.c_str());
            return 2;
        }
    }
    // The nearest grid: 2 side^2 triangles (50 x 50 quads = 5,000).
    Grid grid(std::max(1, int(std::lround(std::sqrt(triangles / 2.0)))));
    dynrt::Engine engine;
    int cycle = 0;
    for (const int target : checkpoints) {
        for (; cycle < target; ++cycle) {
            grid.wave(0.01f * float(cycle));
            dynrt::MeshDesc desc;
            desc.name = "debris";
            desc.positions = grid.positions;
            desc.indices = grid.indices;
            desc.motion = dynrt::Motion::deformable;
            const dynrt::MeshId id = engine.add_mesh(desc);
            if (update) engine.update();
            engine.remove_mesh(id);
        }
        std::printf("cycles %d peak_rss_kb %ld rss_kb %ld\n", cycle, status_kb("VmHWM"), status_kb("VmRSS"));
        std::fflush(stdout);
    }
    return 0;
}
