// The thread-safety contract of dynrt::Engine (api/engine.h): between updates, intersect,
// occluded and render run concurrently from any number of threads and give exactly what they
// give alone; the engine's own thread count (or the caller's arena) changes nothing in the
// results; and a change made while a query is running is refused with invalid_state instead of
// racing.

#include "api/access_guard.h"
#include "api_test_world.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace dynrt::api_test {
namespace {

/// A deforming scene: a static sphere, a rigid one turning, a waving sheet, a pulsing borrowed
/// sphere and exploding debris.
class Deforming {
public:
    explicit Deforming(Engine& engine) : engine_(engine), rng_(21) {
        m_.add(engine, "still", sphere({-1.2f, 0.0f, 0.0f}, 0.6f), Motion::static_);
        arm_ = m_.add(engine, "arm", sphere({0.0f, 0.0f, 0.0f}, 0.5f), Motion::rigid);
        cloth_base_ = sheet(0.0f, 0.0f, -1.0f, 3.0f);
        cloth_ = m_.add(engine, "cloth", cloth_base_, Motion::deformable);
        ball_base_ = sphere({0.0f, 1.0f, 0.0f}, 0.5f);
        ball_positions_ = ball_base_.positions;
        ball_ = m_.add(engine, "ball", ball_base_, Motion::automatic, {}, Ownership::borrow, ball_positions_);
        debris_ = m_.add(engine, "debris", soup(rng_, 100, {0.6f, -0.6f, 0.5f}, 0.5f, 0.1f), Motion::exploding);
    }

