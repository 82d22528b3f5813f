// run_window (viewer_window.h): the event loop. The frames are rendered by a RenderWorker on a
// thread of its own; this loop turns the mouse, keys, panels and the script's commands into
// changes it posts to the worker, and draws the newest finished frame and the panels, so the
// window answers input while a frame renders. A script runs one command at a time: the next
// waits until a frame showing the last one is on screen.

#include "viewer_window.h"

#include "render_worker.h"
#include "script_runner.h"

#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/sequence_output.h"

#include <GLFW/glfw3.h>
#include <OpenImageIO/imageio.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl2.h>
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <vector>

namespace dynrt::viewer {

namespace {

using Clock = std::chrono::steady_clock;
using Shown = RenderWorker::Shown;

/// What the window reads back: its framebuffer as RGB rows from the top, to a PNG.
void capture_window(int width, int height, const std::string& path) {
    std::vector<unsigned char> rows(std::size_t(width) * std::size_t(height) * 3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
    std::vector<unsigned char> top_down(rows.size());
    const std::size_t stride = std::size_t(width) * 3;
    for (int y = 0; y < height; ++y) {
        std::copy_n(rows.data() + std::size_t(height - 1 - y) * stride, stride, top_down.data() + std::size_t(y) * stride);
    }
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
    const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, top_down.data()) || !out->close()) {
        throw std::runtime_error("capture " + path + ": cannot be written");
    }
}

/// What the loop measured: per frame shown, the worker's time for it (render and bytes) and
/// the window's own work to show it (drawing, panels, swap), which runs beside the next
/// render; per posted input, the time from posting it to the swap of the first frame that
/// shows it (glFinish first, so the image is on the display's buffer): the input-to-photon
/// latency as far as the program can see it.
class LoopTimes {
public:
    void posted(std::uint64_t number) { pending_.emplace_back(number, Clock::now()); }
    void shown(const Shown& frame, double draw_ms, Clock::time_point swapped) {
        render_ms_.push_back(frame.render_ms);
        draw_ms_.push_back(draw_ms);
        while (!pending_.empty() && pending_.front().first <= frame.applied) {
            latency_ms_.push_back(std::chrono::duration<double, std::milli>(swapped - pending_.front().second).count());
            pending_.pop_front();
        }
    }
    /// One line each for the frames and the inputs, medians and maxima.
    void print(std::ostream& out) const {
        if (render_ms_.empty()) return;
        out << "view: " << render_ms_.size() << " frames shown: render median " << median(render_ms_)
            << " ms (on its own thread); the window's drawing, panels and swap median " << median(draw_ms_)
            << " ms, max " << max(draw_ms_) << " ms\n";
        if (!latency_ms_.empty()) {
            out << "view: " << latency_ms_.size() << " inputs, input to swap median " << median(latency_ms_) << " ms, max "
                << max(latency_ms_) << " ms\n";
        }
    }

private:
    static double median(std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    }
    static double max(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

    std::deque<std::pair<std::uint64_t, Clock::time_point>> pending_;
    std::vector<double> render_ms_, draw_ms_, latency_ms_;
};

/// Posts changes to the worker, noting each for the latency figures.
class Poster {
public:
    Poster(RenderWorker& worker, LoopTimes& times) : worker_(worker), times_(times) {}
    std::uint64_t operator()(RenderWorker::Change change) {
        const std::uint64_t number = worker_.post(std::move(change));
        times_.posted(number);
        last_ = number;
        return number;
    }
    std::uint64_t last() const { return last_; }

private:
    RenderWorker& worker_;
    LoopTimes& times_;
    std::uint64_t last_ = 0;
};

/// The panels: the shown frame's figures with rolling plots, the time controls, the cameras
/// and the settings. They read the frame's copy of the session and post what is clicked.
class Panels {
public:
    explicit Panels(Poster& post) : post_(post) {}

