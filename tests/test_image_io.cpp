// Tests for core/image_io.cpp: PPM and PNG encoding read back pixel for pixel, and
// atomic writes that leave an existing file and the folder untouched when they fail.
#include <doctest/doctest.h>
#include <stb/stb_image.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <zlib.h>

#include <ImfRgbaFile.h>

#include "image_io.h"
#include "png.h"
#include "test_util.h"

using namespace rt;
namespace fs = std::filesystem;

namespace {

using rt_test::contains;
using rt_test::slurp;

using rt_test::TempDir;

bool have_dev_full() {
    struct stat st;
    return ::stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode);
}

// Runs `fn` in a child process as uid/gid 65534 (nobody) and returns what it returned:
// root ignores file permissions, so the permission rules are checked as nobody.
std::string as_nobody(const std::function<std::string()>& fn) {
    int fds[2];
    REQUIRE(::pipe(fds) == 0);
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        ::close(fds[0]);
        if (::setgid(65534) != 0 || ::setuid(65534) != 0) _exit(3);
        const std::string r = fn();
        const bool ok = ::write(fds[1], r.data(), r.size()) == ssize_t(r.size());
        _exit(ok ? 0 : 4);
    }
    ::close(fds[1]);
    std::string out;
    char buf[512];
    for (ssize_t n; (n = ::read(fds[0], buf, sizeof buf)) > 0;) out.append(buf, std::size_t(n));
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    REQUIRE(WIFEXITED(status));
    REQUIRE(WEXITSTATUS(status) == 0);
    return out;
}

const bool kRoot = ::geteuid() == 0;

void spit(const std::string& path, const std::string& data) {
    std::ofstream out(path, std::ios::binary);
    out << data;
}

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
            REQUIRE(write_rgb8(path, w, h, rgb).ok());
            CHECK(slurp(path).rfind("P6\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n", 0) == 0);
            int rw = 0, rh = 0;
            std::vector<std::uint8_t> back;
            REQUIRE(read_ppm(path, rw, rh, back).ok());
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
    REQUIRE(write_image(dir / "f.PPM", img).ok());
    int rw = 0, rh = 0;
    std::vector<std::uint8_t> back;
    REQUIRE(read_ppm(dir / "f.PPM", rw, rh, back).ok());
    CHECK(back == to_rgb8(img));
}

TEST_CASE("read_ppm reads ASCII P3 with comments, and rejects broken files") {
    TempDir dir("rt-imageio");
    spit(dir / "a.ppm", "P3\n# file 'a.ppm'.\n# made by hand\n2 1\n255\n255 0 7\t1 2 3\t\n");
    int w = 0, h = 0;
    std::vector<std::uint8_t> rgb;
    REQUIRE(read_ppm(dir / "a.ppm", w, h, rgb).ok());
    CHECK(w == 2);
    CHECK(h == 1);
    CHECK(rgb == std::vector<std::uint8_t>{255, 0, 7, 1, 2, 3});

    spit(dir / "max15.ppm", "P3 1 1 15 15 0 5\n");  // another maximum value is rescaled
    REQUIRE(read_ppm(dir / "max15.ppm", w, h, rgb).ok());
    CHECK(rgb == std::vector<std::uint8_t>{255, 0, 85});

    spit(dir / "short.ppm", "P6\n2 2\n255\nabc");
    CHECK(!read_ppm(dir / "short.ppm", w, h, rgb).ok());
    spit(dir / "short3.ppm", "P3\n2 1\n255\n1 2 3 4 5\n");
    CHECK(!read_ppm(dir / "short3.ppm", w, h, rgb).ok());
    spit(dir / "big.ppm", "P3\n1 1\n255\n1 2 256\n");
    CHECK(!read_ppm(dir / "big.ppm", w, h, rgb).ok());
    spit(dir / "png.ppm", "\x89PNG\r\n");
    CHECK(!read_ppm(dir / "png.ppm", w, h, rgb).ok());
    spit(dir / "huge.ppm", "P6\n65536 65536\n255\n");  // claims 12 GB, holds nothing
    CHECK(!read_ppm(dir / "huge.ppm", w, h, rgb).ok());
    CHECK(!read_ppm(dir / "missing.ppm", w, h, rgb).ok());
}

