// Tests for core/image_io.cpp: PPM and PNG encoding read back pixel for pixel, and
// atomic writes that leave an existing file and the folder untouched when they fail.
#include <doctest/doctest.h>
#include <stb/stb_image.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "image_io.h"
#include "test_util.h"

using namespace rt;
namespace fs = std::filesystem;

namespace {

using rt_test::contains;
using rt_test::slurp;
using rt_test::TempDir;
const auto spit = rt_test::put;

std::vector<std::uint8_t> random_rgb(int w, int h, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::vector<std::uint8_t> rgb(std::size_t(w) * h * 3);
    for (auto& b : rgb) b = std::uint8_t(rng());
    return rgb;
}

mode_t mode_of(const std::string& path) {
    struct stat st;
    REQUIRE(::stat(path.c_str(), &st) == 0);
    return st.st_mode & 07777;
}

}  // namespace

TEST_CASE("format_from_path goes by the extension, ignoring case") {
    CHECK(format_from_path("out.ppm") == ImageFormat::Ppm);
    CHECK(format_from_path("dir/OUT.PPM") == ImageFormat::Ppm);
    CHECK(format_from_path("out.png") == ImageFormat::Png);
    CHECK(format_from_path("a.b/Out.Png") == ImageFormat::Png);
    CHECK(format_from_path("out.jpg") == ImageFormat::Unknown);
    CHECK(format_from_path("out") == ImageFormat::Unknown);
    CHECK(format_from_path("out.png.txt") == ImageFormat::Unknown);
    CHECK(format_from_path("pictures.png/out") == ImageFormat::Unknown);  // a dot in a folder name
    CHECK(format_from_path("") == ImageFormat::Unknown);
}

TEST_CASE("to_rgb8 truncates and clamps like the original, NaN to 0") {
    Image img;
    img.width = 3;
    img.height = 2;
    img.rgb = {-1.f, 0.f, 0.5f, 0.999f, 1.f, 7.f, NAN, 0.0059f, 254.9f / 255, 0.25f, 1e-9f, INFINITY};
    const std::vector<std::uint8_t> want = {0, 0, 127, 254, 255, 255, 0, 1, 254, 63, 0, 255};
    CHECK(to_rgb8(img) == want);
}

TEST_CASE("a PPM written is read back pixel for pixel") {
    TempDir dir("rt-imageio");
    for (int w : {1, 7, 64}) {
        for (int h : {1, 5}) {
            const auto rgb = random_rgb(w, h, std::uint64_t(w * 100 + h));
            const std::string path = dir / "out.ppm";
            REQUIRE(write_rgb8(path, w, h, rgb) == "");
            CHECK(slurp(path).rfind("P6\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n", 0) == 0);
            int rw = 0, rh = 0;
            std::vector<std::uint8_t> back;
            REQUIRE(read_ppm(path, rw, rh, back) == "");
            CHECK(rw == w);
            CHECK(rh == h);
            CHECK(back == rgb);
        }
    }
    // And through write_image from a float picture.
    Image img;
    img.width = 4;
    img.height = 3;
    for (int i = 0; i < 36; ++i) img.rgb.push_back(float(i) / 30.f);
    REQUIRE(write_image(dir / "f.PPM", img) == "");
    int rw = 0, rh = 0;
    std::vector<std::uint8_t> back;
    REQUIRE(read_ppm(dir / "f.PPM", rw, rh, back) == "");
    CHECK(back == to_rgb8(img));
}

