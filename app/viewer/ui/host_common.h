// What the two viewer binaries (the GLFW window, main_window.cpp, and the OSMesa
// buffer, main_headless.cpp) share around ViewerApp: the command line up to --help and
// --version, the memory check, the ImGui context with the viewer's font and style,
// the initial scene, one frame, and the exception edge of main().
#pragma once

#include <optional>
#include <string>

#include "app.h"
#include "fonts.h"
#include "options.h"

namespace rtview {

// The parsed command line; on --help, --version or a usage error (printed as
// "PROGRAM: message" and the --help hint) the exit status instead. `headless_binary`
// picks the help text.
std::optional<int> settle_command_line(const char* program, bool headless_binary, int argc, char** argv,
                                       Options& opt);

// Whether a width x height window (or headless image) fits in memory; if not, says so
// and returns false.
bool fits_in_memory(const char* program, const Options& opt, bool headless);

// A new ImGui context: no ini file, the UI font and style at `scale`, ImGui's OpenGL2
// backend. end_imgui() undoes it.
UiFont begin_imgui(float scale);
void end_imgui();

// The initial scene (the command line's or the default; `early`: its load begun already,
// app.h): 0 once it is loading, else
// the message on stderr and 2.
int open_initial_scene(const char* program, ViewerApp& app, EarlyLoad* early = nullptr);

// One ImGui frame of the app: laid out, then (if `paint`) drawn into the current GL
// framebuffer of width x height pixels. The caller starts its backends' frames first.
// `built`: if given, receives the monotonic clock (seconds) when the UI is built, before
// it is drawn.
void app_frame(ViewerApp& app, int width, int height, bool paint = true, double* built = nullptr);

// main(): runs `run`; an exception that reaches here (out of memory, typically) ends
// the program with "PROGRAM: what" and status 2, not an abort.
int guarded_main(const char* program, int (*run)(int, char**), int argc, char** argv);

}  // namespace rtview
