// dynrt_example_cloth: a cloth simulation that renders itself through dynrt::Engine, the library
// API (dynrt/dynrt.h). A square cloth pinned at two corners falls onto a sphere and the ground.
//
// What it shows about the API:
//   - Static meshes (the ground and the sphere) are added once and built once: later updates
//     skip them.
//   - The cloth is a deformable mesh whose positions are *borrowed*: the engine reads the
//     simulation's own position buffer, with no copy per step (see add_cloth below). Each step
//     set_positions() says the buffer changed, and update() refits the cloth's tree (or rebuilds
//     it when the refit's SAH cost degraded past EngineOptions::rebuild_threshold).
//   - update() returns FrameStats, so the step's update, refit, rebuild and top-level times are
//     printed beside the simulation's own time.
//   - render() draws a view into a buffer the program owns; save_image() writes it out.
//   - Every failing call throws dynrt::Error, caught once in main.
//
// The simulation is position-based dynamics (Mueller, Heidelberger, Hennix and Ratcliff 2007,
// "Position Based Dynamics"): Verlet integration predicts the positions, then distance
// constraints (structural: grid neighbours; shear: diagonals) are projected Gauss-Seidel style,
// with sphere and ground collisions as inequality constraints. Gauss-Seidel needs about as many
// iterations as the grid is wide to carry a pin's pull across it, so a pinned cloth of 200x200
// would stretch like rubber; long-range attachments (Kim, Chentanez and Mueller-Fischer 2012,
// "Long Range Attachments - A Method to Simulate Inextensible Clothing in Computer Games") add
// one cheap inequality per vertex and pin: no farther from the pin than at rest (the flat
// cloth's distance, which is the geodesic one). A step is cut into substeps
// with one or two iterations each (Macklin et al. 2019, "Small Steps in Physics Simulation"),
// which stiffens the cloth more cheaply than many iterations of one big step. The constraints
// are grouped into 8 colours (no two constraints of a colour share a vertex), so each colour is
// solved in parallel with oneTBB, which the engine links anyway.

#include "example_common.h"

#include <dynrt/dynrt.h>

#include <oneapi/tbb/parallel_for.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

