// dynrt_example_lidar: a rotating lidar in an animated street scene, as a robotics or driving
// simulation would query it through dynrt::Engine, the library API (dynrt/dynrt.h).
//
// What it shows about the API:
//   - A scene made of static meshes (ground, buildings), rigid ones (cars: only set_transform)
//     and a deforming one (a waving flag: set_positions, copied), all added with
//     Motion::automatic: the engine infers each mesh's class from the calls it sees (printed
//     after the first step).
//   - Each step one update() and two ray batches: intersect() for the lidar's closest hits (t,
//     mesh, triangle, barycentrics) and occluded() for a visibility query: whether each return
//     is in the sun or in shadow (a shadow ray from the hit point towards the sun).
//   - QueryStats: time, Mrays/s, and how many rays went as 16x16 packets or one by one.
//
// The sensor: C channels spread evenly over a vertical fan from -25 to +15 degrees, A azimuth
// steps per revolution (offset by half a step, so no ray lies exactly on an axis plane), and one
// whole revolution per step (10 Hz: the scene moves 0.1 s per step). A real spinning lidar fires
// while the scene moves; here each revolution sees one instant.
//
// Ray order. The engine splits each run of 256 consecutive rays of a batch by the directions'
// signs and traces each group of 16 or more whose directions lie within about 25 degrees of its
// middle ray's as one packet, the rest ray by ray (CpuTracer::as_packet,
// src/rendering/cpu_tracer.h). So the order in
// which the program lays its rays out decides how well the packets fill. --order picks it:
//   firing   for each azimuth, every channel (the order a spinning lidar fires in): a run is
//            8 azimuth columns of the 32 channels; the fan crosses the horizon, so each run
//            splits by the vertical sign into two packets of about half the rays.
//   channel  for each channel, every azimuth (a range image row by row): a run of 256 sweeps
//            90 degrees of azimuth, far too wide for a packet.
//   horizon  (default) the rays below the horizon first, then those above it, each half in
//            firing order: a run is a few azimuth columns of one half of the fan, narrow and of
//            one sign per axis. A run also changes sign where it crosses from one azimuth
//            quadrant to the next; with A = 1024 a quadrant of a half of h channels holds 256 h
//            rays, so runs never straddle one.
// The hits come back in the batch's order; `cell` maps each ray back to (channel, azimuth).

#include "example_common.h"

#include <dynrt/dynrt.h>


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
    int steps = 20;
    int channels = 32;
    int azimuth = 1024;
    int threads = 0;
    float range_m = 100.0f;
    std::string order = "horizon";
    std::string out;  ///< range image pattern, e.g. lidar/%04d.png; empty writes nothing
};

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kFanLowDeg = -25.0, kFanHighDeg = 15.0;
constexpr float kStepSeconds = 0.1f;

struct TriangleMesh {
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
};

