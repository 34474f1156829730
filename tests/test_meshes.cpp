// Triangle meshes: the model readers (OBJ, PLY in its three encodings, the malformed
// files each with its message), the watertight ray-triangle test, the mesh block in
// the parser, and pictures checked against independent references: a tetrahedron's
// faces against the tetrahedron object, icospheres of rising subdivision against the
// sphere, a placed model against the same triangles written out already placed.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "test_bvh_nesting.h"
#include "image_io.h"
#include "model.h"
#include "model_readers.h"
#include "renderer.h"
#include "scene_parser.h"
#include "shapes.h"
#include "simd.h"
#include "test_random.h"
#include "test_util.h"
#include "triangles.h"
#include "world.h"

using namespace rt;
namespace fs = std::filesystem;

namespace {

const std::string kModels = RT_SOURCE_DIR "/tests/models";

MeshData read_ok(const std::string& path) {
    MeshData m;
    ModelError e;
    INFO(path);
    REQUIRE_MESSAGE(read_model(path, m, e), e.line << ": " << e.message);
    return m;
}

// The error reading `text` as a file named `name` in `dir`.
ModelError read_error(const rt_test::TempDir& dir, const std::string& name, const std::string& text) {
    rt_test::put(dir / name, text);
    MeshData m;
    ModelError e;
    CHECK_FALSE(read_model((dir / name).string(), m, e));
    return e;
}

double area(const MeshData& m) {
    double sum = 0;
    for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
        Vec3 p[3];
        for (int k = 0; k < 3; ++k) {
            const float* v = &m.positions[3 * std::size_t(m.triangles[t + std::size_t(k)])];
            p[k] = {v[0], v[1], v[2]};
        }
        sum += 0.5 * length(cross(p[1] - p[0], p[2] - p[0]));
    }
    return sum;
}

// The triangles as corner coordinates, for comparing two readings of one model.
std::vector<float> corners(const MeshData& m) {
    std::vector<float> out;
    for (std::uint32_t v : m.triangles) out.insert(out.end(), &m.positions[3 * v], &m.positions[3 * v] + 3);
    return out;
}

// The model as OBJ text.
std::string obj_text(const MeshData& m) {
    std::string s;
    char buf[128];
    for (std::size_t i = 0; i < m.positions.size(); i += 3) {
        std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", m.positions[i], m.positions[i + 1], m.positions[i + 2]);
        s += buf;
    }
    for (std::size_t i = 0; i < m.triangles.size(); i += 3) {
        std::snprintf(buf, sizeof buf, "f %u %u %u\n", m.triangles[i] + 1, m.triangles[i + 1] + 1, m.triangles[i + 2] + 1);
        s += buf;
    }
    return s;
}

// The model as PLY bytes: "ascii", "binary_little_endian" or "binary_big_endian".
std::string ply_bytes(const MeshData& m, const std::string& format) {
    std::string s = "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(m.vertex_count()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(m.triangle_count()) + "\nproperty list uchar int vertex_indices\nend_header\n";
    const bool big = format == "binary_big_endian";
    auto put = [&](const void* p, std::size_t n) {
        std::string b(static_cast<const char*>(p), n);
        if (big) std::reverse(b.begin(), b.end());
        s += b;
    };
    char buf[128];
    for (std::size_t i = 0; i < m.positions.size(); i += 3) {
        if (format == "ascii") {
            std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g\n", m.positions[i], m.positions[i + 1], m.positions[i + 2]);
            s += buf;
        } else {
            for (int k = 0; k < 3; ++k) put(&m.positions[i + std::size_t(k)], 4);
        }
    }
    for (std::size_t i = 0; i < m.triangles.size(); i += 3) {
        if (format == "ascii") {
            std::snprintf(buf, sizeof buf, "3 %u %u %u\n", m.triangles[i], m.triangles[i + 1], m.triangles[i + 2]);
            s += buf;
        } else {
            s += char(3);
            for (int k = 0; k < 3; ++k) {
                const std::int32_t v = std::int32_t(m.triangles[i + std::size_t(k)]);
                put(&v, 4);
            }
        }
    }
    return s;
}

// An icosphere of radius 1: the icosahedron with each triangle cut in four `level`
// times, the new corners pushed out onto the sphere.
MeshData icosphere(int level) {
    MeshData m;
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& p : v) p = normalize(p);
    std::vector<std::uint32_t> f = {0, 11, 5, 0, 5,  1,  0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                    4, 11, 10, 2, 10, 7, 6,  7, 1, 8, 3, 9,  4, 3,  4,  2, 3, 2, 6, 3,
                                    6, 8,  3, 8,  9,  4, 9,  5, 2, 4, 11, 6, 2, 10, 8,  6, 7, 9, 8, 1};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
        auto middle = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(normalize((v[a] + v[b]) * 0.5));
            return mid[key] = std::uint32_t(v.size() - 1);
        };
        std::vector<std::uint32_t> g;
        for (std::size_t i = 0; i < f.size(); i += 3) {
            const std::uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
            const std::uint32_t ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
            for (std::uint32_t x : {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca}) g.push_back(x);
        }
        f.swap(g);
    }
    for (const Vec3& p : v)
        for (int k = 0; k < 3; ++k) m.positions.push_back(float(p[k]));
    m.triangles = f;
    return m;
}

std::vector<std::uint8_t> render(const std::string& text, const std::string& folder, int w, int h) {
    ParseOptions o;
    o.base_dir = folder;
    ParseResult r = parse_scene(text, o);
    INFO(text);
    REQUIRE_MESSAGE(r.ok(), r.status("scene").message());
    rt::ThreadPool renderer_pool(3);
    Renderer renderer(renderer_pool);
    RenderSettings settings;
    settings.width = w;
    settings.height = h;
    settings.coarse = false;
    renderer.start(compile_world(r.scene), settings);
    renderer.wait();
    return to_rgb8(renderer.snapshot());
}

struct Difference {
    int max = 0;
    double mean = 0;
};
Difference difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
    REQUIRE(a.size() == b.size());
    Difference d;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const int x = std::abs(int(a[i]) - int(b[i]));
        d.max = std::max(d.max, x);
        d.mean += x;
    }
    d.mean /= double(a.size());
    return d;
}

const char* const kStage =
    "special_thing { plane { material { colour 0.6 0.6 0.6 } point 1 0 0 -1 point 2 1 0 -1 point 3 0 1 -1 "
    "point 4 0 0 0 } }\n"
    "light { spotlight { position -4 -6 8 colour 80 80 80 } spotlight { position 5 3 4 colour 20 25 30 } }\n"
    "camera { position 0 -5 1.5 centre 0 0 0 up 0 0 1 angle_x 50 angle_y 37.5 }\n"
    "picture_size { x_max 160 y_max 120 }\nend\n";

}  // namespace