TEST_CASE("a PNG written has the PNG signature and decodes to the same pixels") {
    TempDir dir("rt-imageio");
    const int w = 13, h = 9;
    const auto rgb = random_rgb(w, h, 77);
    REQUIRE(write_rgb8(dir / "out.png", w, h, rgb).ok());
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

namespace {

// A picture with what renders have: smooth gradients, flat runs and noisy patches.
std::vector<std::uint8_t> render_like(int w, int h) {
    std::vector<std::uint8_t> rgb(std::size_t(w) * h * 3);
    std::mt19937 rng(5);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = &rgb[3 * (std::size_t(y) * w + x)];
            const bool noisy = (x / 64 + y / 64) % 3 == 0, flat = (x / 64 + y / 64) % 3 == 1;
            p[0] = noisy ? std::uint8_t(rng()) : flat ? 40 : std::uint8_t(x * 255 / w);
            p[1] = noisy ? std::uint8_t(rng()) : flat ? 200 : std::uint8_t(y * 255 / h);
            p[2] = noisy ? std::uint8_t(rng()) : std::uint8_t((x + y) & 255);
        }
    return rgb;
}

std::uint32_t be32(const std::string& s, std::size_t at) {
    return std::uint32_t(std::uint8_t(s[at])) << 24 | std::uint32_t(std::uint8_t(s[at + 1])) << 16 |
           std::uint32_t(std::uint8_t(s[at + 2])) << 8 | std::uint32_t(std::uint8_t(s[at + 3]));
}

// The chunks' checks, as a strict reader makes them: every CRC, then the IDAT data as
// one zlib stream (inflate checks its Adler-32) of filtered rows of the right length.
// Returns the number of IDAT chunks.
int check_png_structure(const std::string& png, int w, int h) {
    REQUIRE(png.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    std::string idat;
    int idats = 0;
    std::size_t at = 8;
    std::string last;
    while (at + 12 <= png.size()) {
        const std::uint32_t len = be32(png, at);
        REQUIRE(at + 12 + len <= png.size());
        const std::string type = png.substr(at + 4, 4);
        const auto crc = crc32(0, reinterpret_cast<const Bytef*>(png.data() + at + 4), uInt(4 + len));
        CAPTURE(type);
        CHECK(crc == be32(png, at + 8 + len));
        if (type == "IDAT") idat += png.substr(at + 8, len), ++idats;
        last = type;
        at += 12 + len;
    }
    CHECK(at == png.size());
    CHECK(last == "IEND");
    std::vector<Bytef> raw((std::size_t(w) * 3 + 1) * h + 1);
    uLongf got = uLongf(raw.size());
    REQUIRE(uncompress(raw.data(), &got, reinterpret_cast<const Bytef*>(idat.data()), uLong(idat.size())) == Z_OK);
    CHECK(got == raw.size() - 1);
    return idats;
}

}  // namespace

TEST_CASE("a PNG compressed in strips on several threads is one valid stream that decodes to the same pixels") {
    TempDir dir("rt-imageio");
    // Sizes for one strip and for several, with rows of every length down to one pixel.
    for (const auto& [w, h, threads] : std::vector<std::array<int, 3>>{
             {1, 1, 4}, {1, 3000, 3}, {1200, 1000, 3}, {1201, 999, 5}, {640, 480, 1}, {3000, 7, 4}}) {
        CAPTURE(w);
        CAPTURE(h);
        const std::vector<std::uint8_t> rgb = render_like(w, h);
        std::string png;
        REQUIRE(encode_png(rgb.data(), w, h, png, threads));
        const int idats = check_png_structure(png, w, h);
        // (Strips of at least a MiB of raw rows, one per thread.)
        CHECK(idats == std::min<long>(threads, std::max<long>(1, (long(w) * 3 + 1) * h / (1 << 20))));
        int dw = 0, dh = 0, comp = 0;
        unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(png.data()), int(png.size()),
                                                  &dw, &dh, &comp, 3);
        REQUIRE(px != nullptr);
        CHECK(dw == w);
        CHECK(dh == h);
        CHECK(std::equal(rgb.begin(), rgb.end(), px));
        stbi_image_free(px);
        if (w == 1201) {
            // Smaller than the raw bytes (noise and all), and ImageMagick reads it too.
            CHECK(png.size() < rgb.size() * 2 / 3);
            const std::string path = dir / "strips.png";
            spit(path, png);
            const std::string back = dir / "back.ppm";
            if (std::system(("convert " + path + " " + back + " 2>/dev/null").c_str()) == 0) {
                int bw = 0, bh = 0;
                std::vector<std::uint8_t> pixels;
                REQUIRE(read_ppm(back, bw, bh, pixels).ok());
                CHECK(pixels == rgb);
            } else {
                MESSAGE("ImageMagick's convert is not installed: not checked with it");
            }
        }
    }
}

