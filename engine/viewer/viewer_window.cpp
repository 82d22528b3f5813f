// run_window (viewer_window.h): the event loop. Each turn: poll input, carry out the script's
// due commands, turn the mouse and keys into camera, time and panel changes, move the clock
// by the wall time since the last turn, render the clock's frame, draw it and the panels.
// The frame is rendered on this thread: the window answers again when it is done (one frame
// time, 20-50 ms on the bundled scene and CesiumMan).

#include "viewer_window.h"

#include "script_runner.h"

#include "dynrt/engine/frame_stats.h"
#include "dynrt/engine/sequence_output.h"

// glWindowPos2i is OpenGL 1.4: declared by glext.h, exported by every Linux libGL.
#define GL_GLEXT_PROTOTYPES
#define GLFW_INCLUDE_GLEXT
#include <GLFW/glfw3.h>
#include <OpenImageIO/imageio.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl2.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cfloat>
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

/// What the loop measured: per drawn frame, the render's time and the rest of the turn (the
/// image's bytes, drawing, the panels, the swap): the viewer's overhead over the render; per
/// scripted input, the time from carrying it out to the swap of the first frame showing it
/// (glFinish first, so the image is on the display's buffer): the input-to-photon latency as
/// far as the program can see it.
class LoopTimes {
public:
    void input_at(Clock::time_point t) { pending_.push_back(t); }
    void frame(Clock::time_point turn_start, Clock::time_point render_start, Clock::time_point render_end,
               Clock::time_point swapped) {
        render_ms_.push_back(ms(render_end - render_start));
        rest_ms_.push_back(ms(swapped - turn_start) - render_ms_.back());
        for (const Clock::time_point t : pending_) latency_ms_.push_back(ms(swapped - t));
        pending_.clear();
    }
    /// One line each for the frames and the inputs, medians and maxima.
    void print(std::ostream& out) {
        if (render_ms_.empty()) return;
        out << "view: " << render_ms_.size() << " frames: render median " << median(render_ms_)
            << " ms, the viewer's own work besides (bytes, drawing, panels, swap) median " << median(rest_ms_)
            << " ms, max " << max(rest_ms_) << " ms\n";
        if (!latency_ms_.empty()) {
            out << "view: " << latency_ms_.size() << " scripted inputs, input to swap median " << median(latency_ms_)
                << " ms, max " << max(latency_ms_) << " ms\n";
        }
    }

private:
    static double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }
    static double median(std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    }
    static double max(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }

    std::vector<Clock::time_point> pending_;
    std::vector<double> render_ms_, rest_ms_, latency_ms_;
};

/// The panels: the frame's figures with a rolling plot, the time controls and the settings.
class Panels {
public:
    explicit Panels(ViewerSession& session) : session_(session) {}