namespace {

using dynrt_example::median;
using dynrt_example::ms_since;

struct Options {
    int grid = 200;       ///< cloth vertices per side
    int steps = 120;
    int render_every = 1;  ///< render every K-th step (0: never)
    std::string res = "640x480";
    std::string out;      ///< frame file pattern, e.g. cloth/%04d.png; empty writes nothing
    int substeps = 6;
    int iterations = 1;   ///< constraint iterations per substep
    int threads = 0;      ///< EngineOptions::threads
    int reuse = 1;        ///< RenderSettings::reuse_pixels (1: re-trace only what the cloth changed)
};

// ---- The scene's fixed geometry -----------------------------------------------------------

constexpr float kClothSize = 2.4f;    // metres per side
constexpr float kClothHeight = 1.3f;  // starts flat at this height
constexpr dynrt::Vec3 kSphereCentre{0.0f, 0.55f, 0.15f};
constexpr float kSphereRadius = 0.55f;
// Cloth vertices keep this far from the sphere and the ground, so the flat triangles between
// them do not cut into the curved sphere and the renderer sees no z-fighting.
constexpr float kThickness = 0.01f;

struct TriangleMesh {
    std::vector<float> positions;  // x, y, z per vertex
    std::vector<std::uint32_t> indices;
};

/// A UV sphere around the origin (placed with the mesh's transform).
TriangleMesh make_sphere(float radius, int rings, int segments) {
    TriangleMesh mesh;
    for (int r = 0; r <= rings; ++r) {
        const double theta = std::numbers::pi * r / rings;
        for (int s = 0; s <= segments; ++s) {
            const double phi = 2.0 * std::numbers::pi * s / segments;
            mesh.positions.push_back(float(radius * std::sin(theta) * std::cos(phi)));
            mesh.positions.push_back(float(radius * std::cos(theta)));
            mesh.positions.push_back(float(radius * std::sin(theta) * std::sin(phi)));
        }
    }
    const auto vertex = [&](int r, int s) { return std::uint32_t(r * (segments + 1) + s); };
    for (int r = 0; r < rings; ++r) {
        for (int s = 0; s < segments; ++s) {
            // The poles' degenerate triangles are left out.
            if (r != 0) mesh.indices.insert(mesh.indices.end(), {vertex(r, s), vertex(r, s + 1), vertex(r + 1, s)});
            if (r != rings - 1) {
                mesh.indices.insert(mesh.indices.end(),
                                    {vertex(r, s + 1), vertex(r + 1, s + 1), vertex(r + 1, s)});
            }
        }
    }
    return mesh;
}

/// A square on the plane y = 0, centred at the origin.
TriangleMesh make_ground(float half_size) {
    const float h = half_size;
    return {{-h, 0, -h, h, 0, -h, h, 0, h, -h, 0, h}, {0, 2, 1, 0, 3, 2}};
}

// ---- The cloth ------------------------------------------------------------------------------

struct Constraint {
    std::uint32_t a, b;
    float rest;
};

class Cloth {
public:
    explicit Cloth(int n) : n_(n) {
        const std::size_t count = std::size_t(n) * std::size_t(n);
        positions_.resize(3 * count);
        inverse_mass_.assign(count, 1.0f);
        for (int i = 0; i < n; ++i) {        // rows, along z
            for (int j = 0; j < n; ++j) {    // columns, along x
                float* p = &positions_[3 * index(i, j)];
                p[0] = kClothSize * (float(j) / float(n - 1) - 0.5f);
                p[1] = kClothHeight;
                p[2] = kClothSize * (float(i) / float(n - 1) - 0.5f);
            }
        }
        previous_ = positions_;
        // Pinned: the two corners of the back row (infinite mass).
        pins_ = {index(0, 0), index(0, n - 1)};
        for (std::uint32_t pin : pins_) inverse_mass_[pin] = 0.0f;
        for (std::uint32_t pin : pins_) {
            std::vector<float>& rest = pin_rest_.emplace_back(count);
            for (std::size_t v = 0; v < count; ++v) rest[v] = distance(pin, std::uint32_t(v));
        }

        // Two triangles per grid square, split along the same diagonal as the shear constraint.
        for (int i = 0; i + 1 < n; ++i) {
            for (int j = 0; j + 1 < n; ++j) {
                const std::uint32_t v00 = index(i, j), v01 = index(i, j + 1);
                const std::uint32_t v10 = index(i + 1, j), v11 = index(i + 1, j + 1);
                indices_.insert(indices_.end(), {v00, v10, v11, v00, v11, v01});
            }
        }

        // Colours: a constraint between columns j and j+1 shares a vertex only with those of
        // columns j-1 and j+1, so even and odd j form two colours; likewise for the rows of the
        // vertical and both diagonal families.
        const auto add = [&](int colour, std::uint32_t a, std::uint32_t b) {
            colours_[std::size_t(colour)].push_back({a, b, distance(a, b)});
        };
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                if (j + 1 < n) add(0 + j % 2, index(i, j), index(i, j + 1));          // structural
                if (i + 1 < n) add(2 + i % 2, index(i, j), index(i + 1, j));          // structural
                if (i + 1 < n && j + 1 < n) add(4 + i % 2, index(i, j), index(i + 1, j + 1));  // shear
                if (i + 1 < n && j > 0) add(6 + i % 2, index(i, j), index(i + 1, j - 1));      // shear
            }
        }
    }

    /// The positions the engine borrows: x, y, z per vertex. Never resized after construction,
    /// so its data pointer stays valid for the engine (Ownership::borrow's contract).
    const std::vector<float>& positions() const { return positions_; }
    const std::vector<std::uint32_t>& indices() const { return indices_; }

    /// Advances the cloth by `dt` seconds.
    void step(float dt, int substeps, int iterations) {
        const float h = dt / float(substeps);
        for (int s = 0; s < substeps; ++s) {
            predict(h);
            for (int k = 0; k < iterations; ++k) {
                for (const std::vector<Constraint>& colour : colours_) solve(colour);
                attach();
                collide();
            }
        }
    }

    /// Whether every coordinate is finite (the engine checks too, at update()).
    bool finite() const {
        for (float v : positions_) {
            if (!std::isfinite(v)) return false;
        }
        return true;
    }

