#pragma once
// What a render job is, for `render --resume`: every flag of `dynrt render` in one list, each
// either part of the job (it changes a pixel or a figure of the report: kept in the journal's
// header, and a resume with another value is refused) or not (where the files go, how many
// threads or processes do the work). The header also holds a digest of the scene's files
// (file_digest.h), so that a scene edited since the job began is refused too.

#include "frame_args.h"

#include "dynrt/engine/renderer.h"
#include "dynrt/scene/scene.h"

#include <string>
#include <vector>

namespace dynrt::cli {

/// One field of RenderArgs as a job sees it.
struct JobSetting {
    /// The flag ("--camera"), or "scene" for the positional argument.
    std::string flag;
    /// Its canonical value: the resolved one where flags can say the same thing several ways
    /// (the image size and frame rate the scene gave, the clips by name, parsed lights, a
    /// frame range as A-B), else the text given; "default" for a flag not given.
    std::string value;
    /// Part of the job (in the journal's header), or not.
    bool in_job = true;
};

/// Every field of `args` (RenderArgs and its FrameArgs, one entry each, in declaration
/// order), classified. `options` are the resolved render options and `scene` the loaded
/// scene (for the canonical values). A field added to FrameArgs or RenderArgs without an entry
/// here fails to compile (a static_assert on the structs' field counts in job_settings.cpp).
std::vector<JobSetting> job_settings(const RenderArgs& args, const dynrt::RenderOptions& options,
                                     const dynrt::Scene& scene);

/// The journal's header line (one line of JSON): the format, dynrt's version, the settings
/// that are part of the job and a digest of the scene's files (Scene::files, or the scene
/// argument itself when it is a file and the loader listed none).
std::string journal_header(const RenderArgs& args, const dynrt::RenderOptions& options,
                           const dynrt::Scene& scene);

/// Why a journal whose header is `earlier` cannot be resumed by the job whose header is `now`:
/// one line naming the first setting that differs with both values, or the scene file that
/// changed, and what to do. Empty when they are the same job.
std::string job_difference(const std::string& earlier, const std::string& now);

}  // namespace dynrt::cli
