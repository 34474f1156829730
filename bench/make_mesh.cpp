// Writes a big triangle mesh for the benchmarks: a bumpy ball (a sphere displaced by
// a few waves), closed, every vertex shared by its neighbours, made of latitude rings
// so that any triangle count near 4 k^2 can be asked for (k = 500: exactly 1,000,000).
// Formats: OBJ, binary PLY (little- or big-endian), ASCII PLY; with --pov, the
// POV-Ray mesh2 twin of the same triangles (an #include-able object named Blob); with
// --uv, texture coordinates per vertex (longitude and latitude: PLY `u v`, OBJ `vt`);
// with --texture, also an N x N PNG image to map on it (a pattern of stripes and rings
// in many colours, so that neighbouring texels differ).
//   make_mesh TRIANGLES OUT.(obj|ply) [--ascii] [--big-endian] [--pov OUT.inc] [--uv]
//             [--texture N OUT.png]
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "png.h"

namespace {

struct Mesh {
    std::vector<float> v;           // x y z per vertex
    std::vector<float> uv;          // u v per vertex
    std::vector<std::uint32_t> f;   // 3 per triangle
    bool with_uv = false;           // written with the vertices
};

// Rings 1..m-1 of k vertices each between the poles; 2 k (m - 1) triangles.
Mesh make_ball(long m, long k) {
    Mesh mesh;
    const double pi = 3.14159265358979323846;
    auto radius = [](double theta, double phi) {
        return 1.0 + 0.08 * std::sin(7 * theta) * std::cos(5 * phi) + 0.04 * std::sin(13 * phi + 3 * theta) +
               0.02 * std::cos(29 * theta - 17 * phi);
    };
    auto add = [&](double theta, double phi) {
        const double r = radius(theta, phi);
        mesh.v.push_back(float(r * std::sin(theta) * std::cos(phi)));
        mesh.v.push_back(float(r * std::sin(theta) * std::sin(phi)));
        mesh.v.push_back(float(r * std::cos(theta)));
        mesh.uv.push_back(float(phi / (2 * pi)));
        mesh.uv.push_back(float(1 - theta / pi));
    };
    mesh.v.reserve(std::size_t(3 * ((m - 1) * k + 2)));
    add(0, 0);
    for (long i = 1; i < m; ++i)
        for (long j = 0; j < k; ++j) add(pi * double(i) / double(m), 2 * pi * double(j) / double(k));
    add(pi, 0);
    const std::uint32_t south = std::uint32_t((m - 1) * k + 1);
    auto at = [k](long ring, long j) { return std::uint32_t(1 + (ring - 1) * k + (j % k)); };
    mesh.f.reserve(std::size_t(6 * k * (m - 1)));
    auto tri = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        mesh.f.push_back(a), mesh.f.push_back(b), mesh.f.push_back(c);
    };
    for (long j = 0; j < k; ++j) tri(0, at(1, j), at(1, j + 1));  // counter-clockwise seen from outside
    for (long i = 1; i + 1 < m; ++i)
        for (long j = 0; j < k; ++j) {
            tri(at(i, j), at(i + 1, j), at(i + 1, j + 1));
            tri(at(i, j), at(i + 1, j + 1), at(i, j + 1));
        }
    for (long j = 0; j < k; ++j) tri(south, at(m - 1, j + 1), at(m - 1, j));
    return mesh;
}

bool write_obj(const Mesh& m, FILE* out) {
    std::fprintf(out, "# bumpy ball, %zu vertices, %zu triangles (bench/make_mesh)\n", m.v.size() / 3, m.f.size() / 3);
    for (std::size_t i = 0; i < m.v.size(); i += 3) std::fprintf(out, "v %.7g %.7g %.7g\n", m.v[i], m.v[i + 1], m.v[i + 2]);
    if (m.with_uv)
        for (std::size_t i = 0; i < m.uv.size(); i += 2) std::fprintf(out, "vt %.7g %.7g\n", m.uv[i], m.uv[i + 1]);
    for (std::size_t i = 0; i < m.f.size(); i += 3) {
        if (m.with_uv)
            std::fprintf(out, "f %u/%u %u/%u %u/%u\n", m.f[i] + 1, m.f[i] + 1, m.f[i + 1] + 1, m.f[i + 1] + 1, m.f[i + 2] + 1,
                         m.f[i + 2] + 1);
        else
            std::fprintf(out, "f %u %u %u\n", m.f[i] + 1, m.f[i + 1] + 1, m.f[i + 2] + 1);
    }
    return !std::ferror(out);
}

