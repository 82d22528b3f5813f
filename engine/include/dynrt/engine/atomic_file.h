#pragma once
// Files written whole or not at all: each is written to a temporary file beside it and renamed
// over it once complete, so a run killed part way (a crash, a killed MPI job) leaves every file
// either as it was or as it was meant to be, never a torn one. `--resume` relies on it.

#include <filesystem>
#include <string>

namespace dynrt {

/// The temporary file `path` is written to first: ".NAME.partial.EXT" beside it (hidden, and
/// with the same extension, which image writers choose the format by).
std::filesystem::path partial_path(const std::filesystem::path& path);

/// `message` (an image library's error about writing `partial`) with every mention of the
/// temporary file replaced by `path`, the file the user named: errors never name ".a.partial.png".
std::string name_user_file(std::string message, const std::filesystem::path& partial,
                           const std::filesystem::path& path);

/// Renames the finished `partial` over `path`. Throws std::runtime_error naming `path` (and
/// removes `partial`) when it cannot, e.g. when `path` is a folder.
void commit_partial(const std::filesystem::path& partial, const std::filesystem::path& path);

/// Writes `text` to `path` atomically. Throws std::runtime_error naming the file and `what`
/// it holds ("the report") on failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& text,
                           const std::string& what);

}  // namespace dynrt
