#include "dynrt/engine/sequence_output.h"

#include "dynrt/engine/image_output.h"

#include "srgb.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

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
    for (std::size_t i = 0; i < frame.color.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            out[3 * i + std::size_t(c)] =
                std::uint8_t(std::lround(srgb_encode(frame.color[i][c]) * 255.0f));
        }
    }
    return out;
}

}  // namespace

bool is_animated_image(const std::filesystem::path& path) { return lower_extension(path) == ".gif"; }

void refuse_video(const std::filesystem::path& path) {
    const std::string ext = lower_extension(path);
    for (const char* video : {".mp4", ".mov", ".mkv", ".webm", ".avi"}) {
        if (ext != video) continue;
        throw std::invalid_argument(
            "--out " + path.string() + ": dynrt does not write video; write numbered frames "
            "(--out 'frames/%04d.png') and encode them, e.g. ffmpeg -framerate 24 -i "
            "frames/%04d.png -pix_fmt yuv420p " + path.filename().string() +
            ", or an animated GIF (--out " + path.stem().string() + ".gif)");
    }
}

struct AnimatedImageWriter::Impl {
    std::filesystem::path path;
    double fps = 24.0;
    std::unique_ptr<OIIO::ImageOutput> out;
    int width = 0, height = 0;
    bool open = false;
};

AnimatedImageWriter::AnimatedImageWriter(const std::filesystem::path& path, double fps)
    : impl_(std::make_unique<Impl>()) {
    impl_->path = path;
    impl_->fps = fps;
    impl_->out = OIIO::ImageOutput::create(path.string());
    if (!impl_->out || !impl_->out->supports("multiimage") || !impl_->out->supports("appendsubimage")) {
        throw std::invalid_argument(path.string() + ": this format cannot hold several frames "
                                    "(use .gif, or numbered images such as 'frames/%04d.png')");
    }
}

AnimatedImageWriter::~AnimatedImageWriter() {
    if (impl_ && impl_->open) impl_->out->close();  // keeps the frames written so far
}

void AnimatedImageWriter::add(const RenderedFrame& frame) {
    Impl& s = *impl_;
    if (s.open && (frame.width != s.width || frame.height != s.height)) {
        throw std::runtime_error(s.path.string() + ": every frame must have the first one's size");
    }
    OIIO::ImageSpec spec(frame.width, frame.height, 3, OIIO::TypeDesc::UINT8);
    // GIF stores delays in hundredths of a second; OpenImageIO takes the rate as a ratio.
    const int hundredths = std::max(1, int(std::lround(100.0 / s.fps)));
    const int rate[2] = {100, hundredths};
    spec.attribute("FramesPerSecond", OIIO::TypeDesc::TypeRational, rate);
    spec.attribute("gif:LoopCount", 0);  // loop for ever
    const OIIO::ImageOutput::OpenMode mode = s.open ? OIIO::ImageOutput::AppendSubimage : OIIO::ImageOutput::Create;
    const std::vector<std::uint8_t> pixels = to_srgb8(frame);
    if (!s.out->open(s.path.string(), spec, mode) || !s.out->write_image(OIIO::TypeDesc::UINT8, pixels.data())) {
        throw std::runtime_error(s.path.string() + ": " + s.out->geterror());
    }
    s.open = true;
    s.width = frame.width;
    s.height = frame.height;
}

void AnimatedImageWriter::close() {
    Impl& s = *impl_;
    if (!s.open) throw std::runtime_error(s.path.string() + ": no frame was written");
    s.open = false;
    if (!s.out->close()) throw std::runtime_error(s.path.string() + ": " + s.out->geterror());
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