template <class T>
void put(FILE* out, T value, bool big) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &value, sizeof b);
    if (big)
        for (std::size_t i = 0; i < sizeof b / 2; ++i) std::swap(b[i], b[sizeof b - 1 - i]);
    std::fwrite(b, 1, sizeof b, out);
}

bool write_ply(const Mesh& m, FILE* out, bool ascii, bool big) {
    std::fprintf(out, "ply\nformat %s 1.0\ncomment bumpy ball (bench/make_mesh)\nelement vertex %zu\n",
                 ascii ? "ascii" : big ? "binary_big_endian" : "binary_little_endian", m.v.size() / 3);
    std::fprintf(out, "property float x\nproperty float y\nproperty float z\n");
    if (m.with_uv) std::fprintf(out, "property float u\nproperty float v\n");
    std::fprintf(out, "element face %zu\nproperty list uchar int vertex_indices\nend_header\n", m.f.size() / 3);
    if (ascii) {
        for (std::size_t i = 0; i < m.v.size(); i += 3) {
            std::fprintf(out, "%.7g %.7g %.7g", m.v[i], m.v[i + 1], m.v[i + 2]);
            if (m.with_uv) std::fprintf(out, " %.7g %.7g", m.uv[i / 3 * 2], m.uv[i / 3 * 2 + 1]);
            std::fprintf(out, "\n");
        }
        for (std::size_t i = 0; i < m.f.size(); i += 3) std::fprintf(out, "3 %u %u %u\n", m.f[i], m.f[i + 1], m.f[i + 2]);
    } else {
        for (std::size_t i = 0; i < m.v.size(); i += 3) {
            for (int c = 0; c < 3; ++c) put(out, m.v[i + std::size_t(c)], big);
            if (m.with_uv) put(out, m.uv[i / 3 * 2], big), put(out, m.uv[i / 3 * 2 + 1], big);
        }
        for (std::size_t i = 0; i < m.f.size(); i += 3) {
            put(out, std::uint8_t(3), big);
            for (int k = 0; k < 3; ++k) put(out, std::int32_t(m.f[i + std::size_t(k)]), big);
        }
    }
    return !std::ferror(out);
}

// The same triangles as a POV-Ray mesh2 object.
bool write_pov(const Mesh& m, FILE* out) {
    std::fprintf(out, "#declare Blob = mesh2 {\n  vertex_vectors { %zu", m.v.size() / 3);
    for (std::size_t i = 0; i < m.v.size(); i += 3) std::fprintf(out, ",\n<%.7g,%.7g,%.7g>", m.v[i], m.v[i + 1], m.v[i + 2]);
    std::fprintf(out, " }\n  face_indices { %zu", m.f.size() / 3);
    for (std::size_t i = 0; i < m.f.size(); i += 3) std::fprintf(out, ",\n<%u,%u,%u>", m.f[i], m.f[i + 1], m.f[i + 2]);
    std::fprintf(out, " }\n}\n");
    return !std::ferror(out);
}

bool write_file(const std::string& path, bool (*write)(const Mesh&, FILE*, bool, bool), const Mesh& m, bool a, bool b) {
    FILE* out = std::fopen(path.c_str(), "wb");
    if (!out) {
        std::perror(path.c_str());
        return false;
    }
    std::vector<char> buffer(1 << 20);
    std::setvbuf(out, buffer.data(), _IOFBF, buffer.size());
    bool ok = write(m, out, a, b);
    ok = std::fclose(out) == 0 && ok;
    if (!ok) std::fprintf(stderr, "make_mesh: cannot write %s\n", path.c_str());
    return ok;
}

