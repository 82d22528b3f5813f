#pragma once
// Fingerprints of the files a scene was read from, for `render --resume` to tell a scene file
// changed since a job began from the one it began with.
//
// The hash is FNV-1a 64 (Fowler, Noll and Vo; http://www.isthe.com/chongo/tech/comp/fnv/):
// a few lines with no dependency, and what is asked of it is to notice an edited or replaced
// file, not to resist someone forging one; with the file's size beside it, an accidental
// collision over 64 bits is out of reach. A cryptographic hash (SHA-256) would need a library
// for no gain here.

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace dynrt::cli {

/// FNV-1a 64 of `bytes`, continuing from `state` (the offset basis for a fresh hash).
std::uint64_t fnv1a_64(std::span<const unsigned char> bytes,
                       std::uint64_t state = 0xcbf29ce484222325ull);

/// One file as a job read it.
struct FileDigest {
    std::string path;
    /// Empty when the file could not be read (a texture the loader warned about).
    std::optional<std::uint64_t> bytes;
    std::uint64_t fnv1a = 0;
};

/// Reads each of `paths` whole and digests it, in order; a file that cannot be read is kept
/// with no size (so a file that appears or disappears later counts as a change).
std::vector<FileDigest> digest_files(const std::vector<std::string>& paths);

}  // namespace dynrt::cli