TEST_CASE("models: OBJ faces of four corners, normals per corner and relative indices") {
    const MeshData m = read_ok(kModels + "/cube.obj");
    CHECK(m.triangle_count() == 12);
    // Each face's corners carry the face's own normal: split into 6 x 4 vertices.
    CHECK(m.vertex_count() == 24);
    CHECK(m.normals.size() == m.positions.size());
    CHECK(area(m) == doctest::Approx(6.0));
    for (std::uint32_t v : m.triangles) CHECK(v < m.vertex_count());
}

TEST_CASE("models: PLY as ASCII, little- and big-endian binary reads to the same triangles") {
    const MeshData a = read_ok(kModels + "/cube_ascii.ply");
    const MeshData le = read_ok(kModels + "/cube_le.ply");
    const MeshData be = read_ok(kModels + "/cube_be.ply");
    CHECK(a.triangle_count() == 12);
    CHECK(a.vertex_count() == 8);
    CHECK(area(a) == doctest::Approx(6.0));
    CHECK(corners(a) == corners(le));
    CHECK(corners(a) == corners(be));
    // And the same as the OBJ cube's triangles, up to the vertices split for normals.
    CHECK(area(read_ok(kModels + "/cube.obj")) == doctest::Approx(area(a)));
}

TEST_CASE("models: the bunny reads alike from OBJ and from PLY in each encoding") {
    const MeshData obj = read_ok(RT_SOURCE_DIR "/scenes/models/bunny.obj");
    CHECK(obj.triangle_count() == 3674);
    CHECK(obj.vertex_count() == 1839);
    rt_test::TempDir dir;
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        CAPTURE(format);
        rt_test::put(dir / "bunny.ply", ply_bytes(obj, format));
        CHECK(corners(read_ok((dir / "bunny.ply").string())) == corners(obj));
    }
}

TEST_CASE("models: binary PLY records the whole-record reader leaves to the general one read alike") {
    // Vertices with normals and a byte property among them, and a quad between the
    // triangles: the whole-record reading stops at the quad and the general reader
    // goes on from there. The same model in ASCII (read by the general reader alone)
    // gives the same triangles, in either byte order.
    auto ply = [](bool ascii, bool big) {
        std::string s = std::string("ply\nformat ") + (ascii ? "ascii" : big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex 5\nproperty float x\nproperty uchar red\nproperty float y\nproperty float z\n"
                        "property float nx\nproperty float ny\nproperty float nz\nelement face 3\n"
                        "property list uchar int vertex_indices\nend_header\n";
        auto put = [&](const void* p, std::size_t n) {
            std::string b(static_cast<const char*>(p), n);
            if (big) std::reverse(b.begin(), b.end());
            s += b;
        };
        const float v[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 0.5f, 1}};
        for (const auto& p : v) {
            if (ascii) {
                s += std::to_string(p[0]) + " 7 " + std::to_string(p[1]) + " " + std::to_string(p[2]) + " 0 0 1\n";
                continue;
            }
            const float n[3] = {0, 0, 1};
            put(&p[0], 4);
            s += char(7);
            put(&p[1], 4), put(&p[2], 4);
            for (float c : n) put(&c, 4);
        }
        const std::vector<std::vector<std::int32_t>> faces = {{0, 1, 4}, {0, 1, 2, 3}, {2, 3, 4}};
        for (const auto& f : faces) {
            if (ascii) {
                s += std::to_string(f.size());
                for (std::int32_t i : f) s += " " + std::to_string(i);
                s += "\n";
                continue;
            }
            s += char(f.size());
            for (std::int32_t i : f) put(&i, 4);
        }
        return s;
    };
    rt_test::TempDir dir;
    rt_test::put(dir / "a.ply", ply(true, false));
    const MeshData a = read_ok((dir / "a.ply").string());
    CHECK(a.triangle_count() == 4);
    CHECK(a.normals.size() == 15);
    for (bool big : {false, true}) {
        CAPTURE(big);
        rt_test::put(dir / "b.ply", ply(false, big));
        const MeshData b = read_ok((dir / "b.ply").string());
        CHECK(b.triangles == a.triangles);
        CHECK(b.positions == a.positions);
        CHECK(b.normals == a.normals);
        // A bad index in a later triangle is found where it is, in either byte order.
        std::string bad = ply(false, big);
        const std::int32_t far = 5;
        std::string idx(reinterpret_cast<const char*>(&far), 4);
        if (big) std::reverse(idx.begin(), idx.end());
        bad.replace(bad.size() - 4, 4, idx);
        CHECK(read_error(dir, "bad.ply", bad).message == "face 3: face index 5 out of range (5 vertices)");
    }
}

TEST_CASE("models: polygons are cut into triangles that cover them, concave ones too") {
    // An L of six corners (area 3) and a star-like concave octagon (area 2.5).
    rt_test::TempDir dir;
    rt_test::put(dir / "l.obj", "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n");
    const MeshData l = read_ok((dir / "l.obj").string());
    CHECK(l.triangle_count() == 4);
    CHECK(area(l) == doctest::Approx(3.0));
    rt_test::put(dir / "c.obj",
                 "v 0 0 0\nv 3 0 0\nv 3 1 0\nv 1 1 0\nv 1 1.5 0\nv 3 1.5 0\nv 3 2.5 0\nv 0 2.5 0\nf 1 2 3 4 5 6 7 8\n");
    const MeshData c = read_ok((dir / "c.obj").string());
    CHECK(c.triangle_count() == 6);
    CHECK(area(c) == doctest::Approx(7.5 - 2 * 0.5));  // the box less its notch
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// A polygon's area by the shoelace formula in 3D (half the length of its vector area):
// independent of any cutting into triangles. A keyhole's slit, walked there and back,
// adds nothing; its inner ring, walked the other way round, is taken off.
double polygon_area(const std::vector<float>& pos, const std::vector<std::uint32_t>& poly) {
    Vec3 sum;
    for (std::size_t k = 0; k < poly.size(); ++k) {
        const float* a = &pos[3 * poly[k]];
        const float* b = &pos[3 * poly[(k + 1) % poly.size()]];
        sum += cross(Vec3{a[0], a[1], a[2]}, Vec3{b[0], b[1], b[2]});
    }
    return 0.5 * length(sum);
}

// The triangles' areas: signed along `normal` (overlaps and flipped triangles cancel),
// and summed whole (they do not).
struct CutArea {
    double signed_area = 0, whole = 0;
};
CutArea cut_area(const std::vector<float>& pos, const std::vector<std::uint32_t>& tris, const Vec3& normal) {
    CutArea r;
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
        Vec3 p[3];
        for (int k = 0; k < 3; ++k) {
            const float* v = &pos[3 * tris[t + std::size_t(k)]];
            p[k] = {v[0], v[1], v[2]};
        }
        const Vec3 c = cross(p[1] - p[0], p[2] - p[0]);
        r.signed_area += 0.5 * dot(c, normal);
        r.whole += 0.5 * length(c);
    }
    return r;
}

