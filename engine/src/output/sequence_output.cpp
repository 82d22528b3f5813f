#include "dynrt/engine/sequence_output.h"

#include "dynrt/engine/atomic_file.h"
#include "dynrt/engine/image_output.h"

#include "srgb8.h"

#include <OpenImageIO/imageio.h>

#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <stdexcept>
#include <string>
#include <system_error>

namespace dynrt {

namespace {

std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

/// The frame's colour as 8-bit sRGB, RGB interleaved.
std::vector<std::uint8_t> to_srgb8(const RenderedFrame& frame) {
    std::vector<std::uint8_t> out(frame.color.size() * 3);
    encode_srgb8(frame.color, out.data());
    return out;
}

}  // namespace

namespace {

constexpr const char* kVideoExtensions[] = {".mp4", ".mov", ".mkv", ".webm", ".avi"};

bool is_video(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    return std::find_if(std::begin(kVideoExtensions), std::end(kVideoExtensions),
                        [&](const char* v) { return ext == v; }) != std::end(kVideoExtensions);
}

/// The ffmpeg program on the PATH, or an empty path.
std::filesystem::path find_ffmpeg() {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t colon = std::min(dirs.find(':', start), dirs.size());
        const std::filesystem::path candidate = std::filesystem::path(dirs.substr(start, colon - start)) / "ffmpeg";
        std::error_code error;
        if (colon > start && std::filesystem::is_regular_file(candidate, error) &&
            ::access(candidate.c_str(), X_OK) == 0) {
            return candidate;
        }
        start = colon + 1;
    }
    return {};
}

/// `text` quoted for the shell: in single quotes, each ' written as '\''.
std::string shell_quote(const std::string& text) {
    std::string out = "'";
    for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

class GifFile final : public SequenceFile {
public:
    // Written to partial_path(path) and renamed over `path` once closed: a render killed part
    // way leaves no GIF without its trailer under the user's name.
    GifFile(const std::filesystem::path& path, double fps)
        : path_(path), partial_(partial_path(path)), fps_(fps) {
        out_ = OIIO::ImageOutput::create(path.string());
        if (!out_ || !out_->supports("multiimage") || !out_->supports("appendsubimage")) {
            throw std::invalid_argument(path.string() + ": this OpenImageIO cannot write several "
                                        "frames to a GIF; write numbered images ('frames/%04d.png')");
        }
    }
    ~GifFile() override {
        if (!open_) return;
        // Keeps the frames written so far, as a whole GIF.
        try {
            if (out_->close()) commit_partial(partial_, path_);
        } catch (const std::exception&) {
            // A destructor does not throw; commit_partial removed the partial file.
        }
    }

    void add(const RenderedFrame& frame) override {
        if (open_ && (frame.width != width_ || frame.height != height_)) {
            throw std::runtime_error(path_.string() + ": every frame must have the first one's size");
        }
        OIIO::ImageSpec spec(frame.width, frame.height, 3, OIIO::TypeDesc::UINT8);
        // GIF stores delays in hundredths of a second; OpenImageIO takes the rate as a ratio.
        const int rate[2] = {100, std::max(1, int(std::lround(100.0 / fps_)))};
        spec.attribute("FramesPerSecond", OIIO::TypeDesc::TypeRational, rate);
        spec.attribute("gif:LoopCount", 0);  // loop for ever
        const auto mode = open_ ? OIIO::ImageOutput::AppendSubimage : OIIO::ImageOutput::Create;
        const std::vector<std::uint8_t> pixels = to_srgb8(frame);
        if (!out_->open(partial_.string(), spec, mode) ||
            !out_->write_image(OIIO::TypeDesc::UINT8, pixels.data())) {
            throw std::runtime_error(path_.string() + ": " + out_->geterror());
        }
        open_ = true;
        width_ = frame.width;
        height_ = frame.height;
    }

    void close() override {
        if (!open_) throw std::runtime_error(path_.string() + ": no frame was written");
        open_ = false;
        if (!out_->close()) throw std::runtime_error(path_.string() + ": " + out_->geterror());
        commit_partial(partial_, path_);
    }

private:
    std::filesystem::path path_;
    std::filesystem::path partial_;
    double fps_;
    std::unique_ptr<OIIO::ImageOutput> out_;
    int width_ = 0, height_ = 0;
    bool open_ = false;
};

/// Raw RGB frames piped into ffmpeg, started at the first frame (whose size it needs).
class VideoFile final : public SequenceFile {
public:
    // ffmpeg writes partial_path(path), renamed over `path` once it has finished the file.
    VideoFile(const std::filesystem::path& path, double fps)
        : path_(path), partial_(partial_path(path)), fps_(fps) {}
    ~VideoFile() override {
        // ffmpeg finishes what it got: kept, as a whole file.
        if (pipe_ && pclose(pipe_) == 0) {
            try {
                commit_partial(partial_, path_);
            } catch (const std::exception&) {
                // A destructor does not throw; commit_partial removed the partial file.
            }
        }
        if (previous_sigpipe_ != SIG_ERR) std::signal(SIGPIPE, previous_sigpipe_);
    }

    void add(const RenderedFrame& frame) override {
        if (!pipe_) start(frame.width, frame.height);
        if (frame.width != width_ || frame.height != height_) {
            throw std::runtime_error(path_.string() + ": every frame must have the first one's size");
        }
        const std::vector<std::uint8_t> pixels = to_srgb8(frame);
        if (std::fwrite(pixels.data(), 1, pixels.size(), pipe_) != pixels.size()) {
            throw std::runtime_error(path_.string() + ": ffmpeg stopped reading frames");
        }
    }

    void close() override {
        if (!pipe_) throw std::runtime_error(path_.string() + ": no frame was written");
        const int status = pclose(pipe_);
        pipe_ = nullptr;
        if (status != 0) {
            std::error_code ignored;
            std::filesystem::remove(partial_, ignored);
            throw std::runtime_error(path_.string() + ": ffmpeg failed (exit status " +
                                     std::to_string(status) + "); its messages are above");
        }
        commit_partial(partial_, path_);
    }

private:
    void start(int width, int height) {
        width_ = width;
        height_ = height;
        // yuv420p (what players expect) needs even sizes: pad by one pixel when odd.
        // In a session of its own (setsid, when installed): a Ctrl-C at the terminal, or
        // `timeout`'s signal to its process group, is dynrt's to handle; ffmpeg then gets the
        // frames rendered so far and the end of its input, and finishes the file.
        const std::string command =
            std::string(std::filesystem::exists("/usr/bin/setsid") ? "exec /usr/bin/setsid " : "exec ") +
            shell_quote(find_ffmpeg().string()) + " -nostdin -y -loglevel error -f rawvideo -pix_fmt rgb24 -s " +
            std::to_string(width) + "x" + std::to_string(height) + " -r " + std::to_string(fps_) +
            " -i - -vf " + shell_quote("pad=ceil(iw/2)*2:ceil(ih/2)*2") + " -pix_fmt yuv420p " +
            shell_quote(partial_.string());
        // An ffmpeg that exits early must make fwrite fail (EPIPE), not kill dynrt (SIGPIPE).
        previous_sigpipe_ = std::signal(SIGPIPE, SIG_IGN);
        // setsid takes ffmpeg out of dynrt's process group only once it runs: a signal to the
        // group between the fork and then killed the shell, and the stopped render reported a
        // failed video instead of its stop. The child starts with SIGINT and SIGTERM blocked
        // (a mask survives fork and exec), so only dynrt answers them; dynrt's own mask is
        // put back at once, and a signal that came meanwhile is delivered to it then.
        sigset_t stops, previous;
        sigemptyset(&stops);
        sigaddset(&stops, SIGINT);
        sigaddset(&stops, SIGTERM);
        pthread_sigmask(SIG_BLOCK, &stops, &previous);
        pipe_ = popen(command.c_str(), "w");
        pthread_sigmask(SIG_SETMASK, &previous, nullptr);
        if (!pipe_) throw std::runtime_error(path_.string() + ": cannot start ffmpeg");
    }

    std::filesystem::path path_;
    std::filesystem::path partial_;
    double fps_;
    FILE* pipe_ = nullptr;
    int width_ = 0, height_ = 0;
    void (*previous_sigpipe_)(int) = SIG_ERR;
};

}  // namespace

bool is_sequence_file(const std::filesystem::path& path) {
    return lower_extension(path) == ".gif" || is_video(path);
}

void check_sequence_file(const std::filesystem::path& path) {
    if (!is_video(path) || !find_ffmpeg().empty()) return;
    throw std::invalid_argument(
        "--out " + path.string() + ": writing video needs the ffmpeg program, which is not on "
        "the PATH (Debian: apt-get install ffmpeg); or write an animated GIF (--out " +
        path.stem().string() + ".gif) or numbered frames (--out 'frames/%04d.png') and encode "
        "them with ffmpeg -framerate 24 -i frames/%04d.png -pix_fmt yuv420p " +
        path.filename().string());
}

std::unique_ptr<SequenceFile> open_sequence_file(const std::filesystem::path& path, double fps) {
    check_sequence_file(path);
    if (is_video(path)) return std::make_unique<VideoFile>(path, fps);
    return std::make_unique<GifFile>(path, fps);
}

ContactSheet::ContactSheet(int frame_count, int max_frames, int thumb)
    : step_(std::max(1, (frame_count + max_frames - 1) / std::max(1, max_frames))),
      max_frames_(std::max(1, max_frames)),
      thumb_(std::max(1, thumb)) {}

void ContactSheet::add(int index, const RenderedFrame& frame) {
    if (index % step_ != 0 || int(thumbs_.size()) >= max_frames_) return;
    // Box filter: each thumbnail pixel averages the frame's pixels it covers.
    const int scale = std::max(1, (std::max(frame.width, frame.height) + thumb_ - 1) / thumb_);
    RenderedFrame t;
    t.width = std::max(1, frame.width / scale);
    t.height = std::max(1, frame.height / scale);
    t.color.assign(std::size_t(t.width) * std::size_t(t.height), glm::vec3(0.0f));
    for (int y = 0; y < t.height; ++y) {
        for (int x = 0; x < t.width; ++x) {
            glm::vec3 sum(0.0f);
            int n = 0;
            for (int dy = 0; dy < scale && y * scale + dy < frame.height; ++dy) {
                for (int dx = 0; dx < scale && x * scale + dx < frame.width; ++dx) {
                    sum += frame.color[std::size_t(y * scale + dy) * std::size_t(frame.width) +
                                       std::size_t(x * scale + dx)];
                    ++n;
                }
            }
            t.color[std::size_t(y) * std::size_t(t.width) + std::size_t(x)] = sum / float(n);
        }
    }
    thumbs_.push_back(std::move(t));
}

void ContactSheet::write(const std::filesystem::path& path) const {
    if (thumbs_.empty()) throw std::logic_error("contact sheet: no frames");
    const int n = int(thumbs_.size());
    const int columns = int(std::ceil(std::sqrt(double(n))));
    const int rows = (n + columns - 1) / columns;
    const int cell_w = thumbs_.front().width + 1, cell_h = thumbs_.front().height + 1;
    RenderedFrame sheet;
    sheet.width = columns * cell_w - 1;
    sheet.height = rows * cell_h - 1;
    sheet.color.assign(std::size_t(sheet.width) * std::size_t(sheet.height), glm::vec3(0.5f));
    for (int i = 0; i < n; ++i) {
        const RenderedFrame& t = thumbs_[std::size_t(i)];
        const int x0 = (i % columns) * cell_w, y0 = (i / columns) * cell_h;
        for (int y = 0; y < t.height && y0 + y < sheet.height; ++y) {
            for (int x = 0; x < t.width && x0 + x < sheet.width; ++x) {
                sheet.color[std::size_t(y0 + y) * std::size_t(sheet.width) + std::size_t(x0 + x)] =
                    t.color[std::size_t(y) * std::size_t(t.width) + std::size_t(x)];
            }
        }
    }
    write_image(path, sheet);
}

}  // namespace dynrt
