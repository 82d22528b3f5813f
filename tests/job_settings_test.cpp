// What a render job is for `render --resume` (engine/cli/job_settings.h): every flag classified
// in one list, the journal's header made of it, and a resume with another setting or a changed
// scene file refused with a line naming what differs.

#include "field_count.h"
#include "file_digest.h"
#include "frame_args.h"
#include "job_settings.h"
#include "shared_scene_files.h"

#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace dynrt::cli {
namespace {

namespace fs = std::filesystem;

/// The header of the job `args` describes, on its scene as the render would load it.
std::string header_of(const RenderArgs& args) {
    RenderOptions options = render_options(args);
    const Scene scene = load_animated_scene(args, scene_source(args), options);
    return journal_header(args, options, scene);
}

RenderArgs base_args() {
    RenderArgs args;
    args.scene = "sphere:50";
    args.res = "16x16";
    args.frames = "0-3";
    args.out = "f%04d.png";
    return args;
}

/// The list names every field of FrameArgs and RenderArgs: a field added to either without an
/// entry fails this test (and the static_assert in job_settings.cpp stops the build first).
TEST(JobSettings, TheListNamesEveryFieldOfTheArguments) {
    const RenderArgs args = base_args();
    RenderOptions options = render_options(args);
    const Scene scene = load_animated_scene(args, scene_source(args), options);
    const std::vector<JobSetting> list = job_settings(args, options, scene);
    EXPECT_EQ(list.size(), field_count<FrameArgs>() + field_count<RenderArgs>() - 1);
    // field_count counts what it should: a struct of three, and a derived one of base + two.
    struct Three { int a; std::string b; std::vector<std::string> c; };
    struct Derived : Three { bool d; double e; };
    static_assert(field_count<Three>() == 3);
    static_assert(field_count<Derived>() == 3);
}

struct SettingChange {
    const char* flag;
    std::function<void(RenderArgs&)> change;
};

/// Each setting that changes a pixel or a report figure is part of the job: changing it alone
/// makes another header, refused with a line naming that flag and both values.
TEST(JobSettings, EverySettingOfTheJobIsNamedWhenItDiffers) {
    const RenderArgs base = base_args();
    const std::string header = header_of(base);
    const std::vector<SettingChange> changes = {
        {"scene", [](RenderArgs& a) { a.scene = "sphere:60"; }},
        {"--res", [](RenderArgs& a) { a.res = "16x8"; }},
        {"--camera", [](RenderArgs& a) { a.camera = "eye=0,0,5"; }},
        {"--light", [](RenderArgs& a) { a.lights = {"1,2,3"}; }},
        {"--environment-scale", [](RenderArgs& a) { a.environment_scale = 2.0f; }},
        {"--environment-lights", [](RenderArgs& a) { a.environment_lights = 8; }},
        {"--cost-ratio", [](RenderArgs& a) { a.cost_ratio = 0.5f; }},
        {"--leaf-size", [](RenderArgs& a) { a.leaf_size = 2; }},
        {"--tracer", [](RenderArgs& a) { a.tracer = "single"; }},
        {"--bvh", [](RenderArgs& a) { a.bvh = "binary"; }},
        {"--packet-culling", [](RenderArgs& a) { a.packet_culling = "ab"; }},
        {"--adaptive", [](RenderArgs& a) { a.adaptive = 0.1f; }},
        {"--normals", [](RenderArgs& a) { a.normals = "flat"; }},
        {"--depth", [](RenderArgs& a) { a.depth = 1; }},
        {"--cutoff", [](RenderArgs& a) { a.cutoff = 0.5f; }},
        {"--secondary-packet-min", [](RenderArgs& a) { a.secondary_packet_min = 3; }},
        {"--reuse", [](RenderArgs& a) { a.reuse = "off"; }},
        {"--anim", [](RenderArgs& a) { a.anims = {"rigid"}; }},
        {"--treat", [](RenderArgs& a) { a.treats = {"sphere:50=deformable"}; }},
        {"--loop", [](RenderArgs& a) { a.loop = true; }},
        {"--fps", [](RenderArgs& a) { a.fps = 30; }},
        {"--frames", [](RenderArgs& a) { a.frames = "0-4"; }},
        {"--update", [](RenderArgs& a) { a.update = "refit"; }},
        {"--builder", [](RenderArgs& a) { a.builder = "morton"; }},
        {"--rebuild-threshold", [](RenderArgs& a) { a.rebuild_threshold = 0.75; }},
        {"--cost-ratio-exploding", [](RenderArgs& a) { a.cost_ratio_exploding = 0.25f; }},
        {"--out", [](RenderArgs& a) { a.out = "g%04d.png"; }},
        {"--aov", [](RenderArgs& a) { a.aov = "depth"; }},
    };
    for (const SettingChange& c : changes) {
        RenderArgs args = base;
        c.change(args);
        const std::string difference = job_difference(header, header_of(args));
        EXPECT_NE(difference.find("rendered with " + std::string(c.flag) + " '"), std::string::npos)
            << c.flag << ": " << difference;
        EXPECT_NE(difference.find("render without --resume"), std::string::npos) << difference;
    }
    // And those that change neither: where the report and sheet go, threads, the hand-out.
    RenderArgs other = base;
    other.threads = 7;
    other.report = "elsewhere.json";
    other.contact_sheet = "sheet.png";
    other.distribute = "tiles";
    other.resume = true;
    EXPECT_EQ(job_difference(header, header_of(other)), "");
}

/// The case, word for word: another --camera names both values and what to do.
TEST(JobSettings, AnotherCameraIsRefusedNamingBothValues) {
    RenderArgs with_eye = base_args();
    with_eye.camera = "eye=0,0,5";
    RenderArgs with_scene = base_args();
    with_scene.camera = "still";
    EXPECT_EQ(job_difference(header_of(with_eye), header_of(with_scene)),
              "--resume: this job was rendered with --camera 'eye=0,0,5', not 'still'; render "
              "without --resume to start afresh, or resume with the same flags");
    // Ways of writing the same setting are the same job: the light's default intensity, the
    // image size the default gives, the culling stages listed out.
    RenderArgs a = base_args(), b = base_args();
    a.lights = {"1,2,3"};
    b.lights = {"1,2,3,1"};
    a.res = "";
    b.res = "1024x1024";
    a.packet_culling = "all";
    b.packet_culling = "ab,bp,edge,nf";
    EXPECT_EQ(job_difference(header_of(a), header_of(b)), "");
    // Every part of a light is the job's: its options in any order are the same light, and a
    // spot's cone, a colour or a falloff makes another one.
    a = base_args();
    b = base_args();
    a.lights = {"1,2,3,2:spot=0,-1,0,10,20:color=1,0.5,0.5:falloff:range=9"};
    b.lights = {"1,2,3,2:range=9:falloff:color=1,0.5,0.5:spot=0,-1,0,10,20"};
    EXPECT_EQ(job_difference(header_of(a), header_of(b)), "");
    for (const char* other : {"1,2,3,2:spot=0,-1,0,10,21:color=1,0.5,0.5:falloff:range=9",
                              "1,2,3,2:spot=0,-1,0,10,20:color=1,0.5,0.4:falloff:range=9",
                              "1,2,3,2:spot=0,-1,0,10,20:color=1,0.5,0.5:range=9",
                              "1,2,3,2:spot=0,-1,0,10,20:color=1,0.5,0.5:falloff:range=8",
                              "1,2,3,2:directional"}) {
        b.lights = {other};
        EXPECT_NE(job_difference(header_of(a), header_of(b)), "") << other;
    }
    const PointLight sun = parse_light("1,-2,0,3:directional");
    EXPECT_EQ(sun.kind, PointLight::Kind::directional);
    EXPECT_FLOAT_EQ(glm::length(sun.direction), 1.0f);
    EXPECT_FLOAT_EQ(sun.direction.y, -2.0f / std::sqrt(5.0f));
}

/// The clips played are part of the job, by name: another clip is refused naming both, and a
/// clip given by index or by name is the same job (Fox: Survey, Walk, Run; skipped without
/// ../shared/scenes).
TEST(JobSettings, AnotherClipIsRefusedAndAClipByIndexIsTheSameJob) {
    const fs::path fox = fs::path(DYNRT_SHARED_SCENES_DIR) / "fox" / "Fox.glb";
    if (!fs::exists(fox)) GTEST_SKIP() << fox << " not found";
    RenderArgs walk = base_args(), by_index = base_args(), survey = base_args();
    walk.scene = by_index.scene = survey.scene = fox.string();
    walk.clips = {"Walk"};
    by_index.clips = {"1"};
    survey.clips = {};  // the default: Survey, the first of the alternatives
    EXPECT_EQ(job_difference(header_of(walk), header_of(by_index)), "");
    EXPECT_EQ(job_difference(header_of(walk), header_of(survey)),
              "--resume: this job was rendered with --clip 'Walk', not 'Survey'; render without "
              "--resume to start afresh, or resume with the same flags");
}

/// A scene file changed since the job began, or one it pulls in (a BART include), is named.
TEST(JobSettings, AChangedSceneFileIsNamedAsSuch) {
    const fs::path dir = fs::path(testing::TempDir()) / "dynrt_job_settings_files";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::ofstream(dir / "main.aff") << "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 0.01\n"
                                       "resolution 16 16\nl 0 5 5\n"
                                       "fm 0.1 0.1 0.1 0.8 0.2 0.2 0 0 0 1 0 1\ni part.aff\n";
    std::ofstream(dir / "part.aff") << "p 3\n-1 -1 0\n1 -1 0\n0 1 0\n";
    RenderArgs args = base_args();
    args.scene = (dir / "main.aff").string();
    EXPECT_EQ(load_scene(args.scene).files,
              (std::vector<std::string>{args.scene, (dir / "part.aff").string()}));
    const std::string before = header_of(args);
    EXPECT_EQ(job_difference(before, header_of(args)), "");
    std::ofstream(dir / "part.aff") << "p 3\n-1 -1 0\n1 -1 0\n0 2 0\n";
    EXPECT_EQ(job_difference(before, header_of(args)),
              "--resume: the scene's file " + (dir / "part.aff").string() +
                  " has changed since this job was rendered; render without --resume to start "
                  "afresh (or put the file back as it was)");
    std::ofstream(dir / "main.aff", std::ios::app) << "\n";
    EXPECT_NE(job_difference(before, header_of(args)).find("the scene file " + args.scene + " has changed"),
              std::string::npos);
}

/// A glTF's buffers and textures in files of their own are read files too (skipped without
/// ../shared/scenes).
TEST(JobSettings, AGltfListsItsBufferAndTextureFiles) {
    const fs::path file = fs::path(DYNRT_SHARED_SCENES_DIR) / "animatedcube" / "AnimatedCube.gltf";
    if (!fs::exists(file)) GTEST_SKIP() << file << " not found";
    const Scene scene = load_scene(file.string());
    ASSERT_GE(scene.files.size(), 3u);
    EXPECT_EQ(scene.files[0], file.string());
    EXPECT_EQ(fs::path(scene.files[1]).filename(), "AnimatedCube.bin");
    EXPECT_EQ(fs::path(scene.files[2]).filename(), "AnimatedCube_BaseColor.png");
    EXPECT_TRUE(load_scene("sphere:10").files.empty());
}

/// FNV-1a 64's published test vectors (Fowler, Noll and Vo).
TEST(FileDigest, Fnv1a64MatchesItsTestVectors) {
    const auto hash = [](const std::string& text) {
        return fnv1a_64({reinterpret_cast<const unsigned char*>(text.data()), text.size()});
    };
    EXPECT_EQ(hash(""), 0xcbf29ce484222325ull);
    EXPECT_EQ(hash("a"), 0xaf63dc4c8601ec8cull);
    EXPECT_EQ(hash("foobar"), 0x85944171f73967e8ull);
    // Hashed in pieces as in one.
    const std::string text = "foobar";
    const auto* bytes = reinterpret_cast<const unsigned char*>(text.data());
    EXPECT_EQ(fnv1a_64({bytes + 3, 3}, fnv1a_64({bytes, 3})), hash("foobar"));
    const std::vector<FileDigest> missing = digest_files({"/no/such/file"});
    ASSERT_EQ(missing.size(), 1u);
    EXPECT_FALSE(missing[0].bytes.has_value());
}

}  // namespace
}  // namespace dynrt::cli
