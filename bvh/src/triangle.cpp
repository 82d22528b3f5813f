// Triangle predicates. The zero-area test uses an error-free product (Dekker 1971, "A
// floating-point technique for extending the available precision"; here via fma) so that
// "collinear" means exactly collinear, not "almost".

#include "dynrt/bvh/triangle.h"

#include <cmath>
#include <initializer_list>

namespace dynrt::bvh {
namespace {

/// True when a*b == c*d exactly. Each product is split into its rounded value and its exact
/// rounding error (fma gives the error without rounding); the pairs are unique, so equal
/// products have equal pairs and vice versa.
bool products_equal(double a, double b, double c, double d) {
    const double p = a * b;
    const double q = c * d;
    return p == q && std::fma(a, b, -p) == std::fma(c, d, -q);
}

}  // namespace

bool is_degenerate(const Triangle& tri) {
    // Edge vectors in double: the difference of two floats is exact in double unless their
    // exponents differ by more than 29 (coordinates of one triangle spanning a factor > ~5e8),
    // so for every practical triangle the test below decides exact collinearity.
    const double e1x = static_cast<double>(tri.v1.x) - tri.v0.x;
    const double e1y = static_cast<double>(tri.v1.y) - tri.v0.y;
    const double e1z = static_cast<double>(tri.v1.z) - tri.v0.z;
    const double e2x = static_cast<double>(tri.v2.x) - tri.v0.x;
    const double e2y = static_cast<double>(tri.v2.y) - tri.v0.y;
    const double e2z = static_cast<double>(tri.v2.z) - tri.v0.z;
    // cross(e1, e2) == 0 component by component.
    return products_equal(e1y, e2z, e1z, e2y) && products_equal(e1z, e2x, e1x, e2z) &&
           products_equal(e1x, e2y, e1y, e2x);
}

bool is_finite(const Triangle& tri) {
    for (const glm::vec3* v : {&tri.v0, &tri.v1, &tri.v2}) {
        if (!std::isfinite(v->x) || !std::isfinite(v->y) || !std::isfinite(v->z)) return false;
    }
    return true;
}

}  // namespace dynrt::bvh
