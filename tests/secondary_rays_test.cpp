// The renderer's reflection and refraction rays (Whitted; renderer.h has the model) as an
// engine feature: both tracers and both ways of tracing secondary rays (packets, one by one)
// give the same bits; depth 0 and a cut-off above every weight are today's image; the report
// counts what was traced; exact reuse traces reflective pixels again and stays exact; the
// approximate modes step aside. The images
// themselves are checked against the exact reference in whitted_reference_test.cpp.

#include "dynrt/anim/procedural_motion.h"
#include "dynrt/engine/pixel_reuse.h"
#include "dynrt/engine/renderer.h"
#include "dynrt/packet/tiling.h"
#include "dynrt/engine/scene_loading.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

namespace dynrt {
namespace {

/// A mirror floor, a glass sphere on it, a diffuse sphere beside it and a glass pane in front:
/// reflection packets off the flat floor stay coherent, the spheres scatter theirs.
Scene whitted_scene() {
    Scene scene = load_scene(
        "plane:4@0,-1,0,4+sphere:2000@0.9,-0.2,0,0.8+sphere:800@-1.2,-0.4,-1,0.6+plane:2@0,0,1.8,1.5");
    // The pane stands upright in the plane z = 1.8, before the right half of the view.
    for (glm::vec3& p : scene.objects[3].mesh.positions.edit()) {
        p = glm::vec3(0.5f * p.x + 0.8f, 0.5f * (p.z - 1.8f) - 0.4f, 1.8f);
    }
    scene.materials.resize(4);
    Material& floor = scene.materials[0];
    floor.diffuse = glm::vec3(0.3f, 0.3f, 0.35f);
    floor.reflectance = glm::vec3(0.6f);
    Material& glass = scene.materials[1];
    glass.diffuse = glm::vec3(0.02f);
    glass.specular = glm::vec3(0.5f);
    glass.shininess = 80.0f;
    glass.transmittance = glm::vec3(0.9f);
    glass.ior = 1.5f;
    Material& red = scene.materials[2];
    red.diffuse = glm::vec3(0.8f, 0.2f, 0.1f);
    Material& pane = scene.materials[3];
    pane.diffuse = glm::vec3(0.0f);
    pane.transmittance = glm::vec3(0.8f, 0.9f, 0.8f);
    pane.ior = 1.3f;
    for (std::size_t i = 0; i < scene.objects.size(); ++i) scene.objects[i].material = std::uint32_t(i);
    return scene;
}

Camera whitted_camera() {
    Camera camera;
    camera.eye = glm::vec3(0.3f, 0.9f, 4.5f);
    camera.target = glm::vec3(0.0f, -0.5f, 0.0f);
    camera.fov_y_deg = 50.0f;
    return camera;
}

RenderedFrame render(const Scene& scene, RenderOptions options) {
    Renderer renderer(options);
    RenderedFrame frame;
    renderer.render(scene, whitted_camera(), 0, frame);
    return frame;
}

RenderOptions small_options() {
    RenderOptions options;
    options.width = 96;
    options.height = 80;
    options.lights = {{glm::vec3(-3.0f, 5.0f, 4.0f), 0.8f}, {glm::vec3(4.0f, 3.0f, -2.0f), 0.5f}};
    return options;
}

void expect_same_bits(const RenderedFrame& a, const RenderedFrame& b, const char* what) {
    ASSERT_EQ(a.color.size(), b.color.size());
    std::size_t differing = 0;
    for (std::size_t i = 0; i < a.color.size(); ++i) {
        if (a.color[i] != b.color[i] || a.object[i] != b.object[i] || a.prim[i] != b.prim[i] ||
            a.depth[i] != b.depth[i] || a.normal[i] != b.normal[i]) {
            ++differing;
        }
    }
    EXPECT_EQ(differing, 0u) << what;
}

std::size_t differing_colors(const RenderedFrame& a, const RenderedFrame& b) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.color.size(); ++i) n += a.color[i] != b.color[i];
    return n;
}