/// Appends an axis-aligned box standing on y = `base`, centred on (x, z), to `mesh`.
void add_box(TriangleMesh& mesh, float x, float z, float half_x, float half_z, float height,
             float base = 0.0f) {
    const std::uint32_t first = std::uint32_t(mesh.positions.size() / 3);
    for (int k = 0; k < 8; ++k) {
        mesh.positions.push_back(x + (k & 1 ? half_x : -half_x));
        mesh.positions.push_back(base + (k & 2 ? height : 0.0f));
        mesh.positions.push_back(z + (k & 4 ? half_z : -half_z));
    }
    // Two triangles per face: -x, +x, -y, +y, -z, +z.
    static constexpr std::uint32_t kFaces[12][3] = {
        {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
        {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
    for (const auto& face : kFaces) {
        for (std::uint32_t v : face) mesh.indices.push_back(first + v);
    }
}

/// The flag: a grid of `columns` x `rows` vertices in the plane z = 0, hanging from x = 0 (the
/// pole) towards +x, waving in z as a travelling wave that grows away from the pole.
struct Flag {
    static constexpr int kColumns = 48, kRows = 32;
    static constexpr float kWidth = 3.0f, kHeight = 2.0f, kBase = 3.0f;
    TriangleMesh mesh;

    Flag() {
        wave(0.0f);
        for (int r = 0; r + 1 < kRows; ++r) {
            for (int c = 0; c + 1 < kColumns; ++c) {
                const std::uint32_t v = std::uint32_t(r * kColumns + c);
                mesh.indices.insert(mesh.indices.end(),
                                    {v, v + 1, v + kColumns, v + 1, v + kColumns + 1, v + kColumns});
            }
        }
    }

    void wave(float seconds) {
        mesh.positions.resize(3 * kRows * kColumns);
        for (int r = 0; r < kRows; ++r) {
            for (int c = 0; c < kColumns; ++c) {
                const float s = float(c) / float(kColumns - 1);  // 0 at the pole
                float* p = &mesh.positions[3 * std::size_t(r * kColumns + c)];
                p[0] = kWidth * s;
                p[1] = kBase + kHeight * float(r) / float(kRows - 1);
                p[2] = 0.35f * s * std::sin(6.0f * s - 5.0f * seconds + 0.8f * float(r) / kRows);
            }
        }
    }
};

/// Where the lidar rays go, in the batch's order: cell[k] = channel * A + azimuth of ray k.
std::vector<std::uint32_t> ray_order(const std::string& order, int channels, int azimuth,
                                     const std::vector<double>& elevation) {
    std::vector<std::uint32_t> cell;
    cell.reserve(std::size_t(channels) * std::size_t(azimuth));
    const auto column = [&](int a, auto&& take) {
        for (int c = 0; c < channels; ++c) {
            if (take(c)) cell.push_back(std::uint32_t(c * azimuth + a));
        }
    };
    if (order == "firing") {
        for (int a = 0; a < azimuth; ++a) column(a, [](int) { return true; });
    } else if (order == "channel") {
        for (int c = 0; c < channels; ++c) {
            for (int a = 0; a < azimuth; ++a) cell.push_back(std::uint32_t(c * azimuth + a));
        }
    } else {  // horizon
        for (int a = 0; a < azimuth; ++a) column(a, [&](int c) { return elevation[std::size_t(c)] < 0.0; });
        for (int a = 0; a < azimuth; ++a) column(a, [&](int c) { return elevation[std::size_t(c)] >= 0.0; });
    }
    return cell;
}

/// A colour per mesh for the range image.
dynrt::Vec3 mesh_colour(std::uint32_t mesh) {
    static constexpr dynrt::Vec3 kPalette[] = {
        {0.5f, 0.5f, 0.5f}, {0.9f, 0.8f, 0.5f}, {0.9f, 0.3f, 0.2f}, {0.3f, 0.8f, 0.3f},
        {0.3f, 0.5f, 1.0f}, {0.9f, 0.5f, 0.9f}, {0.2f, 0.9f, 0.9f}, {1.0f, 0.6f, 0.2f},
        {1.0f, 1.0f, 1.0f}};
    return kPalette[mesh % (sizeof kPalette / sizeof kPalette[0])];
}

int run(const Options& options) {
    if (!options.out.empty()) dynrt_example::frame_path(options.out, 0);  // check the pattern now
    dynrt::EngineOptions engine_options;
    engine_options.threads = options.threads;
    dynrt::Engine engine(engine_options);
    std::vector<std::string> names;
    const auto add = [&](const std::string& name, const TriangleMesh& mesh, dynrt::Vec3 colour) {
        dynrt::MeshDesc desc;
        desc.name = name;
        desc.positions = mesh.positions;
        desc.indices = mesh.indices;
        desc.motion = dynrt::Motion::automatic;  // inferred from the calls (printed below)
        desc.surface.diffuse = colour;
        names.push_back(name);
        return engine.add_mesh(desc);  // copied: `mesh` may go after this
    };

    // ---- The scene: static ground and buildings, rigid cars, a deforming flag ----
    const TriangleMesh ground{{-150, 0, -150, 150, 0, -150, 150, 0, 150, -150, 0, 150},
                              {0, 2, 1, 0, 3, 2}};
    add("ground", ground, {0.4f, 0.4f, 0.4f});
    TriangleMesh buildings;
    for (int k = 0; k < 14; ++k) {
        // A ring of blocks 25 to 45 m away, of varied size (a fixed pattern, no randomness).
        const double angle = 2.0 * std::numbers::pi * (k + 0.3 * (k % 3)) / 14.0;
        const float distance = 25.0f + 20.0f * float((k * 7) % 5) / 4.0f;
        add_box(buildings, distance * float(std::cos(angle)), distance * float(std::sin(angle)),
                4.0f + float(k % 4), 4.0f + float((k * 3) % 5), 6.0f + 2.0f * float((k * 5) % 8));
    }
    add("buildings", buildings, {0.8f, 0.75f, 0.6f});
    // The cars are made around the origin; set_transform drives them around the sensor.
    TriangleMesh car;
    add_box(car, 0.0f, 0.0f, 2.25f, 0.9f, 1.5f, 0.2f);
    struct Car {
        dynrt::MeshId id;
        float radius_m, speed_rad_s, phase_rad;
    };
    std::vector<Car> cars;
    for (int k = 0; k < 6; ++k) {
        const float radius = 8.0f + 2.5f * float(k);
        const float speed = (k % 2 ? -1.0f : 1.0f) * 8.0f / radius;  // about 8 m/s
        cars.push_back({add("car" + std::to_string(k), car, mesh_colour(std::uint32_t(k + 2))),
                        radius, speed, float(k)});
    }
    Flag flag;
    const dynrt::MeshId flag_id = add("flag", flag.mesh, {0.8f, 0.1f, 0.1f});
    engine.set_transform(flag_id, dynrt::Transform::translation({5.0f, 0.0f, -6.0f}));
    std::printf("meshes:");
    for (std::size_t m = 0; m < names.size(); ++m) std::printf(" %zu %s", m, names[m].c_str());
    std::printf("\n");

    // ---- The sensor ----
    const int channels = options.channels, azimuth = options.azimuth;
    std::vector<double> elevation(std::size_t(channels), 0.0);
    for (int c = 0; c < channels; ++c) {
        elevation[std::size_t(c)] =
            channels == 1 ? kFanLowDeg
                          : kFanLowDeg + (kFanHighDeg - kFanLowDeg) * c / double(channels - 1);
    }
    const std::vector<std::uint32_t> cell = ray_order(options.order, channels, azimuth, elevation);
    // Unit directions per (channel, azimuth), in double and rounded once.
    std::vector<dynrt::Vec3> direction(cell.size());
    for (int c = 0; c < channels; ++c) {
        for (int a = 0; a < azimuth; ++a) {
            const double el = elevation[std::size_t(c)] * kDegree;
            const double az = 2.0 * std::numbers::pi * (a + 0.5) / azimuth;
            direction[std::size_t(c * azimuth + a)] = {float(std::cos(el) * std::cos(az)),
                                                       float(std::sin(el)),
                                                       float(std::cos(el) * std::sin(az))};
        }
    }
    const double sun_length = std::sqrt(0.4 * 0.4 + 0.8 * 0.8 + 0.3 * 0.3);
    const dynrt::Vec3 sun{float(0.4 / sun_length), float(0.8 / sun_length), float(0.3 / sun_length)};

    std::vector<dynrt::Ray> rays(cell.size());
    std::vector<dynrt::RayHit> hits(cell.size());
    std::vector<dynrt::Ray> shadow_rays;
    std::vector<std::uint8_t> shadowed;
    shadow_rays.reserve(cell.size());
    shadowed.reserve(cell.size());
    std::vector<float> range_image;
    const int row_pixels = 4;  // each channel is drawn 4 pixels tall in the range image

    std::printf("lidar: %d channels x %d azimuth steps = %zu rays per revolution, order %s, "
                "range %.0f m\n", channels, azimuth, cell.size(), options.order.c_str(),
                double(options.range_m));
    std::vector<double> update_ms, hit_ms, hit_mrays, hit_packets, shadow_ms, shadow_mrays,
        shadow_packets;
    for (int step = 0; step < options.steps; ++step) {
        const float seconds = kStepSeconds * float(step);
        // ---- Move the scene, then bring the engine up to date ----
        for (const Car& c : cars) {
            const float angle = c.phase_rad + c.speed_rad_s * seconds;
            // Tangent to its circle: a turn of phi about +y takes the car's long axis, +x, to
            // (cos phi, 0, -sin phi), which is the direction of travel (-sin a, 0, cos a) for
            // phi = -a - pi/2.
            const float heading = -angle - float(std::numbers::pi / 2);
            engine.set_transform(c.id, dynrt::Transform::rotation(
                                           {0.0f, 1.0f, 0.0f}, heading,
                                           {c.radius_m * std::cos(angle), 0.0f,
                                            c.radius_m * std::sin(angle)}));
        }
        flag.wave(seconds);
        engine.set_positions(flag_id, flag.mesh.positions);  // copied: flag may change now
        const dynrt::FrameStats frame = engine.update();
        update_ms.push_back(frame.total_ms);
        if (step == 0) {
            std::printf("inferred motion after step 0:");
            for (std::size_t m = 0; m < names.size(); ++m) {
                std::printf(" %s=%s", names[m].c_str(),
                            dynrt::motion_name(engine.motion(dynrt::MeshId{std::uint32_t(m)})));
            }
            std::printf("\n");
        }

        // ---- The revolution: one batch of closest-hit rays ----
        const dynrt::Vec3 sensor{1.0f * seconds, 1.8f, 0.0f};  // driving along +x at 1 m/s
        for (std::size_t k = 0; k < cell.size(); ++k) {
            rays[k] = dynrt::Ray{sensor, direction[cell[k]], 0.0f, options.range_m};
        }
        const dynrt::QueryStats lidar = engine.intersect(rays, hits);

        std::vector<std::size_t> per_mesh(names.size(), 0);
        double range_sum = 0.0;
        shadow_rays.clear();
        for (const dynrt::RayHit& hit : hits) {
            if (!hit.hit()) continue;
            ++per_mesh[hit.mesh.value];
            range_sum += double(hit.t);
        }
        // ---- Visibility: is each return lit by the sun? A ray from the hit point towards the
        // sun. The point is pulled back towards the sensor by 1e-4 of its range, so it starts on
        // the sensor's side of the surface it lies on: a surface facing away from the sun then
        // shadows itself, as it should, and one facing the sun does not. ----
        for (std::size_t k = 0; k < cell.size(); ++k) {
            if (!hits[k].hit()) continue;
            const float t = hits[k].t * (1.0f - 1e-4f);
            const dynrt::Vec3& d = rays[k].direction;
            shadow_rays.push_back(dynrt::Ray{
                {sensor.x + t * d.x, sensor.y + t * d.y, sensor.z + t * d.z}, sun});
        }
        shadowed.resize(shadow_rays.size());
        const dynrt::QueryStats sunlight = engine.occluded(shadow_rays, shadowed);

        const double mean_range = lidar.hits ? range_sum / double(lidar.hits) : 0.0;
        const double hit_packet_share = lidar.rays ? double(lidar.packet_rays) / double(lidar.rays) : 0.0;
        const double shadow_packet_share =
            sunlight.rays ? double(sunlight.packet_rays) / double(sunlight.rays) : 0.0;
        std::printf("step %3d: rays %zu hits %zu [", step, lidar.rays, lidar.hits);
        for (std::size_t m = 0; m < per_mesh.size(); ++m) {
            std::printf(m ? " %zu" : "%zu", per_mesh[m]);
        }
        std::printf("] mean range %.1f m | intersect %.2f ms %.1f Mrays/s packets %zu single %zu "
                    "| occluded %zu rays %.2f ms %.1f Mrays/s packets %zu single %zu, in shadow "
                    "%.0f%% | update %.2f ms\n",
                    mean_range, lidar.ms, lidar.mrays_per_s, lidar.packet_rays, lidar.single_rays,
                    sunlight.rays, sunlight.ms, sunlight.mrays_per_s, sunlight.packet_rays,
                    sunlight.single_rays,
                    sunlight.rays ? 100.0 * double(sunlight.hits) / double(sunlight.rays) : 0.0,
                    frame.total_ms);
        hit_ms.push_back(lidar.ms);
        hit_mrays.push_back(lidar.mrays_per_s);
        hit_packets.push_back(hit_packet_share);
        shadow_ms.push_back(sunlight.ms);
        shadow_mrays.push_back(sunlight.mrays_per_s);
        shadow_packets.push_back(shadow_packet_share);

        // ---- The range image: azimuth across, channels down (highest on top), coloured by
        // mesh and darker with range. `cell` takes each ray back to its pixel. ----
        if (!options.out.empty()) {
            const int height = channels * row_pixels;
            range_image.assign(std::size_t(azimuth) * std::size_t(height) * 3, 0.0f);
            for (std::size_t k = 0; k < cell.size(); ++k) {
                if (!hits[k].hit()) continue;
                const int c = int(cell[k]) / azimuth, a = int(cell[k]) % azimuth;
                const dynrt::Vec3 colour = mesh_colour(hits[k].mesh.value);
                const float shade = 1.0f - 0.8f * hits[k].t / options.range_m;
                for (int y = 0; y < row_pixels; ++y) {
                    float* p = &range_image[3 * (std::size_t((channels - 1 - c) * row_pixels + y) *
                                                     std::size_t(azimuth) + std::size_t(a))];
                    p[0] = shade * colour.x, p[1] = shade * colour.y, p[2] = shade * colour.z;
                }
            }
            const std::string path = dynrt_example::frame_path(options.out, step);
            dynrt_example::make_parent_folder(path);
            dynrt::save_image(path, azimuth, height, range_image);
        }
    }
    std::printf("median over %d steps: intersect %.2f ms, %.1f Mrays/s, %.0f%% as packets | "
                "occluded %.2f ms, %.1f Mrays/s, %.0f%% as packets | update %.2f ms\n",
                options.steps, median(hit_ms), median(hit_mrays), 100.0 * median(hit_packets),
                median(shadow_ms), median(shadow_mrays), 100.0 * median(shadow_packets),
                median(update_ms));
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    Options options;
    dynrt_example::CommandLine command_line{
        "dynrt_example_lidar: a rotating lidar queried through the dynrt library API"};
    command_line.add("--steps", options.steps, "revolutions (steps of 0.1 s)", 0, 1000000);
    command_line.add("--channels", options.channels, "lasers in the vertical fan (-25 to +15 deg)",
                     1, 1024);
    command_line.add("--azimuth", options.azimuth, "azimuth steps per revolution", 1, 1 << 16);
    command_line.add("--threads", options.threads, "engine worker threads (0: all cores)", 0, 1024);
    command_line.add("--range", options.range_m, "maximum range in metres (the rays' tmax)");
    command_line.add("--order", options.order, "ray order in the batch (see lidar.cpp)",
                     {"horizon", "firing", "channel"});
    command_line.add("--out", options.out,
                     "range image file pattern with a step number field, e.g. lidar/%04d.png");
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
