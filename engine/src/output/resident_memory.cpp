// resident_memory (dynrt/engine/resident_memory.h).

#include "dynrt/engine/resident_memory.h"

#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace dynrt {

namespace {

/// Calls found(key, bytes) for each "Key:   12345 kB" line of `path` (Linux's /proc files).
template <typename Found>
void read_kilobyte_lines(const char* path, Found&& found) {
    std::ifstream file(path);
    std::string line;
    while (std::getline(file, line)) {
        const std::size_t colon = line.find(':');
        if (colon == std::string::npos) continue;
        std::istringstream fields(line.substr(colon + 1));
        std::size_t kilobytes = 0;
        if (fields >> kilobytes) found(std::string_view(line).substr(0, colon), kilobytes * 1024);
    }
}

}  // namespace

ResidentMemory resident_memory() {
    ResidentMemory memory;
    read_kilobyte_lines("/proc/self/status", [&](std::string_view key, std::size_t bytes) {
        if (key == "VmHWM") memory.peak = bytes;
        if (key == "VmRSS") memory.current = bytes;
    });
    return memory;
}

std::size_t available_memory() {
    std::size_t available = 0;
    read_kilobyte_lines("/proc/meminfo", [&](std::string_view key, std::size_t bytes) {
        if (key == "MemAvailable") available = bytes;
    });
    return available;
}

bool restart_peak_resident() {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    return bool(clear);
}

}  // namespace dynrt
