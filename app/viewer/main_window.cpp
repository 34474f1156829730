// raytracer-view: the GLFW window around ViewerApp (ImGui GLFW + OpenGL2 backends,
// libGL). With --headless it execs raytracer-view-headless from its own directory,
// because OSMesa and libGL cannot share one process (see CMakeLists.txt).
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl2.h>
#include <limits.h>
#include <unistd.h>

#include <time.h>

#include <algorithm>
#include <atomic>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "app.h"
#include "fonts.h"
#include "frame_paint.h"
#include "glx_present.h"
#include "host_common.h"
#include "parallel.h"
#include "ui_settings.h"

namespace {

// Input of any kind bumps this; the loop draws a frame only when it moved or the app
// has something animating, so an idle viewer sleeps in glfwWaitEvents*.
std::atomic<unsigned> g_events{0};
// The window was exposed (uncovered, restored): its next frame is painted whole.
std::atomic<bool> g_exposed{false};

class GlfwHost : public rtview::Host {
public:
    explicit GlfwHost(GLFWwindow* w) : window_(w) {}
    void set_title(const std::string& title) override { glfwSetWindowTitle(window_, title.c_str()); }
    void quit() override { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
    void wake() override { glfwPostEmptyEvent(); }

private:
    GLFWwindow* window_;
};

// ImGui 1.86 samples input state once per frame and has no input queue, so fast
// input (a quick tap or double-click, xdotool, or any input while the machine is busy
// and frames are slow) goes wrong: a key pressed and released between two frames is
// never seen, nor a key or button released and pressed again (a double-click, a
// repeated Backspace); Ctrl released in the same batch as the S it modifies turns
// Ctrl+S into S; a character typed in the same frame as a Ctrl press is dropped; and
// a click is taken where the pointer is at the next frame, not where it was clicked.
// So input passes through a small queue: a release waits for the frame after its
// press, a press for the frame after a release or after pending characters, a
// character for the frame after a key press (which may move the focus), and the
// pointer's position and buttons are what the events taken so far say (not the live
// state). Events keep their order; the queue is drained after every frame.
struct InputEvent {
    enum class Kind { Key, Char, Button, Motion } kind;
    int key = 0, scancode = 0, action = 0, mods = 0;  // Key; Button: key is the button
    unsigned codepoint = 0;                           // Char
    double x = 0, y = 0;                              // Motion; Button: where
    double time = 0;                                  // Button: when (glfwGetTime)
};
std::vector<InputEvent> g_waiting;  // for the next frame
bool g_frame_has_press = false, g_frame_has_release = false, g_frame_has_chars = false;
// The pointer as the events taken so far leave it.
constexpr int kButtons = 5;
bool g_button_down[kButtons] = {};
bool g_have_pointer = false;
double g_pointer_x = 0, g_pointer_y = 0;
// A second press soon after the first is a double-click by the events' own times:
// ImGui measures between the frames that saw the presses, which a busy machine
// stretches past its limit.
double g_last_press_time = -1e9, g_last_press_x = 0, g_last_press_y = 0;
bool g_double_click = false;  // the press this frame takes is the second of a double-click

// A key that types a character (no Ctrl, Alt or Super): in a text field only its
// character matters, not whether a frame saw the key down.
bool typing_key(const InputEvent& e) {
    if (e.kind != InputEvent::Kind::Key || (e.mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT | GLFW_MOD_SUPER))) return false;
    return (e.key >= GLFW_KEY_SPACE && e.key <= GLFW_KEY_GRAVE_ACCENT) || e.key == GLFW_KEY_WORLD_1 ||
           e.key == GLFW_KEY_WORLD_2 || (e.key >= GLFW_KEY_KP_0 && e.key <= GLFW_KEY_KP_ADD);
}

bool must_wait(const InputEvent& e) {
    if (!g_waiting.empty()) return true;  // never overtake an earlier event
    // Typing into a text field: its characters and their keys all go into one frame
    // (ImGui queues characters), so text arrives as fast as it is typed however slow
    // the frames are; keys that move the focus (Enter, Tab, a Ctrl shortcut) still
    // wait for their frame, and the characters after them for the next.
    if (ImGui::GetIO().WantTextInput && (typing_key(e) || e.kind == InputEvent::Kind::Char))
        return e.kind == InputEvent::Kind::Char && g_frame_has_press;
    switch (e.kind) {
        // Characters after a key press (Enter, Tab, Ctrl+E) go to where that key put
        // the focus, which takes effect in the next frame.
        case InputEvent::Kind::Char: return g_frame_has_press;
        case InputEvent::Kind::Motion: return false;
        case InputEvent::Kind::Key:
            if (e.action == GLFW_PRESS) return g_frame_has_chars || g_frame_has_release;
            return e.action == GLFW_RELEASE && g_frame_has_press;
        case InputEvent::Kind::Button:
            return e.action == GLFW_PRESS ? g_frame_has_press || g_frame_has_release : g_frame_has_press;
    }
    return false;
}

void deliver(GLFWwindow* w, const InputEvent& e) {
    const bool typed = ImGui::GetIO().WantTextInput && typing_key(e);
    if (e.action == GLFW_PRESS && !typed) g_frame_has_press = true;
    if (e.action == GLFW_RELEASE && !typed) g_frame_has_release = true;
    switch (e.kind) {
        case InputEvent::Kind::Char:
            g_frame_has_chars = true;
            ImGui_ImplGlfw_CharCallback(w, e.codepoint);
            break;
        case InputEvent::Kind::Key: ImGui_ImplGlfw_KeyCallback(w, e.key, e.scancode, e.action, e.mods); break;
        case InputEvent::Kind::Button:
            if (e.key >= 0 && e.key < kButtons) g_button_down[e.key] = e.action == GLFW_PRESS;
            if (e.key == 0 && e.action == GLFW_PRESS) {
                const ImGuiIO& io = ImGui::GetIO();
                g_double_click = e.time - g_last_press_time <= double(io.MouseDoubleClickTime) &&
                                 std::hypot(e.x - g_last_press_x, e.y - g_last_press_y) <= double(io.MouseDoubleClickMaxDist);
                g_last_press_time = g_double_click ? -1e9 : e.time;
                g_last_press_x = e.x;
                g_last_press_y = e.y;
            }
            ImGui_ImplGlfw_MouseButtonCallback(w, e.key, e.action, e.mods);
            break;
        case InputEvent::Kind::Motion:
            g_have_pointer = true;
            g_pointer_x = e.x;
            g_pointer_y = e.y;
            break;
    }
}

void route(GLFWwindow* w, const InputEvent& e) {
    ++g_events;
    if (must_wait(e)) g_waiting.push_back(e);
    else deliver(w, e);
}

void key_callback(GLFWwindow* w, int key, int scancode, int action, int mods) {
    InputEvent e{InputEvent::Kind::Key};
    e.key = key, e.scancode = scancode, e.action = action, e.mods = mods;
    route(w, e);
}
void char_callback(GLFWwindow* w, unsigned c) {
    InputEvent e{InputEvent::Kind::Char};
    e.codepoint = c;
    route(w, e);
}
void button_callback(GLFWwindow* w, int button, int action, int mods) {
    InputEvent e{InputEvent::Kind::Button};
    e.key = button, e.action = action, e.mods = mods;
    e.time = glfwGetTime();
    glfwGetCursorPos(w, &e.x, &e.y);
    route(w, e);
}
void motion_callback(GLFWwindow* w, double x, double y) {
    InputEvent e{InputEvent::Kind::Motion};
    e.x = x, e.y = y;
    route(w, e);
}

// Between the backend's new frame and ImGui's: the pointer as the events say, and a
// double-click as their times say (ImGui then compares the frames' times against a
// limit made long enough, or too short, to agree).
void pointer_from_events() {
    ImGuiIO& io = ImGui::GetIO();
    if (g_have_pointer && io.MousePos.x > -FLT_MAX / 2) io.MousePos = ImVec2(float(g_pointer_x), float(g_pointer_y));
    for (int b = 0; b < kButtons; ++b) io.MouseDown[b] = g_button_down[b];
    static const float usual = io.MouseDoubleClickTime;
    io.MouseDoubleClickTime = g_double_click ? 1e6f : usual;
    if (g_double_click) {
        g_double_click = false;
    } else if (io.MouseDown[0] && io.MouseDownDuration[0] < 0) {
        io.MouseDoubleClickTime = 0;  // a first press, whatever ImGui's frame times say
    }
}

// After a frame: the waiting events get their turn (and may wait again).
void next_frame_input(GLFWwindow* w) {
    g_frame_has_press = g_frame_has_release = g_frame_has_chars = false;
    std::vector<InputEvent> events;
    events.swap(g_waiting);
    for (const InputEvent& e : events) route(w, e);
}

rtview::ViewerApp* app_of(GLFWwindow* w) { return static_cast<rtview::ViewerApp*>(glfwGetWindowUserPointer(w)); }

// Installed before ImGui's backend, which chains to them.
void install_callbacks(GLFWwindow* w) {
    glfwSetKeyCallback(w, [](GLFWwindow*, int, int, int, int) { ++g_events; });
    glfwSetCharCallback(w, [](GLFWwindow*, unsigned) { ++g_events; });
    glfwSetMouseButtonCallback(w, [](GLFWwindow*, int, int, int) { ++g_events; });
    glfwSetScrollCallback(w, [](GLFWwindow*, double, double) { ++g_events; });
    glfwSetCursorPosCallback(w, [](GLFWwindow*, double, double) { ++g_events; });
    glfwSetCursorEnterCallback(w, [](GLFWwindow*, int) { ++g_events; });
    glfwSetWindowFocusCallback(w, [](GLFWwindow*, int) { ++g_events; });
    glfwSetFramebufferSizeCallback(w, [](GLFWwindow*, int, int) { ++g_events; });
    glfwSetWindowRefreshCallback(w, [](GLFWwindow*) {
        g_exposed = true;
        ++g_events;
    });
    glfwSetDropCallback(w, [](GLFWwindow* win, int n, const char** paths) {
        ++g_events;
        if (auto* app = app_of(win)) app->drop_files(std::vector<std::string>(paths, paths + n));
    });
    glfwSetWindowCloseCallback(w, [](GLFWwindow* win) {
        ++g_events;
        auto* app = app_of(win);
        if (app && !app->close_requested()) glfwSetWindowShouldClose(win, GLFW_FALSE);
    });
}

int exec_headless(char** argv) {
    std::string dir;
    char self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = 0;
        dir = self;
        dir = dir.substr(0, dir.find_last_of('/') + 1);
    }
    std::string sibling = dir + "raytracer-view-headless";
    argv[0] = const_cast<char*>(sibling.c_str());
    execv(sibling.c_str(), argv);
    // Not next to us (an unusual install): try PATH.
    argv[0] = const_cast<char*>("raytracer-view-headless");
    execvp("raytracer-view-headless", argv);
    std::fprintf(stderr, "raytracer-view: cannot run %s for --headless: %s\n", sibling.c_str(), std::strerror(errno));
    return 2;
}

