// raytracer-view-headless: the same ViewerApp drawn into an OSMesa buffer in main
// memory (no X, no GPU, no GLFW), with ImGui's OpenGL2 backend; waits for the samples
// and writes a screenshot of the whole window. With --render it draws no UI at all and
// makes the final render of the scene instead (the same file as `raytracer`).
#include <GL/osmesa.h>
#include <imgui.h>
#include <imgui_impl_opengl2.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include "app.h"
#include "cli_common.h"
#include "default_scene.h"
#include "diagnostic_text.h"
#include "final_render.h"
#include "fonts.h"
#include "host_common.h"
#include "image_io.h"
#include "scene_parser.h"

namespace {

constexpr int kMaxShownDiagnostics = 20;  // as raytracer

// Signals as raytracer's (app/cli): a signal ends the program at once, unless a
// temporary output file exists; then the write stops, removes it and fails, and main
// exits with 128+N.
const rtcli::Program kProgram{"raytracer-view-headless", "", "", "", ""};  // messages only: no help

class NullHost : public rtview::Host {
public:
    void set_title(const std::string&) override {}
    void quit() override {}
};

// --render OUT: the scene at its own picture_size, as `raytracer --samples N SCENE
// OUT` renders it; the same messages and exit statuses (1: the scene has errors, 2:
// usage or I/O, 128+N: signal N, OUT untouched).
int render_to_file(const rtview::Options& opt) {
    const rtcli::Program& program = kProgram;
    const std::string scene_path = opt.scene;
    if (rt::Status st = rtcli::check_output(program, opt.render, scene_path); !st) return rtcli::report(st);
    rtcli::install_signal_handlers(program);
    rt::Scene scene;
    if (scene_path.empty()) {
        rt::ParseResult parsed = rt::parse_scene(rt::kDefaultScene);
        if (const rt::Status st = parsed.status(rt::kDefaultSceneName); !st) return rtcli::report(st);
        scene = std::move(parsed.scene);
    } else {
        std::string text;
        if (rt::Status st = rtcli::load_scene(program, scene_path, text, scene); !st) return rtcli::report(st);
    }
    auto interrupted = [] {
        std::fprintf(stderr, "raytracer-view-headless: interrupted; nothing written\n");
        return 128 + rtcli::caught_signal();
    };
    if (rtcli::caught_signal()) return interrupted();

    rtview::FinalRender render(opt.threads);
    const rt::RenderRequest request =
        rtview::final_render_request(opt.samples, opt.time_limit, opt.aa_threshold.value_or(-1));
    if (const rt::Status st = render.start(scene, opt.render, request); !st) {
        std::fprintf(stderr, "raytracer-view-headless: cannot render: %s\n", st.message().c_str());
        return rtcli::kExitUsage;
    }
    rtcli::ProgressBar bar(isatty(STDERR_FILENO));
    while (!render.wait_for(0.1)) {
        if (rtcli::caught_signal()) {
            render.cancel();
            bar.clear();
            return interrupted();
        }
        bar.update(render.fraction(), render.progress().elapsed);
    }
    bar.clear();
    if (rtcli::caught_signal()) return interrupted();
    rt::RenderProgress p = render.progress();
    if (const rt::Status st = render.write(); !st) {
        std::fprintf(stderr, "raytracer-view-headless: cannot write '%s': %s\n", opt.render.c_str(), st.message().c_str());
        return rtcli::kExitUsage;
    }
    if (opt.verbose)
        std::fprintf(stderr, "raytracer-view-headless: wrote %s (%dx%d, %d samples per pixel, %.2f s)\n",
                     opt.render.c_str(), p.width, p.height, p.samples, p.elapsed);
    return rtcli::kExitOk;
}

// Before rendering, as raytracer does: a render must not end in "cannot write".
// Returns 0 if the outputs can be written, else says why and returns 2.
int check_outputs(const rtview::Options& opt) {
    if (const rt::ImageFormat f = rt::format_from_path(opt.screenshot); f == rt::ImageFormat::Unknown || rt::is_float_format(f)) {
        std::fprintf(stderr, "raytracer-view-headless: cannot write %s: the name must end in .png or .ppm\n",
                     opt.screenshot.c_str());
        return 2;
    }
    for (const std::string* out : {&opt.screenshot, &opt.view_scene}) {
        if (out->empty()) continue;
        if (const rt::Status st = rt::check_writable(*out); !st) {
            std::fprintf(stderr, "raytracer-view-headless: cannot write %s: %s\n", out->c_str(), st.message().c_str());
            return 2;
        }
    }
    return 0;
}

// The scene loaded: its diagnostics on stderr, the render followed to the end, the
// screenshot (and --view-scene) written. Returns the exit status.
int take_screenshot(rtview::ViewerApp& app, const rtview::Options& opt, int W, int H) {
    const std::string name = opt.scene.empty() ? "default.txt" : opt.scene;
    std::fputs(rt::diagnostics_report(name, app.document().diagnostics(), kMaxShownDiagnostics).c_str(), stderr);
    if (!app.document().has_scene()) return 1;
    if (opt.orbit != 0) app.orbit_degrees(opt.orbit);
    // paint = false: the UI's logic runs (it starts and follows the render), but
    // nothing is rasterised: OSMesa draws on the CPU the workers are using.
    auto frame = [&](bool paint) {
        ImGui::GetIO().DeltaTime = 1.f / 60;
        ImGui_ImplOpenGL2_NewFrame();
        rtview::app_frame(app, W, H, paint);
    };
    auto t0 = std::chrono::steady_clock::now();
    // A few frames first: ImGui sizes auto-fitting items on its first frames.
    for (int n = 0;; ++n) {
        frame(n < 3);
        if (n >= 3 && app.render_settled()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(n < 3 ? 0 : 15));
    }
    frame(true);  // the final film, with the status bar saying "done"
    int status = 0;
    if (const rt::Status st = rtview::save_framebuffer(opt.screenshot, W, H); !st) {
        std::fprintf(stderr, "raytracer-view-headless: cannot write %s: %s\n", opt.screenshot.c_str(), st.message().c_str());
        status = 2;
    }
    if (!opt.view_scene.empty()) {
        if (const rt::Status st = app.write_view_scene(opt.view_scene); !st) {
            std::fprintf(stderr, "raytracer-view-headless: cannot write %s: %s\n", opt.view_scene.c_str(),
                         st.message().c_str());
            status = 2;
        }
    }
    if (opt.verbose) {
        rt::RenderProgress p = app.progress();
        double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::fprintf(stderr,
                     "raytracer-view-headless: %dx%d film, %d samples, first coarse pass %.1f ms, render %.2f s, "
                     "total %.2f s\n",
                     p.width, p.height, p.samples, p.first_coarse_time * 1000, p.elapsed, total);
    }
    return status;
}

// --screenshot: the whole UI drawn into an OSMesa buffer of the --size. Returns the
// exit status.
int screenshot_run(const rtview::Options& opt) {
    // Mesa would otherwise keep a shader cache under $HOME.
    setenv("MESA_SHADER_CACHE_DISABLE", "true", 0);
    const int W = opt.width, H = opt.height;
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
    if (!ctx) {
        std::fprintf(stderr, "raytracer-view-headless: cannot create an OSMesa context\n");
        return 1;
    }
    std::vector<unsigned char> buffer(std::size_t(W) * H * 4);
    if (!OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, W, H)) {
        std::fprintf(stderr, "raytracer-view-headless: cannot bind the OSMesa buffer\n");
        OSMesaDestroyContext(ctx);
        return 1;
    }
    // The UI at scale 1 whatever the user's setting: screenshots are reproducible.
    rtview::begin_imgui(1);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(W), float(H));
    io.DisplayFramebufferScale = ImVec2(1, 1);
    io.MousePos = ImVec2(-FLT_MAX, -FLT_MAX);  // no mouse: nothing is hovered
    int status = 0;
    {
        NullHost host;
        rtview::ViewerApp app(opt, host, false);
        status = rtview::open_initial_scene("raytracer-view-headless", app);
        if (status == 0) status = take_screenshot(app, opt, W, H);
    }
    rtview::end_imgui();
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);  // release the buffer before the context
    OSMesaDestroyContext(ctx);
    return status;
}