    /// `progress`: the frame being rendered now, behind the one shown.
    void draw(const Shown& shown, const RenderProgress& progress) {
        if (!shown.error.empty()) error_ = shown.error;
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowBgAlpha(0.8f);
        ImGui::Begin("dynrt", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
        if (progress.tracing) {
            ImGui::ProgressBar(float(progress.fraction()), ImVec2(260, 0), "rendering the next frame");
        }
        figures(shown);
        time_controls(shown);
        settings(shown);
        ImGui::End();
    }

private:
    void figures(const Shown& shown) {
        if (shown.history.empty()) return;
        const FrameStats& s = shown.history.back();
        ImGui::Text("frame %d  %.1f ms  %d/%d samples%s", shown.frame, s.total_ms, shown.samples, shown.target_samples,
                    shown.converged() ? "" : " (refining)");
        ImGui::Text("update %.2f  build %.2f  camera %.2f  shadow %.2f", s.update_ms, s.build_ms, s.primary_ms, s.shadow_ms);
        ImGui::Text("secondary %.2f  shade %.2f ms", s.secondary_ms, s.shade_ms);
        ImGui::Text("camera %.1f Mrays/s  shadow %.1f Mrays/s", s.primary_mrays_per_s, s.shadow_mrays_per_s);
        ImGui::Text("refit %zu  rebuilt %zu  skipped %zu  nodes %zu  tree %.1f MB", s.objects_refitted, s.objects_rebuilt,
                    s.objects_skipped, s.nodes, double(s.wide_tree_bytes) / 1e6);
        ImGui::Text("reuse %s: %zu traced, %zu kept", s.reuse_mode.c_str(), s.pixels_traced, s.pixels_reused);
        if (s.triangles > 0) {
            const double per = 1.0 / double(s.triangles);
            ImGui::Text("memory per triangle: scene %.0f B, held %.0f B, peak %.0f B", double(s.scene_bytes) * per,
                        double(s.renderer_bytes) * per, double(s.peak_rss_bytes) * per);
        }
        for (const TreeChoice& c : s.choices) ImGui::TextWrapped("%s: %s (%s)", c.name.c_str(), c.chosen.c_str(), c.why.c_str());
        plot(shown, "total ms", [](const FrameStats& f) { return f.total_ms; });
        plot(shown, "build ms", [](const FrameStats& f) { return f.build_ms; });
        plot(shown, "camera ms", [](const FrameStats& f) { return f.primary_ms; });
        plot(shown, "shadow ms", [](const FrameStats& f) { return f.shadow_ms; });
        plot(shown, "secondary ms", [](const FrameStats& f) { return f.secondary_ms; });
    }

    template <typename Figure>
    void plot(const Shown& shown, const char* label, Figure figure) {
        values_.clear();
        for (const FrameStats& f : shown.history) values_.push_back(float(figure(f)));
        ImGui::PlotLines(label, values_.data(), int(values_.size()), 0, nullptr, 0.0f, FLT_MAX, ImVec2(260, 36));
    }

    void time_controls(const Shown& shown) {
        if (ImGui::Button(shown.playing ? "pause" : "play")) {
            post_([](ViewerSession& s) { s.playing() ? s.pause() : s.play(); return true; });
        }
        ImGui::SameLine();
        if (ImGui::Button("<")) post_([](ViewerSession& s) { s.step(-1); return true; });
        ImGui::SameLine();
        if (ImGui::Button(">")) post_([](ViewerSession& s) { s.step(1); return true; });
        ImGui::SameLine();
        bool loop = shown.loop;
        if (ImGui::Checkbox("loop", &loop)) post_([loop](ViewerSession& s) { s.set_loop(loop); return true; });
        int frame = shown.frame;
        if (shown.last_frame > 0 && ImGui::SliderInt("frame", &frame, 0, shown.last_frame)) {
            post_([frame](ViewerSession& s) { s.seek(frame); return true; });
        }
        float speed = float(shown.speed);
        if (ImGui::SliderFloat("speed", &speed, 0.05f, 4.0f, "%.2fx")) post_([speed](ViewerSession& s) { s.set_speed(speed); return true; });
        if (ImGui::Button("reset camera")) post_([](ViewerSession& s) { s.reset_camera(); return true; });
        for (std::size_t k = 0; k < shown.cameras.size(); ++k) {
            ImGui::SameLine();
            const std::string name = shown.cameras[k].empty() ? "camera " + std::to_string(k) : shown.cameras[k];
            if (ImGui::Button((name + "##camera" + std::to_string(k)).c_str())) {
                post_([k](ViewerSession& s) { s.use_scene_camera(k); return true; });
            }
        }
    }

    void settings(const Shown& shown) {
        if (!ImGui::CollapsingHeader("settings", ImGuiTreeNodeFlags_DefaultOpen)) return;
        choice(shown, "tracer", {"packet", "single"});
        choice(shown, "update", {"auto", "refit", "fast", "sah", "threshold"});
        choice(shown, "reuse", {"exact", "off"});
        choice(shown, "culling", {"all", "none", "ab", "ab,bp"});
        choice(shown, "depth", {"0", "1", "2", "5"});
        choice(shown, "spp", {"1", "4", "16"});
        choice(shown, "normals", {"smooth", "flat"});
        choice(shown, "backend", {"dynrt", "embree"});
        choice(shown, "view", {"image", "nodes", "triangles"});
        if (!shown.legend.empty()) ImGui::TextWrapped("%s", shown.legend.c_str());
        if (!error_.empty()) ImGui::TextWrapped("%s", error_.c_str());
    }

    /// A row of buttons, one per value of setting `name`, the current one marked.
    void choice(const Shown& shown, const char* name, std::initializer_list<const char*> values) {
        std::string current;
        for (const auto& [setting, value] : shown.settings) {
            if (setting == name) current = value;
        }
        ImGui::Text("%-10s", name);
        for (const char* value : values) {
            ImGui::SameLine();
            const std::string label = (current == value ? std::string("[") + value + "]" : std::string(value)) + "##" + name;
            if (ImGui::SmallButton(label.c_str())) {
                error_.clear();
                post_([setting = std::string(name), v = std::string(value)](ViewerSession& s) { s.set(setting, v); return true; });
            }
        }
    }

    Poster& post_;
    std::vector<float> values_;
    std::string error_;
};

/// The mouse and keys: left drag orbits, right or middle drag pans, the wheel zooms, W A S D
/// Q E fly, space plays or pauses, the arrows step, R resets the view, F12 writes a
/// screenshot, Escape closes.
class Input {
public:
    Input(GLFWwindow* window, Poster& post) : window_(window), post_(post) {
        glfwSetWindowUserPointer(window, this);
        glfwSetScrollCallback(window, [](GLFWwindow* w, double dx, double dy) {
            ImGui_ImplGlfw_ScrollCallback(w, dx, dy);
            if (!ImGui::GetIO().WantCaptureMouse) static_cast<Input*>(glfwGetWindowUserPointer(w))->scroll_ += dy;
        });
        glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int code, int action, int mods) {
            ImGui_ImplGlfw_KeyCallback(w, key, code, action, mods);
            if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
            static_cast<Input*>(glfwGetWindowUserPointer(w))->key(key);
        });
    }

