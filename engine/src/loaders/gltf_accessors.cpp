// Accessor layout (glTF 2.0 section 3.6.2): element i of an accessor starts at byte
//   bufferView.byteOffset + accessor.byteOffset + i * stride
// of its buffer, stride = bufferView.byteStride or, when 0, the element size. All of
// [accessor.byteOffset, accessor.byteOffset + (count - 1) * stride + element size) must lie
// within the bufferView, and the bufferView within its buffer; both are checked here with
// arithmetic that cannot overflow, since every number comes from an untrusted file.

#include "gltf_accessors.h"

#include "gltf_data_error.h"
#include "message_text.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>

namespace dynrt {

static_assert(std::endian::native == std::endian::little,
              "glTF buffers are little-endian and are read here with memcpy, without byte swaps");

namespace {

/// Where an accessor's elements are, after every range check.
struct ElementRange {
    const unsigned char* first = nullptr;
    std::size_t stride = 0;
    std::size_t count = 0;
};

/// True when offset + (count - 1) * stride + size <= limit (or offset <= limit for count 0),
/// evaluated without overflow.
bool fits(std::size_t offset, std::size_t stride, std::size_t count, std::size_t size, std::size_t limit) {
    if (offset > limit) return false;
    if (count == 0) return true;
    std::size_t room = limit - offset;
    if (size > room) return false;
    room -= size;
    return count - 1 == 0 || stride == 0 || (count - 1) <= room / stride;
}

[[noreturn]] void fail(int accessor, const std::string& what) {
    throw GltfDataError(cat("accessor ", accessor, ": ", what));
}

const char* component_type_name(int type) {
    switch (type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
            return "BYTE";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return "UNSIGNED_BYTE";
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return "SHORT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return "UNSIGNED_SHORT";
        case TINYGLTF_COMPONENT_TYPE_INT:
            return "INT";
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
            return "UNSIGNED_INT";
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return "FLOAT";
        case TINYGLTF_COMPONENT_TYPE_DOUBLE:
            return "DOUBLE";
        default:
            return "an unknown component type";
    }
}

const char* type_name(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return "SCALAR";
        case TINYGLTF_TYPE_VEC2:
            return "VEC2";
        case TINYGLTF_TYPE_VEC3:
            return "VEC3";
        case TINYGLTF_TYPE_VEC4:
            return "VEC4";
        case TINYGLTF_TYPE_MAT2:
            return "MAT2";
        case TINYGLTF_TYPE_MAT3:
            return "MAT3";
        case TINYGLTF_TYPE_MAT4:
            return "MAT4";
        default:
            return "an unknown type";
    }
}

/// Range-checks accessor `index`, whose elements are `element_size` bytes.
ElementRange locate(const tinygltf::Model& model, int index, std::size_t element_size) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        fail(index, cat("does not exist (", model.accessors.size(), " accessors)"));
    }
    const tinygltf::Accessor& accessor = model.accessors[static_cast<std::size_t>(index)];
    if (accessor.sparse.isSparse) fail(index, "sparse accessors are not supported");
    if (accessor.bufferView < 0) {
        fail(index, "has no bufferView (all-zero or compressed data is not supported)");
    }
    if (static_cast<std::size_t>(accessor.bufferView) >= model.bufferViews.size()) {
        fail(index, cat("bufferView ", accessor.bufferView, " does not exist"));
    }
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(accessor.bufferView)];
    const std::string view_name = cat("bufferView ", accessor.bufferView);
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
        fail(index, cat(view_name, ": buffer ", view.buffer, " does not exist"));
    }
    const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
    if (!fits(view.byteOffset, 0, 1, view.byteLength, buffer.data.size())) {
        fail(index, cat(view_name, " (offset ", view.byteOffset, ", length ", view.byteLength,
                        ") exceeds buffer ", view.buffer, " (", buffer.data.size(), " bytes)"));
    }
    const std::size_t stride = view.byteStride != 0 ? view.byteStride : element_size;
    if (stride < element_size) {
        fail(index,
             cat(view_name, " byteStride ", stride, " is smaller than the ", element_size, "-byte element"));
    }
    if (!fits(accessor.byteOffset, stride, accessor.count, element_size, view.byteLength)) {
        fail(index, cat(accessor.count, " elements of ", element_size, " bytes (offset ", accessor.byteOffset,
                        ", stride ", stride, ") exceed ", view_name, " (", view.byteLength, " bytes)"));
    }
    return ElementRange{buffer.data.data() + view.byteOffset + accessor.byteOffset, stride, accessor.count};
}

