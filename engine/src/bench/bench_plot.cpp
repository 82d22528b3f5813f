#include "dynrt/bench/bench_plot.h"

#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace dynrt {

namespace {

/// `text` as a gnuplot single-quoted string, in which only the quote itself needs escaping
/// (by doubling it).
std::string single_quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) {
        out += c;
        if (c == '\'') out += '\'';
    }
    return out + "'";
}

/// The shortest decimal that reads back as `value` (0.1f prints as 0.1).
std::string shortest(float value) {
    char text[32];
    const auto [end, ec] = std::to_chars(text, text + sizeof(text), value);
    return std::string(text, end);
}

enum class Axis { cost_ratio, leaf_size };

float x_of(const BenchRow& row, Axis axis) {
    return axis == Axis::cost_ratio ? row.build.cost_ratio : float(row.build.leaf_size_max);
}

/// The distinct values of a parameter over the rows, ascending.
std::vector<float> distinct(const std::vector<BenchRow>& rows, Axis axis) {
    std::vector<float> values;
    for (const BenchRow& row : rows) values.push_back(x_of(row, axis));
    std::sort(values.begin(), values.end());
    values.erase(std::unique(values.begin(), values.end()), values.end());
    return values;
}

/// One gnuplot datablock: x, then median/min/max of build, trace and total, sorted by x.
void write_block(std::ostream& out, const std::string& name, std::vector<BenchRow> rows,
                 Axis axis) {
    std::sort(rows.begin(), rows.end(), [axis](const BenchRow& a, const BenchRow& b) {
        return x_of(a, axis) < x_of(b, axis);
    });
    out << name << " << EOD\n# x build_median build_min build_max trace_median trace_min "
                   "trace_max total_median total_min total_max\n";
    for (const BenchRow& r : rows) {
        out << shortest(x_of(r, axis));
        for (const Spread* s : {&r.build_ms, &r.trace_ms, &r.total_ms}) {
            out << ' ' << s->median << ' ' << s->min << ' ' << s->max;
        }
        out << '\n';
    }
    out << "EOD\n";
}

void write_x_axis(std::ostream& out, const std::vector<float>& xs, Axis axis) {
    out << "set xlabel "
        << single_quoted(axis == Axis::cost_ratio
                             ? "SAH cost ratio (intersection : traversal)"
                             : "maximum triangles per leaf")
        << "\n";
    if (xs.front() > 0 && xs.back() >= 8 * xs.front()) {
        out << (axis == Axis::leaf_size ? "set logscale x 2\n" : "set logscale x 10\n");
    }
    // Ticks at exactly the swept values; a little margin so end points are not on the frame.
    out << "set xtics (";
    for (std::size_t i = 0; i < xs.size(); ++i) out << (i ? ", " : "") << shortest(xs[i]);
    out << ")\nset autoscale xfix\nset offsets graph 0.05, graph 0.05, graph 0.05, graph 0.02\n";
}

}  // namespace

std::string bench_plot_script(const std::vector<BenchRow>& rows, const std::string& title,
                              const std::filesystem::path& png) {
    if (rows.empty()) throw std::invalid_argument("bench plot: no rows to plot");
    const std::vector<float> costs = distinct(rows, Axis::cost_ratio);
    const std::vector<float> leaves = distinct(rows, Axis::leaf_size);
    const bool both = costs.size() > 1 && leaves.size() > 1;
    const Axis axis = (leaves.size() > 1 && costs.size() == 1) ? Axis::leaf_size
                                                                : Axis::cost_ratio;
    std::ostringstream out;
    out.precision(9);
    out << "# dynrt bench chart; redraw with: gnuplot " << single_quoted(png.string() + ".gp")
        << "\nset terminal pngcairo size " << (both ? 1500 : 1000)
        << ",620 noenhanced font ',11'\nset output " << single_quoted(png.string())
        << "\nset grid\nset key top left\nset ylabel 'ms per frame (median, bars min-max)'\n"
           "set yrange [0:*]\n";
    if (!both) {
        write_block(out, "$rows", rows, axis);
        write_x_axis(out, axis == Axis::cost_ratio ? costs : leaves, axis);
        out << "set title " << single_quoted(title) << "\nplot "
            << "$rows using 1:2:3:4 with yerrorlines lw 2 title 'build', "
            << "$rows using 1:5:6:7 with yerrorlines lw 2 title 'trace (primary + shadow)', "
            << "$rows using 1:8:9:10 with yerrorlines lw 2 title 'total'\n";
        return out.str();
    }
    for (std::size_t i = 0; i < leaves.size(); ++i) {
        std::vector<BenchRow> series;
        for (const BenchRow& r : rows) {
            if (float(r.build.leaf_size_max) == leaves[i]) series.push_back(r);
        }
        write_block(out, "$leaf" + std::to_string(i), series, Axis::cost_ratio);
    }
    write_x_axis(out, costs, Axis::cost_ratio);
    out << "set multiplot layout 1,3 title " << single_quoted(title) << "\n";
    const char* panels[] = {"build", "trace (primary + shadow)", "total"};
    for (int panel = 0; panel < 3; ++panel) {
        const int column = 2 + 3 * panel;
        out << "set title " << single_quoted(panels[panel]) << "\nplot ";
        for (std::size_t i = 0; i < leaves.size(); ++i) {
            out << (i ? ", " : "") << "$leaf" << i << " using 1:" << column << ':' << column + 1
                << ':' << column + 2 << " with yerrorlines lw 2 title "
                << single_quoted("leaf " + shortest(leaves[i]));
        }
        out << '\n';
    }
    out << "unset multiplot\n";
    return out.str();
}