// An n x n picture of stripes and rings in many colours, as a PNG file.
bool write_texture(long n, const std::string& path) {
    std::vector<std::uint8_t> rgb(std::size_t(n) * std::size_t(n) * 3);
    for (long y = 0; y < n; ++y)
        for (long x = 0; x < n; ++x) {
            const double u = double(x) / double(n), v = double(y) / double(n);
            const double a = std::sin(40 * u + 3 * std::sin(9 * v)), b = std::cos(57 * v - 2 * std::cos(7 * u));
            const double r = std::sin(150 * std::hypot(u - 0.5, v - 0.3));
            std::uint8_t* p = &rgb[3 * (std::size_t(y) * std::size_t(n) + std::size_t(x))];
            p[0] = std::uint8_t(127.5 + 127 * a);
            p[1] = std::uint8_t(127.5 + 127 * b);
            p[2] = std::uint8_t(127.5 + 127 * r);
        }
    std::string png;
    if (!rt::encode_png(rgb.data(), int(n), int(n), png)) return false;
    FILE* out = std::fopen(path.c_str(), "wb");
    if (!out) {
        std::perror(path.c_str());
        return false;
    }
    bool ok = std::fwrite(png.data(), 1, png.size(), out) == png.size();
    ok = std::fclose(out) == 0 && ok;
    if (!ok) std::fprintf(stderr, "make_mesh: cannot write %s\n", path.c_str());
    return ok;
}

bool ends_with(const std::string& s, const char* tail) {
    const std::size_t n = std::strlen(tail);
    return s.size() >= n && s.compare(s.size() - n, n, tail) == 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: make_mesh TRIANGLES OUT.(obj|ply) [--ascii] [--big-endian] [--pov OUT.inc] [--uv]"
                             " [--texture N OUT.png]\n");
        return 2;
    }
    const double wanted = std::atof(argv[1]);
    const std::string path = argv[2];
    bool ascii = false, big = false, uv = false;
    std::string pov, texture;
    long texture_size = 0;
    for (int i = 3; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--ascii")) ascii = true;
        else if (!std::strcmp(argv[i], "--big-endian")) big = true;
        else if (!std::strcmp(argv[i], "--pov") && i + 1 < argc) pov = argv[++i];
        else if (!std::strcmp(argv[i], "--uv")) uv = true;
        else if (!std::strcmp(argv[i], "--texture") && i + 2 < argc && std::atol(argv[i + 1]) > 0 &&
                 std::atol(argv[i + 1]) <= 16384) {
            texture_size = std::atol(argv[++i]);
            texture = argv[++i];
        }
        else {
            std::fprintf(stderr, "make_mesh: unknown option %s\n", argv[i]);
            return 2;
        }
    }
    // 2 k (m - 1) triangles with k = 2 (m - 1): 4 (m - 1)^2.
    const long half = std::lround(std::sqrt(std::max(wanted, 8.0) / 4));
    Mesh mesh = make_ball(half + 1, 2 * half);
    mesh.with_uv = uv;
    bool ok;
    if (ends_with(path, ".obj"))
        ok = write_file(path, [](const Mesh& m, FILE* f, bool, bool) { return write_obj(m, f); }, mesh, false, false);
    else if (ends_with(path, ".ply"))
        ok = write_file(path, write_ply, mesh, ascii, big);
    else {
        std::fprintf(stderr, "make_mesh: OUT must end in .obj or .ply\n");
        return 2;
    }
    if (ok && !pov.empty())
        ok = write_file(pov, [](const Mesh& m, FILE* f, bool, bool) { return write_pov(m, f); }, mesh, false, false);
    if (ok && !texture.empty()) ok = write_texture(texture_size, texture);
    if (ok) std::printf("%zu vertices, %zu triangles\n", mesh.v.size() / 3, mesh.f.size() / 3);
    return ok ? 0 : 1;
}
