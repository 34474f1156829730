// raytracer-mpi's options: those of raytracer (app/cli) plus --tile. SCENE and OUT are
// required, because a batch job under mpirun has nobody to answer a prompt; exit
// status 3 reports a failed rank.
#include "cli.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <utility>

namespace rtmpi {

namespace {

const rtcli::Program kProgram{
    "raytracer-mpi",
    "Usage: mpirun [-np N] raytracer-mpi [OPTIONS] SCENE OUT\n"
    "Render a raytracer2 scene file to an image on the ranks of an MPI job. Rank 0\n"
    "reads the scene and hands out tiles on request; every rank renders with all its\n"
    "cores; rank 0 writes OUT. The picture is bit-identical to `raytracer` with the\n"
    "same options.\n"
    "\n"
    "  OUT ends in .ppm (binary PPM, P6) or .png.\n"
    "\n"
    "Options:\n",
    "worker threads per rank",
    "the CPUs the\n"
    "rank may use; mpirun may bind a rank to one core: run one\n"
    "rank per machine with `mpirun --bind-to none`",
    "Exit status (of every rank): 0 success, 1 the scene has errors, 2 usage or I/O\n"
    "error, 3 a rank or MPI failed. A failed run leaves OUT untouched.\n",
    true};

}  // namespace

rt::Status usage_error(const std::string& message) { return rtcli::usage_error(kProgram, message); }

rt::Status parse_args(int argc, char** argv, Options& o) { return rtcli::parse_args(kProgram, argc, argv, o); }

bool print_help_or_version(const Options& o) { return rtcli::print_help_or_version(kProgram, o); }

rt::Status check_scene(const Options& o) { return rtcli::check_scene(kProgram, o); }

rt::Status check_output(const std::string& out, const std::string& scene_path) {
    return rtcli::check_output(kProgram, out, scene_path);
}

rt::Status load_scene(const std::string& path, std::string& text, rt::Scene& scene) {
    return rtcli::load_scene(kProgram, path, text, scene);
}

void install_signal_handlers() { rtcli::install_signal_handlers(kProgram); }

rt::Status print_scene(rt::Scene scene) { return rtcli::print_scene(kProgram, std::move(scene)); }

bool stderr_watched() {
    if (isatty(STDERR_FILENO)) return true;
#ifdef __linux__
    // Open MPI forwards a rank's stderr to mpirun through a pipe (and gives its stdout
    // a pty whether or not anyone watches, so stdout tells nothing). Only for a pipe
    // to the launcher itself: `2> log` or `| tee` must not collect progress lines.
    struct stat st;
    if (fstat(STDERR_FILENO, &st) != 0 || !S_ISFIFO(st.st_mode)) return false;
    const std::string parent = "/proc/" + std::to_string(getppid());
    std::string comm;
    std::getline(std::ifstream(parent + "/comm"), comm);
    if (comm != "mpirun" && comm != "mpiexec" && comm != "orterun" && comm != "prterun") return false;
    const int fd = open((parent + "/fd/2").c_str(), O_WRONLY | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) return false;
    const bool tty = isatty(fd);
    close(fd);
    return tty;
#else
    return false;
#endif
}

}  // namespace rtmpi
