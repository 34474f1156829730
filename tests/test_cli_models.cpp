// `raytracer` on scenes whose mesh names a bad model file: for each kind of malformed
// file (truncated, wrong counts, NaN or huge coordinates, indices out of range, faces
// of two vertices, a header claiming 10^12 faces, UTF-16, a folder, /dev/zero, a
// symbolic link loop, a missing file) the message at the file name with the model's
// own line, exit status 1, and no picture written. And a good model renders.
#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using rt_test::kRaytracer;

struct Run {
    int status = -1;
    std::string err;
};

Run run_in(const fs::path& dir, const std::string& args) {
    const std::string cmd = "cd " + rt_test::shell_quote(dir.string()) + " && " + rt_test::shell_quote(kRaytracer) + " " +
                            args + " </dev/null >/dev/null 2>.stderr";
    const int raw = std::system(cmd.c_str());
    Run r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.err = rt_test::slurp(dir / ".stderr");
    fs::remove(dir / ".stderr");
    return r;
}

// A scene with the mesh's file name on line 2 at column 15.
std::string scene_naming(const std::string& file) {
    return "thing {\n  mesh { file \"" + file + "\" material { colour 0.8 0.5 0.3 } }\n}\n"
           "light { spotlight { position -4 -6 8 colour 80 80 80 } }\n"
           "camera { position 0 -5 1.5 centre 0 0 0 up 0 0 1 angle_x 50 angle_y 37.5 }\n"
           "picture_size { x_max 32 y_max 24 }\nend\n";
}

std::string binary_ply(const std::vector<float>& xyz, const std::vector<std::int32_t>& faces, std::uint64_t claimed_faces) {
    std::string s = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(xyz.size() / 3) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(claimed_faces) + "\nproperty list uchar int vertex_indices\nend_header\n";
    s.append(reinterpret_cast<const char*>(xyz.data()), xyz.size() * 4);
    for (std::size_t i = 0; i < faces.size(); i += 3) {
        s += char(3);
        s.append(reinterpret_cast<const char*>(&faces[i]), 12);
    }
    return s;
}

}  // namespace

TEST_CASE("cli: a malformed model file gives its message at the mesh's file name, exit 1, and no picture") {
    rt_test::TempDir dir("rt-cli-models");
    const std::vector<float> tri = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const std::string good_ply = binary_ply(tri, {0, 1, 2}, 1);
    std::string utf16 = "\xff\xfe";
    for (char c : std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")) utf16 += c, utf16 += '\0';
    struct Case {
        std::string file, content, message;
    };
    const std::vector<Case> cases = {
        {"truncated.ply", good_ply.substr(0, good_ply.size() - 6),
         "truncated.ply: the file ends in face 1 (truncated, or the header's counts are wrong)"},
        {"counts.ply", binary_ply(tri, {0, 1, 2}, 2),
         "counts.ply: the file ends in face 2 (truncated, or the header's counts are wrong)"},
        {"nan.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", "nan.obj:2: vertex coordinate 'nan' is not a number"},
        {"huge.obj", "v 0 0 0\nv 1 0 0\nv 0 1e40 0\nf 1 2 3\n",
         "huge.obj:3: vertex coordinate out of range (magnitude at most 1e15)"},
        {"nan.ply", binary_ply({0, 0, 0, 1, 0, 0, 0, std::nanf(""), 0}, {0, 1, 2}, 1),
         "nan.ply: vertex 3: coordinate y is not a number"},
        {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 3 2 99999\n",
         "range.obj:5: face index 99999 out of range (3 vertices)"},
        {"range.ply", binary_ply(tri, {0, 1, 3}, 1), "range.ply: face 1: face index 3 out of range (3 vertices)"},
        {"two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "two.obj:4: a face needs at least 3 vertices, this one has 2"},
        {"claims.ply", binary_ply(tri, {}, 1000000000000ull),
         "claims.ply: the header claims 1000000000000 face records, but the 0 bytes after it hold at most 0"},
        {"utf16.obj", utf16,
         "utf16.obj: the file looks like UTF-16 (it starts with a UTF-16 byte-order mark); save it as UTF-8 or ASCII"},
    };
    int n = 0;
    for (const Case& c : cases) {
        CAPTURE(c.file);
        rt_test::put(dir / c.file, c.content);
        rt_test::put(dir / ("scene" + std::to_string(n) + ".txt"), scene_naming(c.file));
        const Run r = run_in(dir.path, "scene" + std::to_string(n) + ".txt out.png");
        CHECK(r.status == 1);
        CHECK(r.err == "scene" + std::to_string(n) + ".txt:2:15: error: " + c.message + "\n");
        CHECK_FALSE(fs::exists(dir / "out.png"));
        ++n;
    }
    // Not files of bytes: a folder, a device, a link loop, nothing at all.
    fs::create_directory(dir / "folder.obj");
    fs::create_symlink("/dev/zero", dir / "zero.obj");
    fs::create_symlink("loop2.obj", dir / "loop1.obj");
    fs::create_symlink("loop1.obj", dir / "loop2.obj");
    const std::vector<std::pair<std::string, std::string>> others = {
        {"folder.obj", "folder.obj: is a folder, not a model file"},
        {"zero.obj", "zero.obj: is not a regular file (a device, pipe or socket); models are read from files"},
        {"loop1.obj", "loop1.obj: Too many levels of symbolic links"},
        {"missing.obj", "missing.obj: No such file or directory"},
    };
    for (const auto& [file, message] : others) {
        CAPTURE(file);
        rt_test::put(dir / "scene.txt", scene_naming(file));
        const Run r = run_in(dir.path, "scene.txt out.png");
        CHECK(r.status == 1);
        CHECK(r.err == "scene.txt:2:15: error: " + message + "\n");
        CHECK_FALSE(fs::exists(dir / "out.png"));
    }
}

TEST_CASE("cli: a mesh's file is found relative to the scene file's folder, wherever raytracer runs") {
    rt_test::TempDir dir("rt-cli-models");
    fs::create_directories(dir / "scenes" / "models");
    rt_test::put(dir / "scenes" / "models" / "tri.obj", "v -1 0 -1\nv 1 0 -1\nv 0 0 1\nf 1 2 3\n");
    rt_test::put(dir / "scenes" / "tri.txt", scene_naming("models/tri.obj"));
    const Run r = run_in(dir.path, "scenes/tri.txt out.ppm");
    CHECK(r.status == 0);
    CHECK(r.err.empty());
    CHECK(fs::exists(dir / "out.ppm"));
    // --check reads the model too.
    rt_test::put(dir / "scenes" / "models" / "tri.obj", "v -1 0 -1\nf 1 1 1 1 9\n");
    const Run bad = run_in(dir.path, "--check scenes/tri.txt");
    CHECK(bad.status == 1);
    CHECK(bad.err == "scenes/tri.txt:2:15: error: models/tri.obj:2: face index 9 out of range (1 vertex)\n");
}
