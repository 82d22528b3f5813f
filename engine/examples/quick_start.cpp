// dynrt quick start (docs/library-api.md): a waving grid and a turning panel, updated step by
// step, rendered into quick_start.png, then probed with a few rays.
#include <dynrt/dynrt.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <vector>

int main() try {
    dynrt::Engine engine;  // all cores; EngineOptions sets threads, cost ratio, leaf size

    // A 16x16-vertex grid in the plane z = 0, its vertices moved every step: deformable.
    const std::uint32_t n = 16;
    std::vector<float> grid;
    std::vector<std::uint32_t> grid_indices;
    for (std::uint32_t y = 0; y < n; ++y) {
        for (std::uint32_t x = 0; x < n; ++x) {
            grid.insert(grid.end(), {x / 7.5f - 1, y / 7.5f - 1, 0});
        }
    }
    for (std::uint32_t y = 0; y + 1 < n; ++y) {
        for (std::uint32_t x = 0; x + 1 < n; ++x) {
            const std::uint32_t i = y * n + x;
            grid_indices.insert(grid_indices.end(), {i, i + 1, i + n, i + 1, i + n + 1, i + n});
        }
    }
    dynrt::MeshDesc grid_mesh;  // Ownership::copy (the default): add_mesh copies the positions
    grid_mesh.name = "grid";
    grid_mesh.positions = grid;
    grid_mesh.indices = grid_indices;
    grid_mesh.motion = dynrt::Motion::deformable;
    const dynrt::MeshId cloth = engine.add_mesh(grid_mesh);
    // Two triangles moved by their transform only: Motion::automatic (the default) infers rigid.
    const float quad[] = {-0.3f, -0.3f, 0, 0.3f, -0.3f, 0, 0.3f, 0.3f, 0, -0.3f, 0.3f, 0};
    const std::uint32_t quad_indices[] = {0, 1, 2, 0, 2, 3};
    dynrt::MeshDesc panel_mesh;
    panel_mesh.name = "panel";
    panel_mesh.positions = quad;
    panel_mesh.indices = quad_indices;
    panel_mesh.surface.diffuse = {0.9f, 0.3f, 0.2f};
    const dynrt::MeshId panel = engine.add_mesh(panel_mesh);

    const int width = 96, height = 64;
    std::vector<float> rgb(std::size_t(width) * height * 3);  // the caller's image buffer
    for (int step = 0; step < 4; ++step) {
        for (std::size_t v = 0; v < grid.size(); v += 3) {
            grid[v + 2] = 0.2f * std::sin(3 * grid[v] + 0.5f * step);
        }
        engine.set_positions(cloth, grid);  // copied: `grid` may change right after the call
        engine.set_transform(panel, dynrt::Transform::rotation({0, 1, 0}, 0.3f * step, {0, 0, 1}));
        const dynrt::FrameStats update = engine.update();  // refits the grid, moves the panel
        const dynrt::FrameStats frame =
            engine.render({.eye = {0, 0, 4}}, {.width = width, .height = height, .rgb = rgb});
        std::printf("step %d: update %.3f ms, build %.3f ms (refit %.3f, rebuild %.3f), "
                    "trace %.3f ms\n", step, update.update_ms, update.build_ms, update.refit_ms,
                    update.rebuild_ms, frame.primary_ms + frame.shadow_ms);
    }
    dynrt::save_image("quick_start.png", width, height, rgb);

    // Rays along -z at x = -0.5 (the grid), 0 (the panel) and 2 (nothing).
    std::vector<dynrt::Ray> rays;
    for (float x : {-0.5f, 0.0f, 2.0f}) {
        rays.push_back({.origin = {x, 0.1f, 4}, .direction = {0, 0, -1}});
    }
    std::vector<dynrt::RayHit> hits(rays.size());
    std::vector<std::uint8_t> blocked(rays.size());
    engine.intersect(rays, hits);
    engine.occluded(rays, blocked);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        std::printf("ray %zu: mesh %d triangle %d t %.3f occluded %d\n", i,
                    hits[i].hit() ? int(hits[i].mesh.value) : -1,
                    hits[i].hit() ? int(hits[i].primitive) : -1, hits[i].t, blocked[i]);
    }
    std::printf("panel treated as %s\n", dynrt::motion_name(engine.motion(panel)));
    return 0;
} catch (const dynrt::Error& e) {
    std::fprintf(stderr, "dynrt error %d: %s\n", int(e.code()), e.what());
    return 1;
}