TEST_CASE("write_image refuses unknown extensions and mismatched data, writing nothing") {
    TempDir dir("rt-imageio");
    Image img;
    img.width = 2;
    img.height = 2;
    img.rgb.assign(12, 0.5f);
    CHECK(contains(write_image(dir / "out.jpg", img).message(), ".png"));
    CHECK(!write_rgb8(dir / "out.ppm", 3, 3, std::vector<std::uint8_t>(5)).ok());
    CHECK(!write_rgb8(dir / "out.ppm", 0, 3, {}).ok());
    CHECK(dir.files().empty());
}

TEST_CASE("write_file_atomic replaces the whole file and leaves no temporary behind") {
    TempDir dir("rt-imageio");
    const std::string path = dir / "scene.txt";
    spit(path, std::string(100000, 'x'));
    REQUIRE(write_file_atomic(path, "short").ok());
    CHECK(slurp(path) == "short");  // not "short" followed by the old tail
    REQUIRE(write_file_atomic(path, "").ok());
    CHECK(slurp(path) == "");
    CHECK(dir.files() == std::vector<std::string>{"scene.txt"});

    // A file name without a folder part goes to the current folder.
    const fs::path old_cwd = fs::current_path();
    fs::current_path(dir.path);
    const std::string err = write_file_atomic("plain.txt", "here").message();
    fs::current_path(old_cwd);
    CHECK(err == "");
    CHECK(slurp(dir / "plain.txt") == "here");
}

TEST_CASE("write_file_atomic gives new files the umask's mode and keeps an existing file's") {
    TempDir dir("rt-imageio");
    const mode_t old_mask = ::umask(027);
    const std::string err = write_file_atomic(dir / "new.txt", "n").message();
    ::umask(old_mask);
    REQUIRE(err == "");
    CHECK(mode_of(dir / "new.txt") == 0640);  // not mkstemp's 0600

    REQUIRE(write_file_atomic(dir / "default.txt", "d").ok());
    CHECK(mode_of(dir / "default.txt") == (0666 & ~old_mask));

    spit(dir / "private.txt", "old");
    ::chmod((dir / "private.txt").c_str(), 0600);
    REQUIRE(write_file_atomic(dir / "private.txt", "new").ok());
    CHECK(mode_of(dir / "private.txt") == 0600);
    CHECK(slurp(dir / "private.txt") == "new");
}

TEST_CASE("write_file_atomic writes through a symbolic link, keeping the link") {
    TempDir dir("rt-imageio");
    spit(dir / "real.txt", "old");
    fs::create_symlink("real.txt", dir / "link.txt");
    REQUIRE(write_file_atomic(dir / "link.txt", "new").ok());
    CHECK(fs::is_symlink(dir / "link.txt"));
    CHECK(slurp(dir / "real.txt") == "new");
    CHECK(dir.files() == std::vector<std::string>{"link.txt", "real.txt"});
}

TEST_CASE("write_file_atomic failures say why and touch nothing") {
    TempDir dir("rt-imageio");
    const std::string target = dir / "out.ppm";
    spit(target, "precious");

    SUBCASE("a folder that does not exist") {
        const std::string err = write_file_atomic(dir / "nosuch/out.ppm", "data").message();
        CHECK(contains(err, "No such file or directory"));
    }
    SUBCASE("the target is a folder") {
        fs::create_directory(dir / "sub");
        CHECK(!write_file_atomic(dir / "sub", "data").ok());
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
        const std::string err = write_file_atomic(target, std::string(100000, 'y')).message();
        ::setrlimit(RLIMIT_FSIZE, &old_limit);
        std::signal(SIGXFSZ, old_handler);
        CHECK(contains(err, "File too large"));
    }
    CHECK(slurp(target) == "precious");
    std::vector<std::string> left = dir.files();
    left.erase(std::remove(left.begin(), left.end(), "sub"), left.end());
    CHECK(left == std::vector<std::string>{"out.ppm"});  // no temporary file left behind
}