std::size_t component_count(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        case TINYGLTF_TYPE_MAT4:
            return 16;
        default:
            return 0;
    }
}

/// Bytes per component of an integer or float component type, 0 for others.
std::size_t component_size(int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
    }
}

bool integer_allowed(int component_type, NormalizedIntegers integers) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return integers != NormalizedIntegers::none;
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_SHORT:
            return integers == NormalizedIntegers::any;
        default:
            return false;
    }
}

/// One component at `bytes` as a double; normalised integers per glTF 2.0 section 3.11.
double read_component(const unsigned char* bytes, int component_type) {
    switch (component_type) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            std::int8_t c;
            std::memcpy(&c, bytes, 1);
            return std::max(c / 127.0, -1.0);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return bytes[0] / 255.0;
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            std::int16_t c;
            std::memcpy(&c, bytes, 2);
            return std::max(c / 32767.0, -1.0);
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            std::uint16_t c;
            std::memcpy(&c, bytes, 2);
            return c / 65535.0;
        }
        default: {
            float c;
            std::memcpy(&c, bytes, 4);
            return c;
        }
    }
}

const tinygltf::Accessor& find_accessor(const tinygltf::Model& model, int index) {
    if (index < 0 || static_cast<std::size_t>(index) >= model.accessors.size()) {
        fail(index, cat("does not exist (", model.accessors.size(), " accessors)"));
    }
    return model.accessors[static_cast<std::size_t>(index)];
}

}  // namespace

std::size_t accessor_count(const tinygltf::Model& model, int accessor) {
    return find_accessor(model, accessor).count;
}

std::vector<double> read_numbers(const tinygltf::Model& model, int accessor, int type, NormalizedIntegers integers) {
    const tinygltf::Accessor& a = find_accessor(model, accessor);
    const bool is_float = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    const bool integer_ok = type != TINYGLTF_TYPE_MAT4 && integer_allowed(a.componentType, integers);
    if (a.type != type || (!is_float && !integer_ok)) {
        const char* others = integers == NormalizedIntegers::none          ? ""
                             : integers == NormalizedIntegers::unsigned_only ? " or normalized UNSIGNED_BYTE/SHORT"
                                                                             : " or normalized (UNSIGNED_)BYTE/SHORT";
        fail(accessor, cat("must be FLOAT", others, " ", type_name(type), ", not ", component_type_name(a.componentType),
                           " ", type_name(a.type)));
    }
    if (!is_float && !a.normalized) {
        fail(accessor, cat(component_type_name(a.componentType), " components must be normalized here"));
    }
    const std::size_t components = component_count(type);
    const std::size_t size = component_size(a.componentType);
    const ElementRange range = locate(model, accessor, components * size);
    std::vector<double> numbers(range.count * components);
    for (std::size_t i = 0; i < range.count; ++i) {
        const unsigned char* element = range.first + i * range.stride;
        for (std::size_t c = 0; c < components; ++c) {
            const double value = read_component(element + c * size, a.componentType);
            if (!std::isfinite(value)) fail(accessor, cat("element ", i, " is not finite"));
            numbers[i * components + c] = value;
        }
    }
    return numbers;
}

std::vector<std::uint16_t> read_joint_indices(const tinygltf::Model& model, int accessor) {
    const tinygltf::Accessor& a = find_accessor(model, accessor);
    if (a.type != TINYGLTF_TYPE_VEC4 || (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                         a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)) {
        fail(accessor, cat("joint indices must be UNSIGNED_BYTE or UNSIGNED_SHORT VEC4, not ",
                           component_type_name(a.componentType), " ", type_name(a.type)));
    }
    const std::size_t size = component_size(a.componentType);
    const ElementRange range = locate(model, accessor, 4 * size);
    std::vector<std::uint16_t> joints(range.count * 4);
    for (std::size_t i = 0; i < range.count; ++i) {
        for (std::size_t c = 0; c < 4; ++c) {
            const unsigned char* bytes = range.first + i * range.stride + c * size;
            std::uint16_t value = bytes[0];
            if (size == 2) std::memcpy(&value, bytes, 2);
            joints[i * 4 + c] = value;
        }
    }
    return joints;
}