// The window with an OpenGL 2.1 context, current, with the input callbacks; null
// (said why) if there is no display.
GLFWwindow* open_window(const rtview::Options& opt) {
    glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "raytracer-view: GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) {
        std::fprintf(stderr, "raytracer-view: cannot open a window (is DISPLAY set?); "
                             "use --headless --screenshot OUT for offscreen output\n");
        return nullptr;
    }
    // OpenGL 2.1: the film is one textured quad and ImGui's OpenGL2 backend needs no loader.
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
    GLFWwindow* window = glfwCreateWindow(opt.width, opt.height, "raytracer-view", nullptr, nullptr);
    if (!window) {
        glfwTerminate();
        return nullptr;
    }
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    install_callbacks(window);
    return window;
}

// hi-DPI: content scale over framebuffer scale is how much larger the UI must be
// drawn (X11 reports 1:1 framebuffers and a content scale from Xft.dpi); the UI
// scale setting (Ctrl+ / Ctrl-, kept beside the recent files) multiplies it.
float content_scale(GLFWwindow* window) {
    float xs = 1, ys = 1;
    glfwGetWindowContentScale(window, &xs, &ys);
    int ww, wh, fw, fh;
    glfwGetWindowSize(window, &ww, &wh);
    glfwGetFramebufferSize(window, &fw, &fh);
    float fb = ww > 0 ? float(fw) / ww : 1.f;
    float scale = xs / (fb > 0 ? fb : 1.f);
    return scale > 0.5f ? scale : 1;
}

