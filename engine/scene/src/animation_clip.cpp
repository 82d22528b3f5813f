#include "dynrt/scene/animation_clip.h"

#include <algorithm>
#include <limits>

namespace dynrt {

double AnimationClip::start_time() const {
    double start = std::numeric_limits<double>::infinity();
    for (const AnimationChannel& channel : channels) {
        if (channel.sampler < samplers.size() && !samplers[channel.sampler].times.empty()) {
            start = std::min(start, samplers[channel.sampler].times.front());
        }
    }
    return start == std::numeric_limits<double>::infinity() ? 0.0 : start;
}

double AnimationClip::end_time() const {
    double end = -std::numeric_limits<double>::infinity();
    for (const AnimationChannel& channel : channels) {
        if (channel.sampler < samplers.size() && !samplers[channel.sampler].times.empty()) {
            end = std::max(end, samplers[channel.sampler].times.back());
        }
    }
    return end == -std::numeric_limits<double>::infinity() ? 0.0 : end;
}

}  // namespace dynrt
