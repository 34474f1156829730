// End-to-end tests of the `raytracer` command-line tool: they run the built binary
// in a temporary folder and check exit codes, messages, prompts and the files it
// writes (or, after a failure, leaves alone).
#include <doctest/doctest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "image_io.h"
#include "scene_writer.h"
#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using rt_test::kRaytracer;

// An asymmetric little scene: a red ball on the viewer's left (+y), a mirror ball on
// the right, so mirroring and the recursion limit both change the picture.
const char* const kScene = R"(// test scene
thing {
  sphere { material { colour 1 0.2 0.2 } position 5 1.2 0 radius 1 }
  sphere { material { reflection 1 scattering 0 colour 1 1 1 } position 5 -1.2 0 radius 1 }
}
special_thing {
  plane { material { colour 0.4 0.5 0.6 } point 1 0 0 -1  point 2 1 0 -1  point 3 0 1 -1  point 4 0 0 0 }
}
light { spotlight { colour 30 30 30 position 0 0 5 } }
camera { position 0 0 0 centre 1 0 0 up 1 0 1 projection 2 angle_x 60 angle_y 45 }
picture_size { x_max 32 y_max 24 }
end
)";

using rt_test::contains;
const auto read_all = rt_test::slurp;
const auto write_all = rt_test::put;
const auto quote = rt_test::shell_quote;

struct Result {
    int status = -1;
    std::string out, err;
};

// A fresh folder per test, removed afterwards, in which the binary runs.
struct TempDir : rt_test::TempDir {
    TempDir() : rt_test::TempDir("rt-cli") {}

    // Runs the binary in this folder with `args` (already shell-quoted where needed)
    // and `input` on stdin (empty input: stdin is at end of file). A `cpu_limit_s`
    // kills it (SIGXCPU) once it has used that many seconds of CPU, however long that
    // takes on the clock.
    Result run(const std::string& args, const std::string& input = "", int cpu_limit_s = 0) const {
        write_all(path / ".stdin", input);
        std::string cmd = (cpu_limit_s > 0 ? "ulimit -t " + std::to_string(cpu_limit_s) + " && " : std::string()) +
                          "cd " + quote(path.string()) + " && " + quote(kRaytracer) + " " + args +
                          " <.stdin >.stdout 2>.stderr";
        int raw = std::system(cmd.c_str());
        Result r;
        r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
        r.out = read_all(path / ".stdout");
        r.err = read_all(path / ".stderr");
        fs::remove(path / ".stdin");
        fs::remove(path / ".stdout");
        fs::remove(path / ".stderr");
        return r;
    }
};

// Width and height from a binary PPM's header, or -1 -1.
void ppm_size(const std::string& data, int& w, int& h) {
    w = h = -1;
    std::istringstream in(data);
    std::string magic;
    int maxval = 0;
    in >> magic >> w >> h >> maxval;
    if (magic != "P6" || maxval != 255) w = h = -1;
}

struct Picture {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;
    const std::uint8_t* at(int x, int y) const { return &rgb[3 * (std::size_t(y) * width + x)]; }
};

Picture load_ppm(const fs::path& p) {
    Picture pic;
    std::string err = rt::read_ppm(p.string(), pic.width, pic.height, pic.rgb).message();
    REQUIRE_MESSAGE(err.empty(), err);
    return pic;
}


// Runs the binary in `dir` with `args`, stderr into dir/.stderr; returns its pid.
pid_t start_binary(const fs::path& dir, const std::vector<const char*>& args) {
    std::vector<char*> argv{const_cast<char*>("raytracer")};
    for (const char* a : args) argv.push_back(const_cast<char*>(a));
    argv.push_back(nullptr);
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        if (chdir(dir.c_str()) != 0) _exit(99);
        if (!freopen(".stderr", "w", stderr)) _exit(99);
        execv(kRaytracer.c_str(), argv.data());
        _exit(98);
    }
    return pid;
}