double wall_clock() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

double thread_cpu() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

// --verbose: where a frame's wall time goes, said every few seconds: the UI (ImGui and
// the app, the film's texture upload included), the GL drawing to the end of the
// rasteriser's work (glFinish), and the swap (or the boxes shown); the share of the
// window's pixels painted, and the UI thread's processor time.
struct FrameTimes {
    double start = -1, ui = 0, draw = 0, swap = 0, upload = 0, max_frame = 0, painted = 0, cpu0 = -1;
    long frames = 0, unpainted = 0;
    void add(double t0, double t1, double t2, double t3, double upload_s, double painted_share) {
        if (start < 0) start = t0, cpu0 = thread_cpu();
        ui += t1 - t0, draw += t2 - t1, swap += t3 - t2, upload += upload_s, painted += painted_share;
        unpainted += painted_share == 0;
        max_frame = std::max(max_frame, t3 - t0);
        ++frames;
        if (t3 - start < 3) return;
        const double n = double(frames), ms = 1000 / n;
        std::fprintf(stderr,
                     "raytracer-view: %.1f frames/s; a frame's ms: UI %.1f (texture upload %.1f), drawing %.1f, swap %.1f; "
                     "longest %.0f ms; painted %.0f%% of the window a frame (%ld frames nothing); UI thread %.1f ms of CPU a frame\n",
                     n / (t3 - start), ui * ms, upload * ms, draw * ms, swap * ms, max_frame * 1000, painted / n * 100,
                     unpainted, (thread_cpu() - cpu0) * ms);
        *this = FrameTimes{};
    }
};