// The unit normal of a polygon's vector area.
Vec3 polygon_normal(const std::vector<float>& pos, const std::vector<std::uint32_t>& poly) {
    Vec3 sum;
    for (std::size_t k = 0; k < poly.size(); ++k) {
        const float* a = &pos[3 * poly[k]];
        const float* b = &pos[3 * poly[(k + 1) % poly.size()]];
        sum += cross(Vec3{a[0], a[1], a[2]}, Vec3{b[0], b[1], b[2]});
    }
    return normalize(sum);
}

// Cuts `poly` and checks that the triangles cover it exactly: n - 2 of them, their
// areas summing to the shoelace area with none overlapping or turned over.
void check_cut(const std::vector<float>& pos, const std::vector<std::uint32_t>& poly) {
    std::vector<std::uint32_t> tris;
    triangulate(pos, poly.data(), poly.size(), tris);
    REQUIRE(tris.size() == 3 * (poly.size() - 2));
    const double want = polygon_area(pos, poly);
    const CutArea got = cut_area(pos, tris, polygon_normal(pos, poly));
    CHECK(got.signed_area == doctest::Approx(want).epsilon(1e-5));
    CHECK(got.whole == doctest::Approx(want).epsilon(1e-5));
}

// 2D points (u, v) placed on a tilted plane in 3D, as a model's positions.
std::vector<float> on_tilted_plane(const std::vector<std::pair<double, double>>& uv) {
    const Vec3 origin{0.5, -2, 3}, eu = normalize(Vec3{1, 2, 0.5}), n = normalize(cross(eu, Vec3{0, 0.3, 1}));
    const Vec3 ev = cross(n, eu);
    std::vector<float> pos;
    for (const auto& [u, v] : uv) {
        const Vec3 p = origin + eu * u + ev * v;
        pos.insert(pos.end(), {float(p.x), float(p.y), float(p.z)});
    }
    return pos;
}

}  // namespace