// Sends `sig` to `pid` once it has a handler for it and `ready(pid)` holds (a loaded
// machine may take a while to get there), then waits for it to end: a process that
// ignored the signal would never end, and after `limit` it is killed. Whether it ended
// by itself; its wait status in `status`.
bool interrupt(pid_t pid, int sig, const std::function<bool(pid_t)>& ready, int& status,
               std::chrono::seconds limit = std::chrono::seconds(60)) {
    bool caught = false;
    for (int i = 0; i < 24000 && !caught; ++i) {
        caught = rt_test::catches_signal(pid, sig) && ready(pid);
        if (!caught) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    CHECK(caught);
    kill(pid, sig);
    const auto step = std::chrono::milliseconds(10);
    bool ended = false;
    for (std::chrono::milliseconds waited{0}; waited < limit && !ended; waited += step) {
        ended = waitpid(pid, &status, WNOHANG) == pid;
        if (!ended) std::this_thread::sleep_for(step);
    }
    if (!ended) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
    }
    return ended;
}

// Rendering: 50 ms of CPU, far more than reading the test's scene takes.
bool rendering(pid_t pid) { return rt_test::process_cpu_seconds(pid) >= 0.05; }

}  // namespace

TEST_CASE("cli: SCENE OUT.ppm renders a binary PPM of the scene's size, silently on stdout") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    Result r = dir.run("scene.txt out.ppm");
    CHECK(r.status == 0);
    CHECK(r.out.empty());
    CHECK_MESSAGE(r.err.empty(), r.err);  // stderr is not a terminal: no progress bar
    std::string data = read_all(dir / "out.ppm");
    int w, h;
    ppm_size(data, w, h);
    CHECK(w == 32);
    CHECK(h == 24);
    // Header, then exactly 3 bytes per pixel.
    CHECK(data.size() == std::string("P6\n32 24\n255\n").size() + 32 * 24 * 3);
    Picture pic = load_ppm(dir / "out.ppm");
    bool any_lit = false;
    for (auto b : pic.rgb) any_lit |= b != 0;
    CHECK(any_lit);
    CHECK(dir.files() == std::vector<std::string>{"out.ppm", "scene.txt"});
}

TEST_CASE("cli: --width and --height override the picture size; the extension is case-insensitive") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    Result r = dir.run("--width 17 --height=9 scene.txt OUT.PPM");
    REQUIRE(r.status == 0);
    int w, h;
    ppm_size(read_all(dir / "OUT.PPM"), w, h);
    CHECK(w == 17);
    CHECK(h == 9);
}

TEST_CASE("cli: OUT.png writes a PNG with the picture size in its header") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    Result r = dir.run("scene.txt out.png");
    REQUIRE(r.status == 0);
    std::string data = read_all(dir / "out.png");
    REQUIRE(data.size() > 24);
    CHECK(data.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0);
    auto be32 = [&](std::size_t at) {
        return (unsigned(std::uint8_t(data[at])) << 24) | (unsigned(std::uint8_t(data[at + 1])) << 16) |
               (unsigned(std::uint8_t(data[at + 2])) << 8) | unsigned(std::uint8_t(data[at + 3]));
    };
    CHECK(data.compare(12, 4, "IHDR") == 0);
    CHECK(be32(16) == 32);
    CHECK(be32(20) == 24);
}

TEST_CASE("cli: the same picture whatever the thread count") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    REQUIRE(dir.run("--threads 1 scene.txt one.ppm").status == 0);
    REQUIRE(dir.run("--threads 3 scene.txt three.ppm").status == 0);
    CHECK(read_all(dir / "one.ppm") == read_all(dir / "three.ppm"));
}