    void poll(double seconds) {
        double x = 0.0, y = 0.0;
        glfwGetCursorPos(window_, &x, &y);
        const float dx = float(x - last_x_), dy = float(y - last_y_);
        last_x_ = x;
        last_y_ = y;
        const bool free = !ImGui::GetIO().WantCaptureMouse;
        const auto pressed = [&](int button) { return glfwGetMouseButton(window_, button) == GLFW_PRESS; };
        if (free && (dx != 0.0f || dy != 0.0f)) {
            if (pressed(GLFW_MOUSE_BUTTON_LEFT)) {
                post_([dx, dy](ViewerSession& s) { s.camera().orbit(-0.3f * dx, -0.3f * dy); return true; });
            } else if (pressed(GLFW_MOUSE_BUTTON_RIGHT) || pressed(GLFW_MOUSE_BUTTON_MIDDLE)) {
                post_([dx, dy](ViewerSession& s) { s.camera().pan(-0.002f * dx, 0.002f * dy); return true; });
            }
        }
        if (scroll_ != 0.0) {
            const float factor = float(std::pow(1.1, scroll_));
            post_([factor](ViewerSession& s) { s.camera().zoom(factor); return true; });
        }
        scroll_ = 0.0;
        if (ImGui::GetIO().WantCaptureKeyboard) return;
        const float step = float(seconds);
        const auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS ? 1.0f : 0.0f; };
        const float forward = step * (held(GLFW_KEY_W) - held(GLFW_KEY_S)), right = step * (held(GLFW_KEY_D) - held(GLFW_KEY_A)),
                    up = step * (held(GLFW_KEY_E) - held(GLFW_KEY_Q));
        if (forward != 0.0f || right != 0.0f || up != 0.0f) {
            post_([forward, right, up](ViewerSession& s) { s.camera().fly(forward, right, up); return true; });
        }
    }

private:
    void key(int key) {
        switch (key) {
            case GLFW_KEY_SPACE: post_([](ViewerSession& s) { s.playing() ? s.pause() : s.play(); return true; }); break;
            case GLFW_KEY_RIGHT: post_([](ViewerSession& s) { s.step(1); return true; }); break;
            case GLFW_KEY_LEFT: post_([](ViewerSession& s) { s.step(-1); return true; }); break;
            case GLFW_KEY_R: post_([](ViewerSession& s) { s.reset_camera(); return true; }); break;
            case GLFW_KEY_F12: {
                const std::string name = "dynrt-view-" + std::to_string(++screenshots_) + ".png";
                post_([name](ViewerSession& s) {
                    s.screenshot(name);
                    std::cout << "screenshot: " << name << " (and its report, " << name.substr(0, name.size() - 4)
                              << ".json)\n";
                    return false;
                });
                break;
            }
            case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
            default: break;
        }
    }

