// What the model readers share: cutting polygons into triangles and the final checks.
#include "model_readers.h"

#include <cmath>
#include <string>

namespace rt {

namespace {

// Ear clipping costs n^2 per polygon at least; beyond this size a fan is cut instead.
constexpr std::size_t kMaxEarClipping = 256;

struct P2 {
    double u, v;
};

double cross2(const P2& a, const P2& b, const P2& c) { return (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u); }

// Whether p lies inside or on triangle abc (counter-clockwise).
bool inside(const P2& a, const P2& b, const P2& c, const P2& p) {
    return cross2(a, b, p) >= 0 && cross2(b, c, p) >= 0 && cross2(c, a, p) >= 0;
}

void fan(const std::uint32_t* poly, const std::size_t* idx, std::size_t n, std::vector<std::uint32_t>& out) {
    for (std::size_t k = 1; k + 1 < n; ++k) {
        out.push_back(poly[idx[0]]);
        out.push_back(poly[idx[k]]);
        out.push_back(poly[idx[k + 1]]);
    }
}

// The polygon in 2D, seen along its (Newell) normal, turned counter-clockwise.
std::vector<P2> project(const std::vector<float>& pos, const std::uint32_t* poly, std::size_t n) {
    auto at = [&](std::size_t k) {
        const float* p = &pos[3 * std::size_t(poly[k])];
        return Vec3{p[0], p[1], p[2]};
    };
    Vec3 normal;
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 a = at(k), b = at((k + 1) % n);
        normal += Vec3{(a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y)};
    }
    const Vec3 m{std::fabs(normal.x), std::fabs(normal.y), std::fabs(normal.z)};
    const int drop = m.x >= m.y && m.x >= m.z ? 0 : m.y >= m.z ? 1 : 2;
    const int ua = (drop + 1) % 3, va = (drop + 2) % 3;
    const bool flip = normal[drop] < 0;
    std::vector<P2> out(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Vec3 p = at(k);
        out[k] = flip ? P2{p[va], p[ua]} : P2{p[ua], p[va]};
    }
    return out;
}

}  // namespace

void triangulate(const std::vector<float>& positions, const std::uint32_t* poly, std::size_t n,
                 std::vector<std::uint32_t>& out) {
    std::vector<std::size_t> idx(n);
    for (std::size_t k = 0; k < n; ++k) idx[k] = k;
    if (n > kMaxEarClipping) return fan(poly, idx.data(), n, out);
    const std::vector<P2> p = project(positions, poly, n);
    auto same = [&](std::size_t q, std::size_t r) {
        return q == r || poly[q] == poly[r] || (p[q].u == p[r].u && p[q].v == p[r].v);
    };
    std::size_t left = n, miss = 0;
    for (std::size_t i = 0; left > 3;) {
        const std::size_t a = idx[(i + left - 1) % left], b = idx[i % left], c = idx[(i + 1) % left];
        bool ear = cross2(p[a], p[b], p[c]) > 0;
        for (std::size_t k = 0; ear && k < left; ++k) {
            // A corner of the ear met again (a keyhole polygon walks its slit twice,
            // naming the same vertices, or vertices at the same place) does not block it.
            const std::size_t q = idx[k];
            ear = same(q, a) || same(q, b) || same(q, c) || !inside(p[a], p[b], p[c], p[q]);
        }
        if (ear) {
            out.push_back(poly[a]);
            out.push_back(poly[b]);
            out.push_back(poly[c]);
            idx.erase(idx.begin() + std::ptrdiff_t(i % left));
            --left;
            miss = 0;
            continue;
        }
        // A whole round without an ear: degenerate or self-crossing; a fan covers the rest.
        if (++miss > left) return fan(poly, idx.data(), left, out);
        i = (i + 1) % left;
    }
    fan(poly, idx.data(), left, out);
}

bool check_mesh(const MeshData& m, ModelError& error) {
    if (m.triangles.empty()) {
        error.message = "the file holds no triangles";
        return false;
    }
    if (m.triangle_count() > ModelLimits::max_triangles) {
        error.message = "too many triangles (" + std::to_string(m.triangle_count()) + ", limit " +
                        std::to_string(ModelLimits::max_triangles) + ")";
        return false;
    }
    for (std::size_t i = 0; i < m.positions.size(); ++i)
        if (!(std::fabs(m.positions[i]) <= ModelLimits::max_coordinate)) {
            error.message = "vertex " + std::to_string(i / 3 + 1) + " has a coordinate that is " +
                            (std::isnan(m.positions[i]) ? "not a number" : "out of range (magnitude at most 1e15)");
            return false;
        }
    return true;
}

}  // namespace rt
