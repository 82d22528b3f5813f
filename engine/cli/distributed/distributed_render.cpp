// `dynrt render` across processes: `mpirun -np N dynrt render SCENE --frames A-B --out
// 'dir/%04d.png' [--distribute frames|tiles] [--resume]`, and `--resume` in one process.
//
// frames (the default): rank 0 hands out runs of consecutive frames as ranks ask for them
//   (FrameHandout), each rank renders its runs in order with its own Renderer (its trees and
//   pixel memory stay warm along a run) and writes their images; rank 0 records each frame as
//   it finishes.
// tiles: every rank renders every frame's share of the 16x16 tiles (TraceSettings::tiles,
//   interleaved); rank 0 gathers the shares, writes the image and records the frame.
// Either way images go to their files atomically (temporary file, then rename) and rank 0
// keeps a journal of the frames done (RenderJournal), from which `--resume` skips them and the
// report is written. A rank that fails stops the job, naming itself and the frame.

#include "distributed/distributed_render.h"

#include "command_warnings.h"
#include "stage_progress.h"

#include "distributed/cluster.h"
#include "distributed/render_journal.h"
#include "interrupt.h"
#include "job_settings.h"
#include "render_outputs.h"
#include "dynrt/engine/frame_writer.h"
#include "dynrt/engine/image_output.h"
#include "dynrt/engine/report.h"
#include "dynrt/engine/sequence_output.h"
#include "dynrt/engine/spread.h"
#include "dynrt/engine/stopwatch.h"
#include "dynrt/engine/tile_share.h"

#include <tbb/info.h>

#include <unistd.h>

#include <cstdio>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace dynrt::cli {