TEST_CASE("cli: a parse error prints FILE:LINE:COL: error:, exits 1 and leaves OUT untouched") {
    TempDir dir;
    write_all(dir / "scene.txt", "thing {\n  sphere {\n    positio 1 2 3\n    radius 1\n  }\n}\nend\n");
    const std::string sentinel = "not a picture: must survive a failed run\n";
    write_all(dir / "out.ppm", sentinel);
    Result r = dir.run("scene.txt out.ppm");
    CHECK(r.status == 1);
    CHECK_MESSAGE(contains(r.err, "scene.txt:3:5: error: "), r.err);
    CHECK(contains(r.err, "positio"));
    CHECK(r.out.empty());
    CHECK(read_all(dir / "out.ppm") == sentinel);
    CHECK(dir.files() == std::vector<std::string>{"out.ppm", "scene.txt"});  // no temp file left
}

TEST_CASE("cli: at most 20 errors are printed") {
    TempDir dir;
    std::string text = "thing {\n";
    for (int i = 0; i < 40; ++i) text += "  cube { }\n";
    text += "}\nend\n";
    write_all(dir / "scene.txt", text);
    Result r = dir.run("scene.txt out.ppm");
    CHECK(r.status == 1);
    std::size_t errors = 0;
    for (std::size_t at = 0; (at = r.err.find(": error: ", at)) != std::string::npos; ++at) ++errors;
    CHECK(errors >= 1);
    CHECK(errors <= 20);
    CHECK(!fs::exists(dir / "out.ppm"));
}

TEST_CASE("cli: warnings are printed and do not stop the render") {
    TempDir dir;
    // All-zero weights are a warning (scene-format §8); the ball renders black.
    std::string text = kScene;
    const std::string from = "material { colour 1 0.2 0.2 }";
    text.replace(text.find(from), from.size(),
                 "material { reflection 0 refraction 0 scattering 0 colour 1 0.2 0.2 }");
    write_all(dir / "scene.txt", text);
    Result r = dir.run("scene.txt out.ppm");
    CHECK(r.status == 0);
    CHECK_MESSAGE(contains(r.err, "scene.txt:3:"), r.err);
    CHECK(contains(r.err, ": warning: "));
    CHECK(fs::exists(dir / "out.ppm"));
}

TEST_CASE("cli: --check warns of negative weights, which it reads as written") {
    TempDir dir;
    std::string text = kScene;
    const std::string from = "material { colour 1 0.2 0.2 }";
    text.replace(text.find(from), from.size(), "material { reflection -0.5 refraction -1 scattering 2 colour 1 0.2 0.2 }");
    write_all(dir / "scene.txt", text);
    Result r = dir.run("--check scene.txt");
    CHECK(r.status == 0);
    CHECK_MESSAGE(contains(r.err, "warning: material reflection, refraction are negative: weights are 0 or more"),
                  r.err);
    // 0 and positive weights say nothing.
    write_all(dir / "plain.txt", kScene);
    Result plain = dir.run("--check plain.txt");
    CHECK(plain.status == 0);
    CHECK_MESSAGE(!contains(plain.err, "warning"), plain.err);
}

TEST_CASE("cli: usage and I/O errors exit 2 and write nothing") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);

    SUBCASE("an unsupported extension names the two accepted ones") {
        Result r = dir.run("scene.txt out.jpg");
        CHECK(r.status == 2);
        CHECK(contains(r.err, ".ppm"));
        CHECK(contains(r.err, ".png"));
        CHECK(!fs::exists(dir / "out.jpg"));
    }
    SUBCASE("no extension at all") {
        CHECK(dir.run("scene.txt out").status == 2);
        CHECK(!fs::exists(dir / "out"));
    }
    SUBCASE("a missing scene file") {
        Result r = dir.run("nosuch.txt out.ppm");
        CHECK(r.status == 2);
        CHECK(contains(r.err, "nosuch.txt"));
        CHECK(!fs::exists(dir / "out.ppm"));
    }
    SUBCASE("an output folder that does not exist") {
        Result r = dir.run("scene.txt nosuch/out.ppm");
        CHECK(r.status == 2);
        CHECK(contains(r.err, "nosuch"));
    }
    SUBCASE("an unknown option") {
        Result r = dir.run("--bogus scene.txt out.ppm");
        CHECK(r.status == 2);
        CHECK(contains(r.err, "--bogus"));
    }
    SUBCASE("too many arguments") { CHECK(dir.run("scene.txt a.ppm b.ppm").status == 2); }
    CHECK(dir.files() == std::vector<std::string>{"scene.txt"});
}