TEST_CASE("models: a keyhole polygon (a ring walked around its hole by a slit) keeps its hole") {
    // Outer square 4 x 4 counter-clockwise, the slit from (0, 0) to (1, 1), the inner
    // 2 x 2 square clockwise, the slit back: area 16 - 4.
    const std::vector<float> pos =
        on_tilted_plane({{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {1, 3}, {3, 3}, {3, 1}});
    const std::vector<std::uint32_t> poly = {0, 1, 2, 3, 0, 4, 5, 6, 7, 4};
    CHECK(polygon_area(pos, poly) == doctest::Approx(12.0).epsilon(1e-5));
    check_cut(pos, poly);
    // The same with the slit's ends as vertices of their own at the same places.
    std::vector<float> twice = pos;
    twice.insert(twice.end(), pos.begin(), pos.begin() + 3);
    twice.insert(twice.end(), pos.begin() + 12, pos.begin() + 15);
    check_cut(twice, {0, 1, 2, 3, 8, 4, 5, 6, 7, 9});
}

TEST_CASE("models: concave_polygon.obj (assimp's test model) shows its keyhole") {
    const std::string path = "/usr/share/assimp/models/OBJ/concave_polygon.obj";
    if (access(path.c_str(), R_OK) != 0) {
        MESSAGE("skipped: " << path << " is not installed (assimp-testmodels)");
        return;
    }
    // The face as the file gives it, read here line by line (not by the reader).
    std::vector<float> pos;
    std::vector<std::uint32_t> poly;
    {
        const std::string text = rt_test::slurp(path);
        std::size_t at = 0;
        while (at < text.size()) {
            std::size_t end = text.find('\n', at);
            if (end == std::string::npos) end = text.size();
            const std::string line = text.substr(at, end - at);
            at = end + 1;
            if (line.rfind("v ", 0) == 0) {
                float x, y, z;
                REQUIRE(std::sscanf(line.c_str(), "v %f %f %f", &x, &y, &z) == 3);
                pos.insert(pos.end(), {x, y, z});
            } else if (line.rfind("f ", 0) == 0) {
                for (std::size_t k = 2; k < line.size();) {
                    poly.push_back(std::uint32_t(std::stoul(line.substr(k))) - 1);
                    k = line.find(' ', k);
                    if (k == std::string::npos) break;
                    ++k;
                }
            }
        }
    }
    REQUIRE(poly.size() == 66);
    check_cut(pos, poly);
    // The keyhole's area is 0.2455 (in the file's units), a seventh of the disc it is
    // cut from (the extent in z is the disc's diameter), which a fan would fill.
    CHECK(polygon_area(pos, poly) == doctest::Approx(0.24550).epsilon(1e-3));
    float lo = 1e9f, hi = -1e9f;
    for (std::size_t i = 2; i < pos.size(); i += 3) lo = std::min(lo, pos[i]), hi = std::max(hi, pos[i]);
    const double disc = kPi * 0.25 * double(hi - lo) * double(hi - lo);
    CHECK(polygon_area(pos, poly) / disc == doctest::Approx(0.142).epsilon(0.02));
    // And the reader cuts it so (one face: the same area).
    const MeshData m = read_ok(path);
    CHECK(m.triangle_count() == 64);
    CHECK(area(m) == doctest::Approx(polygon_area(pos, poly)).epsilon(1e-5));
}

TEST_CASE("models: random star-shaped polygons are cut into triangles that cover them exactly") {
    rt_test::Rng rng(2041);
    for (int round = 0; round < 200; ++round) {
        CAPTURE(round);
        // Corners at rising angles, one in each of n equal slices (so no gap between
        // them reaches half a turn and the centre is inside: a simple polygon), at
        // random distances from the centre: concave wherever a corner comes nearer
        // than its neighbours.
        const int n = 4 + int(rng.uni() * 40);
        std::vector<std::pair<double, double>> uv;
        for (int k = 0; k < n; ++k) {
            const double a = (k + 0.9 * rng.uni()) * 2 * kPi / n;
            const double r = 0.2 + rng.uni();
            uv.push_back({r * std::cos(a), r * std::sin(a)});
        }
        std::vector<std::uint32_t> poly(static_cast<std::size_t>(n));
        for (int k = 0; k < n; ++k) poly[std::size_t(k)] = std::uint32_t(round % 2 ? n - 1 - k : k);  // either way round
        check_cut(on_tilted_plane(uv), poly);
    }
}

TEST_CASE("models: a convex polygon is cut as it always was: every picture of a model stays the same") {
    // A convex pentagon: the ear at the first corner, then at the next, then the
    // three corners left (4 0 1, 4 1 2, 2 3 4).
    const std::vector<float> pos = on_tilted_plane({{0, 0}, {2, 0}, {3, 1.5}, {1, 3}, {-1, 1.5}});
    std::vector<std::uint32_t> tris;
    triangulate(pos, std::vector<std::uint32_t>{0, 1, 2, 3, 4}.data(), 5, tris);
    CHECK(tris == std::vector<std::uint32_t>{4, 0, 1, 4, 1, 2, 2, 3, 4});
}

TEST_CASE("models: degenerate and self-crossing polygons give n - 2 triangles and end") {
    auto cut = [](const std::vector<float>& pos, const std::vector<std::uint32_t>& poly) {
        std::vector<std::uint32_t> tris;
        triangulate(pos, poly.data(), poly.size(), tris);
        CHECK(tris.size() == 3 * (poly.size() - 2));
        for (std::uint32_t v : tris) CHECK(std::find(poly.begin(), poly.end(), v) != poly.end());
    };
    // All on a line; all at one point; a bow tie; a pentagram; corners repeated.
    cut(on_tilted_plane({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}}), {0, 1, 2, 3, 4, 5});
    cut(on_tilted_plane({{1, 1}, {1, 1}, {1, 1}, {1, 1}}), {0, 1, 2, 3});
    cut(on_tilted_plane({{0, 0}, {1, 1}, {1, 0}, {0, 1}}), {0, 1, 2, 3});
    std::vector<std::pair<double, double>> star;
    for (int k = 0; k < 5; ++k) star.push_back({std::cos(k * 4 * kPi / 5), std::sin(k * 4 * kPi / 5)});
    cut(on_tilted_plane(star), {0, 1, 2, 3, 4});
    cut(on_tilted_plane({{0, 0}, {1, 0}, {1, 1}}), {0, 1, 1, 2, 2, 0, 0});
    // A square with a corner in the middle of each side (collinear corners): covered.
    check_cut(on_tilted_plane({{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}), {0, 1, 2, 3, 4, 5, 6, 7});
    // Past the ear clipping's size: a fan, at once.
    std::vector<std::pair<double, double>> many;
    for (int k = 0; k < 2000; ++k) many.push_back({std::cos(k * 2 * kPi / 2000), std::sin(k * 2 * kPi / 2000)});
    std::vector<std::uint32_t> all(2000);
    for (std::uint32_t k = 0; k < 2000; ++k) all[k] = k;
    cut(on_tilted_plane(many), all);
}

TEST_CASE("models: every malformed file gets its message, with the line where it has lines") {
    rt_test::TempDir dir;
    struct Case {
        const char* name;
        std::string text;
        long line;
        const char* message;
    };
    const std::string header = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                               "property float y\nproperty float z\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n";
    std::string good_ply = header;
    for (float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) good_ply.append(reinterpret_cast<const char*>(&x), 4);
    good_ply += char(3);
    for (std::int32_t i : {0, 1, 2}) good_ply.append(reinterpret_cast<const char*>(&i), 4);
    std::string nan_ply = good_ply;
    const float nan = std::nanf("");
    std::memcpy(&nan_ply[header.size() + 4], &nan, 4);
    std::string range_ply = good_ply;
    const std::int32_t big = 99999;
    std::memcpy(&range_ply[good_ply.size() - 4], &big, 4);
    // The first index past the end: a check of <= instead of < would let it through
    // and the renderer read past the vertices.
    std::string edge_ply = good_ply;
    const std::int32_t three = 3;
    std::memcpy(&edge_ply[good_ply.size() - 4], &three, 4);
    std::string utf16 = "\xff\xfe";
    for (char ch : std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")) utf16 += ch, utf16 += '\0';
    const std::vector<Case> cases = {
        {"range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99999\n", 5, "face index 99999 out of range (3 vertices)"},
        {"before.obj", "v 0 0 0\nf -2 -1 1\n", 2, "vertex index -2 out of range (1 vertex before it)"},
        {"edge.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 4, "face index 4 out of range (3 vertices)"},
        {"index0.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4, "vertex index 0 (OBJ counts from 1) or not a number"},
        {"two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n", 3, "a face needs at least 3 vertices, this one has 2"},
        {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", 2, "vertex coordinate 'nan' is not a number"},
        {"huge.obj", "v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n", 2, "vertex coordinate out of range (magnitude at most 1e15)"},
        {"short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", 2, "a vertex needs 3 coordinates, this one has 2"},
        {"wrap.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4294967297\n", 4, "a face index is out of range"},
        {"empty.obj", "# nothing\n", 0, "the file holds no triangles"},
        {"utf16.obj", utf16, 0, "the file looks like UTF-16 (it starts with a UTF-16 byte-order mark); save it as UTF-8 or ASCII"},
        {"truncated.ply", good_ply.substr(0, good_ply.size() - 5), 0, "the file ends in face 1 (truncated, or the header's counts are wrong)"},
        {"nan.ply", nan_ply, 0, "vertex 1: coordinate y is not a number"},
        {"range.ply", range_ply, 0, "face 1: face index 99999 out of range (3 vertices)"},
        {"edge.ply", edge_ply, 0, "face 1: face index 3 out of range (3 vertices)"},
        // Found by fuzz_ply: the message converted the index to a 64-bit integer.
        {"bigindex.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                         "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                         "3 0 1 888888888888888888888888\n",
         13, "face index 8.88889e+23 out of range (3 vertices)"},
        {"edge_ascii.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
         13, "face index 3 out of range (3 vertices)"},
        {"huge.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                     "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1e300 0 0\n0 1 0\n3 0 1 2\n",
         11, "coordinate x is out of range (magnitude at most 1e15)"},
        {"two.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
         13, "a face needs at least 3 vertices, this one has 2"},
        {"claims.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                       "property float z\nelement face 1000000000000\nproperty list uchar int vertex_indices\nend_header\n" +
                           std::string(36, '\0'),
         0, "the header claims 1000000000000 face records, but the 0 bytes after it hold at most 0"},
        {"counts.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                       "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         13, "a face needs at least 3 vertices, this one has 2"},  // its last vertex took "3 0 1"
        {"text.ply", "hello\n", 0, "not a PLY file (it does not start with 'ply')"},
        {"model.stl", "solid x\n", 0, "unknown model format '.stl' (expected a .obj or .ply file)"},
    };
    for (const Case& c : cases) {
        CAPTURE(c.name);
        const ModelError e = read_error(dir, c.name, c.text);
        CHECK(e.message == c.message);
        CHECK(e.line == c.line);
    }
    // Not files of bytes at all.
    MeshData m;
    ModelError e;
    fs::create_directory(dir / "folder.obj");
    CHECK_FALSE(read_model((dir / "folder.obj").string(), m, e));
    CHECK(e.message == "is a folder, not a model file");
    fs::create_symlink("/dev/zero", dir / "zero.obj");
    CHECK_FALSE(read_model((dir / "zero.obj").string(), m, e));
    CHECK(e.message == "is not a regular file (a device, pipe or socket); models are read from files");
    fs::create_symlink(dir / "loop2.obj", dir / "loop1.obj");
    fs::create_symlink(dir / "loop1.obj", dir / "loop2.obj");
    CHECK_FALSE(read_model((dir / "loop1.obj").string(), m, e));
    CHECK(e.message == "Too many levels of symbolic links");
    CHECK_FALSE(read_model((dir / "missing.obj").string(), m, e));
    CHECK(e.message == "No such file or directory");
}

TEST_CASE("models: Debian's assimp test models read, or are refused with a message, never crash") {
    const fs::path root = "/usr/share/assimp/models";
    if (!fs::exists(root)) {
        MESSAGE("assimp-testmodels is not installed: skipped");
        return;
    }
    int read = 0, refused = 0;
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        const std::string ext = e.path().extension().string();
        if (ext != ".obj" && ext != ".ply" && ext != ".OBJ" && ext != ".PLY") continue;
        CAPTURE(e.path().string());
        MeshData m;
        ModelError err;
        if (read_model(e.path().string(), m, err)) {
            ++read;
            for (std::uint32_t v : m.triangles) REQUIRE(v < m.vertex_count());
        } else {
            ++refused;
            CHECK(!err.message.empty());
        }
    }
    MESSAGE(read << " read, " << refused << " refused");
    CHECK(read >= 10);
    // The ordinary ones among them.
    for (const char* name : {"OBJ/box.obj", "OBJ/spider.obj", "OBJ/WusonOBJ.obj", "PLY/cube.ply", "PLY/cube_binary.ply",
                             "PLY/Wuson.ply"})
        if (fs::exists(root / name)) CHECK(read_ok((root / name).string()).triangle_count() > 0);
    MeshData m;
    ModelError err;
    if (fs::exists(root / "OBJ/box_UTF16BE.obj")) {
        CHECK_FALSE(read_model((root / "OBJ/box_UTF16BE.obj").string(), m, err));
        CHECK(rt_test::contains(err.message, "UTF-16"));
    }
}

// ---- the triangle test ----------------------------------------------------------

namespace {
// The plain test (Moeller and Trumbore) in long double: t, and the barycentric
// coordinates' distance from the triangle's edges.
bool plain_hit(const Vec3& o, const Vec3& d, const Vec3 v[3], long double& t, long double& margin) {
    typedef long double L;
    const L e1[3] = {L(v[1].x) - v[0].x, L(v[1].y) - v[0].y, L(v[1].z) - v[0].z};
    const L e2[3] = {L(v[2].x) - v[0].x, L(v[2].y) - v[0].y, L(v[2].z) - v[0].z};
    const L p[3] = {d.y * e2[2] - d.z * e2[1], d.z * e2[0] - d.x * e2[2], d.x * e2[1] - d.y * e2[0]};
    const L det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0) return false;
    const L s[3] = {L(o.x) - v[0].x, L(o.y) - v[0].y, L(o.z) - v[0].z};
    const L u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    const L q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
    const L w = (d.x * q[0] + d.y * q[1] + d.z * q[2]) / det;
    t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    margin = std::min({u, w, 1 - u - w});
    return margin >= 0;
}
}  // namespace

TEST_CASE("triangles: the watertight test finds the plain test's hits and distances") {
    rt_test::Rng rng(2718);
    int hits = 0, compared = 0;
    for (int i = 0; i < 20000; ++i) {
        TriBlock b{};
        Vec3 v[3];
        for (int k = 0; k < 3; ++k) {
            v[k] = {float(rng.uni(-2, 2)), float(rng.uni(-2, 2)), float(rng.uni(-2, 2))};
            for (int a = 0; a < 3; ++a) b.v[3 * k + a][0] = float(v[k][a]);
        }
        const Vec3 o{rng.uni(-5, 5), rng.uni(-5, 5), rng.uni(-5, 5)};
        const Vec3 target{rng.uni(-2, 2), rng.uni(-2, 2), rng.uni(-2, 2)};
        const Vec3 d = (target - o) * rng.uni(0.1, 3);  // not unit: t in these units
        long double t = 0, margin = 0;
        const bool plain = plain_hit(o, d, v, t, margin);
        const double w = tri_intersect(TriRay::make(o, d), b, 0);
        if (std::fabs(double(margin)) < 1e-9) continue;  // at an edge: either answer is right there
        ++compared;
        CHECK(plain == !std::isnan(w));
        if (plain && !std::isnan(w)) {
            ++hits;
            CHECK(double(std::fabs(t - w)) <= 1e-12 * (1 + std::fabs(double(t))));
        }
    }
    CHECK(hits > 1000);
    CHECK(compared > 19000);
}

using rt_test::boxes_nested;

// Big nodes (8192+ triangles) are binned a run of triangles with the same bin at a
// time: a closed sphere of 20480 triangles and a height field of 20000 listed row by
// row (long runs) give the plain test's nearest triangle and distance for every ray
// whose nearest hit is clear of edges and of other triangles' distances.
TEST_CASE("triangles: big models' trees give the nearest hits of trying every triangle") {
    MeshData field;
    const int n = 100;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            for (const double c : {i * 0.1 - 5, j * 0.1 - 5, 0.3 * std::sin(i * 0.37) * std::cos(j * 0.23)})
                field.positions.push_back(float(c));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
            for (const std::uint32_t v : {a, b, d, a, d, c}) field.triangles.push_back(v);
        }
    for (const MeshData& m : {icosphere(5), field}) {
        REQUIRE(m.triangle_count() >= 20000);
        const TriangleAccel acc = TriangleAccel::build(m);
        // Every triangle inside its leaf's box, every box inside its parent's: the
        // bins held all the triangles. (A block's unused lanes are zero.)
        const int bad = boxes_nested(acc.bvh.nodes, [&](std::uint32_t s, const float* box) {
            const TriBlock& b = acc.blocks[s / 4];
            bool unused = true;
            for (int r = 0; r < 9; ++r) unused = unused && b.v[r][s % 4] == 0;
            if (unused) return true;
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a)
                    if (!(box[a] <= b.v[3 * k + a][s % 4] && b.v[3 * k + a][s % 4] <= box[3 + a])) return false;
            return true;
        });
        CHECK(bad == 0);
        rt_test::Rng rng(99);
        int compared = 0, hits = 0;
        for (int r = 0; r < 250; ++r) {
            const Vec3 o{rng.uni(-6, 6), rng.uni(-6, 6), rng.uni(1.5, 4)};
            const Vec3 d = Vec3{rng.uni(-1.2, 1.2), rng.uni(-1.2, 1.2), rng.uni(-0.5, 0.5)} - o;
            long double best = HUGE_VALL, second = HUGE_VALL, best_margin = 0;
            std::uint32_t best_id = 0;
            for (std::uint32_t t = 0; t < m.triangle_count(); ++t) {
                Vec3 v[3];
                for (int k = 0; k < 3; ++k) {
                    const std::uint32_t i = m.triangles[3 * std::size_t(t) + std::size_t(k)];
                    v[k] = {m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]};
                }
                long double t_hit = 0, margin = 0;
                if (!plain_hit(o, d, v, t_hit, margin) || t_hit <= 0) continue;
                if (t_hit < best) second = best, best = t_hit, best_id = t, best_margin = margin;
                else if (t_hit < second) second = t_hit;
            }
            if (best < HUGE_VALL && (best_margin < 1e-6 || second - best < 1e-6)) continue;  // an edge, or a near tie
            ++compared;
            TriHit h;
            const bool hit = acc.nearest(TriRay::make(o, d), 0, HUGE_VAL, h);
            CHECK(hit == (best < HUGE_VALL));
            if (hit && best < HUGE_VALL) {
                ++hits;
                CHECK(acc.ids[h.slot] == best_id);
                CHECK(std::fabs(h.t - double(best)) <= 1e-9 * (1 + double(best)));
            }
        }
        CHECK(compared > 200);
        CHECK(hits > 150);
    }
}

