// libFuzzer target: the edit fuzzer (edit_fuzz.h). The input's bytes choose a random
// scene text and a sequence of user edits through the viewer's document; every step
// must keep the text, the scene, the compiled world, the saved file and the undo
// history in agreement. A broken promise aborts with its description and the steps.
#include <stdlib.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <system_error>

#include "edit_fuzz.h"

namespace {

// One folder for the whole session (the scene's file, saves, outside changes), on
// tmpfs where there is one: runs save often, and fsync would dominate them.
std::string g_dir;

void remove_dir() {
    std::error_code ec;
    std::filesystem::remove_all(g_dir, ec);
}

const std::string& fuzz_dir() {
    if (g_dir.empty()) {
        const char* base = std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp";
        std::string tmpl = std::string(base) + "/rt-fuzz-edits-XXXXXX";
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
