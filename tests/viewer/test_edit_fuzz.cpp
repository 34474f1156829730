// The edit fuzzer (tests/fuzz/edit_fuzz.h) on fixed seeds, so that ctest plays a few
// hundred random edit sequences on random scenes without a clang build, and every
// input the libFuzzer target found (tests/fuzz/regressions/edits-*) again.
#include <doctest/doctest.h>
#include <stdlib.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <system_error>
#include <string>
#include <vector>

#include "fuzz/edit_fuzz.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

// The first broken promise of the run these bytes describe, or "".
std::string broken_promise(const std::vector<std::uint8_t>& bytes, const std::string& dir) {
    try {
        rtfuzz::EditRunOptions opt;
        opt.dir = dir;
        rtfuzz::run_edits(bytes.data(), bytes.size(), opt);
    } catch (const rtfuzz::Broken& b) {
        return b.what;
    }
    return {};
}

// A folder on tmpfs where there is one: the runs save often, and fsync on a busy disk
// would take most of their time.
struct FuzzDir {
    std::string path;
    FuzzDir() {
        std::string tmpl = (fs::is_directory("/dev/shm") ? std::string("/dev/shm") : fs::temp_directory_path().string()) +
                           "/rtview-edit-fuzz-XXXXXX";
        REQUIRE(::mkdtemp(tmpl.data()) != nullptr);
        path = tmpl;
    }
    ~FuzzDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

std::vector<std::uint8_t> random_bytes(std::uint64_t seed, std::size_t n) {
    std::mt19937_64 rng(seed);
    std::vector<std::uint8_t> out(n);
    for (std::uint8_t& b : out) b = std::uint8_t(rng());
    return out;
}

}  // namespace

TEST_CASE("edit fuzzing: random edits of random scenes keep text, scene, world, file and history in agreement") {
    FuzzDir dir;
    // RTVIEW_EDIT_FUZZ_RUNS=N plays N runs instead (a longer search without clang).
    const char* runs_env = std::getenv("RTVIEW_EDIT_FUZZ_RUNS");
    const std::uint64_t runs = runs_env ? std::strtoull(runs_env, nullptr, 10) : 300;
    // RTVIEW_EDIT_FUZZ_FIRST=S starts at seed S (one failing seed played again alone).
    const char* first_env = std::getenv("RTVIEW_EDIT_FUZZ_FIRST");
    const std::uint64_t first = first_env ? std::strtoull(first_env, nullptr, 10) : 1;
    int failures = 0;
    for (std::uint64_t seed = first; seed < first + runs && failures < 3; ++seed) {
        const std::string why = broken_promise(random_bytes(seed, 700), dir.path);
        if (why.empty()) continue;
        ++failures;
        CAPTURE(seed);
        FAIL_CHECK(why);
    }
}

TEST_CASE("edit fuzzing: every input the fuzzer saved keeps its promises") {
    const fs::path src = fs::path(RT_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(src))
        if (e.is_regular_file() && e.path().filename().string().rfind("edits-", 0) == 0) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    // The inputs saved so far: a folder emptied or lost fails here, not passes.
    constexpr std::size_t kSaved = 6;
    REQUIRE_MESSAGE(files.size() >= kSaved, src.string() << " holds " << files.size() << " edits-* inputs, fewer than "
                                                         << kSaved);
    FuzzDir dir;
    for (const fs::path& f : files) {
        const std::string bytes = rt_test::slurp(f);
        CAPTURE(f.filename().string());
        CHECK(broken_promise(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), dir.path) == "");
    }
}