namespace {

/// Writes `script` next to the image as "<png>.gp" (kept, so the chart can be restyled or
/// redrawn) and runs gnuplot on it.
void run_gnuplot(const std::filesystem::path& png, const std::string& script_text) {
    const std::filesystem::path script = png.string() + ".gp";
    {
        std::ofstream file(script);
        file << script_text;
        if (!file) throw std::runtime_error(script.string() + ": cannot write");
    }
    std::error_code ignored;
    std::filesystem::remove(png, ignored);  // so a stale image cannot pass for a new one
    // posix_spawnp rather than std::system: no shell, so no quoting of the path is needed.
    std::string program = "gnuplot";
    std::string argument = script.string();
    char* argv[] = {program.data(), argument.data(), nullptr};
    pid_t pid = 0;
    const int spawn_error = posix_spawnp(&pid, "gnuplot", nullptr, nullptr, argv, environ);
    if (spawn_error != 0) {
        throw std::runtime_error("--plot: cannot run gnuplot (" +
                                 std::string(std::strerror(spawn_error)) +
                                 "); install gnuplot-nox (scripts/install-deps.sh does)");
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !std::filesystem::exists(png)) {
        throw std::runtime_error("--plot: gnuplot failed to draw " + png.string() +
                                 " (script kept in " + script.string() + ")");
    }
}

}  // namespace

void plot_bench(const std::filesystem::path& png, const std::vector<BenchRow>& rows,
                const std::string& title) {
    run_gnuplot(png, bench_plot_script(rows, title, png));
}

std::vector<std::size_t> pareto_front(const std::vector<ErrorPoint>& points) {
    std::vector<std::size_t> front;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const ErrorPoint& p = points[i];
        const bool beaten = std::any_of(points.begin(), points.end(), [&](const ErrorPoint& q) {
            return q.total_ms.median <= p.total_ms.median && q.error <= p.error &&
                   (q.total_ms.median < p.total_ms.median || q.error < p.error);
        });
        if (!beaten) front.push_back(i);
    }
    return front;
}

std::string error_plot_script(const std::vector<ErrorPoint>& points, const std::string& title,
                              const std::filesystem::path& png, const ErrorPlotAxes& axes) {
    if (points.empty()) throw std::invalid_argument("error plot: no points to plot");
    double smallest = 0.0, largest = 0.0;
    for (const ErrorPoint& p : points) {
        if (p.error > 0.0 && (smallest == 0.0 || p.error < smallest)) smallest = p.error;
        largest = std::max(largest, p.error);
    }
    const bool log_x = smallest > 0.0 && largest >= 8.0 * smallest;
    // On a log axis 0 has no place: such points sit a decade below the rest, marked "(0)".
    const auto x_of = [&](const ErrorPoint& p) {
        return log_x && p.error == 0.0 ? smallest / 10.0 : p.error;
    };
    const auto label_of = [&](const ErrorPoint& p) {
        std::string label = p.label + (log_x && p.error == 0.0 ? " (0)" : "");
        std::replace(label.begin(), label.end(), '"', '\'');
        return label;
    };
    std::ostringstream out;
    out.precision(9);
    out << "# dynrt bench --error chart; redraw with: gnuplot "
        << single_quoted(png.string() + ".gp")
        << "\nset terminal pngcairo size 1000,620 noenhanced font ',11'\nset output "
        << single_quoted(png.string()) << "\nset title " << single_quoted(title)
        << "\nset grid\nset key top right\nset xlabel " << single_quoted(axes.x)
        << "\nset ylabel " << single_quoted(axes.y)
        << "\nset yrange [0:*]\nset offsets graph 0.05, graph 0.25, graph 0.05, graph 0.02\n";
    if (log_x) {
        out << "set logscale x 10\nset format x '%.0e'\n";
    } else {
        // Enough significant digits that ticks over a narrow range of errors read apart
        // (errors 9.42e-8 to 9.46e-8 with '%.2g' would label every tick "9.4e-08").
        double lowest = largest;
        for (const ErrorPoint& p : points) lowest = std::min(lowest, p.error);
        const double span = largest - lowest;
        const int digits =
            span > 0.0 ? std::clamp(int(std::ceil(std::log10(largest / span))) + 2, 2, 6) : 2;
        out << "set format x '%." << digits << "g'\n";
        const bool all_equal = std::all_of(points.begin(), points.end(), [&](const ErrorPoint& p) {
            return p.error == points.front().error;
        });
        if (all_equal) {
            // Every point at one error (all exact settings, say): give the axis a width.
            out << "set xrange [" << (largest > 0.0 ? 0.5 * largest : -1e-3) << ":"
                << (largest > 0.0 ? 1.5 * largest : 1e-3) << "]\n";
        }
    }
    out << "$points << EOD\n# error total_median total_min total_max label\n";
    for (const ErrorPoint& p : points) {
        out << x_of(p) << ' ' << p.total_ms.median << ' ' << p.total_ms.min << ' '
            << p.total_ms.max << " \"" << label_of(p) << "\"\n";
    }
    out << "EOD\n";
    std::vector<std::size_t> front = pareto_front(points);
    std::sort(front.begin(), front.end(),
              [&](std::size_t a, std::size_t b) { return x_of(points[a]) < x_of(points[b]); });
    out << "$front << EOD\n# error total_median\n";
    for (std::size_t i : front) out << x_of(points[i]) << ' ' << points[i].total_ms.median << '\n';
    out << "EOD\n"
        << "plot $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb '#d62728' "
           "title 'Pareto front', "
        << "$points using 1:2:3:4 with yerrorbars pt 7 ps 1.2 lc rgb '#1f77b4' "
           "title 'configuration', "
        << "$points using 1:2:5 with labels left offset 0.8,0.6 font ',9' notitle\n";
    return out.str();
}

