// Command line of raytracer-view and raytracer-view-headless (one parser, so the two
// binaries accept exactly the same arguments and --headless can be passed through).
#pragma once

#include <optional>
#include <string>

#include "status.h"

namespace rtview {

// Picture: the scene's picture letterboxed at its aspect (what `raytracer` makes);
// Window: the view fills the image area (angle_x refitted).
enum class FitMode { Window, Picture };

struct Options {
    std::string scene;        // empty: the embedded default scene
    bool headless = false;
    std::string screenshot;   // headless: PNG/PPM of the whole UI
    std::string render;       // headless: the final render (the scene's picture_size) to this file
    int width = 1280, height = 800;
    bool size_given = false;
    int samples = 0;          // 0: the mode's default
    double time_limit = 0;    // seconds, 0 = none
    std::optional<double> aa_threshold;  // adaptive anti-aliasing; unset: kDefaultAaThreshold
                                         // (--render: uniform, as raytracer)
    double orbit = 0;         // degrees around the camera centre before rendering
    int threads = 0;          // 0: all hardware threads
    FitMode fit = FitMode::Picture;
    std::string tab;          // sidebar tab to open with: objects, text or render
    std::string select;       // "object N [left|right ...]", "plane N" or "light N" (1-based), for screenshots
    std::string handle;       // the selection's handle to start with: move (default), turn or size
    bool print_layout = false;
    std::string view_scene;   // write the scene exactly as the image region shows it
    bool verbose = false;
    bool help = false, version = false;
};

constexpr int kMinWindowSide = 64;  // --size, each side (at most rt::Limits::max_picture_side)
constexpr int kDefaultSamplesWindow = 64;
constexpr int kDefaultSamplesHeadless = 16;
// The viewer refines adaptively: a pixel settles once it differs from no neighbour by
// this much (the sum of the channel differences, 0..1 units) and its samples agree.
constexpr double kDefaultAaThreshold = 0.02;

// Fills `o`; a usage error (exit code 2) says what is wrong.
rt::Status parse_options(int argc, const char* const* argv, Options& o);
std::string help_text(bool headless_binary);

// Success if a window (or headless image) of width x height pixels fits in the memory
// the process may use (its address-space and data limits, the machine's RAM and swap);
// else "out of memory: ..." with the estimate. Checked before allocating anything.
rt::Status memory_problem(int width, int height, bool headless);

}  // namespace rtview
