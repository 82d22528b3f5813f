// resident_memory (dynrt/engine/resident_memory.h).

#include "dynrt/engine/resident_memory.h"

#include <fstream>
#include <sstream>
#include <string>

namespace dynrt {

ResidentMemory resident_memory() {
    ResidentMemory memory;
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        // "VmHWM:     12345 kB"
        const bool peak = line.rfind("VmHWM:", 0) == 0, current = line.rfind("VmRSS:", 0) == 0;
        if (!peak && !current) continue;
        std::istringstream fields(line.substr(6));
        std::size_t kilobytes = 0;
        fields >> kilobytes;
        (peak ? memory.peak : memory.current) = kilobytes * 1024;
    }
    return memory;
}

bool restart_peak_resident() {
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";
    clear.flush();
    return bool(clear);
}

}  // namespace dynrt
