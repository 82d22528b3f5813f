// `dynrt render`: a frame or a sequence to images (numbered, an animated GIF or a video), a
// contact sheet, AOVs and the frame report.

#include "frame_args.h"
#include "render_outputs.h"

#include "dynrt/engine/image_output.h"
#include "dynrt/engine/report.h"
#include "dynrt/engine/sequence_output.h"

#include <tbb/info.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::cli {

namespace {

/// A one-line progress bar on stderr, redrawn in place, with the time left at the mean pace so
/// far; used only when stderr is a terminal.
void draw_progress(int done, int total, double ms_per_frame) {
    constexpr int kWidth = 30;
    const int filled = total > 0 ? done * kWidth / total : kWidth;
    const double left_s = double(total - done) * ms_per_frame / 1000.0;
    std::cerr << "\r[" << std::string(std::size_t(filled), '#')
              << std::string(std::size_t(kWidth - filled), ' ') << "] " << done << "/" << total
              << " frames, " << std::fixed << std::setprecision(1) << ms_per_frame
              << " ms/frame, " << std::setprecision(0) << left_s << " s left  " << std::flush;
    if (done == total) std::cerr << "\n";
}

}  // namespace

int run_render(const RenderArgs& args) {
    dynrt::RenderOptions options = render_options(args);
    const std::vector<dynrt::Aov> aovs = dynrt::parse_aov_list(args.aov);
    options.hit_buffers = !aovs.empty();
    const dynrt::FrameRange range =
        args.frames.empty() ? dynrt::FrameRange{} : dynrt::parse_frame_range(args.frames);
    // One file for the whole sequence: an animated GIF or a video, named without a frame number.
    const bool animated = dynrt::is_sequence_file(args.out) && !dynrt::has_frame_number(args.out);
    if (animated) dynrt::check_sequence_file(args.out);
    if (range.count() > 1 && !dynrt::has_frame_number(args.out) && !animated) {
        throw std::invalid_argument("--out '" + args.out + "': several frames need a frame "
                                    "number in the name, e.g. 'frames/%04d.png', or an "
                                    "animated .gif or a video (.mp4)");
    }
    if (animated && range.count() > 1 && !aovs.empty()) {
        throw std::invalid_argument("--aov with an animated --out '" + args.out +
                                    "': AOVs are one file per frame, so they need numbered "
                                    "frames ('frames/%04d.png')");
    }
    if (!args.contact_sheet.empty()) dynrt::check_image_path(args.contact_sheet);
    const std::filesystem::path first_path = dynrt::frame_path(args.out, range.first);
    // A numbered output ('frames/%04d.png', one frame or many) goes to a folder of its own,
    // which is made as renderers do, but only once the scene has loaded: a run that fails
    // before rendering leaves nothing behind. Until then only the format is checked.
    const bool makes_folder = dynrt::has_frame_number(args.out) && first_path.has_parent_path();
    // A sequence file's format was checked above (a video is not an image format).
    if (!animated) dynrt::check_image_path(makes_folder ? first_path.filename() : first_path);
    check_render_outputs(render_outputs(args, range, /*with_journal=*/false), range);

    const std::string source = scene_source(args);
    const dynrt::Scene scene = load_animated_scene(args, source, options);
    warn_past_the_end(scene, options.pose, range);
    note_single_frame(std::cout, args.frames);
    if (makes_folder) {
        std::filesystem::create_directories(first_path.parent_path());
        dynrt::check_image_path(first_path);
    }
    const dynrt::CameraSource view = camera_source(scene, args, options.pose, range);

    dynrt::Renderer renderer(options);
    dynrt::RenderedFrame frame;
    std::vector<dynrt::FrameStats> frames;
    const bool progress = range.count() > 1 && isatty(fileno(stderr));
    std::cout << "dynrt: " << source << ": " << scene.objects.size() << " objects, "
              << scene.triangle_count() << " triangles, " << options.width << "x"
              << options.height << ", frames " << range.first << "-" << range.last << " -> "
              << args.out << std::endl;
    double total_ms = 0.0;
    std::unique_ptr<dynrt::SequenceFile> sequence_file;
    if (animated) sequence_file = dynrt::open_sequence_file(args.out, options.pose.fps);
    std::optional<dynrt::ContactSheet> sheet;
    if (!args.contact_sheet.empty()) sheet.emplace(range.count());
    for (int f = range.first; f <= range.last; ++f) {
        renderer.render(scene, f, view, frame);
        const std::string path = dynrt::frame_path(args.out, f);
        if (sequence_file) {
            sequence_file->add(frame);
        } else {
            dynrt::write_image(path, frame);
        }
        if (sheet) sheet->add(f - range.first, frame);
        for (dynrt::Aov aov : aovs) dynrt::write_aov(path, aov, frame);
        frames.push_back(frame.stats);
        total_ms += frame.stats.total_ms;
        if (progress) draw_progress(f - range.first + 1, range.count(), total_ms / double(frames.size()));
    }

    if (sequence_file) sequence_file->close();
    if (sheet) {
        sheet->write(args.contact_sheet);
        std::cout << "contact sheet: " << args.contact_sheet << " (" << sheet->size()
                  << " frames)\n";
    }
    if (frames.front().degenerate_skipped > 0) {
        std::cout << "degenerate triangles skipped: " << frames.front().degenerate_skipped << "\n";
    }
    print_ignored(std::cout, scene);
    dynrt::print_frame_header(std::cout);
    // A sequence prints its summary; every frame's figures are in the --report file.
    if (frames.size() <= 8) {
        for (const dynrt::FrameStats& f : frames) dynrt::print_frame_row(std::cout, f);
    }
    dynrt::print_summary(std::cout, frames);
    dynrt::print_secondary_summary(std::cout, frames);
    print_rebuild_summary(std::cout, frames);
    print_update_choices(std::cout, frames);
    if (!args.report.empty()) {
        const dynrt::RunInfo run{source, options.width, options.height, options.build.cost_ratio,
                                 options.build.leaf_size_max,
                                 args.threads > 0 ? args.threads
                                                  : tbb::info::default_concurrency(),
                                 scene.ignored};
        dynrt::write_report(args.report, run, frames);
        std::cout << "report: " << args.report << "\n";
    }
    return 0;
}

}  // namespace dynrt::cli
