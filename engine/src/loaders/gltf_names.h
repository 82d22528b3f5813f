#pragma once
// The names dynrt gives glTF elements in object names and messages: their own, else the kind
// and index ("node3", "skin0", "animation1"), so every element can be named.

#include "message_text.h"

#include <string>
#include <vector>

namespace dynrt {

/// elements[index].name when `index` is valid and the name is not empty, else kind + index.
template <class Element>
std::string gltf_element_name(const std::vector<Element>& elements, int index, const char* kind) {
    if (index >= 0 && static_cast<std::size_t>(index) < elements.size() &&
        !elements[static_cast<std::size_t>(index)].name.empty()) {
        return elements[static_cast<std::size_t>(index)].name;
    }
    return cat(kind, index);
}

}  // namespace dynrt