// Found by fuzz_ply: centres a few denormals apart made the binned build's scale
// infinite, and 0 * inf a NaN bin number (undefined behaviour: the sanitizer build of
// these tests reports it). Every triangle must still be found.
TEST_CASE("triangles: a model whose triangles lie denormals apart builds and answers rays") {
    MeshData m;
    const float tiny = std::numeric_limits<float>::denorm_min();
    for (int k = 0; k < 64; ++k) {
        const float x = float(k % 8) * tiny, z = float(k);
        for (const float p : {x, 0.f, z, x, 1.f, z, x, 0.f, z + 1.f}) m.positions.push_back(p);
        for (int c = 0; c < 3; ++c) m.triangles.push_back(std::uint32_t(3 * k + c));
    }
    const TriangleAccel acc = TriangleAccel::build(m, 1);
    int found = 0;
    for (int k = 0; k < 64; ++k) {
        TriHit h{-1, 0};
        const bool hit = acc.nearest(TriRay::make({1, 0.25, k + 0.25}, {-1, 0, 0}), 0, HUGE_VAL, h);
        found += hit && acc.ids[h.slot] == std::uint32_t(k) && std::fabs(h.t - 1) < 1e-9;
    }
    CHECK(found == 64);
}

TEST_CASE("triangles: rays aimed exactly at a closed mesh's shared edges and corners never pass through") {
    const MeshData m = icosphere(3);
    const TriangleAccel acc = TriangleAccel::build(m);
    rt_test::Rng rng(31);
    auto vertex = [&](std::uint32_t i) { return Vec3{m.positions[3 * i], m.positions[3 * i + 1], m.positions[3 * i + 2]}; };
    std::vector<Vec3> targets;
    for (std::uint32_t i = 0; i < m.vertex_count(); ++i) targets.push_back(vertex(i));
    for (std::size_t t = 0; t < m.triangles.size(); t += 3)
        for (int k = 0; k < 3; ++k) {  // points along each edge, the midpoint among them
            const Vec3 a = vertex(m.triangles[t + std::size_t(k)]), b = vertex(m.triangles[t + std::size_t((k + 1) % 3)]);
            targets.push_back(a + (b - a) * 0.5);
            targets.push_back(a + (b - a) * 0.25);
        }
    int misses = 0, rays = 0;
    for (const Vec3& p : targets) {
        // From inside (the centre, and a point off it), the ray through p must meet the
        // surface: a leak at p would let it out. From outside, coming in about along the
        // normal at p, it must meet the surface by p and, from just past it, leave again.
        // (A ray from anywhere outside may rightly only graze a corner or an edge.)
        const Vec3 outside = p * 3.0 + Vec3{rng.uni(-0.3, 0.3), rng.uni(-0.3, 0.3), rng.uni(-0.3, 0.3)};
        for (const Vec3& o : {Vec3{0, 0, 0}, Vec3{0.1, -0.2, 0.15}, outside}) {
            const Vec3 d = p - o;
            TriHit h;
            ++rays;
            if (!acc.nearest(TriRay::make(o, d), 0, HUGE_VAL, h) || h.t > 1 + 1e-9) {
                ++misses;
                continue;
            }
            if (o == outside) {
                TriHit out;
                ++rays;
                misses += !acc.nearest(TriRay::make(o + d * (h.t + 1e-6), d), 0, HUGE_VAL, out);
            }
        }
    }
    CHECK(rays > 10000);
    CHECK(misses == 0);
}