TEST(SecondaryRays, PacketsAndSingleRaysGiveTheSameBits) {
    const Scene scene = whitted_scene();
    RenderOptions options = small_options();
    const RenderedFrame packets = render(scene, options);
    ASSERT_GT(packets.stats.reflection_rays, 0u);
    ASSERT_GT(packets.stats.refraction_rays, 0u);
    EXPECT_GT(packets.stats.secondary_packet_rays, 0u);
    EXPECT_GT(packets.stats.secondary_single_rays, 0u) << "the spheres should scatter some rays";

    options.tracer = Tracer::single;
    const RenderedFrame single = render(scene, options);
    expect_same_bits(packets, single, "single-ray tracer");
    EXPECT_EQ(single.stats.secondary_packet_rays, 0u);

    options.tracer = Tracer::packet;
    options.secondary.min_packet_rays = 0;  // every group a packet
    const RenderedFrame all_packets = render(scene, options);
    expect_same_bits(packets, all_packets, "every secondary group as a packet");
    EXPECT_EQ(all_packets.stats.secondary_single_rays, 0u);
    options.secondary.min_packet_rays = 257;  // never
    const RenderedFrame no_packets = render(scene, options);
    expect_same_bits(packets, no_packets, "every secondary ray alone");
    EXPECT_EQ(no_packets.stats.secondary_packet_rays, 0u);
}

// The secondary stage gathers the rays of every tile traced and sorts them into packets across
// the image: which tiles a process traces (a share of them, as an MPI rank does) may change
// the packets, never a pixel.
TEST(SecondaryRays, APixelIsTheSameWhicheverTilesAreTracedWithIt) {
    const Scene scene = whitted_scene();
    RenderOptions options = small_options();
    options.secondary.max_depth = 4;
    const RenderedFrame whole = render(scene, options);
    ASSERT_GT(whole.stats.refraction_rays, 0u);
    for (int r = 0; r < 3; ++r) {
        options.tiles = packet::TileShare{r, 3};
        const RenderedFrame part = render(scene, options);
        const packet::Tiling share(options.width, options.height, options.tiles);
        std::size_t compared = 0, differing = 0;
        for (int t = 0; t < share.count(); ++t) {
            const packet::Tile tile = share.tile(t);
            for (int y = tile.y0; y < tile.y1; ++y) {
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const std::size_t p = std::size_t(y) * std::size_t(options.width) + std::size_t(x);
                    ++compared;
                    differing += part.color[p] != whole.color[p];
                }
            }
        }
        EXPECT_GT(compared, 0u);
        EXPECT_EQ(differing, 0u) << "share " << r << " of 3";
        EXPECT_LT(part.stats.reflection_rays + part.stats.refraction_rays,
                  whole.stats.reflection_rays + whole.stats.refraction_rays);
    }
}

TEST(SecondaryRays, DepthZeroAndAHighCutoffAreThePhongImage) {
    Scene scene = whitted_scene();
    RenderOptions options = small_options();
    options.secondary.max_depth = 0;
    const RenderedFrame depth0 = render(scene, options);
    EXPECT_EQ(depth0.stats.reflection_rays + depth0.stats.refraction_rays, 0u);
    options.secondary.max_depth = 5;
    options.secondary.cutoff = 1.0f;  // above every weight of this scene
    // Shadow rays still pass through its glass above the cut-off (the light it transmits is
    // not a secondary ray), so the cut-off is compared on the scene with its glass opaque.
    Scene no_glass = scene;
    for (Material& m : no_glass.materials) m.transmittance = glm::vec3(0.0f);
    RenderOptions depth0_options = options;
    depth0_options.secondary.max_depth = 0;
    expect_same_bits(render(no_glass, depth0_options), render(no_glass, options), "cut-off above every weight");
    EXPECT_NE(render(scene, depth0_options).color, render(scene, options).color) << "light through glass above the cut-off";

    Scene opaque = scene;
    for (Material& m : opaque.materials) {
        m.reflectance = glm::vec3(0.0f);
        m.transmittance = glm::vec3(0.0f);
    }
    options.secondary.cutoff = SecondaryRays{}.cutoff;
    expect_same_bits(depth0, render(opaque, options), "materials without Whitted terms");

    // And the secondary rays do change the image, more with each level of depth.
    const RenderedFrame depth1 = [&] {
        RenderOptions o = options;
        o.secondary.max_depth = 1;
        return render(scene, o);
    }();
    const RenderedFrame depth5 = render(scene, options);
    const std::size_t changed1 = differing_colors(depth0, depth1);
    EXPECT_GT(changed1, depth0.color.size() / 4);
    EXPECT_GT(differing_colors(depth1, depth5), 0u);
}

