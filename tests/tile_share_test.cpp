// A frame split into tile shares (TraceSettings::tiles, dynrt/engine/tile_share.h), as
// `mpirun dynrt render --distribute tiles` splits it: each share rendered by its own Renderer,
// packed and unpacked into one frame, must give the bits of the whole frame rendered at once,
// in every buffer and every frame of a sequence (exact reuse per share included), with both
// tracers, adaptive sampling, and reflections. The MPI runs themselves are tests/mpi.

#include "same_bits.h"
#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/camera.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/engine/scene_loading.h"
#include "dynrt/engine/tile_share.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace dynrt {
namespace tile_share_test {

Scene moving_scene(bool mirror) {
    const std::string plane = "plane:8@0,-1,0,4#808080";
    const std::string rigid = "sphere:600@-0.8,-0.4,0.3,0.6#e04020";
    const std::string wave = "sphere:300@1.2,-0.5,-0.6,0.5#2050e0";
    const std::string explode = "soup:600@-0.6,-1,-2,1.4#40c060";
    Scene scene = load_scene(plane + "+" + rigid + "+" + wave + "+" + explode);
    const std::vector<std::string> motions{"rigid:" + rigid, "wave:" + wave, "explode:" + explode};
    anim::add_procedural_motions(scene, motions);
    if (mirror) scene.materials.at(scene.objects.at(0).material).reflectance = glm::vec3(0.5f);
    return scene;
}

using dynrt::test::same_bits;

/// Renders `frames` whole and split into `ranks` shares (one Renderer per share, as one per
/// process); the gathered frames must equal the whole ones bit for bit. Returns the shares'
/// primary rays summed over the frames, against the whole frames' in `whole_rays`.
std::size_t expect_split_equals_whole(const Scene& scene, RenderOptions options, int ranks,
                                      std::initializer_list<int> frames, std::size_t& whole_rays) {
    const Camera camera = default_camera(scene_bounds(scene));
    Renderer whole(options);
    std::vector<std::unique_ptr<Renderer>> shares;
    for (int r = 0; r < ranks; ++r) {
        RenderOptions share_options = options;
        share_options.tiles = packet::TileShare{r, ranks};
        shares.push_back(std::make_unique<Renderer>(share_options));
    }
    std::vector<RenderedFrame> parts(static_cast<std::size_t>(ranks));
    RenderedFrame expected, gathered;
    std::size_t share_rays = 0;
    whole_rays = 0;
    for (const int f : frames) {
        SCOPED_TRACE("frame " + std::to_string(f));
        whole.render(scene, camera, f, expected);
        whole_rays += expected.stats.primary_rays;
        gathered = RenderedFrame{};
        gathered.width = options.width;
        gathered.height = options.height;
        gathered.color.assign(expected.color.size(), glm::vec3(-1.0f));
        gathered.depth.assign(expected.depth.size(), -1.0f);
        gathered.object.assign(expected.object.size(), -2);
        gathered.prim.assign(expected.prim.size(), -2);
        gathered.normal.assign(expected.normal.size(), glm::vec3(-1.0f));
        for (int r = 0; r < ranks; ++r) {
            shares[std::size_t(r)]->render(scene, camera, f, parts[std::size_t(r)]);
            share_rays += parts[std::size_t(r)].stats.primary_rays;
            std::vector<float> packed;
            pack_tiles(parts[std::size_t(r)], packet::TileShare{r, ranks}, packed);
            unpack_tiles(packed, packet::TileShare{r, ranks}, options.hit_buffers, gathered);
        }
        EXPECT_TRUE(same_bits(gathered.color, expected.color)) << "colour";
        EXPECT_TRUE(same_bits(gathered.depth, expected.depth)) << "depth";
        EXPECT_TRUE(same_bits(gathered.object, expected.object)) << "object";
        EXPECT_TRUE(same_bits(gathered.prim, expected.prim)) << "prim";
        EXPECT_TRUE(same_bits(gathered.normal, expected.normal)) << "normal";
    }
    return share_rays;
}

TEST(TileShare, SharesCoverEveryTileOnceInterleaved) {
    for (const int ranks : {1, 2, 3, 7, 40}) {
        const packet::Tiling all(88, 72);
        using Corner = std::pair<int, int>;
        std::multiset<Corner> seen;
        std::size_t pixels = 0;
        for (int r = 0; r < ranks; ++r) {
            const packet::Tiling share(88, 72, packet::TileShare{r, ranks});
            pixels += share.pixel_count();
            for (int i = 0; i < share.count(); ++i) {
                const packet::Tile t = share.tile(i);
                seen.insert({t.x0, t.y0});
                // Interleaved: the share's i-th tile is the whole tiling's (r + i ranks)-th.
                const packet::Tile u = all.tile(r + i * ranks);
                EXPECT_EQ(t.x0, u.x0);
                EXPECT_EQ(t.y1, u.y1);
            }
        }
        EXPECT_EQ(seen.size(), std::size_t(all.count())) << ranks << " ranks";
        EXPECT_EQ(std::set<Corner>(seen.begin(), seen.end()).size(), seen.size());
        EXPECT_EQ(pixels, std::size_t(88 * 72));
    }
}

TEST(TileShare, GatheredSharesEqualTheWholeFrameWithBothTracersAndExactReuse) {
    const Scene scene = moving_scene(false);
    for (const Tracer tracer : {Tracer::packet, Tracer::single}) {
        for (const PixelReuse reuse : {PixelReuse::exact, PixelReuse::off}) {
            SCOPED_TRACE(std::string(tracer == Tracer::packet ? "packet" : "single") + ", reuse " +
                         pixel_reuse_name(reuse));
            RenderOptions options;
            options.width = 88;  // edge tiles clipped on both axes
            options.height = 72;
            options.tracer = tracer;
            options.reuse.mode = reuse;
            std::size_t whole_rays = 0;
            const std::size_t share_rays =
                expect_split_equals_whole(scene, options, 3, {0, 1, 2, 2, 7, 3}, whole_rays);
            // Each share traced its own tiles only: together no more rays than the whole.
            if (reuse == PixelReuse::off) {
                EXPECT_EQ(share_rays, whole_rays);
            }
            EXPECT_LE(share_rays, whole_rays + 6 * 256);
        }
    }
}

TEST(TileShare, GatheredSharesEqualTheWholeFrameWithAdaptiveSamplingAndReflections) {
    RenderOptions adaptive;
    adaptive.width = 72;
    adaptive.height = 40;
    adaptive.adaptive_tolerance = 0.05f;
    std::size_t whole_rays = 0;
    expect_split_equals_whole(moving_scene(false), adaptive, 2, {0, 4}, whole_rays);
    RenderOptions mirror;
    mirror.width = 72;
    mirror.height = 40;
    expect_split_equals_whole(moving_scene(true), mirror, 2, {0, 1, 5}, whole_rays);
}

TEST(TileShare, ColourOnlyFramesPackThreeFloatsPerPixel) {
    RenderOptions options;
    options.width = 40;
    options.height = 24;
    options.hit_buffers = false;
    std::size_t whole_rays = 0;
    expect_split_equals_whole(moving_scene(false), options, 2, {0, 1}, whole_rays);
    EXPECT_EQ(packed_share_size(40, 24, packet::TileShare{0, 2}, false), std::size_t(3 * (256 + 128 + 128)));  // tiles 0, 2, 4 of 3 x 2
}

TEST(TileShare, BadSharesAndApproximateReuseAreRefused) {
    const Scene scene = moving_scene(false);
    const Camera camera = default_camera(scene_bounds(scene));
    RenderOptions options;
    options.width = 32;
    options.height = 32;
    options.tiles = packet::TileShare{2, 2};
    RenderedFrame frame;
    EXPECT_THROW(Renderer(options).render(scene, camera, 0, frame), std::invalid_argument);
    options.tiles = packet::TileShare{0, 2};
    options.reuse = parse_reuse("cache:0.25");
    try {
        Renderer(options).render(scene, camera, 0, frame);
        ADD_FAILURE() << "render cache with a tile share accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("whole image"), std::string::npos) << e.what();
    }
    std::vector<float> short_share(5);
    frame.width = frame.height = 32;
    EXPECT_THROW(unpack_tiles(short_share, packet::TileShare{0, 2}, false, frame),
                 std::invalid_argument);
}

}  // namespace tile_share_test
}  // namespace dynrt