TEST_CASE("write_file_atomic writes straight into devices, reporting a full one" * doctest::skip(!have_dev_full())) {
    struct stat st;
    CHECK(contains(write_file_atomic("/dev/full", "data").message(), "No space left on device"));
    CHECK(::stat("/dev/full", &st) == 0);
    CHECK(S_ISCHR(st.st_mode));  // still the device, not replaced by a regular file
    CHECK(write_file_atomic("/dev/null", "data").ok());
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
    REQUIRE(read_file(dir / "f", out, data.size()).ok());
    CHECK(out == data);
    out = "stale";
    CHECK(contains(read_file(dir / "f", out, data.size() - 1).message(), std::to_string(data.size() - 1)));
    CHECK(out.empty());
    CHECK(contains(read_file(dir / "missing", out, 100).message(), "No such file or directory"));
    CHECK(!read_file(dir.path.string(), out, 100).ok());  // a folder
    // Files without a size (pipes, /proc) are read to the end, limit included.
    if (fs::exists("/proc/self/status")) {
        CHECK(read_file("/proc/self/status", out, 1 << 20).ok());
        CHECK(contains(out, "Umask"));
        CHECK(!read_file("/proc/self/status", out, 10).ok());
    }
    // The same into a FileText (no zero fill as it grows).
    FileText text;
    text.resize(3);
    REQUIRE(read_file(dir / "f", text, data.size()).ok());
    CHECK(text.view() == data);
    CHECK(contains(read_file(dir / "f", text, data.size() - 1).message(), std::to_string(data.size() - 1)));
    CHECK(text.size() == 0);
    CHECK(!read_file(dir / "missing", text, 100).ok());
    if (fs::exists("/proc/self/status")) {
        CHECK(read_file("/proc/self/status", text, 1 << 20).ok());
        CHECK(contains(std::string(text.view()), "Umask"));
        CHECK(!read_file("/proc/self/status", text, 10).ok());
    }
    // A pipe's bytes arrive as written, past the first buffer's size.
    const fs::path fifo = dir / "fifo";
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    std::thread writer([&] { spit(fifo, data); });
    const Status piped = read_file(fifo, text, data.size());
    writer.join();
    CHECK(piped.ok());
    CHECK(text.view() == data);
}

TEST_CASE("read_file: a big file, read in two halves at once, comes back byte for byte") {
    TempDir dir("rt-imageio");
    std::string data((std::size_t(9) << 20) + 12345, '\0');
    std::uint32_t x = 12345;
    for (char& c : data) {
        x = x * 1664525u + 1013904223u;
        c = char(x >> 24);
    }
    spit(dir / "big", data);
    std::string out;
    REQUIRE(read_file(dir / "big", out, data.size()).ok());
    CHECK(out.size() == data.size());
    CHECK(out == data);
    CHECK(contains(read_file(dir / "big", out, data.size() - 1).message(), std::to_string(data.size() - 1)));
    CHECK(out.empty());
    FileText text;
    REQUIRE(read_file(dir / "big", text, data.size()).ok());
    CHECK(text.view() == data);
}

// --- the rules of check_writable (image_io.h), shared by write_file_atomic ---------

TEST_CASE("a read-only folder refuses the write (as an unprivileged user)" * doctest::skip(kRoot)) {
    TempDir dir;
    spit(dir / "out.ppm", "precious");
    REQUIRE(::chmod(dir.path.c_str(), 0555) == 0);
    const std::string check = check_writable(dir / "out.ppm").message(), err = write_file_atomic(dir / "out.ppm", "data").message();
    ::chmod(dir.path.c_str(), 0700);
    CHECK(contains(check, "Permission denied"));
    CHECK(contains(err, "Permission denied"));
    CHECK(slurp(dir / "out.ppm") == "precious");
}

