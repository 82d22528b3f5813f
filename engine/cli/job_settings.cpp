// The one list of `dynrt render`'s settings (job_settings.h) and the journal header made of it.

#include "job_settings.h"

#include "field_count.h"
#include "file_digest.h"

#include "dynrt/engine/image_output.h"
#include "dynrt/engine/pixel_reuse.h"
#include "dynrt/engine/sequence.h"

#include <nlohmann/json.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

namespace dynrt::cli {

// A field added to FrameArgs or RenderArgs must be classified in job_settings() below (part of
// the job, or not) before this compiles again; then update these counts. RenderArgs counts
// its FrameArgs base as one field.
static_assert(field_count<FrameArgs>() == 39,
              "a FrameArgs field was added or removed: classify it in job_settings()");
static_assert(field_count<RenderArgs>() == 1 + 8,
              "a RenderArgs field was added or removed: classify it in job_settings()");

namespace {

constexpr int kJournalFormat = 2;

/// The shortest text that reads back as the same number.
template <class Number>
std::string number_text(Number value) {
    char text[64];
    const auto [end, ec] = std::to_chars(text, text + sizeof text, value);
    return ec == std::errc() ? std::string(text, end) : std::string("?");
}

/// A light as --light reads it.
std::string light_text(const dynrt::PointLight& light) {
    const auto vec = [](const glm::vec3& v) {
        return number_text(v.x) + "," + number_text(v.y) + "," + number_text(v.z);
    };
    using Kind = dynrt::PointLight::Kind;
    const bool directional = light.kind == Kind::directional;
    std::string text = vec(directional ? light.direction : light.position) + "," + number_text(light.intensity);
    if (light.shape == dynrt::PointLight::Shape::sphere) text += ":sphere=" + number_text(light.radius);
    if (light.shape == dynrt::PointLight::Shape::quad) text += ":quad=" + vec(light.edge_u) + "," + vec(light.edge_v);
    if (light.kind == Kind::spot) {
        text += ":spot=" + vec(light.direction) + "," + number_text(glm::degrees(light.inner_cone)) + "," +
                number_text(glm::degrees(light.outer_cone));
    }
    if (directional) text += ":directional";
    if (light.color != glm::vec3(1.0f)) text += ":color=" + vec(light.color);
    if (light.inverse_square) text += ":falloff";
    if (light.range > 0.0f) text += ":range=" + number_text(light.range);
    return text;
}

std::string joined(const std::vector<std::string>& values) {
    if (values.empty()) return "default";
    std::string out;
    for (const std::string& v : values) out += (out.empty() ? "" : "; ") + v;
    return out;
}

std::string or_default(const std::string& value) { return value.empty() ? "default" : value; }

}  // namespace

std::vector<JobSetting> job_settings(const RenderArgs& args, const dynrt::RenderOptions& options,
                                     const dynrt::Scene& scene) {
    std::vector<JobSetting> list;
    const auto job = [&](const char* flag, std::string value) { list.push_back({flag, std::move(value), true}); };
    const auto not_job = [&](const char* flag, std::string value) {
        list.push_back({flag, std::move(value), false});
    };
    std::vector<std::string> lights;
    for (const dynrt::PointLight& l : options.lights) lights.push_back(light_text(l));
    std::vector<std::string> clips;
    for (const std::size_t c : options.pose.clips.value_or(std::vector<std::size_t>{})) {
        clips.push_back(scene.clips[c].name);
    }
    const dynrt::FrameRange range = args.frames.empty() ? dynrt::FrameRange{} : dynrt::parse_frame_range(args.frames);

    // FrameArgs, in declaration order.
    job("scene", scene_source(args));
    job("--res", std::to_string(options.width) + "x" + std::to_string(options.height));
    job("--camera", args.camera == "gltf" ? "scene" : or_default(args.camera));
    job("--light", joined(lights));
    job("--cost-ratio", number_text(args.cost_ratio));  // the trees: the report's SAH costs
    job("--leaf-size", std::to_string(args.leaf_size));
    // A machine's resource: the same pixels and counts with any number of threads (a job may
    // be resumed on another machine, as with another number of MPI processes).
    not_job("--threads", std::to_string(args.threads));
    job("--tracer", args.tracer);  // the same image, other counters in the report
    job("--backend", args.backend);  // another tracer's hits may differ at edge pixels
    job("--bvh", args.bvh);
    job("--leaves", args.leaves);  // the same image, other memory and times
    job("--nodes", args.nodes);    // the same image, other memory and times
    // A machine's resource, as --threads: it picks the layout, which changes no pixel.
    not_job("--memory-budget", args.memory_budget.empty() ? "none" : args.memory_budget);
    job("--packet-culling", dynrt::packet::PacketCulling::parse(args.packet_culling).to_string());
    job("--adaptive", number_text(args.adaptive));
    job("--lod", number_text(args.lod));
    job("--normals", args.normals);
    job("--occluder-cache", args.occluder_cache);  // the same image either way
    job("--spp", std::to_string(args.spp));
    job("--filter", args.filter);
    job("--aa-contrast", number_text(args.aa_contrast));
    job("--background", number_text(options.background.x) + "," + number_text(options.background.y) + "," +
                            number_text(options.background.z));  // as resolved: the file's, or the flag's
    job("--environment", args.environment.empty() ? "none" : args.environment);  // its bytes: scene_files
    job("--environment-scale", number_text(args.environment_scale));
    job("--environment-lights", std::to_string(args.environment_lights));
    job("--depth", std::to_string(args.depth));
    job("--cutoff", number_text(args.cutoff));
    job("--secondary-packet-min", std::to_string(args.secondary_packet_min));
    job("--reuse", dynrt::to_string(dynrt::parse_reuse(args.reuse)));
    job("--anim", joined(args.anims));
    job("--treat", joined(args.treats));
    job("--clip", clips.empty() ? std::string("none") : joined(clips));  // as resolved: names
    job("--loop", args.loop ? "yes" : "no");
    job("--fps", number_text(options.pose.fps));
    // The default camera frames the scene's bounds over the whole range: another range is
    // another view.
    job("--frames", std::to_string(range.first) + "-" + std::to_string(range.last));
    job("--update", args.update);
    job("--builder", args.builder);
    job("--rebuild-threshold", number_text(args.rebuild_threshold));
    job("--cost-ratio-exploding", number_text(args.cost_ratio_exploding));
    // RenderArgs' own.
    job("--out", args.out);
    // Written from the frames at the end (and refused with --resume): no frame's pixels.
    not_job("--contact-sheet", or_default(args.contact_sheet));
    // Where the report goes (the journal sits beside it), not what it says.
    not_job("--report", or_default(args.report));
    job("--aov", args.aov.empty() ? std::string("none") : args.aov);
    job("--exposure", number_text(args.exposure));  // the 8-bit files' bytes
    job("--tone", args.tone);
    // How the work is shared: the same bits either way (tests/mpi_render_test.cpp).
    not_job("--distribute", or_default(args.distribute));
    not_job("--resume", args.resume ? "yes" : "no");
    return list;
}

std::string journal_header(const RenderArgs& args, const dynrt::RenderOptions& options,
                           const dynrt::Scene& scene) {
    nlohmann::ordered_json settings = nlohmann::ordered_json::object();
    for (const JobSetting& s : job_settings(args, options, scene)) {
        if (s.in_job) settings[s.flag] = s.value;
    }
    std::vector<std::string> files = scene.files;
    const std::string source = scene_source(args);
    if (files.empty() && std::filesystem::is_regular_file(source)) files.push_back(source);
    if (!args.environment.empty()) files.push_back(args.environment);  // a changed image changes pixels
    nlohmann::ordered_json digests = nlohmann::ordered_json::array();
    for (const FileDigest& d : digest_files(files)) {
        char hash[17];
        std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(d.fnv1a));
        nlohmann::ordered_json entry = {{"path", d.path}};
        if (d.bytes) {
            entry["bytes"] = *d.bytes;
            entry["fnv1a64"] = hash;
        } else {
            entry["missing"] = true;
        }
        digests.push_back(entry);
    }
    const nlohmann::ordered_json header = {{"dynrt_journal", kJournalFormat},
                                           {"dynrt", DYNRT_VERSION},
                                           {"settings", settings},
                                           {"scene_files", digests}};
    return header.dump();
}