    GLFWwindow* window_;
    Poster& post_;
    double last_x_ = 0.0, last_y_ = 0.0, scroll_ = 0.0;
    int screenshots_ = 0;
};

/// A script carried out one command at a time: a command on the session is posted, and the
/// next waits until a frame showing it is on screen; the window's own commands are done here.
class ScriptPlayer {
public:
    ScriptPlayer(const std::vector<ScriptCommand>& script, std::string source, Poster& post, GLFWwindow* window)
        : script_(script), source_(std::move(source)), post_(post), window_(window) {}

    /// Runs the commands due at `elapsed` seconds that may run with `shown` on screen. Sets
    /// `capture` to a file to read the window back to after drawing, `overlay` as told, and
    /// returns false when the script quits.
    bool run(double elapsed, const Shown& shown, std::string& capture, bool& overlay) {
        while (next_ < script_.size() && script_[next_].at_seconds <= elapsed) {
            if (shown.number == 0 || shown.applied < post_.last() || hold_frames_ > 0) return true;
            if (wait_still_ && !shown.converged()) return true;
            wait_still_ = false;
            // A resize is done when a frame of the new size is shown (the loop posts it when
            // the window system has resized the framebuffer).
            if (resize_width_ > 0 && (shown.width != resize_width_ || shown.height != resize_height_)) return true;
            resize_width_ = resize_height_ = 0;
            const ScriptCommand& command = script_[next_++];
            const WindowStep step = window_step(command, source_);
            switch (step.action) {
                case WindowStep::Action::quit: return false;
                case WindowStep::Action::overlay: overlay = step.on; continue;
                case WindowStep::Action::wait_frames: hold_frames_ = step.frames; continue;
                case WindowStep::Action::wait_still: wait_still_ = true; continue;  // all its samples
                case WindowStep::Action::resize:
                    resize_width_ = step.width;
                    resize_height_ = step.height;
                    glfwSetWindowSize(window_, step.width, step.height);
                    continue;
                case WindowStep::Action::capture:
                    capture = step.file;
                    return true;  // drawn, then read back, before the next command
                case WindowStep::Action::none: break;
            }
            post_([command, source = source_](ViewerSession& s) {
                run_command(s, command, source);
                return command.name != "screenshot";  // a screenshot changes nothing shown
            });
        }
        return true;
    }