// The share of a width x height window the boxes cover.
double share(const std::vector<rtview::PixelBox>& boxes, int width, int height) {
    double a = 0;
    for (const rtview::PixelBox& b : boxes) a += double(b.area());
    return width > 0 && height > 0 ? a / (double(width) * height) : 0;
}

// Frames until the window closes: only when input came or the app has something
// animating, so an idle viewer sleeps in glfwWaitEvents*.
void event_loop(GLFWwindow* window, rtview::ViewerApp& app, const rtview::Options& opt, float scale) {
    const rtview::WindowPresenter presenter(window);
    rtview::FramePainter painter(presenter.partial(), presenter.check());
    if (opt.verbose)
        std::fprintf(stderr, "raytracer-view: renderer %s: %s\n", presenter.renderer(),
                     presenter.partial() ? "frames paint and show only what changed" : "frames painted whole");
    unsigned seen = g_events.load() - 1;  // draw the first frame at once
    int settle = 0;
    bool was_working = false;
    long frames = 0;
    double frame_cpu = 0;  // UI thread CPU seconds spent drawing frames (--verbose)
    FrameTimes times;
    while (!glfwWindowShouldClose(window)) {
        // While settling after input, ImGui needs its next frames promptly (a
        // click is seen released, a focus request lands one frame later).
        double timeout = settle > 0 ? 1.0 / 60 : app.wait_timeout();
        if (timeout <= 0) glfwPollEvents();
        else glfwWaitEventsTimeout(timeout);
        unsigned ev = g_events.load();
        if (ev != seen) {
            seen = ev;
            settle = 3;  // ImGui settles hover and popup state over a few frames
        }
        // What ended the app's work (a render done, a file written, a check
        // finished) happened during the last frame it worked in, after parts of that
        // frame were drawn: the frames after it show the state it ended in, with no
        // input event needed.
        const bool working = app.working();
        if (was_working && !working) settle = std::max(settle, 3);
        was_working = working;
        bool draw = settle > 0 || app.needs_frame();
        if (!draw) {
            if (!app.idle_tick()) continue;  // idle: no frame, no CPU
            settle = 3;                      // a reload or a message: let ImGui settle it
        }
        if (settle > 0) --settle;

        double cpu0 = thread_cpu();
        const double t0 = opt.verbose ? wall_clock() : 0;
        ImGui_ImplOpenGL2_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        pointer_from_events();
        int fw, fh;
        glfwGetFramebufferSize(window, &fw, &fh);
        double t1 = 0;
        rtview::app_frame(app, fw, fh, false, opt.verbose ? &t1 : nullptr);
        if (g_exposed.exchange(false)) painter.invalidate();
        const std::vector<rtview::PixelBox>& painted = painter.paint(ImGui::GetDrawData(), fw, fh);
        if (opt.verbose) glFinish();
        const double t2 = opt.verbose ? wall_clock() : 0;
        app.after_render(fw, fh);
        presenter.present(painted, fh);
        if (opt.verbose) times.add(t0, t1, t2, wall_clock(), app.last_upload_seconds(), share(painted, fw, fh));
        next_frame_input(window);
        if (app.take_ui_scale_change()) {
            // Between frames: a new font atlas at the new size, and its texture.
            ImGui_ImplOpenGL2_DestroyFontsTexture();
            rtview::build_ui_font_and_style(float(app.ui_scale()) * scale);
            ImGui_ImplOpenGL2_CreateFontsTexture();
            painter.invalidate();
            settle = 3;
        }
        frame_cpu += thread_cpu() - cpu0;
        ++frames;
    }
    if (opt.verbose)
        std::fprintf(stderr, "raytracer-view: %ld frames, %.2f ms of UI-thread CPU each\n", frames,
                     frames ? frame_cpu / double(frames) * 1000 : 0.0);
    if (presenter.check())
        std::fprintf(stderr, "raytracer-view: %ld partial frames checked, %ld differed from whole ones\n", painter.checked(),
                     painter.differed());
}

