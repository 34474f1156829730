// Small double-precision vector maths shared by the whole core.
// Geometry is double, as in the 2013 program; its epsilon (1.5e-5) assumes it.
#pragma once

#include <cmath>
#include <cstdint>

namespace rt {

struct Vec3 {
    double x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
    constexpr bool operator!=(const Vec3& o) const { return !(*this == o); }
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Per-channel product, used for colours.
constexpr Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
constexpr double length2(const Vec3& v) { return dot(v, v); }
// Unit vector; the zero vector stays zero rather than becoming NaN.
inline Vec3 normalize(const Vec3& v) {
    double l = length(v);
    return l > 0 ? v / l : Vec3{};
}
// Plain comparisons rather than std::fmin/fmax, which compile to library calls; a NaN
// in `b` is ignored, as with fmin.
constexpr double dmin(double a, double b) { return b < a ? b : a; }
constexpr double dmax(double a, double b) { return b > a ? b : a; }
constexpr Vec3 vmin(const Vec3& a, const Vec3& b) { return {dmin(a.x, b.x), dmin(a.y, b.y), dmin(a.z, b.z)}; }
constexpr Vec3 vmax(const Vec3& a, const Vec3& b) { return {dmax(a.x, b.x), dmax(a.y, b.y), dmax(a.z, b.z)}; }
inline bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

using Colour = Vec3;

struct Ray {
    Vec3 origin;
    Vec3 dir;  // unit length
};

// Orthonormal frame with `w` as the given axis.
struct Frame {
    Vec3 u, v, w;
    static Frame from_axis(const Vec3& axis) {
        Frame f;
        f.w = normalize(axis);
        // Pixar's branchless basis (Duff et al. 2017).
        double sign = std::copysign(1.0, f.w.z);
        double a = -1.0 / (sign + f.w.z);
        double b = f.w.x * f.w.y * a;
        f.u = {1.0 + sign * f.w.x * f.w.x * a, sign * b, -sign * f.w.x};
        f.v = {b, sign + f.w.y * f.w.y * a, -f.w.y};
        return f;
    }
    Vec3 to_local(const Vec3& p) const { return {dot(p, u), dot(p, v), dot(p, w)}; }
    Vec3 to_world(const Vec3& p) const { return u * p.x + v * p.y + w * p.z; }
};

struct Aabb {
    Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL};
    Vec3 hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    void grow(const Vec3& p) { lo = vmin(lo, p); hi = vmax(hi, p); }
    void grow(const Aabb& b) { lo = vmin(lo, b.lo); hi = vmax(hi, b.hi); }
    bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    Vec3 centre() const { return (lo + hi) * 0.5; }
    double area() const {
        if (empty()) return 0;
        Vec3 e = hi - lo;
        return 2 * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
};

inline Aabb intersect(const Aabb& a, const Aabb& b) {
    Aabb r;
    r.lo = vmax(a.lo, b.lo);
    r.hi = vmin(a.hi, b.hi);
    return r;
}

}  // namespace rt