namespace {
// A wide tree's shape: every slot of the model in exactly one leaf, no inner node with
// fewer than two children, and the children per node on average.
template <class Node, int W>
double children_per_node(const Chunked<Node>& nodes, std::size_t slots) {
    std::vector<int> seen(slots, 0), entered(nodes.size(), 0);
    std::size_t kids = 0;
    int thin = 0;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        int k = 0;
        for (int j = 0; j < W; ++j) {
            const std::uint32_t c = nodes[i].child[j];
            if (c == BvhNode::kEmpty) continue;
            ++k;
            if (!BvhNode::is_leaf(c)) {
                REQUIRE(c < nodes.size());
                ++entered[c];
                continue;
            }
            for (std::uint32_t s = BvhNode::leaf_first(c); s < BvhNode::leaf_first(c) + BvhNode::leaf_count(c); ++s)
                ++seen[s];
        }
        thin += k < 2;
        kids += std::size_t(k);
    }
    CHECK(thin == 0);
    // Every node but the root is one node's child; every slot in one leaf at most (the
    // slots in none are the unused lanes of blocks).
    CHECK(entered[0] == 0);
    CHECK(std::count(entered.begin() + 1, entered.end(), 1) == std::ptrdiff_t(nodes.size() - 1));
    CHECK(std::count_if(seen.begin(), seen.end(), [](int n) { return n > 1; }) == 0);
    CHECK(std::size_t(std::count(seen.begin(), seen.end(), 1)) > slots * 3 / 4);
    return double(kids) / double(nodes.size());
}
}  // namespace