TEST_CASE("read_ppm reads ASCII P3 with comments, and rejects broken files") {
    TempDir dir("rt-imageio");
    spit(dir / "a.ppm", "P3\n# file 'a.ppm'.\n# made by hand\n2 1\n255\n255 0 7\t1 2 3\t\n");
    int w = 0, h = 0;
    std::vector<std::uint8_t> rgb;
    REQUIRE(read_ppm(dir / "a.ppm", w, h, rgb) == "");
    CHECK(w == 2);
    CHECK(h == 1);
    CHECK(rgb == std::vector<std::uint8_t>{255, 0, 7, 1, 2, 3});

    spit(dir / "max15.ppm", "P3 1 1 15 15 0 5\n");  // another maximum value is rescaled
    REQUIRE(read_ppm(dir / "max15.ppm", w, h, rgb) == "");
    CHECK(rgb == std::vector<std::uint8_t>{255, 0, 85});

    spit(dir / "short.ppm", "P6\n2 2\n255\nabc");
    CHECK(read_ppm(dir / "short.ppm", w, h, rgb) != "");
    spit(dir / "short3.ppm", "P3\n2 1\n255\n1 2 3 4 5\n");
    CHECK(read_ppm(dir / "short3.ppm", w, h, rgb) != "");
    spit(dir / "big.ppm", "P3\n1 1\n255\n1 2 256\n");
    CHECK(read_ppm(dir / "big.ppm", w, h, rgb) != "");
    spit(dir / "png.ppm", "\x89PNG\r\n");
    CHECK(read_ppm(dir / "png.ppm", w, h, rgb) != "");
    spit(dir / "huge.ppm", "P6\n65536 65536\n255\n");  // claims 12 GB, holds nothing
    CHECK(read_ppm(dir / "huge.ppm", w, h, rgb) != "");
    CHECK(read_ppm(dir / "missing.ppm", w, h, rgb) != "");
}

TEST_CASE("a PNG written has the PNG signature and decodes to the same pixels") {
    TempDir dir("rt-imageio");
    const int w = 13, h = 9;
    const auto rgb = random_rgb(w, h, 77);
    REQUIRE(write_rgb8(dir / "out.png", w, h, rgb) == "");
    const std::string png = slurp(dir / "out.png");
    REQUIRE(png.size() > 33);
    CHECK(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    int dw = 0, dh = 0, comp = 0;
    unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()), int(png.size()),
                                              &dw, &dh, &comp, 3);
    REQUIRE(px != nullptr);
    CHECK(dw == w);
    CHECK(dh == h);
    CHECK(std::vector<std::uint8_t>(px, px + w * h * 3) == rgb);
    stbi_image_free(px);
}

TEST_CASE("write_image refuses unknown extensions and mismatched data, writing nothing") {
    TempDir dir("rt-imageio");
    Image img;
    img.width = 2;
    img.height = 2;
    img.rgb.assign(12, 0.5f);
    CHECK(contains(write_image(dir / "out.jpg", img), ".png"));
    CHECK(write_rgb8(dir / "out.ppm", 3, 3, std::vector<std::uint8_t>(5)) != "");
    CHECK(write_rgb8(dir / "out.ppm", 0, 3, {}) != "");
    CHECK(dir.files().empty());
}

TEST_CASE("write_file_atomic replaces the whole file and leaves no temporary behind") {
    TempDir dir("rt-imageio");
    const std::string path = dir / "scene.txt";
    spit(path, std::string(100000, 'x'));
    REQUIRE(write_file_atomic(path, "short") == "");
    CHECK(slurp(path) == "short");  // not "short" followed by the old tail
    REQUIRE(write_file_atomic(path, "") == "");
    CHECK(slurp(path) == "");
    CHECK(dir.files() == std::vector<std::string>{"scene.txt"});

    // A file name without a folder part goes to the current folder.
    const fs::path old_cwd = fs::current_path();
    fs::current_path(dir.path);
    const std::string err = write_file_atomic("plain.txt", "here");
    fs::current_path(old_cwd);
    CHECK(err == "");
    CHECK(slurp(dir / "plain.txt") == "here");
}

TEST_CASE("write_file_atomic gives new files the umask's mode and keeps an existing file's") {
    TempDir dir("rt-imageio");
    const mode_t old_mask = ::umask(027);
    const std::string err = write_file_atomic(dir / "new.txt", "n");
    ::umask(old_mask);
    REQUIRE(err == "");
    CHECK(mode_of(dir / "new.txt") == 0640);  // not mkstemp's 0600

    REQUIRE(write_file_atomic(dir / "default.txt", "d") == "");
    CHECK(mode_of(dir / "default.txt") == (0666 & ~old_mask));

    spit(dir / "private.txt", "old");
    ::chmod((dir / "private.txt").c_str(), 0600);
    REQUIRE(write_file_atomic(dir / "private.txt", "new") == "");
    CHECK(mode_of(dir / "private.txt") == 0600);
    CHECK(slurp(dir / "private.txt") == "new");
}