TEST_CASE("cli: numeric options are validated with a message naming the option") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    const char* bad[][2] = {
        {"--width", "0"},       {"--width", "16385"},  {"--height", "-3"},  {"--height", "12x"},
        {"--samples", "0"},     {"--samples", "65537"}, {"--threads", "0"}, {"--threads", "257"},
        {"--max-depth", "0"},   {"--max-depth", "1001"}, {"--width", ""},   {"--time-limit", "0"},
        {"--time-limit", "abc"}, {"--width", "99999999999999999999"}, {"--aa-threshold", "-0.1"},
        {"--aa-threshold", "3.01"}, {"--aa-threshold", "1e9"}, {"--aa-threshold", "x"}, {"--aa-threshold", ""},
    };
    for (auto& b : bad) {
        CAPTURE(b[0]);
        CAPTURE(b[1]);
        Result r = dir.run(std::string(b[0]) + " " + quote(b[1]) + " scene.txt out.ppm");
        CHECK(r.status == 2);
        CHECK(contains(r.err, b[0]));
    }
    CHECK(dir.run("scene.txt out.ppm --width").status == 2);  // value missing
    CHECK(!fs::exists(dir / "out.ppm"));
    // The limits themselves are accepted.
    CHECK(dir.run("--width 1 --height 1 --samples 2 --threads 256 --max-depth 1000 scene.txt out.ppm").status == 0);
    CHECK(dir.run("--aa-threshold 0 --samples 2 scene.txt out.ppm").status == 0);
    CHECK(dir.run("--aa-threshold 3 scene.txt out.ppm").status == 0);
    const Result r = dir.run("--aa-threshold 5 scene.txt out.ppm");
    CHECK(contains(r.err, "--aa-threshold must be between 0 and 3, got 5"));
}

TEST_CASE("cli: missing arguments are asked for on stderr and read from stdin") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);

    SUBCASE("both") {
        Result r = dir.run("", "scene.txt\nout.ppm\n");
        CHECK(r.status == 0);
        CHECK(r.out.empty());
        CHECK(contains(r.err, "Scene file"));
        CHECK(contains(r.err, "Output"));
        int w, h;
        ppm_size(read_all(dir / "out.ppm"), w, h);
        CHECK(w == 32);
    }
    SUBCASE("only the output") {
        Result r = dir.run("scene.txt", "out.png\n");
        CHECK(r.status == 0);
        CHECK(!contains(r.err, "Scene file"));
        CHECK(contains(r.err, "Output"));
        CHECK(fs::exists(dir / "out.png"));
    }
    SUBCASE("end of input at a prompt is a usage error") {
        CHECK(dir.run("").status == 2);
        CHECK(dir.run("", "scene.txt\n").status == 2);
        CHECK(dir.run("scene.txt").status == 2);
        CHECK(dir.files() == std::vector<std::string>{"scene.txt"});
    }
    SUBCASE("a prompted extension is checked too") {
        Result r = dir.run("scene.txt", "out.bmp\n");
        CHECK(r.status == 2);
        CHECK(contains(r.err, ".ppm"));
    }
}

TEST_CASE("cli: --check reports without rendering") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    write_all(dir / "bad.txt", "camera {\n  position 0 0 0 centre\n}\n");
    Result ok = dir.run("--check scene.txt");
    CHECK(ok.status == 0);
    CHECK(ok.out.empty());
    Result bad = dir.run("--check bad.txt");
    CHECK(bad.status == 1);
    CHECK_MESSAGE(contains(bad.err, "bad.txt:"), bad.err);
    CHECK(contains(bad.err, ": error: "));
    CHECK(dir.run("--check nosuch.txt").status == 2);
    CHECK(dir.files() == std::vector<std::string>{"bad.txt", "scene.txt"});
}