private:
    std::uint32_t index(int i, int j) const { return std::uint32_t(i * n_ + j); }

    float distance(std::uint32_t a, std::uint32_t b) const {
        const float* pa = &positions_[3 * a];
        const float* pb = &positions_[3 * b];
        const float dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2];
        return std::sqrt(dx * dx + dy * dy + dz * dz);
    }

    /// Verlet: x' = x + damping (x - x_previous) + g h^2, for every free vertex.
    void predict(float h) {
        constexpr float kDamping = 0.998f;
        const float gravity = -9.81f * h * h;
        const std::size_t count = inverse_mass_.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t v = range.begin(); v < range.end(); ++v) {
                if (inverse_mass_[v] == 0.0f) continue;
                for (int c = 0; c < 3; ++c) {
                    float& x = positions_[3 * v + std::size_t(c)];
                    const float velocity = kDamping * (x - previous_[3 * v + std::size_t(c)]);
                    previous_[3 * v + std::size_t(c)] = x;
                    x += velocity + (c == 1 ? gravity : 0.0f);
                }
            }
        });
    }

    /// Projects each constraint of one colour: moves its two ends along their difference, in
    /// proportion to their inverse masses, until they are `rest` apart.
    void solve(const std::vector<Constraint>& colour) {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, colour.size(), 2048),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t k = range.begin(); k < range.end(); ++k) {
                const Constraint& c = colour[k];
                const float wa = inverse_mass_[c.a], wb = inverse_mass_[c.b];
                if (wa + wb == 0.0f) continue;
                float* pa = &positions_[3 * c.a];
                float* pb = &positions_[3 * c.b];
                const float dx = pb[0] - pa[0], dy = pb[1] - pa[1], dz = pb[2] - pa[2];
                const float length = std::sqrt(dx * dx + dy * dy + dz * dz);
                if (length < 1e-9f) continue;
                const float scale = (length - c.rest) / (length * (wa + wb));
                pa[0] += wa * scale * dx, pa[1] += wa * scale * dy, pa[2] += wa * scale * dz;
                pb[0] -= wb * scale * dx, pb[1] -= wb * scale * dy, pb[2] -= wb * scale * dz;
            }
        });
    }

    /// Long-range attachments: pulls each vertex farther from a pin than its rest distance back
    /// onto that distance (pins do not move, so only the vertex does).
    void attach() {
        const std::size_t count = inverse_mass_.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t p = 0; p < pins_.size(); ++p) {
                const float* pin = &positions_[3 * pins_[p]];
                for (std::size_t v = range.begin(); v < range.end(); ++v) {
                    float* x = &positions_[3 * v];
                    const float dx = x[0] - pin[0], dy = x[1] - pin[1], dz = x[2] - pin[2];
                    const float length = std::sqrt(dx * dx + dy * dy + dz * dz);
                    const float rest = pin_rest_[p][v];
                    if (length <= rest || length < 1e-9f) continue;
                    const float scale = rest / length;
                    x[0] = pin[0] + dx * scale, x[1] = pin[1] + dy * scale, x[2] = pin[2] + dz * scale;
                }
            }
        });
    }

    /// Pushes vertices out of the sphere and above the ground; contacts lose most of their
    /// velocity (by moving the previous position towards the current one), which acts as friction.
    void collide() {
        constexpr float kFriction = 0.5f;
        const std::size_t count = inverse_mass_.size();
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 4096),
                          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t v = range.begin(); v < range.end(); ++v) {
                if (inverse_mass_[v] == 0.0f) continue;
                float* p = &positions_[3 * v];
                float* q = &previous_[3 * v];
                bool contact = false;
                const float dx = p[0] - kSphereCentre.x, dy = p[1] - kSphereCentre.y,
                            dz = p[2] - kSphereCentre.z;
                const float distance = std::sqrt(dx * dx + dy * dy + dz * dz);
                const float reach = kSphereRadius + kThickness;
                if (distance < reach && distance > 1e-6f) {
                    const float push = reach / distance;
                    p[0] = kSphereCentre.x + dx * push;
                    p[1] = kSphereCentre.y + dy * push;
                    p[2] = kSphereCentre.z + dz * push;
                    contact = true;
                }
                if (p[1] < kThickness) {
                    p[1] = kThickness;
                    contact = true;
                }
                if (contact) {
                    for (int c = 0; c < 3; ++c) q[c] += kFriction * (p[c] - q[c]);
                }
            }
        });
    }

    int n_;
    std::vector<float> positions_;
    std::vector<float> previous_;
    std::vector<float> inverse_mass_;
    std::vector<std::uint32_t> indices_;
    std::array<std::vector<Constraint>, 8> colours_;
    std::vector<std::uint32_t> pins_;
    /// pin_rest_[p][v]: vertex v's rest distance from pin p.
    std::vector<std::vector<float>> pin_rest_;
};