TEST_CASE("write_file_atomic writes through a symbolic link, keeping the link") {
    TempDir dir("rt-imageio");
    spit(dir / "real.txt", "old");
    fs::create_symlink("real.txt", dir / "link.txt");
    REQUIRE(write_file_atomic(dir / "link.txt", "new") == "");
    CHECK(fs::is_symlink(dir / "link.txt"));
    CHECK(slurp(dir / "real.txt") == "new");
    CHECK(dir.files() == std::vector<std::string>{"link.txt", "real.txt"});
}

TEST_CASE("write_file_atomic failures say why and touch nothing") {
    TempDir dir("rt-imageio");
    const std::string target = dir / "out.ppm";
    spit(target, "precious");

    SUBCASE("a folder that does not exist") {
        const std::string err = write_file_atomic(dir / "nosuch/out.ppm", "data");
        CHECK(contains(err, "No such file or directory"));
    }
    SUBCASE("the target is a folder") {
        fs::create_directory(dir / "sub");
        CHECK(write_file_atomic(dir / "sub", "data") != "");
        CHECK(fs::is_directory(dir / "sub"));
    }
    SUBCASE("a write that fails halfway (file size limit, as on a full disk)") {
        // RLIMIT_FSIZE makes write() fail with EFBIG part-way through, exercising the
        // same clean-up as ENOSPC; SIGXFSZ would otherwise kill the test.
        struct rlimit old_limit;
        REQUIRE(::getrlimit(RLIMIT_FSIZE, &old_limit) == 0);
        auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
        struct rlimit small = old_limit;
        small.rlim_cur = 4096;
        REQUIRE(::setrlimit(RLIMIT_FSIZE, &small) == 0);
        const std::string err = write_file_atomic(target, std::string(100000, 'y'));
        ::setrlimit(RLIMIT_FSIZE, &old_limit);
        std::signal(SIGXFSZ, old_handler);
        CHECK(contains(err, "File too large"));
    }
    SUBCASE("a read-only folder") {
        if (::geteuid() == 0) {
            MESSAGE("skipped: running as root, where a read-only folder is still writable");
        } else {
            REQUIRE(::chmod(dir.path.c_str(), 0555) == 0);
            const std::string err = write_file_atomic(target, "data");
            ::chmod(dir.path.c_str(), 0700);
            CHECK(contains(err, "Permission denied"));
        }
    }
    CHECK(slurp(target) == "precious");
    std::vector<std::string> left = dir.files();
    left.erase(std::remove(left.begin(), left.end(), "sub"), left.end());
    CHECK(left == std::vector<std::string>{"out.ppm"});  // no temporary file left behind
}

TEST_CASE("write_file_atomic writes straight into devices, reporting a full one") {
    struct stat st;
    if (::stat("/dev/full", &st) != 0 || !S_ISCHR(st.st_mode)) {
        MESSAGE("skipped: no /dev/full");
        return;
    }
    CHECK(contains(write_file_atomic("/dev/full", "data"), "No space left on device"));
    CHECK(::stat("/dev/full", &st) == 0);
    CHECK(S_ISCHR(st.st_mode));  // still the device, not replaced by a regular file
    CHECK(write_file_atomic("/dev/null", "data") == "");
    CHECK(::stat("/dev/null", &st) == 0);
    CHECK(S_ISCHR(st.st_mode));
}

TEST_CASE("read_file returns the exact bytes and enforces the size limit") {
    TempDir dir("rt-imageio");
    std::string data("a\0b\r\n", 5);
    data += std::string(70000, 'z');  // more than one read() buffer
    data.push_back('\0');
    spit(dir / "f", data);
    std::string out = "stale";
    REQUIRE(read_file(dir / "f", out, data.size()) == "");
    CHECK(out == data);
    out = "stale";
    CHECK(contains(read_file(dir / "f", out, data.size() - 1), std::to_string(data.size() - 1)));
    CHECK(out.empty());
    CHECK(contains(read_file(dir / "missing", out, 100), "No such file or directory"));
    CHECK(read_file(dir.path.string(), out, 100) != "");  // a folder
    // Files without a size (pipes, /proc) are read to the end, limit included.
    if (fs::exists("/proc/self/status")) {
        CHECK(read_file("/proc/self/status", out, 1 << 20) == "");
        CHECK(contains(out, "Umask"));
        CHECK(read_file("/proc/self/status", out, 10) != "");
    }
}