TEST_CASE("cli: --print-scene prints a normalised scene that reads back the same") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    Result first = dir.run("--print-scene scene.txt");
    REQUIRE(first.status == 0);
    CHECK(contains(first.out, "sphere"));
    CHECK(contains(first.out, "end"));
    write_all(dir / "printed.txt", first.out);
    Result second = dir.run("--print-scene printed.txt");
    CHECK(second.status == 0);
    CHECK(second.out == first.out);
    // And it renders the same picture as the original text.
    REQUIRE(dir.run("scene.txt a.ppm").status == 0);
    REQUIRE(dir.run("printed.txt b.ppm").status == 0);
    CHECK(read_all(dir / "a.ppm") == read_all(dir / "b.ppm"));
}

TEST_CASE("cli: --print-scene keeps includes, names and transforms; --flatten writes one whole scene") {
    TempDir dir;
    std::filesystem::create_directories(dir / "scenes" / "lib");
    write_all(dir / "scenes" / "lib" / "parts.txt",
              "define { material brass { colour 0.9 0.7 0.3 } }\n"
              "thing { box { material brass corner_1 4 -1 0 corner_2 5 0 1 rotation 0 0 10 } }\n");
    write_all(dir / "scenes" / "scene.txt",
              "include \"lib/parts.txt\"\n"
              "thing { sphere { material brass position 0 0 0 radius 0.5 scale 1 1 2 translate 5 1 1 } }\n"
              "light { lamp { position 2 3 6 colour 50 50 50 size 0.2 } }\n"
              "camera { position 0 0 1 centre 5 0 1 up 5 0 2 angle_x 60 angle_y 45 }\n"
              "picture_size { x_max 32 y_max 24 }\nend\n");
    Result printed = dir.run("--print-scene scenes/scene.txt");
    REQUIRE(printed.status == 0);
    CHECK(printed.out.rfind("include \"lib/parts.txt\"\nthing {\n  sphere {\n    material brass\n", 0) == 0);
    CHECK(contains(printed.out, "    scale 1 1 2\n    translate 5 1 1\n"));
    CHECK_FALSE(contains(printed.out, "box"));
    Result flat = dir.run("--print-scene --flatten scenes/scene.txt");
    REQUIRE(flat.status == 0);
    CHECK_FALSE(contains(flat.out, "include"));
    CHECK_FALSE(contains(flat.out, "brass"));
    CHECK(contains(flat.out, "    rotation 0 0 10\n"));
    // Both read back (the first from beside the scene, for its include), and all three
    // render the same picture.
    write_all(dir / "scenes" / "printed.txt", printed.out);
    write_all(dir / "flat.txt", flat.out);
    REQUIRE(dir.run("scenes/scene.txt a.ppm").status == 0);
    REQUIRE(dir.run("scenes/printed.txt b.ppm").status == 0);
    REQUIRE(dir.run("flat.txt c.ppm").status == 0);
    CHECK(read_all(dir / "a.ppm") == read_all(dir / "b.ppm"));
    CHECK(read_all(dir / "a.ppm") == read_all(dir / "c.ppm"));
    CHECK(dir.run("--flatten scenes/scene.txt x.ppm").status == 2);
}

TEST_CASE("cli: --help-format prints the format's reference to stdout, exit 0, with no scene") {
    TempDir dir;
    Result r = dir.run("--help-format");
    CHECK(r.status == 0);
    CHECK(r.out == rt::format_reference());
    CHECK(r.err.empty());
}

TEST_CASE("cli: --version and --help") {
    TempDir dir;
    Result v = dir.run("--version");
    CHECK(v.status == 0);
    CHECK(v.out.rfind("raytracer ", 0) == 0);
    Result h = dir.run("--help");
    CHECK(h.status == 0);
    for (const char* o : {"--width", "--height", "--samples", "--threads", "--max-depth", "--time-limit",
                          "--aa-threshold", "--mirror",
                          "--quiet", "--stats", "--check", "--print-scene", "--help-format", "--version", "--help", ".ppm", ".png"}) {
        CAPTURE(o);
        CHECK(contains(h.out, o));
    }
}