    void draw() {
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowBgAlpha(0.8f);
        ImGui::Begin("dynrt", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
        figures();
        time_controls();
        settings();
        ImGui::End();
    }

private:
    void figures() {
        const auto& history = session_.history();
        if (history.empty()) return;
        const FrameStats& s = history.back();
        ImGui::Text("frame %d  %.1f ms  (%.0f fps)", session_.frame(), s.total_ms, s.total_ms > 0 ? 1000.0 / s.total_ms : 0.0);
        ImGui::Text("update %.2f  build %.2f  camera %.2f  shadow %.2f", s.update_ms, s.build_ms, s.primary_ms, s.shadow_ms);
        ImGui::Text("secondary %.2f  shade %.2f ms", s.secondary_ms, s.shade_ms);
        ImGui::Text("camera %.1f Mrays/s  shadow %.1f Mrays/s", s.primary_mrays_per_s, s.shadow_mrays_per_s);
        ImGui::Text("refit %zu  rebuilt %zu  skipped %zu  nodes %zu  tree %.1f MB", s.objects_refitted,
                    s.objects_rebuilt, s.objects_skipped, s.nodes, double(s.wide_tree_bytes) / 1e6);
        ImGui::Text("reuse %s: %zu traced, %zu kept", s.reuse_mode.c_str(), s.pixels_traced, s.pixels_reused);
        for (const TreeChoice& c : s.choices) {
            ImGui::TextWrapped("%s: %s (%s)", c.name.c_str(), c.chosen.c_str(), c.why.c_str());
        }
        // Rolling plots of the total and of each stage.
        plot("total ms", [](const FrameStats& f) { return f.total_ms; });
        plot("build ms", [](const FrameStats& f) { return f.build_ms; });
        plot("camera ms", [](const FrameStats& f) { return f.primary_ms; });
        plot("shadow ms", [](const FrameStats& f) { return f.shadow_ms; });
        plot("secondary ms", [](const FrameStats& f) { return f.secondary_ms; });
    }

    template <typename Figure>
    void plot(const char* label, Figure figure) {
        values_.clear();
        for (const FrameStats& f : session_.history()) values_.push_back(float(figure(f)));
        ImGui::PlotLines(label, values_.data(), int(values_.size()), 0, nullptr, 0.0f, FLT_MAX, ImVec2(260, 36));
    }

    void time_controls() {
        if (ImGui::Button(session_.playing() ? "pause" : "play")) session_.playing() ? session_.pause() : session_.play();
        ImGui::SameLine();
        if (ImGui::Button("<")) session_.step(-1);
        ImGui::SameLine();
        if (ImGui::Button(">")) session_.step(1);
        ImGui::SameLine();
        bool loop = session_.loop();
        if (ImGui::Checkbox("loop", &loop)) session_.set_loop(loop);
        int frame = session_.frame();
        if (session_.last_frame() > 0 && ImGui::SliderInt("frame", &frame, 0, session_.last_frame())) session_.seek(frame);
        float speed = float(session_.speed());
        if (ImGui::SliderFloat("speed", &speed, 0.05f, 4.0f, "%.2fx")) session_.set_speed(speed);
        if (ImGui::Button("reset camera")) session_.reset_camera();
        const std::vector<std::string> cameras = session_.camera_names();
        for (std::size_t k = 0; k < cameras.size(); ++k) {
            ImGui::SameLine();
            const std::string label = (cameras[k].empty() ? "camera " + std::to_string(k) : cameras[k]) + "##camera" + std::to_string(k);
            if (ImGui::Button(label.c_str())) session_.use_scene_camera(k);
        }
    }

    void settings() {
        if (!ImGui::CollapsingHeader("settings", ImGuiTreeNodeFlags_DefaultOpen)) return;
        choice("tracer", {"packet", "single"});
        choice("update", {"auto", "refit", "fast", "sah", "threshold"});
        choice("reuse", {"exact", "off"});
        choice("culling", {"all", "none", "ab", "ab,bp"});
        choice("depth", {"0", "1", "2", "5"});
        choice("spp", {"1", "4", "16"});
        choice("normals", {"smooth", "flat"});
        choice("backend", {"dynrt", "embree"});
        if (!error_.empty()) ImGui::TextWrapped("%s", error_.c_str());
    }

    /// A row of buttons, one per value of setting `name`, the current one marked.
    void choice(const char* name, std::initializer_list<const char*> values) {
        std::string current;
        for (const auto& [setting, value] : session_.settings()) {
            if (setting == name) current = value;
        }
        ImGui::Text("%-10s", name);
        for (const char* value : values) {
            ImGui::SameLine();
            const std::string label = (current == value ? std::string("[") + value + "]" : std::string(value)) + "##" + name;
            if (ImGui::SmallButton(label.c_str())) {
                try {
                    session_.set(name, value);
                    error_.clear();
                } catch (const std::exception& e) {
                    error_ = e.what();
                }
            }
        }
    }

    ViewerSession& session_;
    std::vector<float> values_;
    std::string error_;
};

/// The mouse and keys: left drag orbits, right or middle drag pans, the wheel zooms, W A S D
/// Q E fly, space plays or pauses, the arrows step, R resets the view, F12 writes a
/// screenshot, Escape closes.
class Input {
public:
    Input(GLFWwindow* window, ViewerSession& session) : window_(window), session_(session) {
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
        const bool free = !ImGui::GetIO().WantCaptureMouse;
        if (free && glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
            session_.camera().orbit(-0.3f * float(x - last_x_), -0.3f * float(y - last_y_));
        } else if (free && (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
                            glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)) {
            session_.camera().pan(-0.002f * float(x - last_x_), 0.002f * float(y - last_y_));
        }
        last_x_ = x;
        last_y_ = y;
        if (scroll_ != 0.0) session_.camera().zoom(float(std::pow(1.1, scroll_)));
        scroll_ = 0.0;
        if (ImGui::GetIO().WantCaptureKeyboard) return;
        const float step = float(seconds);
        const auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS ? 1.0f : 0.0f; };
        const float forward = held(GLFW_KEY_W) - held(GLFW_KEY_S), right = held(GLFW_KEY_D) - held(GLFW_KEY_A),
                    up = held(GLFW_KEY_E) - held(GLFW_KEY_Q);
        if (forward != 0.0f || right != 0.0f || up != 0.0f) session_.camera().fly(step * forward, step * right, step * up);
    }

private:
    void key(int key) {
        switch (key) {
            case GLFW_KEY_SPACE: session_.playing() ? session_.pause() : session_.play(); break;
            case GLFW_KEY_RIGHT: session_.step(1); break;
            case GLFW_KEY_LEFT: session_.step(-1); break;
            case GLFW_KEY_R: session_.reset_camera(); break;
            case GLFW_KEY_F12: {
                const std::string name = "dynrt-view-" + std::to_string(++screenshots_) + ".png";
                session_.screenshot(name);
                std::cout << "screenshot: " << name << " (and its report, " << name.substr(0, name.size() - 4) << ".json)\n";
                break;
            }
            case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window_, GLFW_TRUE); break;
            default: break;
        }
    }

    GLFWwindow* window_;
    ViewerSession& session_;
    double last_x_ = 0.0, last_y_ = 0.0, scroll_ = 0.0;
    int screenshots_ = 0;
};

