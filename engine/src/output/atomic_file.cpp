#include "dynrt/engine/atomic_file.h"

#include <fstream>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace dynrt {

std::filesystem::path partial_path(const std::filesystem::path& path) {
    // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "." + std::string.
    std::string name(1, '.');
    name.append(path.stem().string()).append(".partial").append(path.extension().string());
    std::filesystem::path partial = path;
    partial.replace_filename(name);
    return partial;
}

std::string name_user_file(std::string message, const std::filesystem::path& partial,
                           const std::filesystem::path& path) {
    // The whole path first, then the bare name, which some messages give alone.
    for (const auto& [temporary, user] :
         {std::pair{partial.string(), path.string()},
          std::pair{partial.filename().string(), path.filename().string()}}) {
        for (std::size_t at = message.find(temporary); at != std::string::npos;
             at = message.find(temporary, at + user.size())) {
            message.replace(at, temporary.size(), user);
        }
    }
    return message;
}

void commit_partial(const std::filesystem::path& partial, const std::filesystem::path& path) {
    std::error_code error;
    std::filesystem::rename(partial, path, error);
    if (error) {
        std::error_code ignored;  // the rename's error is the one to report
        std::filesystem::remove(partial, ignored);
        throw std::runtime_error(path.string() + ": cannot write: " +
                                 (std::filesystem::is_directory(path) ? std::string("is a folder")
                                                                      : error.message()));
    }
}

void write_file_atomically(const std::filesystem::path& path, const std::string& text,
                           const std::string& what) {
    const std::filesystem::path partial = partial_path(path);
    {
        std::ofstream file(partial, std::ios::binary);
        file << text;
        file.flush();
        if (!file) {
            std::error_code ignored;
            std::filesystem::remove(partial, ignored);
            throw std::runtime_error(path.string() + ": cannot write " + what);
        }
    }
    commit_partial(partial, path);
}

}  // namespace dynrt
