#include "dynrt/embree/embree_backend.h"

namespace dynrt::embree {

namespace {

class EmbreeBackend final : public FrameBackend {
public:
    explicit EmbreeBackend(BuildQuality quality) : quality_(quality) {}

    std::string name() const override { return embree_backend_name(quality_); }

    double load(const Scene& scene, const FrameGeometry& geometry) override {
        const FrameLoad load = tracer_.load_geometry(scene, geometry, quality_);
        return load.upload_ms + load.commit_ms;
    }

    void forget() override { tracer_.forget(); }

    int closest(const packet::RayPacket& rays, RayCoherence coherence, HitTarget hits,
                TraceWork* /*work*/) const override {
        tracer_.closest_lanes(rays, coherence == RayCoherence::tile, hits);
        return rays.active.count();  // every ray in a packet of 16
    }

    packet::LaneMask occluded(const packet::RayPacket& rays, RayCoherence coherence,
                              TraceWork* /*work*/) const override {
        return tracer_.occluded_lanes(rays, coherence == RayCoherence::tile);
    }

private:
    BuildQuality quality_;
    EmbreeTracer tracer_;
};

}  // namespace

std::shared_ptr<FrameBackend> make_embree_backend(BuildQuality quality) {
    return std::make_shared<EmbreeBackend>(quality);
}

std::string embree_backend_name(BuildQuality quality) {
    return std::string("embree-") + quality_name(quality);
}

bool parse_backend_quality(const std::string& name, BuildQuality& quality) {
    for (const BuildQuality q : {BuildQuality::low, BuildQuality::medium, BuildQuality::high, BuildQuality::refit}) {
        if (name == embree_backend_name(q)) {
            quality = q;
            return true;
        }
    }
    return false;
}

}  // namespace dynrt::embree
