#pragma once
// Every file a `dynrt render` writes, listed once (render_outputs), and checked before the
// scene loads (check_render_outputs): each one's folder takes a new file, none is a folder,
// and no two name the same file. A render that cannot write its report, contact sheet or
// journal thus fails at once with nothing written, not after its frames.

#include "frame_args.h"

#include "dynrt/engine/sequence.h"

#include <filesystem>
#include <string>
#include <vector>

namespace dynrt::cli {

/// One file, or one numbered series of files, that a render writes.
struct RenderOutput {
    /// What the user wrote to ask for it, for messages: "--out", "--aov depth", "--report",
    /// "--contact-sheet", "the journal".
    std::string flag;
    /// The file; for a numbered output the pattern its frames' names are made from
    /// ('frames/%04d.png').
    std::string path;
    /// One file per frame: `path` is a pattern (dynrt/engine/sequence.h).
    bool numbered = false;
    /// Its folder is made by the render when missing (a numbered output's, and what goes
    /// beside it); else the folder must exist.
    bool makes_folder = false;
};

/// The journal of a resumable render: beside the report (REPORT.frames.jsonl), else hidden
/// beside the first frame (.dynrt-frames.jsonl).
std::filesystem::path journal_path(const RenderArgs& args, const dynrt::FrameRange& range);

/// Every output of a render with `args`: the image, numbered frames or sequence file (--out),
/// each AOV beside it, the report, the contact sheet, and the journal when `with_journal`.
/// Throws std::invalid_argument for an --out pattern sequence.h refuses or an unknown --aov.
std::vector<RenderOutput> render_outputs(const RenderArgs& args, const dynrt::FrameRange& range,
                                         bool with_journal);

/// Checks `outputs` (of frames `range`) before anything is loaded or written: no output names
/// an existing folder; each folder exists and takes a new file (a probe file is made and
/// removed), or, for one the render makes, its nearest existing folder does; no two outputs
/// name the same file (a numbered output: any of the range's frames). Throws
/// std::invalid_argument naming the flag and the path the user gave.
void check_render_outputs(const std::vector<RenderOutput>& outputs, const dynrt::FrameRange& range);

}  // namespace dynrt::cli