TEST(SecondaryRays, ReportCountsEveryRayOnce) {
    const Scene scene = whitted_scene();
    RenderOptions options = small_options();
    options.secondary.max_depth = 3;
    const RenderedFrame frame = render(scene, options);
    const FrameStats& s = frame.stats;
    const std::size_t total = s.reflection_rays + s.refraction_rays;
    ASSERT_EQ(s.secondary_rays_per_depth.size(), 3u);
    EXPECT_EQ(std::accumulate(s.secondary_rays_per_depth.begin(), s.secondary_rays_per_depth.end(),
                              std::size_t(0)),
              total);
    EXPECT_EQ(s.secondary_packet_rays + s.secondary_single_rays, total);
    ASSERT_EQ(s.secondary_packet_rays_per_depth.size(), 3u);
    EXPECT_EQ(std::accumulate(s.secondary_packet_rays_per_depth.begin(),
                              s.secondary_packet_rays_per_depth.end(), std::size_t(0)),
              s.secondary_packet_rays);
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_LE(s.secondary_packet_rays_per_depth[k], s.secondary_rays_per_depth[k]) << k;
    }
    // Every camera ray that hits the floor, the glass or the pane spawns at least one ray.
    EXPECT_GT(s.secondary_rays_per_depth[0], std::size_t(options.width * options.height) / 3);
    EXPECT_GT(s.secondary_rays_per_depth[2], 0u);
    EXPECT_GT(s.secondary_shadow_rays, 0u);
    EXPECT_GT(s.secondary_ms, 0.0);
    EXPECT_GT(s.reflection_mrays_per_s, 0.0);
    EXPECT_GT(s.refraction_mrays_per_s, 0.0);
}

TEST(SecondaryRays, ExactReuseTracesReflectivePixelsAgainAndMatchesFullRenders) {
    // The red sphere turns: it moves in the floor's and the glass's reflections far from its
    // own pixels, which exact reuse must catch.
    Scene scene = whitted_scene();
    const std::vector<std::string> motions{"rigid:" + scene.objects[2].name};
    anim::add_procedural_motions(scene, motions);
    RenderOptions reusing = small_options();  // exact reuse, the default
    RenderOptions full = small_options();
    full.reuse.mode = PixelReuse::off;
    Renderer a(reusing), b(full);
    RenderedFrame ra, rb;
    std::size_t reused = 0;
    for (int frame = 0; frame < 4; ++frame) {
        a.render(scene, whitted_camera(), frame, ra);
        b.render(scene, whitted_camera(), frame, rb);
        SCOPED_TRACE(frame);
        expect_same_bits(ra, rb, "exact reuse against a full render");
        if (frame > 0) {
            EXPECT_EQ(ra.stats.reuse_reason, "1 object changed");
            // Every reflective or transmissive pixel is traced again from its hit on.
            EXPECT_GT(ra.stats.pixels_shadows_retraced, ra.color.size() / 3);
            EXPECT_GT(ra.stats.reflection_rays, 0u);
            reused += ra.stats.pixels_reused;
        }
    }
    EXPECT_GT(reused, 0u);
    // Nothing changed: every pixel kept, reflections included.
    a.render(scene, whitted_camera(), 3, ra);
    EXPECT_EQ(ra.stats.reuse_reason, "nothing changed");
    EXPECT_EQ(ra.stats.reflection_rays, 0u);
    expect_same_bits(ra, rb, "a still frame");
}

TEST(SecondaryRays, ApproximateModesAndAdaptiveSamplingStepAside) {
    const Scene scene = whitted_scene();
    RenderOptions cache = small_options();
    cache.reuse = parse_reuse("cache:0.25");
    const RenderedFrame cached = render(scene, cache);
    EXPECT_EQ(cached.stats.reuse_reason, "secondary rays");
    expect_same_bits(render(scene, small_options()), cached, "render cache with secondary rays");

    RenderOptions adaptive = small_options();
    adaptive.adaptive_tolerance = 0.5f;
    const RenderedFrame sampled = render(scene, adaptive);
    EXPECT_EQ(sampled.stats.interpolated_pixels, 0u);
    EXPECT_EQ(sampled.stats.reuse_reason, "secondary rays");
    expect_same_bits(render(scene, small_options()), sampled, "adaptive sampling with secondary rays");
}

}  // namespace
}  // namespace dynrt