TEST_CASE("permission rules checked as nobody: read-only folder, read-only file, sticky folder" * doctest::skip(!kRoot)) {
    TempDir dir;
    REQUIRE(::chmod(dir.path.c_str(), 0755) == 0);
    const std::string ro_dir = dir / "ro", open_dir = dir / "open", sticky = dir / "sticky";
    for (const auto& d : {ro_dir, open_dir, sticky}) fs::create_directory(d);
    REQUIRE(::chmod(ro_dir.c_str(), 0555) == 0);
    REQUIRE(::chmod(open_dir.c_str(), 0777) == 0);
    REQUIRE(::chmod(sticky.c_str(), 01777) == 0);
    spit(ro_dir + "/out.ppm", "precious");
    ::chmod((ro_dir + "/out.ppm").c_str(), 0666);
    spit(open_dir + "/readonly.ppm", "precious");
    REQUIRE(::chown((open_dir + "/readonly.ppm").c_str(), 65534, 65534) == 0);
    ::chmod((open_dir + "/readonly.ppm").c_str(), 0444);
    spit(sticky + "/roots.ppm", "precious");  // root's file, writable by all, in a sticky folder
    ::chmod((sticky + "/roots.ppm").c_str(), 0666);

    CHECK(contains(as_nobody([&] { return check_writable(ro_dir + "/out.ppm").message(); }), "Permission denied"));
    CHECK(contains(as_nobody([&] { return write_file_atomic(ro_dir + "/out.ppm", "new").message(); }), "Permission denied"));
    CHECK(contains(as_nobody([&] { return check_writable(open_dir + "/readonly.ppm").message(); }), "Permission denied"));
    CHECK(contains(as_nobody([&] { return write_file_atomic(open_dir + "/readonly.ppm", "new").message(); }),
                   "Permission denied"));
    CHECK(contains(as_nobody([&] { return check_writable(sticky + "/roots.ppm").message(); }), "Operation not permitted"));
    CHECK(contains(as_nobody([&] { return write_file_atomic(sticky + "/roots.ppm", "new").message(); }),
                   "Operation not permitted"));
    // Nobody's own new file in the sticky folder is fine.
    CHECK(as_nobody([&] { return write_file_atomic(sticky + "/mine.ppm", "new").message(); }) == "");
    CHECK(slurp(ro_dir + "/out.ppm") == "precious");
    CHECK(slurp(open_dir + "/readonly.ppm") == "precious");
    CHECK(slurp(sticky + "/roots.ppm") == "precious");
    for (const auto& d : {ro_dir, open_dir}) {
        ::chmod(d.c_str(), 0755);
        CHECK(fs::directory_iterator(d)->path().filename().string().rfind(".", 0) != 0);  // no temporary left
    }
    CHECK(std::distance(fs::directory_iterator(sticky), fs::directory_iterator()) == 2);
}

TEST_CASE("root replaces another user's file, which keeps its owner, group and mode" * doctest::skip(!kRoot)) {
    TempDir dir;
    const std::string f = dir / "theirs.ppm";
    spit(f, "old");
    REQUIRE(::chown(f.c_str(), 65534, 65534) == 0);
    REQUIRE(::chmod(f.c_str(), 0444) == 0);  // read-only does not stop root
    REQUIRE(check_writable(f).ok());
    REQUIRE(write_file_atomic(f, "new").ok());
    struct stat st;
    REQUIRE(::stat(f.c_str(), &st) == 0);
    CHECK(slurp(f) == "new");
    CHECK(st.st_uid == 65534);
    CHECK(st.st_gid == 65534);
    CHECK((st.st_mode & 07777) == 0444);
}

TEST_CASE("names of 248..255 bytes work: the temporary name is shortened to fit NAME_MAX") {
    TempDir dir;
    for (std::size_t len : {248, 250, 255}) {
        CAPTURE(len);
        const std::string name = std::string(len - 4, 'n') + ".ppm";
        CHECK(check_writable(dir / name).ok());
        REQUIRE(write_file_atomic(dir / name, "data").ok());
        CHECK(slurp(dir / name) == "data");
        REQUIRE(write_file_atomic(dir / name, "again").ok());  // replacing works too
        CHECK(slurp(dir / name) == "again");
        CHECK(dir.files() == std::vector<std::string>{name});
        fs::remove(dir / name);
    }
    // 256 bytes is too long for the file itself: the system's reason.
    const std::string too_long = std::string(252, 'n') + ".ppm";
    CHECK(contains(check_writable(dir / too_long).message(), "File name too long"));
    CHECK(contains(write_file_atomic(dir / too_long, "data").message(), "File name too long"));
}

TEST_CASE("a path longer than PATH_MAX fails with the system's reason") {
    TempDir dir;
    std::string path = dir.path.string();
    while (path.size() <= PATH_MAX) path += "/" + std::string(200, 'd');
    path += "/out.ppm";
    CHECK(contains(check_writable(path).message(), "File name too long"));
    CHECK(contains(write_file_atomic(path, "data").message(), "File name too long"));
}

