// libFuzzer target: the edit fuzzer (edit_fuzz.h). The input's bytes choose a random
// scene text and a sequence of user edits through the viewer's document; every step
// must keep the text, the scene, the compiled world, the saved file and the undo
// history in agreement. A broken promise aborts with its description and the steps.
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include "edit_fuzz.h"

namespace {

// One folder for the whole session (the scene's file, saves, outside changes), on
// tmpfs where there is one: runs save often, and fsync would dominate them. Its name
// holds the process id: libFuzzer ends a run that is interrupted, times out or finds a
// crash with _Exit, which skips atexit, so each session first removes the folders of
// sessions whose process is gone.
const char kPrefix[] = "rt-fuzz-edits-";
std::string g_dir;

void remove_orphans(const std::string& base) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(base, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(kPrefix, 0) != 0) continue;
        const long pid = std::strtol(name.c_str() + sizeof kPrefix - 1, nullptr, 10);
        if (pid <= 0 || pid == long(::getpid())) continue;
        if (::kill(pid_t(pid), 0) == 0 || errno != ESRCH) continue;  // alive (or not ours to ask)
        std::error_code ignored;
        std::filesystem::remove_all(entry.path(), ignored);
    }
}

void remove_dir() {
    std::error_code ec;
    std::filesystem::remove_all(g_dir, ec);
}

const std::string& fuzz_dir() {
    if (g_dir.empty()) {
        const char* base = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
        remove_orphans(base);
        std::string tmpl = std::string(base) + "/" + kPrefix + std::to_string(::getpid()) + "-XXXXXX";
        if (!::mkdtemp(tmpl.data())) {
            std::perror("mkdtemp");
            std::abort();
        }
        g_dir = tmpl;
        std::atexit(remove_dir);
    }
    return g_dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    rtfuzz::EditRunOptions opt;
    opt.dir = fuzz_dir();
    rtfuzz::or_abort([&] { rtfuzz::run_edits(data, size, opt); });
    return 0;
}