    void step(int k) {
        engine_.set_transform(arm_, Transform::rotation({0.0f, 0.0f, 1.0f}, 0.3f * float(k), {1.2f, 0.0f, 0.0f}));
        engine_.set_positions(cloth_, waved(cloth_base_, 0.5f * float(k)));
        ball_positions_ = scaled(ball_base_, {0.0f, 1.0f, 0.0f}, 1.0f + 0.05f * float(k % 5));
        engine_.set_positions(ball_, ball_positions_);
        engine_.set_positions(debris_, soup(rng_, 100, {0.6f, -0.6f, 0.5f}, 0.5f, 0.1f).positions);
    }

private:
    Engine& engine_;
    std::mt19937 rng_;
    Mirror m_;
    MeshId arm_, cloth_, ball_, debris_;
    MeshData cloth_base_, ball_base_;
    std::vector<float> ball_positions_;
};

/// Rays of both kinds: two coherent runs and incoherent ones, 1024 in all.
std::vector<Ray> mixed_rays(std::mt19937& rng) {
    std::vector<Ray> rays = coherent_rays(rng, {4.0f, 3.0f, 5.0f}, {0.0f, 0.0f, 0.0f}, 0.2f, 256);
    const std::vector<Ray> more = coherent_rays(rng, {-3.0f, -2.0f, 4.0f}, {0.0f, 0.0f, 0.0f}, 0.2f, 256);
    const std::vector<Ray> wild = incoherent_rays(rng, {0.0f, 0.0f, 0.0f}, 4.0f, 1.8f, 512);
    rays.insert(rays.end(), more.begin(), more.end());
    rays.insert(rays.end(), wild.begin(), wild.end());
    return rays;
}

constexpr int kImage = 48;

std::vector<float> render_alone(const Engine& engine) {
    std::vector<float> rgb(kImage * kImage * 3);
    engine.render(View{{1.0f, 2.0f, 6.0f}}, ImageView{kImage, kImage, rgb});
    return rgb;
}

TEST(ApiThreads, ConcurrentQueriesAndRendersBetweenUpdatesGiveTheSingleThreadedAnswers) {
    EngineOptions options;
    options.threads = 2;
    Engine engine(options);
    Deforming scene(engine);
    std::mt19937 rng(5);
    const std::vector<Ray> rays = mixed_rays(rng);
    constexpr int kThreads = 6, kSteps = 8;
    std::atomic<int> mismatches{0}, failures{0};
    for (int k = 0; k < kSteps; ++k) {
        if (k > 0) scene.step(k);
        engine.update();
        // The single-threaded answers of this step: one batch on this thread.
        std::vector<RayHit> want(rays.size());
        std::vector<std::uint8_t> want_any(rays.size());
        engine.intersect(rays, want);
        engine.occluded(rays, want_any);
        const std::vector<float> want_rgb = render_alone(engine);

        std::vector<std::thread> threads;
        for (int t = 0; t < kThreads; ++t) {
            threads.emplace_back([&, t] {
                try {
                    // Thread 0 renders; the others query sub-batches of shifting sizes.
                    for (int round = 0; round < 4; ++round) {
                        if (t == 0) {
                            if (render_alone(engine) != want_rgb) ++mismatches;
                            continue;
                        }
                        const std::size_t size = 1 + std::size_t(t * 97 + round * 131) % rays.size();
                        for (std::size_t first = std::size_t(t * 13) % size; first < rays.size(); first += size) {
                            const std::size_t n = std::min(size, rays.size() - first);
                            const std::span<const Ray> batch(rays.data() + first, n);
                            std::vector<RayHit> hits(n);
                            std::vector<std::uint8_t> any(n);
                            engine.intersect(batch, hits);
                            engine.occluded(batch, any);
                            for (std::size_t i = 0; i < n; ++i) {
                                if (!identical(hits[i], want[first + i]) || any[i] != want_any[first + i]) {
                                    ++mismatches;
                                }
                            }
                        }
                    }
                } catch (...) {
                    ++failures;
                }
            });
        }
        for (std::thread& thread : threads) thread.join();
        ASSERT_EQ(failures.load(), 0) << "step " << k;
        ASSERT_EQ(mismatches.load(), 0) << "step " << k;
    }
}

/// The answers and figures of a fixed sequence of steps on an engine made with `options`.
struct StepResults {
    std::vector<std::vector<RayHit>> hits;
    std::vector<std::vector<std::uint8_t>> any;
    std::vector<std::vector<float>> rgb;
    std::vector<FrameStats> stats;
};

StepResults run_with(const EngineOptions& options) {
    Engine engine(options);
    Deforming scene(engine);
    std::mt19937 rng(5);
    const std::vector<Ray> rays = mixed_rays(rng);
    StepResults run;
    for (int k = 0; k < 4; ++k) {
        if (k > 0) scene.step(k);
        run.stats.push_back(engine.update());
        run.hits.emplace_back(rays.size());
        run.any.emplace_back(rays.size());
        engine.intersect(rays, run.hits.back());
        engine.occluded(rays, run.any.back());
        run.rgb.push_back(render_alone(engine));
    }
    return run;
}

TEST(ApiThreads, ThreadCountAndArenaChangeNoResult) {
    EngineOptions one;
    one.threads = 1;
    const StepResults want = run_with(one);
    EngineOptions three;
    three.threads = 3;
    tbb::task_arena arena(2);
    EngineOptions caller;
    caller.arena = &arena;
    caller.threads = 1;  // overridden by the arena
    for (const EngineOptions& options : {three, caller, EngineOptions{}}) {
        const StepResults got = run_with(options);
        for (std::size_t k = 0; k < want.hits.size(); ++k) {
            SCOPED_TRACE("step " + std::to_string(k));
            for (std::size_t i = 0; i < want.hits[k].size(); ++i) {
                ASSERT_TRUE(identical(got.hits[k][i], want.hits[k][i])) << "ray " << i;
            }
            EXPECT_EQ(got.any[k], want.any[k]);
            EXPECT_EQ(got.rgb[k], want.rgb[k]);
            EXPECT_EQ(got.stats[k].objects_rebuilt, want.stats[k].objects_rebuilt);
            EXPECT_EQ(got.stats[k].objects_refitted, want.stats[k].objects_refitted);
            EXPECT_EQ(got.stats[k].objects_skipped, want.stats[k].objects_skipped);
            EXPECT_EQ(got.stats[k].nodes, want.stats[k].nodes);
            EXPECT_EQ(got.stats[k].sah_cost, want.stats[k].sah_cost);
        }
    }
}

/// A latch for two threads (std::latch would do, but needs waiting with a timeout here).
class Gate {
public:
    void open() {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            open_ = true;
        }
        cv_.notify_all();
    }
    bool wait_for(std::chrono::seconds limit) {
        std::unique_lock<std::mutex> lock(mutex_);
        return cv_.wait_for(lock, limit, [&] { return open_; });
    }

private:
    std::mutex mutex_;
    std::condition_variable cv_;
    bool open_ = false;
};

/// Holds one chosen thread at its entry into an arena until released: a query that runs in
/// that arena has then taken the engine (its guard comes before its work) and cannot finish.
class EntryGate final : public tbb::task_scheduler_observer {
public:
    explicit EntryGate(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) { observe(true); }
    ~EntryGate() override { observe(false); }

    void hold(std::thread::id id) { held_ = id; }
    void on_scheduler_entry(bool) override {
        if (std::this_thread::get_id() != held_.load()) return;
        entered.open();
        release.wait_for(std::chrono::seconds(20));
    }