TEST_CASE("symbolic links are followed to their end; a dangling one creates its target; a loop fails") {
    TempDir dir;
    fs::create_symlink("target.ppm", dir / "dangling.ppm");
    REQUIRE(write_file_atomic(dir / "dangling.ppm", "new").ok());
    CHECK(fs::is_symlink(dir / "dangling.ppm"));
    CHECK(slurp(dir / "target.ppm") == "new");
    // A chain of links, one of them relative to a subfolder.
    fs::create_directory(dir / "sub");
    fs::create_symlink("../final.ppm", dir / "sub/hop.ppm");
    fs::create_symlink("sub/hop.ppm", dir / "first.ppm");
    REQUIRE(write_file_atomic(dir / "first.ppm", "chained").ok());
    CHECK(slurp(dir / "final.ppm") == "chained");
    CHECK(fs::is_symlink(dir / "first.ppm"));
    CHECK(fs::is_symlink(dir / "sub/hop.ppm"));
    // Loops: to itself and through two links.
    fs::create_symlink("self.ppm", dir / "self.ppm");
    fs::create_symlink("b.ppm", dir / "a.ppm");
    fs::create_symlink("a.ppm", dir / "b.ppm");
    for (const char* name : {"self.ppm", "a.ppm"}) {
        CHECK(contains(check_writable(dir / name).message(), "Too many levels of symbolic links"));
        CHECK(contains(write_file_atomic(dir / name, "x").message(), "Too many levels of symbolic links"));
    }
    CHECK(fs::is_symlink(dir / "self.ppm"));
    CHECK(dir.files() == std::vector<std::string>{"a.ppm", "b.ppm", "dangling.ppm", "final.ppm", "first.ppm",
                                                  "self.ppm", "sub", "target.ppm"});
}

TEST_CASE("check_writable creates nothing and names the problem") {
    TempDir dir;
    spit(dir / "out.ppm", "precious");
    CHECK(check_writable(dir / "out.ppm").ok());
    CHECK(check_writable(dir / "new.ppm").ok());
    CHECK(contains(check_writable(dir / "nosuch/out.ppm").message(), "No such file or directory"));
    CHECK(contains(check_writable(dir / "out.ppm/x.ppm").message(), "Not a directory"));
    CHECK(contains(check_writable(dir.path.string()).message(), "Is a directory"));
    CHECK(check_writable("/dev/null").ok());
    CHECK(dir.files() == std::vector<std::string>{"out.ppm"});
    CHECK(slurp(dir / "out.ppm") == "precious");
}

namespace {

// The size of a file `pid` has open for writing in `dir` (-1: none): /proc/PID/fd's
// links name the files, an unnamed one as "DIR/#INODE (deleted)".
long long file_being_written(pid_t pid, const std::string& dir) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec)) {
        const std::string target = fs::read_symlink(e.path(), ec).string();
        if (ec || target.rfind(dir + "/", 0) != 0) continue;
        struct stat st {};
        if (::stat(e.path().c_str(), &st) == 0) return (long long)st.st_size;
    }
    return -1;
}

}  // namespace

// SIGKILL runs no handler: whatever name the new file has while it is written stays
// behind. With WhileWriting::NoName (the viewer's saves) it has none until complete.
TEST_CASE("write_file_atomic: killed mid-write, NoName leaves nothing behind (a temporary name would stay)") {
    for (WhileWriting how : {WhileWriting::NoName, WhileWriting::TempName}) {
        const bool no_name = how == WhileWriting::NoName;
        CAPTURE(no_name);
        TempDir dir("rt-imageio");
        const std::string path = dir / "scene.txt";
        spit(path, "precious");
        std::fflush(nullptr);
        const pid_t pid = fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            const std::string big(std::size_t(128) << 20, 'x');
            (void)write_file_atomic(path, big, how);
            _exit(0);
        }
        // Killed once the new file has some of its bytes (polled, not timed).
        bool caught = false;
        for (int i = 0; i < 200000 && !caught; ++i) {
            const long long n = file_being_written(pid, dir.path.string());
            caught = n > 0 && n < (128ll << 20);
            if (!caught) std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        ::kill(pid, SIGKILL);
        int status = 0;
        ::waitpid(pid, &status, 0);
        REQUIRE(caught);
        CHECK(slurp(path) == "precious");
        if (no_name) CHECK(dir.files() == std::vector<std::string>{"scene.txt"});
        else CHECK(dir.files().size() == 2);  // ".scene.txt.XXXXXX", half written
    }
}

