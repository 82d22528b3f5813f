#include "dynrt/scene/scene.h"

namespace dynrt {

std::size_t Scene::triangle_count() const {
    std::size_t n = 0;
    for (const Object& o : objects) n += o.mesh.triangles.size();
    return n;
}

}  // namespace dynrt
