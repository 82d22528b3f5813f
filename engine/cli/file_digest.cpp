#include "file_digest.h"

#include <array>
#include <fstream>

namespace dynrt::cli {

std::uint64_t fnv1a_64(std::span<const unsigned char> bytes, std::uint64_t state) {
    constexpr std::uint64_t kPrime = 0x100000001b3ull;
    for (const unsigned char byte : bytes) {
        state ^= byte;
        state *= kPrime;
    }
    return state;
}

std::vector<FileDigest> digest_files(const std::vector<std::string>& paths) {
    std::vector<FileDigest> digests;
    for (const std::string& path : paths) {
        FileDigest digest{path, std::nullopt, fnv1a_64({})};
        std::ifstream in(path, std::ios::binary);
        if (in) {
            std::array<char, 1 << 16> buffer;
            std::uint64_t size = 0;
            while (in.read(buffer.data(), buffer.size()) || in.gcount() > 0) {
                const auto n = std::size_t(in.gcount());
                digest.fnv1a = fnv1a_64({reinterpret_cast<const unsigned char*>(buffer.data()), n},
                                        digest.fnv1a);
                size += n;
            }
            if (!in.bad()) digest.bytes = size;
        }
        digests.push_back(std::move(digest));
    }
    return digests;
}

}  // namespace dynrt::cli
