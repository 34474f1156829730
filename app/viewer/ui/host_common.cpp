// The set-up both viewer binaries share (host_common.h).
#include "host_common.h"

#include <imgui.h>
#include <imgui_impl_opengl2.h>

#include <cstdio>
#include <ctime>
#include <exception>
#include <new>

#include "frame_paint.h"

namespace rtview {

std::optional<int> settle_command_line(const char* program, bool headless_binary, int argc, char** argv,
                                       Options& opt) {
    if (const rt::Status st = parse_options(argc, argv, opt); !st) {
        std::fprintf(stderr, "%s: %s\nTry '%s --help' for more information.\n", program, st.message().c_str(), program);
        return st.exit_code();
    }
    if (opt.help) {
        std::fputs(help_text(headless_binary).c_str(), stdout);
        return 0;
    }
    if (opt.version) {
        std::printf("%s 1.0.0\n", program);
        return 0;
    }
    return std::nullopt;
}

bool fits_in_memory(const char* program, const Options& opt, bool headless) {
    const rt::Status st = memory_problem(opt.width, opt.height, headless);
    if (st) return true;
    std::fprintf(stderr, "%s: %s\n", program, st.message().c_str());
    return false;
}

UiFont begin_imgui(float scale) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is fixed; nothing worth remembering in a file
    UiFont font = build_ui_font_and_style(scale);
    ImGui_ImplOpenGL2_Init();
    return font;
}

void end_imgui() {
    ImGui_ImplOpenGL2_Shutdown();
    ImGui::DestroyContext();
}

int open_initial_scene(const char* program, ViewerApp& app, EarlyLoad* early) {
    const rt::Status st = app.open_initial(early);
    if (st) return 0;
    std::fprintf(stderr, "%s: %s\n", program, st.message().c_str());
    return st.exit_code();
}

void app_frame(ViewerApp& app, int width, int height, bool paint, double* built) {
    ImGui::NewFrame();
    app.frame();
    ImGui::Render();
    if (built) {
        timespec t{};
        clock_gettime(CLOCK_MONOTONIC, &t);
        *built = double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
    }
    if (paint) paint_whole(ImGui::GetDrawData(), width, height);
}

int guarded_main(const char* program, int (*run)(int, char**), int argc, char** argv) {
    try {
        return run(argc, argv);
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "%s: out of memory\n", program);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: %s\n", program, e.what());
    }
    return 2;
}

}  // namespace rtview
