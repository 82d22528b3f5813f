#pragma once
// The heap bytes a container holds, for the engine's byte count (dynrt::Engine::memory_bytes):
// its capacity, not its size, since capacity is what stays allocated after a clear().

#include <cstddef>
#include <string>

namespace dynrt {

/// Bytes of `container`'s allocated storage (capacity times element size). Elements' own heap
/// storage (a vector of vectors) is the caller's to add.
template <typename Container>
std::size_t held_bytes(const Container& container) {
    return container.capacity() * sizeof(typename Container::value_type);
}

/// A string's heap storage: none while it fits in the string itself (the small-string buffer).
inline std::size_t held_bytes(const std::string& text) {
    return text.capacity() > std::string().capacity() ? text.capacity() + 1 : 0;
}

}  // namespace dynrt
