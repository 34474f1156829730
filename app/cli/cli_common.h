// What the two command-line renderers (raytracer, raytracer-mpi) share: the option
// parser and help text, scene loading with its diagnostics, --print-scene, building
// the world, the output checks, the progress bar and the signal flag. Each program
// supplies its name, the parts of its help text of its own, and extra options.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render_request.h"
#include "renderer.h"
#include "scene.h"
#include "status.h"
#include "world.h"

namespace rtcli {

// 0; 1: the scene file has errors; 2: bad arguments, unreadable input, unwritable output.
using rt::kExitOk;
using rt::kExitScene;
using rt::kExitUsage;

// The help text is assembled by help_text(): the program's own head and exit-status
// paragraph around the option lines made from the option table both programs share
// (with the program's --threads description, and --tile where it has tiles).
struct Program {
    const char* name;          // in messages: "NAME: ..."
    const char* help_head;     // usage and description, up to and including "Options:\n"
    const char* threads_what;     // --threads' help: what the threads are (per process or per rank)
    const char* threads_default;  // and how many there are by default
    const char* help_tail;     // after the option list: the exit statuses
    bool tile_option = false;  // accepts --tile N (8..256)
};

// What --help prints.
std::string help_text(const Program& program);

struct Options {
    std::optional<int> width, height;
    // --samples, --time-limit, --aa-threshold, --threads, --max-depth, --tile, --mirror
    rt::RenderRequest render;
    bool quiet = false, stats = false, print_scene = false;
    bool flatten = false;  // --print-scene --flatten
    bool help = false, version = false, help_format = false;  // printed by print_help_or_version
    std::optional<std::string> check;
    std::vector<std::string> positional;
};

// The failures of these functions carry the complete text for stderr (whole lines)
// and the exit status; the programs' run() returns them to main, which report()s.

// "NAME: MESSAGE\n" with `exit_code`.
rt::Status failure(const Program& program, const std::string& message, int exit_code);
// "NAME: MESSAGE" and the --help hint; kExitUsage.
rt::Status usage_error(const Program& program, const std::string& message);
// Prints the failure's text on stderr (nothing for success); returns the exit status.
int report(const rt::Status& st);

// Fills `o`, or says what is wrong with the command line.
rt::Status parse_args(const Program& program, int argc, char** argv, Options& o);
// Prints the help or the version if `o` asks for one, and then returns true.
bool print_help_or_version(const Program& program, const Options& o);

// Reads and parses; prints the warnings. Fills the text and the scene; a scene with
// errors fails with the diagnostics (kExitScene), an unreadable file with kExitUsage.
rt::Status load_scene(const Program& program, const std::string& path, std::string& text, rt::Scene& scene);
// The same for a caller that needs only the scene: the text is read without a zero
// fill first and let go before returning.
rt::Status load_scene(const Program& program, const std::string& path, rt::Scene& scene);

// --check: parses o.check and reports errors and warnings, or a one-line summary
// (unless --quiet).
rt::Status check_scene(const Program& program, const Options& o);

// Before a long render: success if OUT can be written as a picture (a .ppm, .png, .pfm or .exr
// name that rt::check_writable accepts, not the scene file itself); else why, with
// the system's error (kExitUsage).
rt::Status check_output(const Program& program, const std::string& out, const std::string& scene_path);

// The scene compiled for rendering, with --max-depth in place of the scene's own
// recursion limit.
std::shared_ptr<const rt::World> build_world(const rt::Scene& scene, int max_depth);

// What `raytracer` renders with: rt::final_settings of o.render for the picture size
// given (the scene's, after --width and --height). The viewer's final render makes
// the same (tests/viewer/test_final_render.cpp).
rt::RenderSettings render_settings(const Options& o, int width, int height);

// --print-scene: writes the scene in normalised form, every default written out,
// including the material an object or plane gets without a material block. Both
// programs print through here, so their outputs agree.
rt::Status print_scene(const Program& program, rt::Scene scene, bool flatten = false);

// Writes `text` to stdout and flushes it; a failure says why (a full disk, a closed
// stdout), kExitUsage.
rt::Status print_to_stdout(const Program& program, const std::string& text);

std::string count(std::size_t n, const char* noun);
std::string with_commas(std::uint64_t v);
double seconds_since(std::chrono::steady_clock::time_point t0);

// SIGINT, SIGTERM and SIGHUP end the process at once with 128+N and "interrupted ...; nothing
// written", in any phase (a blocking open, parsing, building, rendering), unless a
// temporary output file exists: then they stop the write (rt::interrupt_writes),
// which removes it and fails with "interrupted", and caught_signal() says which
// signal came (0 if none) so that the main thread can exit with 128+N.
void install_signal_handlers(const Program& program);
int caught_signal();

// A one-line progress bar on stderr: "[####   ]  42%  1.3 s, ETA 1.8 s", with
// `detail` (if any) before the time.
class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled) {}
    void update(double fraction, double elapsed, const std::string& detail = "");
    void clear();

private:
    bool enabled_;
    bool drawn_ = false;
    double shown_ = 0;
};

}  // namespace rtcli