TEST_CASE("cli: --mirror gives the 2013 program's left-right mirrored picture") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    REQUIRE(dir.run("scene.txt plain.ppm").status == 0);
    REQUIRE(dir.run("--mirror scene.txt mirrored.ppm").status == 0);
    Picture a = load_ppm(dir / "plain.ppm"), b = load_ppm(dir / "mirrored.ppm");
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    CHECK(a.rgb != b.rgb);
    // The original's grid is not symmetric (column 0 sits on the half-angle edge, the
    // last column one step short of the other), so mirrored column i looks exactly
    // where plain column W - i does; column 0 has no twin.
    int differing = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 1; x < a.width; ++x)
            for (int c = 0; c < 3; ++c) differing += b.at(x, y)[c] != a.at(a.width - x, y)[c];
    CHECK(differing == 0);
    // The red ball sits at +y, the viewer's left in a right-handed z-up world: the left
    // half of the plain picture is the redder one.
    auto red_excess = [](const Picture& p, int x0, int x1) {
        long s = 0;
        for (int y = 0; y < p.height; ++y)
            for (int x = x0; x < x1; ++x) s += long(p.at(x, y)[0]) - p.at(x, y)[2];
        return s;
    };
    CHECK(red_excess(a, 0, a.width / 2) > red_excess(a, a.width / 2, a.width));
    CHECK(red_excess(b, 0, b.width / 2) < red_excess(b, b.width / 2, b.width));
}

TEST_CASE("cli: --max-depth limits recursion; --samples, --time-limit, --stats, --quiet") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    REQUIRE(dir.run("scene.txt deep.ppm").status == 0);
    REQUIRE(dir.run("--max-depth 1 scene.txt shallow.ppm").status == 0);
    // At depth 1 the mirror ball reflects nothing (a reflection costs 2 levels).
    CHECK(read_all(dir / "deep.ppm") != read_all(dir / "shallow.ppm"));

    Result s = dir.run("--samples 4 --stats --quiet scene.txt s4.ppm");
    CHECK(s.status == 0);
    CHECK(s.out.empty());
    CHECK(contains(s.err, "rays: "));
    CHECK(contains(s.err, "rays/s"));
    CHECK(contains(s.err, "4 samples"));

    // Adaptive: a threshold alone refines up to 16 samples; --stats says how it went.
    Result a = dir.run("--aa-threshold 0.1 --stats --quiet scene.txt a.ppm");
    CHECK(a.status == 0);
    CHECK(contains(a.err, "samples per pixel on average (adaptive, 0 not settled)"));
    CHECK(read_all(dir / "a.ppm") != read_all(dir / "deep.ppm"));
    REQUIRE(dir.run("--aa-threshold 0 --samples 4 scene.txt a0.ppm").status == 0);
    CHECK(read_all(dir / "a0.ppm") == read_all(dir / "s4.ppm"));  // threshold 0: every pixel, every sample

    // A time limit alone asks for up to 65536 samples: the limit, not the count, ends
    // it, after its 0.3 s (as --stats counts them; a loaded machine only lowers the count).
    Result t = dir.run("--time-limit 0.3 --stats --threads 2 scene.txt timed.ppm");
    CHECK(t.status == 0);
    CAPTURE(t.err);
    int samples = 0;
    double render_s = 0;
    const std::size_t at = t.err.find("32x24, ");
    REQUIRE(at != std::string::npos);
    CHECK(std::sscanf(t.err.c_str() + at, "32x24, %d sample", &samples) == 1);
    const std::size_t render_at = t.err.find("render ");
    REQUIRE(render_at != std::string::npos);
    CHECK(std::sscanf(t.err.c_str() + render_at, "render %lf s", &render_s) == 1);
    CHECK(samples >= 1);
    CHECK(samples < 65536);
    CHECK(render_s >= 0.3);
    int w, h;
    ppm_size(read_all(dir / "timed.ppm"), w, h);
    CHECK(w == 32);
}

