#include "distributed/render_journal.h"

#include "dynrt/engine/report.h"
#include "job_settings.h"

#include <iostream>
#include <stdexcept>

namespace dynrt::cli {

RenderJournal::RenderJournal(std::filesystem::path path, const std::string& header, bool resume)
    : path_(std::move(path)) {
    if (resume && std::filesystem::exists(path_)) {
        std::ifstream in(path_);
        std::string line;
        std::getline(in, line);
        if (const std::string difference = job_difference(line, header); !difference.empty()) {
            throw std::invalid_argument(difference + " (journal " + path_.string() + ")");
        }
        int number = 1;
        while (std::getline(in, line)) {
            ++number;
            if (line.empty()) continue;
            try {
                const FrameStats record = parse_frame_report_json(line);
                earlier_[record.frame] = record;
            } catch (const std::invalid_argument&) {
                // A run killed while writing its last record: that frame is rendered again.
                std::cerr << "warning: " << path_.string() << ": line " << number
                          << " is not a whole frame record; ignored\n";
            }
        }
    }
    if (resume && !earlier_.empty()) {
        // A line break first: a record torn by a kill must not run into the next one.
        file_.open(path_, std::ios::app);
        file_ << '\n';
    } else {
        file_.open(path_, std::ios::trunc);
        file_ << header << '\n';
    }
    file_.flush();
    if (!file_) throw std::runtime_error(path_.string() + ": cannot write the render journal");
}

void RenderJournal::append(const std::string& record) {
    file_ << record << '\n';
    file_.flush();
    if (!file_) throw std::runtime_error(path_.string() + ": cannot write the render journal");
}

}  // namespace dynrt::cli
