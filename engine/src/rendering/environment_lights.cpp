// environment_lights (environment_lights.h): median cut over an equirectangular map.

#include "dynrt/engine/environment_lights.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace dynrt {

namespace {

constexpr double kPi = std::numbers::pi;

double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

/// Texels [x0, x1) x [y0, y1) of the map.
struct Region {
    int x0, y0, x1, y1;
    double energy = 0.0;
};

/// Per texel energy (luminance times solid angle) and its summed-area table, for region sums.
class EnergyTable {
public:
    explicit EnergyTable(const EnvironmentMap& map) : width_(map.width()), height_(map.height()) {
        sums_.assign(std::size_t(width_ + 1) * std::size_t(height_ + 1), 0.0);
        for (int y = 0; y < height_; ++y) {
            const double row_angle = solid_angle(y);
            for (int x = 0; x < width_; ++x) {
                const double e = luminance(glm::dvec3(map.texel(x, y))) * row_angle;
                at(x + 1, y + 1) = e + at(x, y + 1) + at(x + 1, y) - at(x, y);
            }
        }
    }

    /// Solid angle of a texel of row y.
    double solid_angle(int y) const {
        const double theta = (double(y) + 0.5) / double(height_) * kPi;
        return (2.0 * kPi / double(width_)) * (kPi / double(height_)) * std::sin(theta);
    }

    double energy(int x0, int y0, int x1, int y1) const {
        return at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0);
    }

    /// `r` cut in two of about equal energy across its longer side; false when it is one texel.
    bool split(const Region& r, Region& a, Region& b) const {
        const int w = r.x1 - r.x0, h = r.y1 - r.y0;
        if (w <= 1 && h <= 1) return false;
        const double middle_theta = 0.5 * double(r.y0 + r.y1) / double(height_) * kPi;
        const double across = double(w) / double(width_) * 2.0 * kPi * std::sin(middle_theta);
        const double down = double(h) / double(height_) * kPi;
        const bool vertical_cut = h <= 1 || (w > 1 && across >= down);  // cut at an x
        const int lo = vertical_cut ? r.x0 : r.y0, hi = vertical_cut ? r.x1 : r.y1;
        // The first cut whose near part holds at least half the energy, kept inside (lo, hi).
        int cut = lo + 1;
        while (cut < hi - 1) {
            const double near = vertical_cut ? energy(r.x0, r.y0, cut, r.y1) : energy(r.x0, r.y0, r.x1, cut);
            if (near >= 0.5 * r.energy) break;
            ++cut;
        }
        a = r;
        b = r;
        if (vertical_cut) {
            a.x1 = b.x0 = cut;
        } else {
            a.y1 = b.y0 = cut;
        }
        a.energy = energy(a.x0, a.y0, a.x1, a.y1);
        b.energy = energy(b.x0, b.y0, b.x1, b.y1);
        return true;
    }

private:
    double& at(int x, int y) { return sums_[std::size_t(y) * std::size_t(width_ + 1) + std::size_t(x)]; }
    double at(int x, int y) const { return sums_[std::size_t(y) * std::size_t(width_ + 1) + std::size_t(x)]; }

    int width_, height_;
    std::vector<double> sums_;
};

/// The unit direction the map shows at texel (x, y)'s centre (environment_map.h's mapping).
glm::dvec3 texel_direction(const EnvironmentMap& map, int x, int y) {
    const double theta = (double(y) + 0.5) / double(map.height()) * kPi;
    const double phi = ((double(x) + 0.5) / double(map.width()) - 0.5) * 2.0 * kPi;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

}  // namespace

std::vector<PointLight> environment_lights(const EnvironmentMap& map, int count) {
    if (count < 1 || count > kEnvironmentLightsMax) {
        throw std::invalid_argument("environment lights: " + std::to_string(count) + " must be in [1, " +
                                    std::to_string(kEnvironmentLightsMax) + "]");
    }
    const EnergyTable table(map);
    std::vector<Region> regions{Region{0, 0, map.width(), map.height(), 0.0}};
    regions[0].energy = table.energy(0, 0, map.width(), map.height());
    std::vector<Region> whole;  // regions of one texel, which cannot be cut further
    while (int(regions.size() + whole.size()) < count && !regions.empty()) {
        const auto most = std::max_element(regions.begin(), regions.end(),
                                           [](const Region& a, const Region& b) { return a.energy < b.energy; });
        if (!(most->energy > 0.0)) break;
        Region a, b;
        if (!table.split(*most, a, b)) {
            whole.push_back(*most);
            regions.erase(most);
            continue;
        }
        *most = a;
        regions.push_back(b);
    }
    regions.insert(regions.end(), whole.begin(), whole.end());
    std::vector<PointLight> lights;
    for (const Region& r : regions) {
        glm::dvec3 colour(0.0), centroid(0.0);
        for (int y = r.y0; y < r.y1; ++y) {
            const double angle = table.solid_angle(y);
            for (int x = r.x0; x < r.x1; ++x) {
                const glm::dvec3 radiance(map.texel(x, y));
                colour += radiance * angle;
                centroid += luminance(radiance) * angle * texel_direction(map, x, y);
            }
        }
        if (!(luminance(colour) > 0.0) || !(glm::length(centroid) > 0.0)) continue;
        PointLight light;
        light.kind = PointLight::Kind::directional;
        light.direction = glm::vec3(-glm::normalize(centroid));  // it travels away from the sky
        light.intensity = 1.0f;
        light.color = glm::vec3(colour / kPi);
        light.name = "environment " + std::to_string(lights.size());
        lights.push_back(light);
    }
    return lights;
}

}  // namespace dynrt
