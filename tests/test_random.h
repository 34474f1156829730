// Seeded random numbers and vector printing shared by the property tests. The
// standard fixes the engine (mt19937) but not the distributions, so they are built
// here to give the same numbers on every platform.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <random>
#include <string>

#include "math.h"
#include "scene.h"

namespace rt_test {

struct Rng {
    std::mt19937 g;
    explicit Rng(unsigned seed) : g(seed) {}
    double uni() { return (double(g()) + 0.5) / 4294967296.0; }
    double uni(double a, double b) { return a + (b - a) * uni(); }
    std::size_t index(std::size_t n) { return std::min(n - 1, std::size_t(uni() * double(n))); }
    rt::Vec3 unit() {
        for (;;) {
            rt::Vec3 v{uni(-1, 1), uni(-1, 1), uni(-1, 1)};
            double l2 = rt::length2(v);
            if (l2 > 1e-4 && l2 <= 1) return v / std::sqrt(l2);
        }
    }
    rt::Vec3 in_ball(double r) {
        for (;;) {
            rt::Vec3 v{uni(-1, 1), uni(-1, 1), uni(-1, 1)};
            if (rt::length2(v) <= 1) return v * r;
        }
    }
};

inline std::string fmt(const rt::Vec3& v) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", v.x, v.y, v.z);
    return buf;
}

// A sphere, tetrahedron, cylinder or torus of size about s around c.
inline rt::Shape random_primitive_shape(Rng& rng, const rt::Vec3& c, double s) {
    switch (rng.index(4)) {
        case 0: return rt::Sphere{c, s};
        case 1: {
            rt::Tetrahedron t;
            for (rt::Vec3& v : t.v) v = c + rng.in_ball(2 * s);
            return t;
        }
        case 2: return rt::Cylinder{c - rng.unit() * s, c + rng.unit() * s, 0.4 * s};
        default: return rt::Torus{c, rng.unit(), s, 0.3 * s};
    }
}

}  // namespace rt_test