// The wide nodes are chosen for the least total area of their boxes: with leaves of
// four to eight triangles the nodes come nearly full, where opening each node's
// largest children first left 8-wide nodes with about four children.
TEST_CASE("triangles: the wide trees hold every leaf once in well-filled nodes") {
    const Isa saved = active_isa();
    const MeshData m = read_ok(RT_SOURCE_DIR "/scenes/models/bunny.obj");
    for (Isa isa : {Isa::Sse2, Isa::Avx2}) {
        if (!isa_supported(isa)) continue;
        REQUIRE(set_isa(isa));
        const TriangleAccel acc = TriangleAccel::build(m);
        REQUIRE(acc.bvh.nodes.size() > 100);
        CHECK(children_per_node<BvhNode, 4>(acc.bvh.nodes, acc.ids.size()) > 3.3);
        if (isa == Isa::Avx2) CHECK(children_per_node<BvhNode8, 8>(acc.bvh.nodes8, acc.ids.size()) > 5.5);
    }
    set_isa(saved);
}

#if RT_HAVE_AVX2_KERNELS
// Skipped where the processor lacks AVX2 (ctest's isa_avx2 entry runs it).
TEST_CASE("triangles: the four-lane AVX2 test and walk give the scalar one's hits bit for bit" *
          doctest::skip(!isa_supported(Isa::Avx2))) {
    const Isa saved = active_isa();
    REQUIRE(set_isa(Isa::Avx2));
    const MeshData m = read_ok(RT_SOURCE_DIR "/scenes/models/bunny.obj");
    const TriangleAccel acc = TriangleAccel::build(m);
    CHECK(!acc.bvh.nodes8.empty());
    rt_test::Rng rng(5);
    std::vector<TriRay> rays;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 o{rng.uni(-8, 8), rng.uni(-2, 12), rng.uni(-8, 8)};
        const Vec3 at{rng.uni(-4, 4), rng.uni(0, 9), rng.uni(-3, 3)};
        rays.push_back(TriRay::make(o, at - o));
    }
    auto trace = [&] {
        std::vector<TriHit> out;
        for (const TriRay& r : rays) {
            TriHit h{-1, 0};
            if (!acc.nearest(r, 0, HUGE_VAL, h)) h = {-1, 0};
            out.push_back(h);
        }
        return out;
    };
    const std::vector<TriHit> wide = trace();
    REQUIRE(set_isa(Isa::Sse2));
    const std::vector<TriHit> scalar = trace();
    set_isa(saved);
    int hits = 0, same = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits += wide[i].t >= 0;
        same += std::memcmp(&wide[i].t, &scalar[i].t, sizeof(double)) == 0 && wide[i].slot == scalar[i].slot;
    }
    CHECK(hits > 3000);
    CHECK(same == int(rays.size()));
}
#endif

// ---- the mesh block ---------------------------------------------------------------