std::string job_difference(const std::string& earlier, const std::string& now) {
    if (earlier == now) return {};
    const std::string what_to_do = "render without --resume to start afresh, or resume with the same flags";
    const nlohmann::json before = nlohmann::json::parse(earlier, nullptr, false);
    const nlohmann::json after = nlohmann::json::parse(now);
    if (before.is_discarded() || !before.is_object() ||
        before.value("dynrt_journal", 0) != after.at("dynrt_journal").get<int>()) {
        return "--resume: the journal's first line is not a job header of this dynrt's "
               "(written by an older dynrt, or not a journal); render without --resume to start afresh";
    }
    if (before.value("dynrt", "") != after.at("dynrt").get<std::string>()) {
        return "--resume: this job was rendered by dynrt " + before.value("dynrt", "?") +
               ", this is dynrt " + after.at("dynrt").get<std::string>() +
               " (its pixels may differ); render without --resume to start afresh";
    }
    const nlohmann::json& was = before.value("settings", nlohmann::json::object());
    for (const auto& [flag, value] : after.at("settings").items()) {
        const std::string old = was.contains(flag) ? was.at(flag).get<std::string>() : "(absent)";
        if (old == value.get<std::string>()) continue;
        return "--resume: this job was rendered with " + flag + " '" + old + "', not '" +
               value.get<std::string>() + "'; " + what_to_do;
    }
    const nlohmann::json& files_before = before.value("scene_files", nlohmann::json::array());
    const nlohmann::json& files_now = after.at("scene_files");
    for (std::size_t i = 0; i < std::max(files_before.size(), files_now.size()); ++i) {
        if (i < files_before.size() && i < files_now.size() && files_before[i] == files_now[i]) continue;
        const nlohmann::json& file = i < files_now.size() ? files_now[i] : files_before[i];
        const std::string path = file.value("path", "?");
        const std::string role = i == 0 ? "the scene file " : "the scene's file ";
        std::string change = "has changed since this job was rendered";
        if (i >= files_before.size()) change = "is read now but was not when this job was rendered";
        else if (i >= files_now.size()) change = "was read when this job was rendered but is not now";
        else if (file.value("missing", false)) change = "is missing now";
        return "--resume: " + role + path + " " + change + "; render without --resume to start "
               "afresh (or put the file back as it was)";
    }
    return "--resume: the journal records another job; " + what_to_do;
}

}  // namespace dynrt::cli