int run(int argc, char** argv) {
    rtview::Options opt;
    if (auto status = rtview::settle_command_line("raytracer-view-headless", true, argc, argv, opt)) return *status;
    if (!opt.render.empty()) {
        if (!opt.screenshot.empty()) {
            std::fprintf(stderr, "raytracer-view-headless: --render and --screenshot are separate runs; give one\n");
            return 2;
        }
        return render_to_file(opt);
    }
    if (opt.screenshot.empty()) {
        std::fprintf(stderr, "raytracer-view-headless: --screenshot OUT or --render OUT is required\n");
        return 2;
    }
    if (!rtview::fits_in_memory("raytracer-view-headless", opt, true)) return 2;
    rtcli::install_signal_handlers(kProgram);
    if (int r = check_outputs(opt); r != 0) return r;
    const int status = screenshot_run(opt);
    if (rtcli::caught_signal()) {  // came while a file was written: that write stopped and cleaned up
        std::fprintf(stderr, "raytracer-view-headless: interrupted; nothing more written\n");
        return 128 + rtcli::caught_signal();
    }
    return status;
}

}  // namespace

// Allocation failure anywhere on this thread ends the program with a message, not an
// abort (the picture size itself is checked up front by memory_problem).
int main(int argc, char** argv) { return rtview::guarded_main("raytracer-view-headless", run, argc, argv); }