int run(int argc, char** argv) {
    rtview::Options opt;
    if (auto status = rtview::settle_command_line("raytracer-view", false, argc, argv, opt)) return *status;
    if (opt.headless) return exec_headless(argv);
    if (!rtview::fits_in_memory("raytracer-view", opt, false)) return 2;
    // The start-up file loads while the window opens and the fonts are made (a file
    // that cannot be read is left to the app, which says why).
    // The render and loading threads make way for the UI thread and the GL
    // rasteriser's: frames (typing, menus, the picture's progress) keep their rate
    // while every processor renders.
    rt::set_process_worker_nice(10);
    rtview::EarlyLoad early;
    if (!opt.scene.empty() && ::access(opt.scene.c_str(), R_OK) == 0) {
        rt::set_process_threads(opt.threads);
        early.loader.start(opt.scene, true, early.models.get());
    }
    GLFWwindow* window = open_window(opt);
    if (!window) return 1;

    const float scale = content_scale(window);
    rtview::UiFont font = rtview::begin_imgui(float(rtview::UiSettings().ui_scale()) * scale);
    ImGui::GetIO().ConfigInputTextCursorBlink = false;  // a blinking cursor would need frames while idle
    if (opt.verbose)
        std::fprintf(stderr, "raytracer-view: UI font %s, fixed-width font %s, %.0f px\n",
                     font.path.empty() ? "(ImGui's own)" : font.path.c_str(),
                     font.mono_path.empty() ? "(ImGui's own)" : font.mono_path.c_str(), font.pixels);
    ImGui_ImplGlfw_InitForOpenGL(window, true);
    // In front of ImGui's own key, character and button callbacks, which deliver() calls.
    glfwSetKeyCallback(window, key_callback);
    glfwSetCharCallback(window, char_callback);
    glfwSetMouseButtonCallback(window, button_callback);
    glfwSetCursorPosCallback(window, motion_callback);

    int status = 0;
    {
        GlfwHost host(window);
        rtview::ViewerApp app(opt, host, true);
        status = rtview::open_initial_scene("raytracer-view", app, &early);
        if (status == 0) {
            // The scene loads in the background; its diagnostics are printed when it arrives.
            glfwSetWindowUserPointer(window, &app);
            event_loop(window, app, opt, scale);
            glfwSetWindowUserPointer(window, nullptr);
        }
    }  // the app (and its GL texture) goes while the context is still current

    ImGui_ImplGlfw_Shutdown();
    rtview::end_imgui();
    glfwDestroyWindow(window);
    glfwTerminate();
    return status;
}

}  // namespace

int main(int argc, char** argv) { return rtview::guarded_main("raytracer-view", run, argc, argv); }
