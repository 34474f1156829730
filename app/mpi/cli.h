// raytracer-mpi's command line, run on rank 0 only: raytracer's options (the shared
// app/cli module, named raytracer-mpi) plus --tile, and whether anyone watches the
// progress line. None of it touches MPI.
#pragma once

#include <string>

#include "cli_common.h"
#include "scene.h"

namespace rtmpi {

using rtcli::kExitOk;
using rtcli::kExitScene;
using rtcli::kExitUsage;
constexpr int kExitMpi = 3;  // a rank or the MPI runtime failed; nothing written

using rtcli::caught_signal;
using rtcli::count;
using rtcli::Options;
using rtcli::ProgressBar;
using rtcli::seconds_since;
using rtcli::with_commas;

// The functions of rtcli with this program's name; failures carry the text for
// stderr (see cli_common.h), which rtcli::report prints.
using rtcli::report;

// "raytracer-mpi: MESSAGE" and the --help hint.
rt::Status usage_error(const std::string& message);

// Fills `o`, or says what is wrong with the command line.
rt::Status parse_args(int argc, char** argv, Options& o);
// --help or --version, if asked for: printed, and true.
bool print_help_or_version(const Options& o);

// --check (see rtcli::check_scene).
rt::Status check_scene(const Options& o);
// Whether OUT can be written (rtcli::check_output).
rt::Status check_output(const std::string& out, const std::string& scene_path);

// Reads and parses; prints the warnings (once: only rank 0 calls this). Fills both
// the text (which is what gets broadcast) and the scene.
rt::Status load_scene(const std::string& path, std::string& text, rt::Scene& scene);

// rtcli::install_signal_handlers, with this program's name in the messages.
void install_signal_handlers();

// --print-scene's output, the same as raytracer's (rtcli::print_scene).
rt::Status print_scene(rt::Scene scene);

// Whether somebody watches stderr on a terminal (for the progress bar). Under mpirun
// a rank's stderr is a pipe to mpirun, so there it is mpirun's stderr that counts.
bool stderr_watched();

}  // namespace rtmpi