/// GLFW, the window and Dear ImGui, torn down in reverse on every way out.
class WindowContext {
public:
    WindowContext(int width, int height, const std::string& title) {
        glfwSetErrorCallback([](int, const char* text) { std::cerr << "dynrt view: GLFW: " << text << "\n"; });
        if (!glfwInit()) throw std::runtime_error("no window system could be opened (GLFW failed to start)");
        glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
        window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
        if (window_ == nullptr) {
            glfwTerminate();
            throw std::runtime_error("no window could be made (no OpenGL on this display?)");
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(0);  // the render paces the loop; vsync would add up to a refresh to it
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
    GLFWwindow* window = context->window();
    std::unique_ptr<SequenceFile> record;
    try {
        if (!record_path.empty()) record = open_sequence_file(record_path, session.fps());
    } catch (const std::exception& e) {
        std::cerr << "dynrt: error: " << e.what() << "\n";
        return 1;
    }
    Input input(window, session);
    Panels panels(session);
    bool overlay = true;
    std::size_t next = 0;          // the script's next command
    int hold_frames = 0;           // wait-frames left
    const Clock::time_point start = Clock::now();
    Clock::time_point last = start;
    LoopTimes times;
    while (!glfwWindowShouldClose(window)) {
        glfwPollEvents();
        const Clock::time_point now = Clock::now();
        const double seconds = std::chrono::duration<double>(now - last).count();
        last = now;
        const double elapsed = std::chrono::duration<double>(now - start).count();
        std::string capture;
        // The script's due commands, one frame apart at most for the window's own.
        while (next < script.size() && hold_frames == 0 && script[next].at_seconds <= elapsed) {
            WindowStep step;
            times.input_at(Clock::now());
            try {
                step = run_command(session, script[next++], script_source);
            } catch (const std::exception& e) {
                std::cerr << "dynrt: error: " << e.what() << "\n";
                return 1;
            }
            if (step.action == WindowStep::Action::overlay) overlay = step.on;
            if (step.action == WindowStep::Action::wait_frames) hold_frames = step.frames;
            if (step.action == WindowStep::Action::quit) glfwSetWindowShouldClose(window, GLFW_TRUE);
            if (step.action == WindowStep::Action::capture) {
                capture = step.file;
                break;
            }
        }
        if (glfwWindowShouldClose(window)) break;
        input.poll(seconds);
        session.advance(seconds);
        int fb_width = 0, fb_height = 0;
        glfwGetFramebufferSize(window, &fb_width, &fb_height);
        if (fb_width == 0 || fb_height == 0) {  // minimised: nothing to draw
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        const Clock::time_point render_start = Clock::now();
        session.render();
        const Clock::time_point render_end = Clock::now();
        if (record) record->add(session.image());
        const std::vector<unsigned char> bytes = session.display_bytes();
        glViewport(0, 0, fb_width, fb_height);
        glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glWindowPos2i(0, fb_height);
        glPixelZoom(1.0f, -1.0f);  // the image's rows run down from the top
        glDrawPixels(width, height, GL_RGB, GL_UNSIGNED_BYTE, bytes.data());
        if (overlay) {
            ImGui_ImplOpenGL2_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            ImGui::NewFrame();
            panels.draw();
            ImGui::Render();
            ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());
        }
        if (!capture.empty()) {
            try {
                capture_window(fb_width, fb_height, capture);
            } catch (const std::exception& e) {
                std::cerr << "dynrt: error: " << e.what() << "\n";
                return 1;
            }
        }
        glfwSwapBuffers(window);
        glFinish();
        times.frame(now, render_start, render_end, Clock::now());
        if (hold_frames > 0) --hold_frames;
    }
    times.print(std::cout);
    if (record) record->close();
    return 0;
}

}  // namespace dynrt::viewer
