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
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "app.h"
#include "fonts.h"
#include "host_common.h"
#include "ui_settings.h"

namespace {

// Input of any kind bumps this; the loop draws a frame only when it moved or the app
// has something animating, so an idle viewer sleeps in glfwWaitEvents*.
std::atomic<unsigned> g_events{0};

class GlfwHost : public rtview::Host {
public:
    explicit GlfwHost(GLFWwindow* w) : window_(w) {}
    void set_title(const std::string& title) override { glfwSetWindowTitle(window_, title.c_str()); }
    void quit() override { glfwSetWindowShouldClose(window_, GLFW_TRUE); }

private:
    GLFWwindow* window_;
};

// ImGui 1.86 samples key state once per frame and has no input queue, so fast input
// (a quick tap, or xdotool) goes wrong in three ways: a key pressed and released
// between two frames is never seen; Ctrl released in the same batch as the S it
// modifies turns Ctrl+S into S; a character typed in the same frame as a Ctrl press
// is dropped (text fields ignore characters while Ctrl is down); and a key pressed
// again in the frame its release reaches looks held, not pressed anew (the second of
// two quick Backspaces is lost). So key and character events pass through a small
// queue: a release waits for the frame after its press, a key press waits for the
// frame after pending characters or after that key's release. Events keep their
// order; the queue is drained after every frame.
struct InputEvent {
    bool is_char;
    int key, scancode, action, mods;
    unsigned codepoint;
};
std::vector<InputEvent> g_waiting;  // for the next frame
bool g_frame_has_press = false, g_frame_has_chars = false;
std::vector<int> g_frame_released;  // keys released for this frame

void route(GLFWwindow* w, const InputEvent& e) {
    ++g_events;
    bool wait = !g_waiting.empty();  // never overtake an earlier event
    if (!wait && !e.is_char) {
        if (e.action == GLFW_PRESS)
            wait = g_frame_has_chars ||
                   std::find(g_frame_released.begin(), g_frame_released.end(), e.key) != g_frame_released.end();
        else if (e.action == GLFW_RELEASE) wait = g_frame_has_press;
    }
    if (wait) {
        g_waiting.push_back(e);
        return;
    }
    if (e.is_char) {
        g_frame_has_chars = true;
        ImGui_ImplGlfw_CharCallback(w, e.codepoint);
    } else {
        if (e.action == GLFW_PRESS) g_frame_has_press = true;
        if (e.action == GLFW_RELEASE) g_frame_released.push_back(e.key);
        ImGui_ImplGlfw_KeyCallback(w, e.key, e.scancode, e.action, e.mods);
    }
}

void key_callback(GLFWwindow* w, int key, int scancode, int action, int mods) {
    route(w, {false, key, scancode, action, mods, 0});
}
void char_callback(GLFWwindow* w, unsigned c) { route(w, {true, 0, 0, 0, 0, c}); }

// After a frame: the waiting events get their turn (and may wait again).
void next_frame_input(GLFWwindow* w) {
    g_frame_has_press = g_frame_has_chars = false;
    g_frame_released.clear();
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
    glfwSetWindowRefreshCallback(w, [](GLFWwindow*) { ++g_events; });
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

double thread_cpu() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

// Frames until the window closes: only when input came or the app has something
// animating, so an idle viewer sleeps in glfwWaitEvents*.
void event_loop(GLFWwindow* window, rtview::ViewerApp& app, const rtview::Options& opt, float scale) {
    unsigned seen = g_events.load() - 1;  // draw the first frame at once
    int settle = 0;
    bool was_working = false;
    long frames = 0;
    double frame_cpu = 0;  // UI thread CPU seconds spent drawing frames (--verbose)
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
        ImGui_ImplOpenGL2_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        int fw, fh;
        glfwGetFramebufferSize(window, &fw, &fh);
        rtview::app_frame(app, fw, fh);
        app.after_render(fw, fh);
        glfwSwapBuffers(window);
        next_frame_input(window);
        if (app.take_ui_scale_change()) {
            // Between frames: a new font atlas at the new size, and its texture.
            ImGui_ImplOpenGL2_DestroyFontsTexture();
            rtview::build_ui_font_and_style(float(app.ui_scale()) * scale);
            ImGui_ImplOpenGL2_CreateFontsTexture();
            settle = 3;
        }
        frame_cpu += thread_cpu() - cpu0;
        ++frames;
    }
    if (opt.verbose)
        std::fprintf(stderr, "raytracer-view: %ld frames, %.2f ms of UI-thread CPU each\n", frames,
                     frames ? frame_cpu / double(frames) * 1000 : 0.0);
}

int run(int argc, char** argv) {
    rtview::Options opt;
    if (auto status = rtview::settle_command_line("raytracer-view", false, argc, argv, opt)) return *status;
    if (opt.headless) return exec_headless(argv);
    if (!rtview::fits_in_memory("raytracer-view", opt, false)) return 2;
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
    // In front of ImGui's own key and character callbacks, which route() calls.
    glfwSetKeyCallback(window, key_callback);
    glfwSetCharCallback(window, char_callback);

    int status = 0;
    {
        GlfwHost host(window);
        rtview::ViewerApp app(opt, host, true);
        status = rtview::open_initial_scene("raytracer-view", app);
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