namespace {

/// For the tests of the hand-out only, not a user option: DYNRT_TEST_SLOW_FRAMES="F:MS,..."
/// makes frame F take MS ms longer (a sleep after its render), so that a test can make frames
/// deliberately uneven, or slow enough to kill a job part way, on any scene.
std::map<int, int> test_slow_frames() {
    std::map<int, int> slow;
    const char* spec = std::getenv("DYNRT_TEST_SLOW_FRAMES");
    if (!spec) return slow;
    std::istringstream in(spec);
    std::string item;
    while (std::getline(in, item, ',')) {
        const std::size_t colon = item.find(':');
        if (colon == std::string::npos) continue;
        slow[std::stoi(item.substr(0, colon))] = std::stoi(item.substr(colon + 1));
    }
    return slow;
}

/// A frame is done when its record and its files (image and AOVs) are all there.
bool frame_done(const RenderJournal& journal, int frame, const std::string& out,
                const std::vector<Aov>& aovs) {
    if (!journal.earlier().contains(frame)) return false;
    const std::filesystem::path image = frame_path(out, frame);
    if (!std::filesystem::is_regular_file(image)) return false;
    return std::all_of(aovs.begin(), aovs.end(), [&](Aov aov) {
        return std::filesystem::is_regular_file(aov_path(image, aov));
    });
}

/// A one-line progress bar on stderr, redrawn in place, with the time left at the mean pace so
/// far; used only when stderr is a terminal.
void draw_progress(int done, int total, double ms_per_frame) {
    constexpr int kWidth = 30;
    const int filled = total > 0 ? done * kWidth / total : kWidth;
    const double left_s = double(total - done) * ms_per_frame / 1000.0;
    std::cerr << "\r[" << std::string(std::size_t(filled), '#')
              << std::string(std::size_t(kWidth - filled), ' ') << "] " << done << "/" << total
              << " frames, " << std::fixed << std::setprecision(1) << ms_per_frame
              << " ms/frame, " << std::setprecision(0) << left_s << " s left  " << std::flush;
    if (done == total) std::cerr << "\n";
}

/// The figures each rank sends rank 0 per frame in tiles mode: its trace time, then the counts
/// that add up over the shares.
std::vector<double> share_figures(const FrameStats& s) {
    return {s.primary_ms + s.shadow_ms + s.shade_ms + s.secondary_ms,
            double(s.primary_rays), double(s.shadow_rays), double(s.interpolated_pixels),
            double(s.pixels_traced), double(s.pixels_shadows_retraced), double(s.pixels_reused),
            double(s.reflection_rays), double(s.refraction_rays), double(s.secondary_shadow_rays),
            double(s.pixels_refined)};
}

void add_share_figures(const std::vector<double>& all, int ranks, FrameStats& s) {
    const std::size_t n = all.size() / std::size_t(ranks);
    s.rank_trace_ms.clear();
    s.primary_rays = s.shadow_rays = s.interpolated_pixels = 0;
    s.pixels_traced = s.pixels_shadows_retraced = s.pixels_reused = 0;
    s.reflection_rays = s.refraction_rays = s.secondary_shadow_rays = 0;
    s.pixels_refined = 0;
    for (int r = 0; r < ranks; ++r) {
        const double* f = all.data() + std::size_t(r) * n;
        s.rank_trace_ms.push_back(f[0]);
        s.primary_rays += std::size_t(f[1]);
        s.shadow_rays += std::size_t(f[2]);
        s.interpolated_pixels += std::size_t(f[3]);
        s.pixels_traced += std::size_t(f[4]);
        s.pixels_shadows_retraced += std::size_t(f[5]);
        s.pixels_reused += std::size_t(f[6]);
        s.reflection_rays += std::size_t(f[7]);
        s.refraction_rays += std::size_t(f[8]);
        s.secondary_shadow_rays += std::size_t(f[9]);
        s.pixels_refined += std::size_t(f[10]);
    }
}

/// Fails before anything is rendered when the flags cannot make a distributed render. One
/// process that does not resume writes what `dynrt render` writes; across processes or with
/// --resume, only numbered images (a GIF, a video or a contact sheet needs every frame in one
/// process, in order).
void check_distributed_args(const RenderArgs& args, const FrameRange& range, int ranks) {
    if (args.distribute != "frames" && args.distribute != "tiles") {
        throw std::invalid_argument("--distribute " + args.distribute + ": frames or tiles");
    }
    if (args.distribute == "tiles" && parse_reuse(args.reuse).approximate()) {
        throw std::invalid_argument("--reuse " + args.reuse + " with --distribute tiles: the "
                                    "render cache and frameless rendering need the whole image; "
                                    "use --reuse exact or off");
    }
    const std::vector<Aov> aovs = parse_aov_list(args.aov);
    if (args.distribute == "tiles" && std::find(aovs.begin(), aovs.end(), Aov::cost) != aovs.end()) {
        throw std::invalid_argument("--aov cost with --distribute tiles: the pixel costs are not gathered "
                                    "across processes; use --distribute frames");
    }
    // One process not resuming writes whatever run_render accepted (a GIF, a video, a sheet).
    if (ranks == 1 && !args.resume) return;
    if (is_sequence_file(args.out) && !has_frame_number(args.out)) {
        throw std::invalid_argument("--out '" + args.out + "': a render across processes (or "
                                    "--resume) writes one image per frame: give a numbered "
                                    "name, e.g. 'frames/%04d.png'");
    }
    if (range.count() > 1 && !has_frame_number(args.out)) {
        throw std::invalid_argument("--out '" + args.out + "': several frames need a frame "
                                    "number in the name, e.g. 'frames/%04d.png'");
    }
    if (!args.contact_sheet.empty()) {
        throw std::invalid_argument("--contact-sheet: not with a render across processes or "
                                    "--resume (render the sheet from the frames afterwards)");
    }
}

/// The per-rank lines under the table: the frames each rank rendered, as runs ("0-2, 9-10"),
/// and their median time (`frames`), or the median trace time of its tiles (`tiles`); then the
/// median hand-out or gather per frame.
void print_ranks(std::ostream& out, const std::vector<FrameStats>& frames, int ranks, bool tiles) {
    const auto median = [](std::vector<double> values) {
        return values.empty() ? 0.0 : spread_of(std::move(values)).median;
    };
    for (int r = 0; r < ranks; ++r) {
        std::vector<double> ms;
        std::vector<std::pair<int, int>> runs;  // first and last frame of each run
        for (const FrameStats& f : frames) {
            if (tiles) {
                if (std::size_t(r) < f.rank_trace_ms.size()) ms.push_back(f.rank_trace_ms[std::size_t(r)]);
            } else if (f.rank == r) {
                if (!runs.empty() && runs.back().second + 1 == f.frame) {
                    runs.back().second = f.frame;
                } else {
                    runs.emplace_back(f.frame, f.frame);
                }
                ms.push_back(f.total_ms);
            }
        }
        out << "rank " << r << ": ";
        if (tiles) {
            out << "median trace of its tiles " << median(ms) << " ms\n";
            continue;
        }
        out << ms.size() << " frames in " << runs.size() << (runs.size() == 1 ? " run (" : " runs (");
        for (std::size_t i = 0; i < runs.size(); ++i) {
            out << (i ? ", " : "") << runs[i].first;
            if (runs[i].second != runs[i].first) out << "-" << runs[i].second;
        }
        out << "), median " << median(ms) << " ms/frame\n";
    }
    std::vector<double> handout, gather, wait;
    for (const FrameStats& f : frames) {
        handout.push_back(f.handout_ms);
        gather.push_back(f.gather_ms);
        wait.push_back(f.wait_ms);
    }
    if (tiles) {
        out << "gather: median " << median(gather) << " ms/frame, after " << median(wait)
            << " ms waiting for the slowest share\n";
    } else {
        out << "hand-out: median " << median(handout) << " ms/frame\n";
    }
}

/// `--distribute tiles`: every rank's share of the frame in `image` gathered on rank 0, with
/// the figures of each share; returns true on rank 0, whose `image` then holds the whole frame.
bool gather_shares(Cluster& cluster, const RenderOptions& options, RenderedFrame& image) {
    const int rank = cluster.rank(), ranks = cluster.size();
    // The small figures first: once rank 0 has them every share is done, so their wait is the
    // load imbalance and the gather after it the transfer alone.
    Stopwatch clock;
    const std::vector<double> figures = cluster.gather_figures(share_figures(image.stats));
    const double wait_ms = clock.lap_ms();
    // Rank 0's own share is in place already: it sends none.
    std::vector<float> packed;
    if (rank != 0) pack_tiles(image, options.tiles, packed);
    const std::vector<float> all = cluster.gather(packed);
    if (rank != 0) return false;
    std::size_t offset = 0;
    for (int r = 1; r < ranks; ++r) {
        const packet::TileShare share{r, ranks};
        const std::size_t size =
            packed_share_size(options.width, options.height, share, options.hit_buffers);
        if (all.size() < offset + size) {
            throw std::runtime_error("rank " + std::to_string(r) + "'s tiles came short");
        }
        unpack_tiles({all.data() + offset, size}, share, options.hit_buffers, image);
        offset += size;
    }
    FrameStats& stats = image.stats;
    stats.wait_ms = wait_ms;
    stats.gather_ms = clock.elapsed_ms();
    stats.total_ms += stats.wait_ms + stats.gather_ms;
    stats.rank = 0;
    add_share_figures(figures, ranks, stats);
    return true;
}

/// Rank 0's view of a job's frames: its journal (kept by every render of numbered images, so
/// that any of them can be resumed), the frames left to render, and the records of the frames
/// done, by frame.
struct FramesLeft {
    std::optional<RenderJournal> journal;
    std::vector<int> todo;
    std::map<int, FrameStats> records;
};

/// Opens the journal of the render `args` describe (refusing, with --resume, one of another
/// job) and finds the frames of `range` still to render: all, or with --resume those whose
/// record or files (image and AOVs) are missing.
FramesLeft frames_left(const RenderArgs& args, const FrameRange& range, const RenderOptions& options,
                       const Scene& scene, const std::vector<Aov>& aovs) {
    FramesLeft left;
    if (has_frame_number(args.out) || args.resume) {
        left.journal.emplace(journal_path(args, range), journal_header(args, options, scene), args.resume);
    }
    for (int f = range.first; f <= range.last; ++f) {
        if (args.resume && frame_done(*left.journal, f, args.out, aovs)) {
            left.records[f] = left.journal->earlier().at(f);
        } else {
            left.todo.push_back(f);
        }
    }
    return left;
}

/// The records of the frames done, in frame order (the range's frames only).
std::vector<FrameStats> frames_of(const FramesLeft& left) {
    std::vector<FrameStats> frames;
    for (const auto& [f, stats] : left.records) frames.push_back(stats);
    return frames;
}

/// The line of a render stopped by SIGINT or SIGTERM: how far it got, and how to go on.
void print_stop(const RenderArgs& args, int rendered, std::size_t todo) {
    std::cout << std::flush;
    std::cerr << "dynrt: stopped by " << InterruptGuard::signal_name() << " after " << rendered
              << " of " << todo << " frames, all written"
              << (!has_frame_number(args.out) ? ""
                  : args.contact_sheet.empty()
                      ? "; run the same command with --resume to render the rest"
                      // A sheet needs every frame rendered in one run.
                      : "; run the same command with --resume, without --contact-sheet, to render "
                        "the rest")
              << "\n";
}

/// The line that says what a render will do: the scene, the image, the frames and where they
/// go; under mpirun (`ranks` > 0) how the processes share them; with --resume what is left.
void print_job(const RenderArgs& args, const std::string& source, const Scene& scene,
               const RenderOptions& options, const FrameRange& range, int ranks, bool tiles,
               const FramesLeft& left) {
    std::cout << "dynrt: " << source << ": " << scene.objects.size() << " objects, "
              << scene.triangle_count() << " triangles, " << options.width << "x" << options.height
              << ", frames " << range.first << "-" << range.last << " -> " << args.out;
    if (ranks > 0) {
        std::cout << ", " << ranks << (ranks == 1 ? " process" : " processes") << " sharing "
                  << (tiles ? "each frame's tiles" : "the frames");
    }
    std::cout << std::endl;
    if (args.resume) {
        std::cout << "resume: " << left.records.size() << " frames done, " << left.todo.size()
                  << " to render" << std::endl;
    }
}

/// What a render prints once its frames are done: the table (every frame's row for up to 8),
/// its summaries, each rank's share under mpirun (`ranks` > 0), the textures read (rank 0's),
/// the output stage's time and where the journal is.
void print_results(const RenderArgs& args, const Scene& scene, const FramesLeft& left, int ranks,
                   bool tiles, const TextureFigures& textures, const FrameWriter& writer) {
    const std::vector<FrameStats> frames = frames_of(left);
    if (!args.contact_sheet.empty() && writer.contact_sheet_frames() > 0) {
        std::cout << "contact sheet: " << args.contact_sheet << " ("
                  << writer.contact_sheet_frames() << " frames)\n";
    }
    if (!frames.empty() && frames.front().degenerate_skipped > 0) {
        std::cout << "degenerate triangles skipped: " << frames.front().degenerate_skipped << "\n";
    }
    print_ignored(std::cout, scene);
    print_frame_header(std::cout);
    if (frames.size() <= 8) {
        for (const FrameStats& f : frames) print_frame_row(std::cout, f);
    }
    print_summary(std::cout, frames);
    print_secondary_summary(std::cout, frames);
    print_shadow_summary(std::cout, frames);
    print_sampling_summary(std::cout, frames);
    print_rebuild_summary(std::cout, frames);
    print_update_choices(std::cout, frames);
    if (ranks > 0) print_ranks(std::cout, frames, ranks, tiles);
    print_textures(std::cout, textures);
    print_memory(std::cout, frames);
    print_writer_summary(std::cout, frames, writer.wait_ms());
    if (left.journal) std::cout << "journal: " << left.journal->path().string() << "\n";
}

}  // namespace