TEST_CASE("an interrupted write (interrupt_writes, as from a signal handler) removes its temporary file") {
    TempDir dir;
    spit(dir / "out.ppm", "precious");
    CHECK_FALSE(interrupt_writes());  // no temporary file exists now
    const std::string err = write_file_atomic(dir / "out.ppm", std::string(10 << 20, 'x')).message();
    const std::string err_new = write_file_atomic(dir / "new.ppm", "data").message();
    reset_write_interrupt();
    CHECK(err == "interrupted");
    CHECK(err_new == "interrupted");
    CHECK(slurp(dir / "out.ppm") == "precious");
    CHECK(dir.files() == std::vector<std::string>{"out.ppm"});
    REQUIRE(write_file_atomic(dir / "out.ppm", "after").ok());  // and writes work again after the reset
    CHECK(slurp(dir / "out.ppm") == "after");
}

TEST_CASE("float pictures: .pfm and .exr hold the film's values unclamped, the bytes' rounding left out") {
    Image img;
    img.width = 3;
    img.height = 2;
    // Below 0, inside, above 1, and the non-finite values pixels never show.
    img.rgb = {-0.25f, 0.0f, 0.5f, 1.0f, 2.5f, 1000.0f, 0.125f, 0.75f, 3.0f,
               std::nanf(""), INFINITY, -INFINITY, 0.3f, 0.6f, 0.9f, 7.0f, 0.01f, 42.0f};
    TempDir dir;
    const std::string pfm = (dir.path / "a.pfm").string(), exr = (dir.path / "a.exr").string();
    REQUIRE(format_from_path(pfm) == ImageFormat::Pfm);
    REQUIRE(format_from_path("X.EXR") == ImageFormat::Exr);
    REQUIRE(write_image(pfm, img).ok());
    // PFM: the header, then rows bottom first, little-endian floats.
    const std::string bytes = slurp(pfm);
    const std::string header = "PF\n3 2\n-1.0\n";
    REQUIRE(bytes.size() == header.size() + 18 * sizeof(float));
    CHECK(bytes.compare(0, header.size(), header) == 0);
    auto value = [&](int x, int y, int c) {
        float v;
        std::memcpy(&v, &bytes[header.size() + sizeof(float) * (3 * std::size_t((1 - y) * 3 + x) + std::size_t(c))], sizeof v);
        return v;
    };
    CHECK(value(0, 0, 0) == -0.25f);
    CHECK(value(1, 0, 2) == 1000.0f);
    CHECK(value(2, 0, 2) == 3.0f);
    CHECK(value(0, 1, 0) == 0.0f);   // NaN as a pixel shows it: 0
    CHECK(value(0, 1, 1) == 1e30f);  // +inf: 1e30
    CHECK(value(0, 1, 2) == 0.0f);   // -inf: 0
    CHECK(value(2, 1, 2) == 42.0f);
    // EXR, read back through OpenEXR: half floats of the same values.
    REQUIRE(write_image(exr, img).ok());
    Imf::RgbaInputFile in(exr.c_str());
    const Imath::Box2i dw = in.dataWindow();
    REQUIRE(dw.max.x - dw.min.x + 1 == 3);
    REQUIRE(dw.max.y - dw.min.y + 1 == 2);
    std::vector<Imf::Rgba> px(6);
    in.setFrameBuffer(px.data() - dw.min.x - dw.min.y * 3, 1, 3);
    in.readPixels(dw.min.y, dw.max.y);
    CHECK(float(px[0].r) == -0.25f);
    CHECK(float(px[1].b) == 1000.0f);
    CHECK(float(px[2].b) == 3.0f);
    CHECK(float(px[4].r) == doctest::Approx(0.3f).epsilon(1e-3));
    CHECK(float(px[5].b) == 42.0f);
    CHECK(float(px[3].g) == 65504.0f);  // +inf: the largest half
    // A byte format from the same film rounds as ever.
    const std::string ppm = (dir.path / "a.ppm").string();
    REQUIRE(write_image(ppm, img).ok());
    CHECK(slurp(ppm).substr(slurp(ppm).size() - 18, 3) == std::string("\0\0\x7f", 3));
}