    bool done() const { return next_ >= script_.size(); }
    /// Whether the script waits for frames to be drawn (the window then draws every turn).
    bool wants_draw() const { return hold_frames_ > 0; }
    /// A frame was drawn and swapped.
    void drawn(const Shown& shown) {
        if (hold_frames_ > 0 && shown.applied >= post_.last()) --hold_frames_;
    }

private:
    const std::vector<ScriptCommand>& script_;
    std::string source_;
    Poster& post_;
    GLFWwindow* window_;
    std::size_t next_ = 0;
    int hold_frames_ = 0;
    bool wait_still_ = false;
    int resize_width_ = 0, resize_height_ = 0;  ///< a resize waited for
};

/// The frame drawn 1:1 at the window's top left, as a texture on a quad (uploaded when a new
/// frame arrives): with Mesa's software OpenGL this cost a third of glDrawPixels of the same
/// bytes. Nearest sampling at texel centres, so the window shows the frame's bytes exactly.
class ImageQuad {
public:
    ImageQuad() { glGenTextures(1, &texture_); }
    ~ImageQuad() { glDeleteTextures(1, &texture_); }
    ImageQuad(const ImageQuad&) = delete;
    ImageQuad& operator=(const ImageQuad&) = delete;

    void draw(const Shown& shown, bool upload, int fb_width, int fb_height) {
        glBindTexture(GL_TEXTURE_2D, texture_);
        if (upload || shown.width != width_ || shown.height != height_) {
            glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
            if (shown.width != width_ || shown.height != height_) {
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
                glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
                glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, shown.width, shown.height, 0, GL_RGB, GL_UNSIGNED_BYTE,
                             shown.bytes.data());
                width_ = shown.width;
                height_ = shown.height;
            } else {
                glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, shown.width, shown.height, GL_RGB, GL_UNSIGNED_BYTE,
                                shown.bytes.data());
            }
        }
        // Window pixels: x right, y down from the top left, as the image's rows run.
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        glOrtho(0.0, fb_width, fb_height, 0.0, -1.0, 1.0);
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        glDisable(GL_BLEND);
        glEnable(GL_TEXTURE_2D);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
        const float w = float(width_), h = float(height_);
        glBegin(GL_QUADS);
        glTexCoord2f(0.0f, 0.0f);
        glVertex2f(0.0f, 0.0f);
        glTexCoord2f(1.0f, 0.0f);
        glVertex2f(w, 0.0f);
        glTexCoord2f(1.0f, 1.0f);
        glVertex2f(w, h);
        glTexCoord2f(0.0f, 1.0f);
        glVertex2f(0.0f, h);
        glEnd();
        glDisable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, 0);
    }

private:
    GLuint texture_ = 0;
    int width_ = 0, height_ = 0;
};

/// GLFW, the window and Dear ImGui, torn down in reverse on every way out.
class WindowContext {
public:
    WindowContext(int width, int height, const std::string& title) {
        glfwSetErrorCallback([](int, const char* text) { std::cerr << "dynrt view: GLFW: " << text << "\n"; });
        if (!glfwInit()) throw std::runtime_error("no window system could be opened (GLFW failed to start)");
        glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);  // the image follows the window's size
        window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
        if (window_ == nullptr) {
            glfwTerminate();
            throw std::runtime_error("no window could be made (no OpenGL on this display?)");
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(0);  // the frames arrive when rendered; vsync would only add delay
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left behind
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window_, false);  // its callbacks chained by Input
        ImGui_ImplOpenGL2_Init();
    }
    ~WindowContext() {
        ImGui_ImplOpenGL2_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    WindowContext(const WindowContext&) = delete;
    WindowContext& operator=(const WindowContext&) = delete;

    GLFWwindow* window() const { return window_; }

private:
    GLFWwindow* window_ = nullptr;
};

}  // namespace

std::string display_problem() {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((x11 == nullptr || *x11 == '\0') && (wayland == nullptr || *wayland == '\0')) {
        return "no display available (neither DISPLAY nor WAYLAND_DISPLAY is set): run it on a desktop, "
               "or headless under xvfb-run";
    }
    return {};
}

