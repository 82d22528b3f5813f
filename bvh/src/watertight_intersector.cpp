// Watertight ray/triangle intersection (Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
// Intersection", JCGT 2(1)). The test itself lives in watertight_kernel.h so traversal loops can
// inline the identical arithmetic.

#include "watertight_kernel.h"

namespace dynrt::bvh {

bool intersect_watertight(const WatertightRay& ray, const Triangle& tri, float tmin, float tmax,
                          Hit& hit) {
    return detail::watertight_test(ray, tri, tmin, tmax, hit);
}

}  // namespace dynrt::bvh