int run_distributed_render(const RenderArgs& args, Cluster& cluster) {
    const int rank = cluster.rank(), ranks = cluster.size();
    const bool tiles = args.distribute == "tiles";
    // Under mpirun (any number of ranks) each frame names its rank and the report has each
    // rank's line; a render in one process is a plain render.
    const bool mpi_job = started_by_mpirun();
    // One process stops between frames on SIGINT or SIGTERM (interrupt.h). Under mpirun the
    // job is ended by mpirun instead; its journal and atomic files make it resumable.
    std::optional<InterruptGuard> interrupt;
    if (!mpi_job) interrupt.emplace();
    const auto stopping = [&] { return interrupt && InterruptGuard::received() != 0; };
    Stopwatch startup;
    // Only rank 0 speaks, but for errors.
    if (rank != 0) std::cout.setstate(std::ios::failbit);
    int frame = -1;  // the frame at hand, for the failure message
    try {
        RenderOptions options = render_options(args);
        const std::vector<Aov> aovs = parse_aov_list(args.aov);
        options.hit_buffers = !aovs.empty();
        options.pixel_cost = std::find(aovs.begin(), aovs.end(), Aov::cost) != aovs.end();
        if (tiles) options.tiles = packet::TileShare{rank, ranks};
        const FrameRange range = args.frames.empty() ? FrameRange{} : parse_frame_range(args.frames);
        check_distributed_args(args, range, ranks);
        const bool numbered = has_frame_number(args.out);
        const bool sequence_file = is_sequence_file(args.out) && !numbered;
        const std::filesystem::path first_path = frame_path(args.out, range.first);
        if (!sequence_file) check_image_path(first_path.filename());
        // Every output (and the journal of numbered frames) before the scene loads.
        check_render_outputs(render_outputs(args, range, /*with_journal=*/numbered || args.resume), range);

        const std::string source = scene_source(args);
        const Scene scene = load_animated_scene(args, source, options);
        if (rank == 0) {
            warn_past_the_end(scene, options.pose, range);
            note_single_frame(std::cout, args.frames);
        }
        if (first_path.has_parent_path()) std::filesystem::create_directories(first_path.parent_path());
        const CameraSource view = camera_source(scene, args, options.pose, range);

        // Rank 0 decides which frames are left and keeps the journal.
        FramesLeft left;
        if (rank == 0) {
            left = frames_left(args, range, options, scene, aovs);
            print_job(args, source, scene, options, range, mpi_job ? ranks : 0, tiles, left);
        }
        const std::vector<int> todo = cluster.broadcast(left.todo);
        const auto keep = [&](const std::string& record) {
            if (left.journal) left.journal->append(record);
            const FrameStats stats = parse_frame_report_json(record);
            left.records[stats.frame] = stats;
        };
        const std::map<int, int> slow = test_slow_frames();
        const auto slow_down = [&](int f) {
            if (const auto it = slow.find(f); it != slow.end()) {
                std::this_thread::sleep_for(std::chrono::milliseconds(it->second));
            }
        };

        // The output stage: every rank that writes images writes them through it, and a frame
        // is recorded once its files are in place.
        std::optional<FrameWriter> writer;
        std::function<void()> record_written = [] {};
        if (!tiles || rank == 0) {
            writer.emplace(FrameOutputs{args.out, aovs, options.pose.fps, args.contact_sheet, range.first,
                                        range.count(),
                                        DisplayTransform{args.exposure, parse_tone_curve(args.tone)}});
            record_written = [&] {
                for (const FrameStats& stats : writer->take_written()) {
                    if (tiles) {
                        keep(frame_report_json(stats));
                    } else {
                        cluster.send_record(frame_report_json(stats));
                    }
                }
            };
        }
        const double startup_ms = startup.elapsed_ms();
        if (rank == 0) {
            std::cout << "start-up: " << std::fixed << std::setprecision(0) << startup_ms
                      << " ms (scene loaded, trees not yet built)" << std::endl;
            std::cout.unsetf(std::ios::floatfield);
        }

        const bool progress = ranks == 1 && todo.size() > 1 && isatty(fileno(stderr)) && verbosity() != Verbosity::quiet;
        int rendered = 0;
        double rendered_ms = 0.0;
        const auto hand_over = [&](RenderedFrame& image) {
            writer->submit(image);
            record_written();
            ++rendered;
            rendered_ms += image.stats.total_ms;
            if (progress) draw_progress(rendered, int(todo.size()), rendered_ms / rendered);
        };

        // What the renderer read of the scene's textures, once, at its first frame.
        TextureFigures textures;
        try {
            Renderer renderer(options);
            RenderedFrame image;
            bool first_frame = true;
            const auto render_frame = [&](int f) {
                // The first frame builds every tree: on a big scene the run's longest wait.
                std::optional<StageProgress> progress;
                if (first_frame && ranks == 1) progress.emplace("frame " + std::to_string(f) + " (building the trees)");
                first_frame = false;
                renderer.render(scene, f, view, image);
            };
            if (!tiles) {
                cluster.start_handout(todo, keep);
                while (!stopping()) {
                    // Another rank's records reach rank 0 only while rank 0 hands out work:
                    // every frame of its last run is reported before it asks again.
                    if (rank != 0) {
                        writer->flush();
                        record_written();
                    }
                    Stopwatch ask;
                    const std::vector<int> run = cluster.next_run();
                    if (run.empty()) break;
                    const double ask_ms = ask.elapsed_ms() / double(run.size());
                    for (const int f : run) {
                        if (stopping()) break;
                        frame = f;
                        render_frame(f);
                        slow_down(f);
                        image.stats.rank = mpi_job ? rank : -1;
                        image.stats.handout_ms = ask_ms;
                        hand_over(image);
                    }
                }
                frame = -1;
                writer->finish();
                record_written();
                cluster.finish_handout();
            } else {
                for (const int f : todo) {
                    if (stopping()) break;
                    frame = f;
                    render_frame(f);
                    slow_down(f);
                    if (!gather_shares(cluster, options, image)) continue;
                    hand_over(image);
                }
                frame = -1;
                if (writer) {
                    writer->finish();
                    record_written();
                }
            }
            textures = renderer.texture_figures();
        } catch (const std::exception&) {
            // The frames the writer finished before the failure keep their record, so that
            // --resume skips them; the writer writes nothing more after an error.
            if (writer) {
                try {
                    writer->finish();
                } catch (const std::exception&) {
                    // The error being thrown is the one to report.
                }
                record_written();
            }
            throw;
        }
        if (rank != 0) return 0;
        const RunInfo run{source, options.width, options.height, options.build.cost_ratio,
                          options.build.leaf_size_max,
                          args.threads > 0 ? args.threads : tbb::info::default_concurrency(),
                          scene.ignored, startup_ms, writer->wait_ms(), textures};
        print_results(args, scene, left, mpi_job ? ranks : 0, tiles, textures, *writer);
        if (!args.report.empty()) {
            write_report(args.report, run, frames_of(left));
            std::cout << "report: " << args.report << "\n";
        }
        if (!stopping()) return 0;
        print_stop(args, rendered, todo.size());
        return InterruptGuard::exit_code();
    } catch (const std::exception& e) {
        if (ranks == 1) throw;
        // A frame the output stage failed to write names itself ("frame F: FILE: why").
        if (dynamic_cast<const FrameWriteError*>(&e)) {
            cluster.fail("rank " + std::to_string(rank) + ", " + e.what());
        }
        std::string where = "rank " + std::to_string(rank);
        if (frame >= 0) where += ", frame " + std::to_string(frame);
        cluster.fail(where + ": " + e.what());
    }
    return 1;  // not reached: fail() ends the job
}

}  // namespace dynrt::cli