// ---- The loop ---------------------------------------------------------------------------------

int run(const Options& options) {
    const auto [width, height] = dynrt_example::parse_resolution(options.res);
    if (!options.out.empty()) dynrt_example::frame_path(options.out, 0);  // check the pattern now

    dynrt::EngineOptions engine_options;
    engine_options.threads = options.threads;
    dynrt::Engine engine(engine_options);

    const TriangleMesh ground = make_ground(6.0f);
    dynrt::MeshDesc ground_desc;
    ground_desc.name = "ground";
    ground_desc.positions = ground.positions;
    ground_desc.indices = ground.indices;
    ground_desc.motion = dynrt::Motion::static_;
    ground_desc.surface.diffuse = {0.55f, 0.55f, 0.5f};
    ground_desc.surface.specular = {0.0f, 0.0f, 0.0f};
    engine.add_mesh(ground_desc);

    // The sphere is made around the origin and placed with its transform; a static mesh's
    // transform is applied once, when the static tree is built.
    const TriangleMesh sphere = make_sphere(kSphereRadius, 48, 96);
    dynrt::MeshDesc sphere_desc;
    sphere_desc.name = "sphere";
    sphere_desc.positions = sphere.positions;
    sphere_desc.indices = sphere.indices;
    sphere_desc.motion = dynrt::Motion::static_;
    sphere_desc.transform = dynrt::Transform::translation(kSphereCentre);
    sphere_desc.surface.diffuse = {0.7f, 0.2f, 0.15f};
    sphere_desc.surface.specular = {0.5f, 0.5f, 0.5f};
    sphere_desc.surface.shininess = 64.0f;
    engine.add_mesh(sphere_desc);
    // ground.positions and sphere.positions could go now: both meshes were added with the
    // default Ownership::copy.

    Cloth cloth(options.grid);
    // The cloth is borrowed: the engine keeps a pointer to cloth.positions() instead of copying
    // 3 floats per vertex at add_mesh and at every set_positions. In exchange the program
    // promises that the buffer stays alive and at the same address (the vector is never
    // resized) and is not written while the engine reads it: in add_mesh and in update(), which
    // here runs after the simulation step, on the same thread. set_positions(cloth, buffer)
    // after each step costs nothing; it tells the engine the buffer changed.
    dynrt::MeshDesc cloth_desc;
    cloth_desc.name = "cloth";
    cloth_desc.positions = cloth.positions();
    cloth_desc.indices = cloth.indices();
    cloth_desc.motion = dynrt::Motion::deformable;
    cloth_desc.ownership = dynrt::Ownership::borrow;
    cloth_desc.surface.diffuse = {0.2f, 0.4f, 0.75f};
    cloth_desc.surface.specular = {0.1f, 0.1f, 0.1f};
    const dynrt::MeshId cloth_id = engine.add_mesh(cloth_desc);

    const dynrt::View view{{2.9f, 2.1f, 3.4f}, {0.0f, 0.45f, 0.0f}, {0.0f, 1.0f, 0.0f}, 45.0f};
    dynrt::RenderSettings settings;
    settings.lights.push_back({{-2.0f, 5.0f, 3.0f}, 0.9f});
    settings.reuse_pixels = options.reuse != 0;
    std::vector<float> rgb(std::size_t(width) * std::size_t(height) * 3);
    const dynrt::ImageView image{width, height, rgb};

    // The first update builds every tree: report it apart from the steps.
    const dynrt::FrameStats first = engine.update();
    std::printf("cloth %dx%d vertices, %zu triangles in the scene; first build %.2f ms\n",
                options.grid, options.grid, first.triangles, first.total_ms);
    // Columns: the simulation's own time, then FrameStats of update() under their field
    // names (total_ms is the whole update; update_ms only its first stage, checking and
    // gathering the vertices), then render()'s primary_ms + shadow_ms + shade_ms.
    std::printf("%5s %7s %9s %8s %10s %12s %8s %7s %8s\n", "step", "sim_ms", "update_ms",
                "refit_ms", "rebuild_ms", "top_level_ms", "total_ms", "ref/reb", "trace_ms");

    constexpr float kDt = 1.0f / 60.0f;
    std::vector<double> sim_ms, update_ms, refit_ms, rebuild_ms, top_ms, trace_ms, engine_ms,
        traced_share;
    std::size_t rebuilds = 0, images = 0;
    for (int step = 1; step <= options.steps; ++step) {
        const auto sim_start = std::chrono::steady_clock::now();
        cloth.step(kDt, options.substeps, options.iterations);
        sim_ms.push_back(ms_since(sim_start));
        if (!cloth.finite()) {
            std::fprintf(stderr, "cloth: the simulation diverged at step %d\n", step);
            return 1;
        }

        engine.set_positions(cloth_id, cloth.positions());  // same buffer: "it changed"
        const dynrt::FrameStats stats = engine.update();
        update_ms.push_back(stats.update_ms);
        refit_ms.push_back(stats.refit_ms);
        rebuild_ms.push_back(stats.rebuild_ms);
        top_ms.push_back(stats.top_level_ms);
        engine_ms.push_back(stats.total_ms);
        rebuilds += stats.objects_rebuilt;

        char trace[32] = "-";
        if (options.render_every > 0 && step % options.render_every == 0) {
            const dynrt::FrameStats frame = engine.render(view, image, settings);
            const double ms = frame.primary_ms + frame.shadow_ms + frame.shade_ms;
            trace_ms.push_back(ms);
            traced_share.push_back(double(frame.pixels_traced) / (double(width) * height));
            std::snprintf(trace, sizeof trace, "%.2f", ms);
            if (!options.out.empty()) {
                const std::string path = dynrt_example::frame_path(options.out, step);
                dynrt_example::make_parent_folder(path);
                dynrt::save_image(path, width, height, rgb);
                ++images;
            }
        }
        std::printf("%5d %7.2f %9.2f %8.2f %10.2f %12.3f %8.2f %3zu/%-3zu %8s", step,
                    sim_ms.back(), stats.update_ms, stats.refit_ms, stats.rebuild_ms,
                    stats.top_level_ms, stats.total_ms, stats.objects_refitted,
                    stats.objects_rebuilt, trace);
        // Why a tree was rebuilt: for the cloth, its refitted tree's SAH cost passed
        // (1 + EngineOptions::rebuild_threshold) times its cost at the last build.
        for (const dynrt::TreeRebuild& rebuild : stats.rebuilds) {
            std::printf("  rebuilt %s: %s", rebuild.name.c_str(),
                        dynrt::rebuild_reason_name(rebuild.reason));
            if (rebuild.sah_at_last_build > 0.0) {
                std::printf(" (SAH %.1f -> %.1f)", rebuild.sah_at_last_build, rebuild.sah_refitted);
            }
        }
        std::printf("\n");
    }

    std::printf("median over %d steps: sim %.2f ms, update total %.2f ms (update_ms %.2f, "
                "refit %.2f, rebuild %.2f, top level %.3f), trace %.2f ms (%zu renders at "
                "%dx%d, %.1f%% of the pixels traced); %zu rebuilds; %zu images written\n",
                options.steps, median(sim_ms), median(engine_ms), median(update_ms),
                median(refit_ms), median(rebuild_ms), median(top_ms), median(trace_ms),
                trace_ms.size(), width, height, 100.0 * median(traced_share), rebuilds, images);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    dynrt_example::CommandLine command_line{
        "dynrt_example_cloth: a cloth simulation rendered through the dynrt library API"};
    command_line.add("--grid", options.grid, "cloth vertices per side (triangles: 2 (N-1)^2)", 2,
                     4096);
    command_line.add("--steps", options.steps, "simulation steps of 1/60 s", 0, 1000000);
    command_line.add("--every", options.render_every, "render every K-th step (0: never)", 0,
                     1000000);
    command_line.add("--res", options.res, "image size WxH");
    command_line.add("--out", options.out,
                     "image file pattern with a frame number field, e.g. cloth/%04d.png "
                     "(default: render but write nothing)");
    command_line.add("--substeps", options.substeps, "simulation substeps per step", 1, 1000);
    command_line.add("--iterations", options.iterations, "constraint iterations per substep", 1,
                     1000);
    command_line.add("--threads", options.threads, "engine worker threads (0: all cores)", 0, 1024);
    command_line.add("--reuse", options.reuse,
                     "1: re-trace only the pixels the moving cloth may change (exact), 0: all", 0, 1);
    if (const int exit_code = command_line.parse(argc, argv); exit_code >= 0) return exit_code;
    try {
        return run(options);
    } catch (const dynrt::Error& e) {
        std::fprintf(stderr, "dynrt error: %s\n", e.what());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
    }
    return 1;
}