    Gate entered, release;

private:
    std::atomic<std::thread::id> held_{};
};

TEST(ApiThreads, AChangeDuringAQueryIsRefusedAndHarmsNothing) {
    // Deterministic: the engine runs in an arena of ours, whose observer holds the query's
    // thread as it enters the arena, that is while the query is inside the engine. Changes are
    // tried until one is refused (before the query is inside they succeed, and are harmless:
    // queries see the last update); only then is the query let go.
    // One slot, reserved for callers: no worker thread ever enters, so when the gate stops
    // observing no thread still holds its observer (oneTBB would then free it late, or never:
    // LeakSanitizer saw that with a two-thread arena).
    tbb::task_arena arena(1);
    EntryGate gate(arena);
    EngineOptions options;
    options.arena = &arena;
    Engine engine(options);
    Mirror m;
    const MeshId ball = m.add(engine, "ball", sphere({0.0f, 0.0f, 0.0f}, 1.0f), Motion::rigid);
    engine.update();
    std::mt19937 rng(3);
    const std::vector<Ray> rays = incoherent_rays(rng, {0.0f, 0.0f, 0.0f}, 4.0f, 1.0f, 2000);
    std::vector<RayHit> want(rays.size());
    engine.intersect(rays, want);

    std::vector<RayHit> got(rays.size());
    std::atomic<bool> query_done{false};
    std::atomic<int> query_refused{0};
    std::thread query([&] {
        gate.hold(std::this_thread::get_id());  // before this thread can enter the engine
        for (;;) {
            try {
                engine.intersect(rays, got);
                break;
            } catch (const Error& e) {
                // Refused because a change below was inside at that moment: also correct.
                if (e.code() != Error::Code::invalid_state) throw;
                ++query_refused;
            }
        }
        query_done = true;
    });
    int refused = 0;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (refused == 0 && std::chrono::steady_clock::now() < deadline) {
        try {
            engine.set_transform(ball, Transform::translation({0.0f, 0.0f, 0.0f}));
        } catch (const Error& e) {
            EXPECT_EQ(int(e.code()), int(Error::Code::invalid_state));
            EXPECT_NE(std::string(e.what()).find("tracing"), std::string::npos) << e.what();
            ++refused;
        }
        std::this_thread::yield();
    }
    // Refused only while the query is inside the engine: held at (or on its way to) the
    // arena's entry, so it cannot have finished.
    EXPECT_FALSE(query_done.load());
    EXPECT_TRUE(gate.entered.wait_for(std::chrono::seconds(20)));
    EXPECT_FALSE(query_done.load());
    // update() is refused the same way.
    try {
        engine.update();
        ADD_FAILURE() << "update during a query was accepted";
    } catch (const Error& e) {
        EXPECT_EQ(int(e.code()), int(Error::Code::invalid_state));
    }
    gate.release.open();
    query.join();
    ASSERT_EQ(refused, 1) << "no change was refused within 20 s";
    // The query's answers are those of the last update; a later update works.
    for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_TRUE(identical(got[i], want[i])) << "ray " << i;
    m.set_transform(engine, ball, Transform::translation({5.0f, 0.0f, 0.0f}));
    engine.update();
    const Ray ray{{5.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}};
    RayHit hit;
    engine.intersect(std::span<const Ray>(&ray, 1), std::span<RayHit>(&hit, 1));
    EXPECT_TRUE(hit.hit() && hit.mesh == ball);
}

TEST(ApiThreads, AccessGuardAdmitsReadersOrOneWriter) {
    // The other direction (a query while a change is inside) cannot be held open from outside
    // the engine: every reading call enters the engine's arena. The guard itself, directly.
    api_detail::AccessGuard guard;
    {
        const api_detail::AccessGuard::Read first(guard);
        const api_detail::AccessGuard::Read second(guard);
        expect_error([&] { api_detail::AccessGuard::Write w(guard); }, Error::Code::invalid_state, {"tracing"});
    }
    {
        const api_detail::AccessGuard::Write write(guard);
        expect_error([&] { api_detail::AccessGuard::Read r(guard); }, Error::Code::invalid_state, {"query"});
        expect_error([&] { api_detail::AccessGuard::Write w(guard); }, Error::Code::invalid_state, {"changing"});
    }
    // Released: both kinds are admitted again, and a refused call left no trace.
    { const api_detail::AccessGuard::Write write(guard); }
    { const api_detail::AccessGuard::Read read(guard); }
    { const api_detail::AccessGuard::Write write(guard); }
}

}  // namespace
}  // namespace dynrt::api_test
