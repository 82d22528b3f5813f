#include "render_outputs.h"

#include "dynrt/engine/image_output.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>
#include <set>
#include <stdexcept>
#include <system_error>

namespace dynrt::cli {

namespace fs = std::filesystem;

namespace {

/// The form two names of one file share: absolute, without "." and "..". (Symbolic links are
/// not followed: the frames' folders may not exist yet.)
std::string comparable(const std::string& path) {
    std::error_code ignored;
    return fs::absolute(path, ignored).lexically_normal().string();
}

/// `label` for messages: "--report r.json".
std::string label(const RenderOutput& o) { return o.flag + " '" + o.path + "'"; }

/// Fails unless a new file can be made in the existing folder `folder` (a probe, made and
/// removed at once: permissions, read-only or full file systems and special folders such as
/// /proc all answer as a real write would).
void check_folder_takes_files(const fs::path& folder, const RenderOutput& o) {
    const fs::path probe = folder / (".dynrt-probe-" + std::to_string(getpid()));
    const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0) {
        throw std::invalid_argument(label(o) + ": cannot write in folder " + folder.string() +
                                    " (" + std::strerror(errno) + ")");
    }
    ::close(fd);
    ::unlink(probe.c_str());
}

/// Checks the folder of one output, which `probed` remembers so that each is tried once.
void check_folder(const RenderOutput& o, std::set<std::string>& probed) {
    // A numbered output's folder may itself hold the frame number ('%04d/img.png'): then the
    // folder checked is the nearest existing one above it, found below.
    fs::path folder = fs::path(o.numbered ? frame_path(o.path, 0) : o.path).parent_path();
    if (folder.empty()) folder = ".";
    std::error_code ec;
    if (!fs::exists(folder, ec)) {
        if (!o.makes_folder) {
            throw std::invalid_argument(label(o) + ": folder " + folder.string() + " does not exist");
        }
        // Made by the render: its nearest existing ancestor must be a folder taking files.
        while (!folder.empty() && !fs::exists(folder, ec)) folder = folder.parent_path();
        if (folder.empty()) folder = ".";
    }
    if (!fs::is_directory(folder, ec)) {
        throw std::invalid_argument(label(o) + ": " + folder.string() + " is a file, not a folder");
    }
    if (probed.insert(comparable(folder.string())).second) check_folder_takes_files(folder, o);
}

/// Fails when the output names an existing folder (for a numbered one: its first frame).
void check_not_a_folder(const RenderOutput& o, const dynrt::FrameRange& range) {
    const std::string file = o.numbered ? frame_path(o.path, range.first) : o.path;
    std::error_code ec;
    if (fs::is_directory(file, ec)) throw std::invalid_argument(label(o) + ": " + file + " is a folder");
}

/// Fails when `a` and `b` name the same file for some frame of `range`.
void check_distinct(const RenderOutput& a, const RenderOutput& b, const dynrt::FrameRange& range) {
    const std::string pa = comparable(a.path), pb = comparable(b.path);
    const auto clash = [&](const std::string& what) {
        throw std::invalid_argument(label(a) + " and " + label(b) + " " + what +
                                    ": the second would overwrite the first; give them "
                                    "different names");
    };
    if (!a.numbered && !b.numbered) {
        if (pa == pb) clash("are the same file");
        return;
    }
    // A numbered output against a file, or two numbered outputs compared at the first frame
    // of each (their patterns differ only in what surrounds the number).
    const auto frame_clash = [&](const RenderOutput& series, const std::string& pattern,
                                 const std::string& file) {
        const std::optional<int> frame = dynrt::frame_of_path(pattern, file);
        if (frame && *frame >= range.first && *frame <= range.last) {
            clash("name the same file (frame " + std::to_string(*frame) + " of " + series.flag + ")");
        }
    };
    if (a.numbered) frame_clash(a, pa, b.numbered ? comparable(frame_path(b.path, range.first)) : pb);
    if (b.numbered) frame_clash(b, pb, a.numbered ? comparable(frame_path(a.path, range.first)) : pa);
}

}  // namespace

fs::path journal_path(const RenderArgs& args, const dynrt::FrameRange& range) {
    if (!args.report.empty()) return args.report + ".frames.jsonl";
    fs::path path = dynrt::frame_path(args.out, range.first);
    path.replace_filename(".dynrt-frames.jsonl");
    return path;
}

std::vector<RenderOutput> render_outputs(const RenderArgs& args, const dynrt::FrameRange& range,
                                         bool with_journal) {
    std::vector<RenderOutput> outputs;
    const bool numbered = dynrt::has_frame_number(args.out);
    // A single file's name is the pattern with "%%" read as "%".
    const std::string out = numbered ? args.out : dynrt::frame_path(args.out, 0);
    outputs.push_back({"--out", out, numbered, numbered});
    for (const dynrt::Aov aov : dynrt::parse_aov_list(args.aov)) {
        // aov_path keeps the folder and the stem, so a numbered image's AOVs are numbered too
        // ('f%04d.png' -> 'f%04d.depth.exr').
        outputs.push_back({std::string("--aov ") + dynrt::aov_name(aov),
                           dynrt::aov_path(out, aov).string(), numbered, numbered});
    }
    if (!args.report.empty()) outputs.push_back({"--report", args.report, false, false});
    if (!args.contact_sheet.empty()) {
        outputs.push_back({"--contact-sheet", args.contact_sheet, false, false});
    }
    if (with_journal) {
        // Beside the report, or beside the frames in the folder the render makes.
        outputs.push_back({"the journal", journal_path(args, range).string(), false,
                           args.report.empty() && numbered});
    }
    return outputs;
}

void check_render_outputs(const std::vector<RenderOutput>& outputs, const dynrt::FrameRange& range) {
    std::set<std::string> probed;
    for (std::size_t i = 0; i < outputs.size(); ++i) {
        check_not_a_folder(outputs[i], range);
        for (std::size_t j = 0; j < i; ++j) check_distinct(outputs[j], outputs[i], range);
    }
    // Folders after names: a clash is the clearer message when both apply.
    for (const RenderOutput& o : outputs) check_folder(o, probed);
}

}  // namespace dynrt::cli