void plot_error(const std::filesystem::path& png, const std::vector<ErrorPoint>& points,
                const std::string& title, const ErrorPlotAxes& axes) {
    run_gnuplot(png, error_plot_script(points, title, png, axes));
}

namespace {

/// A first frame this many times the slowest steady frame is drawn off the scale.
constexpr double kColdFrameOffScale = 1.6;

std::string off_scale_label(double first_ms) {
    std::ostringstream label;
    label.precision(0);
    label << std::fixed << "first frame " << first_ms << " ms (cold: every tree built), off the scale";
    return label.str();
}

}  // namespace

std::string timeline_plot_script(const std::vector<FrameStats>& frames, const std::string& title,
                                 const std::filesystem::path& png) {
    if (frames.empty()) throw std::invalid_argument("timeline plot: no frames");
    std::ostringstream out;
    out << "set terminal pngcairo size 1000,520 noenhanced font ',11'\n"
        << "set output " << single_quoted(png.string()) << "\n"
        << "set title " << single_quoted(title) << "\n"
        << "set xlabel 'frame'\nset ylabel 'ms'\n"
        << "set style data histograms\nset style histogram rowstacked\n"
        << "set style fill solid 0.8 border -1\nset boxwidth 0.8\n"
        << "set key outside right top\n"
        << "set xtics rotate by -45\n";
    // The first frame builds every tree from nothing: often many times a steady frame. The y
    // axis is the steady frames' when it would squash them, and the first frame's bar runs
    // off the top, its time written over it.
    const auto stacked_ms = [](const FrameStats& f) {
        return f.update_ms + f.refit_ms + f.rebuild_ms + f.top_level_ms + f.primary_ms + f.shadow_ms + f.shade_ms;
    };
    double steady_max = 0.0;
    for (std::size_t i = 1; i < frames.size(); ++i) steady_max = std::max(steady_max, stacked_ms(frames[i]));
    const double first = stacked_ms(frames.front());
    if (frames.size() > 1 && steady_max > 0.0 && first > kColdFrameOffScale * steady_max) {
        out << "set yrange [0:" << 1.25 * steady_max << "]\n"
            << "set label 1 " << single_quoted(off_scale_label(first)) << " at first 0, graph 0.97 left front\n";
    } else {
        out << "set yrange [0:*]\n";
    }
    // Inline data: frame, update, refit, rebuild, top level, primary, shadow, shade.
    out << "$frames << EOD\n";
    for (const FrameStats& f : frames) {
        out << f.frame << ' ' << f.update_ms << ' ' << f.refit_ms << ' ' << f.rebuild_ms << ' '
            << f.top_level_ms << ' ' << f.primary_ms << ' ' << f.shadow_ms << ' ' << f.shade_ms
            << '\n';
    }
    out << "EOD\n";
    // Label only every k-th frame so long sequences stay readable.
    const std::size_t step = std::max<std::size_t>(1, frames.size() / 32);
    const char* labels[] = {"update (animation)", "refit", "rebuild", "top level",
                            "primary rays", "shadow rays", "shade"};
    out << "plot ";
    for (int c = 0; c < 7; ++c) {
        out << (c == 0 ? "" : ", ") << "$frames using " << c + 2;
        if (c == 0) out << ":xtic(int($0) % " << step << " == 0 ? stringcolumn(1) : '')";
        out << " title " << single_quoted(labels[c]);
    }
    out << "\n";
    return out.str();
}

void plot_timeline(const std::filesystem::path& png, const std::vector<FrameStats>& frames,
                   const std::string& title) {
    run_gnuplot(png, timeline_plot_script(frames, title, png));
}

}  // namespace dynrt