TEST_CASE("cli: SIGINT or SIGTERM during a render cancels it and writes nothing") {
    for (int sig : {SIGINT, SIGTERM}) {
        CAPTURE(sig);
        TempDir dir;
        write_all(dir / "scene.txt", kScene);
        const std::string sentinel = "old picture\n";
        write_all(dir / "out.ppm", sentinel);
        // Far more work than the test waits for; the signal comes once it is under way.
        const pid_t pid = start_binary(dir.path, {"--threads", "2", "--samples", "65536", "--width", "2000",
                                                  "--height", "2000", "scene.txt", "out.ppm"});
        int status = 0;
        const bool ended = interrupt(pid, sig, rendering, status);
        REQUIRE_MESSAGE(ended, "the render did not stop within 60 s of the signal");
        REQUIRE(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) == 128 + sig);
        CHECK(contains(read_all(dir / ".stderr"), "interrupted"));
        CHECK(read_all(dir / "out.ppm") == sentinel);
        fs::remove(dir / ".stderr");
        CHECK(dir.files() == std::vector<std::string>{"out.ppm", "scene.txt"});
    }
}

TEST_CASE("cli: numbers on the command line are whole decimal tokens, as in scene files") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    for (const char* args : {"--time-limit 0x1p3", "--time-limit inf", "--time-limit nan", "--time-limit ' 2'",
                             "--time-limit 2s", "--width ' 12'", "--width 0x10", "--width '12 '", "--width 1e2",
                             "--samples +", "--threads ''", "--max-depth 5.0", "--aa-threshold 0x1p-2",
                             "--aa-threshold nan", "--aa-threshold inf", "--aa-threshold ' 0.3'"}) {
        CAPTURE(args);
        const Result r = dir.run(std::string(args) + " scene.txt out.ppm");
        CHECK(r.status == 2);
        CHECK(contains(r.err, "decimal number"));
        CHECK(contains(r.err, "--help"));
    }
    CHECK(dir.run("--width +20 --height 10 --time-limit 0.5e0 --quiet scene.txt out.ppm").status == 0);
    Picture p = load_ppm(dir / "out.ppm");
    CHECK(p.width == 20);
    CHECK(p.height == 10);
}

TEST_CASE("cli: --print-scene to a full or closed stdout says why and exits 2") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    for (const char* redirect : {">/dev/full", ">&-"}) {
        CAPTURE(redirect);
        const std::string cmd = "cd " + quote(dir.path.string()) + " && " + quote(kRaytracer) +
                                " --print-scene scene.txt " + redirect + " 2>.stderr";
        const int raw = std::system(cmd.c_str());
        CHECK((WIFEXITED(raw) && WEXITSTATUS(raw) == 2));
        CHECK(contains(read_all(dir / ".stderr"), redirect[1] == '/' ? "cannot write to standard output: No space left"
                                                                     : "cannot write to standard output: Bad file"));
    }
}

TEST_CASE("cli: UTF-16 files are named as such; Latin-1 and control bytes are escaped in messages") {
    TempDir dir;
    std::string utf16 = "\xFF\xFE";
    for (char c : std::string(kScene)) utf16 += std::string{c, '\0'};
    write_all(dir / "utf16.txt", utf16);
    Result r = dir.run("--check utf16.txt");
    CHECK(r.status == 1);
    CHECK(contains(r.err, "utf16.txt:1:1: error: the file looks like UTF-16"));
    CHECK(r.err.find('\0') == std::string::npos);
    write_all(dir / "utf16-nobom.txt", utf16.substr(2));
    r = dir.run("--check utf16-nobom.txt");
    CHECK(r.status == 1);
    CHECK(contains(r.err, "looks like UTF-16"));

    // Latin-1 "é" (0xE9) and an escape character in an unknown key.
    write_all(dir / "latin1.txt", "thing { sph\xE9re\x1B[31m { } }\nend\n");
    r = dir.run("--check latin1.txt");
    CHECK(r.status == 1);
    CHECK(contains(r.err, "\\xe9"));
    CHECK(contains(r.err, "\\x1b"));
    for (char c : r.err) CHECK((static_cast<unsigned char>(c) < 0x80 && (c >= 0x20 || c == '\n' || c == '\t')));
    // Valid UTF-8 passes through unchanged.
    write_all(dir / "utf8.txt", "thing { sph\xC3\xA9re { } }\nend\n");
    r = dir.run("--check utf8.txt");
    CHECK(contains(r.err, "sph\xC3\xA9re"));
}

