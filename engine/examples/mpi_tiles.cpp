// An embedder's own MPI program (docs/mpi.md "Rendering across processes"): every rank holds an
// Engine with the same meshes and moves them alike each step; each renders its interleaved
// share of the 16x16 tiles (RenderSettings::tile_share), packs those pixels in
// tile_share_pixels order and MPI_Gatherv sends them to rank 0, which unpacks them into the
// whole image. Then a batch of rays split with ray_share, each rank casting its part.
// With --check, rank 0 also renders the whole frame alone and the gathered one must be the
// same bits (the example's smoke test runs it so).
//
//   mpirun -np 2 dynrt_example_mpi_tiles [--steps N] [--check] [--out mpi_tiles.png]
#include <dynrt/dynrt.h>
#include <mpi.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

/// A waving 24x24 grid over a floor: the same on every rank.
struct World {
    dynrt::Engine engine{dynrt::EngineOptions{.threads = 1}};
    std::vector<float> grid;
    std::vector<std::uint32_t> indices;
    dynrt::MeshId cloth{};
    World() {
        const std::uint32_t n = 24;
        for (std::uint32_t y = 0; y < n; ++y) {
            for (std::uint32_t x = 0; x < n; ++x) grid.insert(grid.end(), {x / 11.5f - 1, 0, y / 11.5f - 1});
        }
        for (std::uint32_t y = 0; y + 1 < n; ++y) {
            for (std::uint32_t x = 0; x + 1 < n; ++x) {
                const std::uint32_t i = y * n + x;
                indices.insert(indices.end(), {i, i + n, i + 1, i + 1, i + n, i + n + 1});
            }
        }
        dynrt::MeshDesc mesh;
        mesh.positions = grid;
        mesh.indices = indices;
        mesh.motion = dynrt::Motion::deformable;
        mesh.surface.diffuse = {0.2f, 0.4f, 0.9f};
        cloth = engine.add_mesh(mesh);
        const float floor[] = {-3, -0.6f, -3, 3, -0.6f, -3, 3, -0.6f, 3, -3, -0.6f, 3};
        const std::uint32_t quad[] = {0, 2, 1, 0, 3, 2};
        dynrt::MeshDesc ground;
        ground.positions = floor;
        ground.indices = quad;
        engine.add_mesh(ground);
    }
    void step(int s) {
        for (std::size_t v = 0; v < grid.size(); v += 3) {
            grid[v + 1] = 0.25f * std::sin(4 * grid[v] + 0.6f * s) * std::cos(3 * grid[v + 2]);
        }
        engine.set_positions(cloth, grid);
        engine.update();
    }
};

}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    int steps = 3;
    bool check = false;
    std::string out = "mpi_tiles.png";
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--steps" && i + 1 < argc) steps = std::stoi(argv[++i]);
        else if (arg == "--check") check = true;
        else if (arg == "--out" && i + 1 < argc) out = argv[++i];
    }
    int status = 0;
    try {
        World world;
        const int width = 160, height = 120;
        const std::size_t pixels = std::size_t(width) * height;
        const dynrt::View view{.eye = {0, 1.6f, 3.2f}, .target = {0, -0.2f, 0}};
        std::vector<float> rgb(pixels * 3), whole(pixels * 3), packed, gathered;
        // Which pixels each rank renders, and where they land in the gathered buffer.
        const std::vector<std::size_t> mine = dynrt::tile_share_pixels(width, height, rank, ranks);
        std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
        for (int r = 0; r < ranks; ++r) {
            counts[std::size_t(r)] = int(dynrt::tile_share_pixels(width, height, r, ranks).size() * 3);
            offsets[std::size_t(r)] = r ? offsets[std::size_t(r - 1)] + counts[std::size_t(r - 1)] : 0;
        }
        dynrt::RenderSettings share;
        share.tile_share = rank;
        share.tile_shares = ranks;
        dynrt::RenderSettings alone;  // the check's whole render, traced in full
        alone.reuse_pixels = false;
        for (int s = 0; s < steps; ++s) {
            world.step(s);
            world.engine.render(view, {.width = width, .height = height, .rgb = rgb}, share);
            packed.clear();
            for (const std::size_t p : mine) packed.insert(packed.end(), &rgb[3 * p], &rgb[3 * p] + 3);
            gathered.resize(rank == 0 ? pixels * 3 : 0);
            MPI_Gatherv(packed.data(), int(packed.size()), MPI_FLOAT, gathered.data(), counts.data(),
                        offsets.data(), MPI_FLOAT, 0, MPI_COMM_WORLD);
            if (rank != 0) continue;
            for (int r = 0; r < ranks; ++r) {
                const float* from = gathered.data() + offsets[std::size_t(r)];
                for (const std::size_t p : dynrt::tile_share_pixels(width, height, r, ranks)) {
                    std::memcpy(&rgb[3 * p], from, 3 * sizeof(float));
                    from += 3;
                }
            }
            if (check) {
                world.engine.render(view, {.width = width, .height = height, .rgb = whole},
                                    alone);
                const bool same = std::memcmp(whole.data(), rgb.data(), whole.size() * sizeof(float)) == 0;
                std::printf("step %d: %d ranks' tiles %s the whole render\n", s, ranks,
                            same ? "equal" : "DIFFER from");
                if (!same) status = 1;
            }
        }
        if (rank == 0) dynrt::save_image(out, width, height, rgb);

        // A ray batch split into contiguous parts: each rank casts its own rays.
        std::vector<dynrt::Ray> rays;
        for (int i = 0; i < 4096; ++i) {
            const float a = 6.2831853f * float(i) / 4096.0f;
            rays.push_back(dynrt::Ray{.origin = {0, 2, 0}, .direction = {std::cos(a), -1, std::sin(a)}});
        }
        const dynrt::RayShare part = dynrt::ray_share(rays.size(), rank, ranks);
        std::vector<dynrt::RayHit> hits(part.end - part.begin);
        world.engine.intersect(std::span(rays).subspan(part.begin, part.end - part.begin), hits);
        long long hit = 0, total = 0;
        for (const dynrt::RayHit& h : hits) hit += h.hit();
        MPI_Reduce(&hit, &total, 1, MPI_LONG_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
        if (rank == 0) std::printf("rays: %lld of %zu hit, cast by %d ranks\n", total, rays.size(), ranks);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "mpi_tiles: rank %d: %s\n", rank, e.what());
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
    return status;
}
