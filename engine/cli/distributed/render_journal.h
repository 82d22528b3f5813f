#pragma once
// The record of a sequence render as its frames finish, for `--resume`: a JSON-lines file, a
// header line naming the job (every setting that changes a pixel or a report figure and a
// digest of the scene's files: journal_header in job_settings.h), then one frame record
// per line (frame_report_json, with the rank that made it) written and flushed by rank 0 as
// each frame's image is in place. A job killed part way leaves every finished frame's record;
// a torn last line is ignored.

#include "dynrt/engine/frame_stats.h"

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

namespace dynrt::cli {

class RenderJournal {
public:
    /// Opens the journal at `path` for the job `header` describes (journal_header). With
    /// `resume`, first reads what an earlier run of the same job recorded; a journal of another
    /// job is refused (std::invalid_argument: job_difference's line, naming the first setting
    /// or scene file that differs). Without, starts it afresh.
    RenderJournal(std::filesystem::path path, const std::string& header, bool resume);

    /// The records read at opening, by frame (a frame recorded twice: the later record).
    const std::map<int, FrameStats>& earlier() const { return earlier_; }

    /// Appends a frame's record (one line) and flushes it. Throws std::runtime_error naming
    /// the file when it cannot.
    void append(const std::string& record);

    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    std::map<int, FrameStats> earlier_;
    std::ofstream file_;
};

}  // namespace dynrt::cli
