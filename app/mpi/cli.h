// raytracer-mpi's command line, run on rank 0 only: options, help, reading and
// checking the scene, the output path check and the progress line. It mirrors
// app/raytracer.cpp's options and messages (named raytracer-mpi) so the two tools
// take the same arguments; none of it touches MPI.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "scene.h"

namespace rtmpi {

constexpr int kExitOk = 0;
constexpr int kExitScene = 1;  // the scene file has errors
constexpr int kExitUsage = 2;  // bad arguments, unreadable input, unwritable output
constexpr int kExitMpi = 3;    // a rank or the MPI runtime failed; nothing written

struct Options {
    std::optional<int> width, height;
    std::optional<int> samples;
    int threads = 0;  // per rank; 0: all cores of that rank's machine
    int max_depth = 20;
    int tile = 32;
    double time_limit = 0;
    bool mirror = false, quiet = false, stats = false, print_scene = false;
    std::optional<std::string> check;
    std::vector<std::string> positional;
};

// "raytracer-mpi: MESSAGE" and the --help hint on stderr; returns kExitUsage.
int usage_error(const std::string& message);

// Returns -1 to continue, else the exit status (for --help, --version and errors).
int parse_args(int argc, char** argv, Options& o);

// Reads and parses; prints the diagnostics (once: only rank 0 calls this). On success
// returns -1 and fills both the text (which is what gets broadcast) and the scene.
int load_scene(const std::string& path, std::string& text, rt::Scene& scene);

// Lowercase extension including the dot, or "".
std::string extension(const std::string& path);
// "" or why OUT could not be written (checked before a long render).
std::string check_output_path(const std::string& out, const std::string& scene_path);

// Whether somebody watches stderr on a terminal (for the progress bar). Under mpirun
// a rank's stderr is a pipe to mpirun, so there it is mpirun's stderr that counts.
bool stderr_watched();

std::string count(std::size_t n, const char* noun);
std::string with_commas(std::uint64_t v);
double seconds_since(std::chrono::steady_clock::time_point t0);

// raytracer's progress bar with the cluster's figures after it.
class ProgressBar {
public:
    explicit ProgressBar(bool enabled) : enabled_(enabled) {}
    void update(double fraction, double elapsed, const std::string& detail);
    void clear();

private:
    bool enabled_;
    bool drawn_ = false;
    double shown_ = 0;
};

}  // namespace rtmpi