int run_window(ViewerSession& session, const std::vector<ScriptCommand>& script, const std::string& script_source,
               const std::string& title, const std::string& record_path) {
    const int width = session.options().width, height = session.options().height;
    std::unique_ptr<WindowContext> context;
    try {
        context = std::make_unique<WindowContext>(width, height, title);
    } catch (const std::runtime_error& e) {
        std::cerr << "dynrt view: " << e.what() << "\n";
        return 1;
    }
    std::unique_ptr<SequenceFile> record;
    try {
        if (!record_path.empty()) record = open_sequence_file(record_path, session.fps());
    } catch (const std::exception& e) {
        std::cerr << "dynrt: error: " << e.what() << "\n";
        return 1;
    }
    GLFWwindow* window = context->window();
    if (record) session.set_recorder(record.get());
    int status = 0;
    LoopTimes times;
    {
        // The session is the worker's until it is gone; each frame it finishes wakes this loop.
        RenderWorker worker(session, [] { glfwPostEmptyEvent(); });
        Poster post(worker, times);
        Input input(window, post);
        Panels panels(post);
        ImageQuad image;
        ScriptPlayer player(script, script_source, post, window);
        bool overlay = true;
        Shown shown;
        int image_width = width, image_height = height;  // the size the session renders at
        const Clock::time_point start = Clock::now();
        Clock::time_point last = start, last_draw = start;
        while (!glfwWindowShouldClose(window)) {
            // Wait for input or a frame (the worker wakes us), or the panels' and the script's
            // next turn.
            glfwWaitEventsTimeout(0.016);
            const Clock::time_point now = Clock::now();
            const double seconds = std::chrono::duration<double>(now - last).count();
            last = now;
            const bool new_frame = worker.take(shown);
            std::string capture;
            try {
                if (!script.empty() && !shown.error.empty() && new_frame) throw std::invalid_argument(shown.error);
                if (!player.run(std::chrono::duration<double>(now - start).count(), shown, capture, overlay)) break;
            } catch (const std::exception& e) {
                std::cerr << "dynrt: error: " << e.what() << "\n";
                status = 1;
                break;
            }
            input.poll(seconds);
            // The image follows the window: a new size is posted once (minimised, the
            // framebuffer is 0 x 0 and the image keeps its size).
            int fb_width = 0, fb_height = 0;
            glfwGetFramebufferSize(window, &fb_width, &fb_height);
            if (fb_width > 0 && fb_height > 0 && (fb_width != image_width || fb_height != image_height)) {
                image_width = fb_width;
                image_height = fb_height;
                post([fb_width, fb_height](ViewerSession& s) { s.resize(fb_width, fb_height); return true; });
            }
            // Drawn when a frame arrives, for a capture, and for the panels at 30 Hz at most.
            const bool panels_due = overlay && now - last_draw > std::chrono::milliseconds(33);
            if (shown.number == 0 || (!new_frame && capture.empty() && !panels_due && !player.wants_draw())) continue;
            last_draw = now;
            if (fb_width == 0 || fb_height == 0) continue;  // minimised: nothing to draw
            const Clock::time_point draw_start = Clock::now();
            glViewport(0, 0, fb_width, fb_height);
            glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            image.draw(shown, new_frame, fb_width, fb_height);
            if (overlay) {
                ImGui_ImplOpenGL2_NewFrame();
                ImGui_ImplGlfw_NewFrame();
                ImGui::NewFrame();
                panels.draw(shown, worker.progress());
                ImGui::Render();
                ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());
            }
            if (!capture.empty()) {
                try {
                    capture_window(fb_width, fb_height, capture);
                } catch (const std::exception& e) {
                    std::cerr << "dynrt: error: " << e.what() << "\n";
                    status = 1;
                    break;
                }
            }
            glfwSwapBuffers(window);
            glFinish();
            player.drawn(shown);
            if (new_frame) times.shown(shown, std::chrono::duration<double, std::milli>(Clock::now() - draw_start).count(), Clock::now());
        }
    }
    session.set_recorder(nullptr);
    times.print(std::cout);
    if (record && status == 0) record->close();
    return status;
}

}  // namespace dynrt::viewer