TEST_CASE("mesh: the parser reads the model once per file and reports its errors at the file name") {
    rt_test::TempDir dir;
    rt_test::put(dir / "bad model.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    rt_test::put(dir / "tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string tail = "camera { position 0 0 5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 8 y_max 8 }\nend\n";
    ParseOptions o;
    o.base_dir = dir.path.string();
    ParseResult r = parse_scene("thing {\n  mesh { file \"bad model.obj\" }\n}\n" + tail, o);
    REQUIRE(r.diagnostics.size() == 1);
    CHECK(r.diagnostics[0].line == 2);
    CHECK(r.diagnostics[0].col == 15);
    CHECK(r.diagnostics[0].message == "bad model.obj:4: face index 7 out of range (3 vertices)");
    // The same file under every mesh: one model.
    std::string many = "thing {\n";
    for (int i = 0; i < 1000; ++i) many += "  mesh { file tri.obj position " + std::to_string(i) + " 0 0 }\n";
    r = parse_scene(many + "}\n" + tail, o);
    REQUIRE(r.ok());
    REQUIRE(r.scene.objects.size() == 1000);
    const MeshModel* first = std::get<Mesh>(r.scene.objects[0].shape).model.get();
    REQUIRE(first != nullptr);
    for (const Object& ob : r.scene.objects) CHECK(std::get<Mesh>(ob.shape).model.get() == first);
    // Compiled, the instances share the model's triangles too.
    const auto world = compile_world(r.scene);
    CHECK(world->geometry->model_bytes() < 4096);
}

TEST_CASE("mesh: a thousand model files, and a clear error past the limit of files") {
    rt_test::TempDir dir;
    std::string scene = "thing {\n";
    for (std::size_t i = 0; i <= ModelLimits::max_files; ++i) {
        const std::string name = "m" + std::to_string(i) + ".obj";
        rt_test::put(dir / name, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        scene += "  mesh { file " + name + " position " + std::to_string(i % 100) + " " + std::to_string(i / 100) + " 0 }\n";
        if (i + 1 == 1000) {
            ParseOptions o;
            o.base_dir = dir.path.string();
            ParseResult r = parse_scene(scene + "}\ncamera { position 50 -50 50 centre 50 50 0 up 50 50 1 angle_x 60 "
                                                "angle_y 45 }\npicture_size { x_max 8 y_max 8 }\nend\n",
                                        o);
            REQUIRE(r.ok());
            REQUIRE(r.scene.objects.size() == 1000);
            // Each its own model, and each found where it was placed in the world.
            std::set<const MeshModel*> models;
            for (const Object& ob : r.scene.objects) models.insert(std::get<Mesh>(ob.shape).model.get());
            CHECK(models.size() == 1000);
            CHECK(models.count(nullptr) == 0);
            const auto world = compile_world(r.scene);
            int found = 0;
            for (int k = 0; k < 1000; ++k) {
                const PickResult p = pick(*world, Ray{{k % 100 + 0.2, k / 100 + 0.2, 5}, {0, 0, -1}});
                found += p.hit && p.object == k && std::fabs(p.t - 5) < 1e-9;
            }
            CHECK(found == 1000);
        }
    }
    ParseOptions o;
    o.base_dir = dir.path.string();
    ParseResult r = parse_scene(scene + "}\ncamera { position 0 0 5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
                                        "picture_size { x_max 8 y_max 8 }\nend\n",
                                o);
    REQUIRE(!r.ok());
    CHECK(r.diagnostics.back().message == "too many model files (limit 10000)");
}

TEST_CASE("mesh: block errors, file names with and without quotes, and no mesh in a CSG") {
    const std::string tail = "camera { position 0 0 5 centre 0 0 0 up 0 1 0 angle_x 60 angle_y 45 }\n"
                             "picture_size { x_max 8 y_max 8 }\nend\n";
    ParseOptions o;
    o.read_models = false;
    // The first error about the key (a file name's problem also leaves the block
    // without one, which is reported too, at the block's name).
    auto first_error = [&](const std::string& things) {
        ParseResult r = parse_scene("thing {\n" + things + "\n}\n" + tail, o);
        for (const Diagnostic& d : r.diagnostics)
            if (d.col > 1 || r.diagnostics.size() == 1) return d.message;
        return std::string();
    };
    CHECK(first_error("mesh { position 1 2 3 }") == "mesh needs a 'file' (the model to show)");
    CHECK(first_error("mesh { file a.obj scale 1 0 1 }") == "mesh scale must not be 0 on any axis");
    CHECK(first_error("mesh { file a.obj smooth 2 }") == "smooth must be 0 (flat triangles) or 1 (smooth)");
    CHECK(first_error("mesh { file \"a.obj }") == "the file name has no closing quote on its line");
    CHECK(first_error("mesh { file \"a.obj\"x }") == "expected a space after the file name's closing quote");
    CHECK(first_error("mesh { file \"\" }") == "the file name is empty");
    CHECK(first_error("mesh { file { } }") == "expected a file name in double quotes after 'file', got '{'");
    CHECK(first_error("constructive_solid_geometry { left { mesh { file a.obj } } right { sphere { } } }") ==
          "a mesh cannot be a CSG operand: CSG combines solids (sphere, tetrahedron, cylinder, torus, box, "
          "cone, constructive_solid_geometry)");
    ParseResult r = parse_scene("thing { mesh { file \"my models/a b.obj\" scale 2 } mesh { file c.ply scale 1 2 3 } }\n" + tail, o);
    REQUIRE(r.ok());
    CHECK(std::get<Mesh>(r.scene.objects[0].shape).file == "my models/a b.obj");
    CHECK(std::get<Mesh>(r.scene.objects[0].shape).scale == Vec3{2, 2, 2});
    CHECK(std::get<Mesh>(r.scene.objects[1].shape).file == "c.ply");
    CHECK(std::get<Mesh>(r.scene.objects[1].shape).scale == Vec3{1, 2, 3});
}

TEST_CASE("mesh: a tetrahedron's four faces render like the tetrahedron with the same corners") {
    rt_test::TempDir dir;
    // Corners whose coordinates are floats exactly, as a model file holds them; the
    // faces wound every which way (the surface is lit on whichever side is seen).
    rt_test::put(dir / "tetra.obj", "v -1 -0.75 -1\nv 1.25 -0.5 -1\nv 0 1 -1\nv 0.25 0 1.5\nf 1 2 3\nf 1 4 2\nf 2 4 3\nf 3 1 4\n");
    const std::string corners = "vect1 -1 -0.75 -1 vect2 1.25 -0.5 -1 vect3 0 1 -1 vect4 0.25 0 1.5";
    for (const char* material : {"{ colour 0.9 0.5 0.2 }", "{ reflection 0.6 scattering 0.4 colour 0.9 0.9 0.9 }",
                                 "{ refraction 0.8 scattering 0.2 translusans 0.7 refractive_index 1.4 colour 0.8 1 0.9 }"}) {
        CAPTURE(material);
        const auto solid = render("thing { tetrahedron { " + corners + " material " + material + " } }\n" + kStage,
                                  dir.path.string(), 160, 120);
        const auto mesh = render("thing { mesh { file tetra.obj material " + std::string(material) + " } }\n" + kStage,
                                 dir.path.string(), 160, 120);
        const Difference d = difference(solid, mesh);
        CHECK(d.max <= 1);
    }
}

TEST_CASE("mesh: icospheres of rising subdivision converge to the sphere's picture") {
    rt_test::TempDir dir;
    const auto sphere = render("thing { sphere { position 0 0 0 radius 1 material { colour 0.9 0.5 0.2 } } }\n" + std::string(kStage),
                               dir.path.string(), 160, 120);
    double last = HUGE_VAL;
    for (int level = 1; level <= 5; ++level) {
        CAPTURE(level);
        rt_test::put(dir / "ico.obj", obj_text(icosphere(level)));
        const auto mesh = render("thing { mesh { file ico.obj smooth 1 material { colour 0.9 0.5 0.2 } } }\n" + std::string(kStage),
                                 dir.path.string(), 160, 120);
        const Difference d = difference(sphere, mesh);
        MESSAGE("level " << level << ": mean difference " << d.mean << ", largest " << d.max);
        CHECK(d.mean < last);
        last = d.mean;
    }
    CHECK(last < 0.1);
}

TEST_CASE("mesh: scale, rotation and position place the model as its triangles written out placed would be") {
    rt_test::TempDir dir;
    MeshData m = read_ok(RT_SOURCE_DIR "/scenes/models/bunny.obj");
    rt_test::put(dir / "bunny.obj", obj_text(m));
    const MeshInstance placed = MeshInstance::make({0.3, -0.2, -1}, {0.2, 0.25, 0.15}, {90, 30, -20});
    for (std::size_t i = 0; i < m.positions.size(); i += 3) {
        const Vec3 p = placed.point_to_world({m.positions[i], m.positions[i + 1], m.positions[i + 2]});
        for (int k = 0; k < 3; ++k) m.positions[i + std::size_t(k)] = float(p[k]);
    }
    rt_test::put(dir / "placed.obj", obj_text(m));
    const auto a = render("thing { mesh { file bunny.obj position 0.3 -0.2 -1 scale 0.2 0.25 0.15 rotation 90 30 -20 "
                          "material { colour 0.9 0.5 0.2 } } }\n" + std::string(kStage),
                          dir.path.string(), 160, 120);
    const auto b = render("thing { mesh { file placed.obj material { colour 0.9 0.5 0.2 } } }\n" + std::string(kStage),
                          dir.path.string(), 160, 120);
    const Difference d = difference(a, b);
    // (The written-out corners are rounded to float: a pixel at a silhouette may differ.)
    CHECK(d.mean < 0.05);
    std::size_t off = 0;
    for (std::size_t i = 0; i < a.size(); ++i) off += std::abs(int(a[i]) - int(b[i])) > 1;
    CHECK(off < a.size() / 500);
}