TEST_CASE("cli: a FIFO as SCENE or OUT does not swallow SIGTERM or SIGINT") {
    for (int sig : {SIGTERM, SIGINT}) {
        for (const char* which : {"scene", "out"}) {
            CAPTURE(sig);
            CAPTURE(which);
            TempDir dir;
            write_all(dir / "scene.txt", kScene);
            const bool scene_fifo = which == std::string("scene");
            REQUIRE(mkfifo((dir / "fifo.ppm").c_str(), 0644) == 0);
            // Blocked in open() until somebody opens the other end, which nobody does.
            const pid_t pid = start_binary(dir.path, {"--quiet", scene_fifo ? "fifo.ppm" : "scene.txt",
                                                      scene_fifo ? "out.ppm" : "fifo.ppm"});
            int status = 0;
            const bool ended = interrupt(pid, sig, rt_test::blocked_opening_fifo, status);
            REQUIRE_MESSAGE(ended, "not ended within 60 s of the signal");
            REQUIRE(WIFEXITED(status));
            CHECK(WEXITSTATUS(status) == 128 + sig);
            CHECK(contains(read_all(dir / ".stderr"), "interrupted"));
        }
    }
}

TEST_CASE("cli: OUT names up to 255 bytes work; longer names and paths fail before rendering with the reason") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    const std::string longest = std::string(251, 'o') + ".ppm";
    Result r = dir.run("--quiet scene.txt " + longest);
    CHECK(r.status == 0);
    CHECK(load_ppm(dir / longest).width == 32);
    r = dir.run("--quiet scene.txt " + longest);  // and replacing it
    CHECK(r.status == 0);
    // Pictures of hours, refused first: a render first would be killed at 10 s of CPU,
    // which a refusal is nowhere near, however loaded the machine.
    r = dir.run("--samples 65536 --width 2000 --height 2000 scene.txt " + std::string(252, 'o') + ".ppm", "", 10);
    CHECK(r.status == 2);
    CHECK(contains(r.err, "File name too long"));
    std::string deep;
    while (deep.size() <= 4096) deep += std::string(200, 'd') + "/";
    r = dir.run("--samples 65536 --width 2000 --height 2000 scene.txt " + deep + "out.ppm", "", 10);
    CHECK(r.status == 2);
    CHECK(contains(r.err, "File name too long"));
    CHECK_FALSE(contains(r.err, "does not exist"));
    CHECK(dir.files() == std::vector<std::string>{longest, "scene.txt"});
}

TEST_CASE("cli: OUT links are followed: a dangling link creates its target, a loop fails before rendering") {
    TempDir dir;
    write_all(dir / "scene.txt", kScene);
    fs::create_symlink("target.ppm", dir / "dangling.ppm");
    Result r = dir.run("--quiet scene.txt dangling.ppm");
    CHECK(r.status == 0);
    CHECK(fs::is_symlink(dir / "dangling.ppm"));
    CHECK(load_ppm(dir / "target.ppm").width == 32);
    fs::create_symlink("loop-b.ppm", dir / "loop-a.ppm");
    fs::create_symlink("loop-a.ppm", dir / "loop-b.ppm");
    r = dir.run("--samples 65536 --width 2000 --height 2000 scene.txt loop-a.ppm", "", 10);  // (refused first)
    CHECK(r.status == 2);
    CHECK(contains(r.err, "Too many levels of symbolic links"));
    CHECK(fs::is_symlink(dir / "loop-a.ppm"));
}
