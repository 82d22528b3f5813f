// `dynrt render`: a frame or a sequence to images (numbered, an animated GIF or a video), a
// contact sheet, AOVs and the frame report. This file checks the flags before anything is
// loaded; the frames go through the render driver (distributed/distributed_render.cpp), the
// one frame loop of every render, with this process alone.

#include "distributed/distributed_render.h"
#include "frame_args.h"

#include "dynrt/engine/image_output.h"
#include "dynrt/engine/sequence_output.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynrt::cli {

int run_render(const RenderArgs& args) {
    const std::vector<dynrt::Aov> aovs = dynrt::parse_aov_list(args.aov);
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
    // The outputs' folders and clashes are checked by the frame loop, before the scene loads.

    // The frames are rendered and written by the one frame loop of every render
    // (distributed_render.cpp), here with this process alone.
    RenderArgs one_process = args;
    if (one_process.distribute.empty()) one_process.distribute = "frames";
    return run_distributed_render(one_process, *local_cluster());
}

}  // namespace dynrt::cli