std::vector<unsigned char> read_buffer_view(const tinygltf::Model& model, int index) {
    const std::string name = cat("bufferView ", index);
    if (index < 0 || static_cast<std::size_t>(index) >= model.bufferViews.size()) {
        throw GltfDataError(cat(name, " does not exist (", model.bufferViews.size(), " bufferViews)"));
    }
    const tinygltf::BufferView& view = model.bufferViews[static_cast<std::size_t>(index)];
    if (view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= model.buffers.size()) {
        throw GltfDataError(cat(name, ": buffer ", view.buffer, " does not exist"));
    }
    const tinygltf::Buffer& buffer = model.buffers[static_cast<std::size_t>(view.buffer)];
    if (!fits(view.byteOffset, 0, 1, view.byteLength, buffer.data.size())) {
        throw GltfDataError(cat(name, " (offset ", view.byteOffset, ", length ", view.byteLength,
                                ") exceeds buffer ", view.buffer, " (", buffer.data.size(), " bytes)"));
    }
    const auto first = buffer.data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset);
    return std::vector<unsigned char>(first, first + static_cast<std::ptrdiff_t>(view.byteLength));
}

std::vector<glm::vec3> read_positions(const tinygltf::Model& model, int accessor) {
    if (accessor >= 0 && static_cast<std::size_t>(accessor) < model.accessors.size()) {
        const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(accessor)];
        if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.type != TINYGLTF_TYPE_VEC3) {
            fail(accessor, cat("POSITION must be FLOAT VEC3, not ", component_type_name(a.componentType), " ",
                               type_name(a.type)));
        }
    }
    const ElementRange range = locate(model, accessor, 3 * sizeof(float));
    if (range.count > UINT32_MAX) fail(accessor, "more than 2^32 - 1 positions");

    std::vector<glm::vec3> positions(range.count);
    for (std::size_t i = 0; i < range.count; ++i) {
        float xyz[3];
        // memcpy: glTF only guarantees 4-byte alignment relative to the buffer start.
        std::memcpy(xyz, range.first + i * range.stride, sizeof(xyz));
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) {
            std::ostringstream what;
            what << "position " << i << " is not finite (" << xyz[0] << ", " << xyz[1] << ", " << xyz[2]
                 << ")";
            fail(accessor, what.str());
        }
        positions[i] = glm::vec3(xyz[0], xyz[1], xyz[2]);
    }
    return positions;
}

namespace {

/// An index accessor's elements, read one at a time, widened to 32 bits and checked below the
/// vertex count.
class IndexElements {
public:
    IndexElements(const tinygltf::Model& model, int accessor, std::size_t vertex_count)
        : accessor_(accessor), vertex_count_(vertex_count) {
        if (accessor >= 0 && static_cast<std::size_t>(accessor) < model.accessors.size()) {
            const tinygltf::Accessor& a = model.accessors[static_cast<std::size_t>(accessor)];
            switch (a.componentType) {
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                    size_ = 1;
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
                    size_ = 2;
                    break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
                    size_ = 4;
                    break;
                default:
                    break;
            }
            if (size_ == 0 || a.type != TINYGLTF_TYPE_SCALAR) {
                fail(accessor, cat("indices must be SCALAR UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, not ",
                                   component_type_name(a.componentType), " ", type_name(a.type)));
            }
        }
        range_ = locate(model, accessor, size_);
    }

    std::size_t count() const { return range_.count; }

    std::uint32_t operator[](std::size_t i) const {
        const unsigned char* element = range_.first + i * range_.stride;
        std::uint32_t value = 0;
        if (size_ == 1) {
            value = element[0];
        } else if (size_ == 2) {
            std::uint16_t v16;
            std::memcpy(&v16, element, 2);
            value = v16;
        } else {
            std::memcpy(&value, element, 4);
        }
        if (value >= vertex_count_) {
            fail(accessor_, cat("index ", i, " (value ", value, ") out of range of ", vertex_count_, " positions"));
        }
        return value;
    }

private:
    int accessor_;
    std::size_t vertex_count_;
    std::size_t size_ = 0;
    ElementRange range_;
};

}  // namespace

std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, int accessor,
                                        std::size_t vertex_count) {
    const IndexElements elements(model, accessor, vertex_count);
    std::vector<std::uint32_t> indices(elements.count());
    for (std::size_t i = 0; i < indices.size(); ++i) indices[i] = elements[i];
    return indices;
}

std::vector<glm::uvec3> read_index_triples(const tinygltf::Model& model, int accessor, std::size_t vertex_count) {
    const IndexElements elements(model, accessor, vertex_count);
    std::vector<glm::uvec3> triangles(elements.count() / 3);
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        triangles[t] = glm::uvec3(elements[3 * t], elements[3 * t + 1], elements[3 * t + 2]);
    }
    // A remainder is ignored, as assemble_triangles ignores it, but its indices are checked.
    for (std::size_t i = 3 * triangles.size(); i < elements.count(); ++i) (void)elements[i];
    return triangles;
}

}  // namespace dynrt
