// One model of the bounded primitives for the property tests (shapes, CSG), written
// from each shape's definition (docs/rendering.md §7) rather than from core/shapes.cpp,
// so that the spans the core reports can be checked against it; and the checks every
// span list must pass, whatever solid it belongs to.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "math.h"
#include "scene.h"
#include "shapes.h"
#include "test_random.h"
#include "test_util.h"

namespace rt_test {

// A sphere, tetrahedron, cylinder or torus. sd() is negative inside, zero on the
// surface, positive outside; for the sphere and torus it is the exact signed
// distance, for the tetrahedron and cylinder the largest signed distance to a
// bounding plane or tube.
struct Prim {
    enum Kind { Sph, Tet, Cyl, Tor, Bx, Con } kind = Sph;
    rt::Vec3 c;              // sphere centre, torus centre
    double r = 1;            // sphere radius, cylinder radius, torus minor
    rt::Vec3 v[4];           // tetrahedron corners
    rt::Vec3 e1, e2;         // cylinder and cone ends, box corners
    double r2 = 0;           // cone radius at e2 (r: at e1)
    rt::Vec3 axis{0, 0, 1};  // torus axis (any length: the format normalises it)
    double R = 1;            // torus major

    rt::Shape shape() const {
        switch (kind) {
            case Sph: return rt::Sphere{c, r};
            case Tet: {
                rt::Tetrahedron t;
                for (int i = 0; i < 4; ++i) t.v[i] = v[i];
                return t;
            }
            case Cyl: return rt::Cylinder{e1, e2, r};
            case Tor: return rt::Torus{c, axis, R, r};
            case Bx: return rt::Box{e1, e2};
            case Con: return rt::Cone{e1, e2, r, r2};
        }
        return rt::Sphere{};
    }
    rt::Object object() const {
        rt::Object o;
        o.shape = shape();
        return o;
    }

    // Barycentric coordinates of p in the tetrahedron (Cramer's rule).
    void bary(const rt::Vec3& p, double l[4]) const {
        rt::Vec3 a = v[1] - v[0], b = v[2] - v[0], cc = v[3] - v[0], q = p - v[0];
        double det = dot(a, cross(b, cc));
        l[1] = dot(q, cross(b, cc)) / det;
        l[2] = dot(a, cross(q, cc)) / det;
        l[3] = dot(a, cross(b, q)) / det;
        l[0] = 1 - l[1] - l[2] - l[3];
    }
    // Height of corner i over the opposite face: turns a barycentric coordinate
    // into a distance.
    double height(int i) const {
        const rt::Vec3& a = v[(i + 1) % 4];
        const rt::Vec3& b = v[(i + 2) % 4];
        const rt::Vec3& cc = v[(i + 3) % 4];
        double vol6 = std::fabs(dot(v[1] - v[0], cross(v[2] - v[0], v[3] - v[0])));
        double area2 = length(cross(b - a, cc - a));
        return vol6 / area2;
    }
    // Torus local coordinates in a frame built here (not rt::Frame::from_axis).
    rt::Vec3 torus_local(const rt::Vec3& p) const {
        rt::Vec3 w = rt::normalize(axis);
        rt::Vec3 helper = std::fabs(w.x) < 0.9 ? rt::Vec3{1, 0, 0} : rt::Vec3{0, 1, 0};
        rt::Vec3 u = rt::normalize(cross(helper, w));
        rt::Vec3 vv = cross(w, u);
        rt::Vec3 q = p - c;
        return {dot(q, u), dot(q, vv), dot(q, w)};
    }
    // The signed "distances" of the pieces whose maximum is sd (one for the sphere
    // and torus), to tell whether a point is near an edge.
    int pieces(const rt::Vec3& p, double out[4]) const {
        switch (kind) {
            case Sph: out[0] = length(p - c) - r; return 1;
            case Tet: {
                double l[4];
                bary(p, l);
                for (int i = 0; i < 4; ++i) out[i] = -l[i] * height(i);
                return 4;
            }
            case Cyl: {
                rt::Vec3 a = rt::normalize(e2 - e1);
                double len = length(e2 - e1);
                double s = dot(p - e1, a);
                double radial = length((p - e1) - a * s);
                out[0] = -s;
                out[1] = s - len;
                out[2] = radial - r;
                return 3;
            }
            case Tor: {
                rt::Vec3 l = torus_local(p);
                double rho = std::sqrt(l.x * l.x + l.y * l.y);
                out[0] = std::sqrt((R - rho) * (R - rho) + l.z * l.z) - r;
                return 1;
            }
            case Bx:
                // Per axis: the distance outside the slab between the corners (< 0 inside).
                for (int k = 0; k < 3; ++k)
                    out[k] = std::fabs(p[k] - (e1[k] + e2[k]) / 2) - std::fabs(e2[k] - e1[k]) / 2;
                return 3;
            case Con: {
                // Caps as the cylinder's; the side: how far beyond the radius at that
                // height, measured square to the slanted side.
                rt::Vec3 a = rt::normalize(e2 - e1);
                double len = length(e2 - e1);
                double s = dot(p - e1, a);
                double radial = length((p - e1) - a * s);
                double k = (r2 - r) / len;
                out[0] = -s;
                out[1] = s - len;
                out[2] = (radial - (r + k * s)) / std::sqrt(1 + k * k);
                return 3;
            }
        }
        return 0;
    }
    double sd(const rt::Vec3& p) const {
        double q[4] = {};
        int n = pieces(p, q);
        double m = q[0];
        for (int i = 1; i < n; ++i) m = std::max(m, q[i]);
        return m;
    }
    bool inside(const rt::Vec3& p) const { return sd(p) < 0; }
    // How many pieces are within `tol` of their surface: more than one near an edge.
    int near_pieces(const rt::Vec3& p, double tol) const {
        double q[4] = {};
        int n = pieces(p, q), k = 0;
        for (int i = 0; i < n; ++i) k += std::fabs(q[i]) < tol;
        return k;
    }
    // Roughly how far p is from an edge: the second-smallest piece distance; +inf for
    // the smooth shapes.
    double edge_margin(const rt::Vec3& p) const {
        double q[4] = {};
        int n = pieces(p, q);
        double first = HUGE_VAL, second = HUGE_VAL;
        for (int i = 0; i < n; ++i) {
            double a = std::fabs(q[i]);
            if (a < first) {
                second = first, first = a;
            } else if (a < second) {
                second = a;
            }
        }
        return second;
    }
    // A ball that holds the solid.
    void bound(rt::Vec3& centre, double& radius) const {
        switch (kind) {
            case Sph: centre = c, radius = r; return;
            case Tet:
                centre = (v[0] + v[1] + v[2] + v[3]) / 4;
                radius = 0;
                for (const rt::Vec3& p : v) radius = std::max(radius, length(p - centre));
                return;
            case Cyl:
                centre = (e1 + e2) / 2;
                radius = std::sqrt(length2(e2 - e1) / 4 + r * r);
                return;
            case Tor: centre = c, radius = R + r; return;
            case Bx: centre = (e1 + e2) / 2, radius = length(e2 - e1) / 2; return;
            case Con:
                centre = (e1 + e2) / 2;
                radius = std::sqrt(length2(e2 - e1) / 4 + std::max(r, r2) * std::max(r, r2));
                return;
        }
    }
};

// One object compiled alone, and its node in the geometry.
struct CompiledObject {
    rt::Scene scene;
    rt::Geometry g;
    std::uint32_t node = 0;
    explicit CompiledObject(rt::Object o) {
        scene.objects.push_back(std::move(o));
        g = rt::build_geometry(scene);
        node = g.object_node[0];
    }
};

// Checks the inside spans a solid reports along the line o + t d (d unit) against a
// model of the solid:
//  - spans ascending and disjoint, each with in < out (in <= out if `allow_empty`,
//    for a primitive a ray can graze);
//  - at 200 jittered points of the line through the ball (centre, radius) that holds
//    the solid, "inside a span" agrees with inside(p), except within rounding of a
//    surface: surface(p) is the distance from p to the model's nearest surface;
//  - span ends are finite and on a surface; their normals are unit, face against the
//    ray at entries and along it at exits; normal_check(p, n, why) may add what the
//    solid knows about its normal at an end (report through `why`).
// Counts the sample points that were inside in `inside_samples`.
template <class Inside, class Surface, class NormalCheck>
void check_spans(const std::vector<rt::Span>& spans, const rt::Geometry& g, const rt::Vec3& o, const rt::Vec3& d,
                 const rt::Vec3& centre, double radius, bool allow_empty, Rng& rng, Failures& f, int& inside_samples,
                 Inside inside, Surface surface, NormalCheck normal_check) {
    const std::string ray = "o=" + fmt(o) + " d=" + fmt(d);
    for (std::size_t i = 0; i < spans.size(); ++i) {
        if (allow_empty ? !(spans[i].in.t <= spans[i].out.t) : !(spans[i].in.t < spans[i].out.t))
            f.add("empty or reversed span; " + ray);
        if (i > 0 && !(spans[i - 1].out.t <= spans[i].in.t)) f.add("spans not ascending and disjoint; " + ray);
    }

    const double tc = dot(centre - o, d);
    const double t0 = tc - 1.2 * radius, t1 = tc + 1.2 * radius;
    const int kSamples = 200;
    for (int k = 0; k < kSamples; ++k) {
        const double t = t0 + (t1 - t0) * (k + rng.uni()) / kSamples;
        const double eps = 1e-6 * std::max(1.0, std::fabs(t));
        bool in_span = false, near_end = false;
        for (const rt::Span& s : spans) {
            if (t > s.in.t + eps && t < s.out.t - eps) in_span = true;
            if (std::fabs(t - s.in.t) <= eps || std::fabs(t - s.out.t) <= eps) near_end = true;
        }
        if (near_end) continue;
        const rt::Vec3 p = o + d * t;
        if (surface(p) < 1e-9) continue;  // within rounding of a surface: either way
        const bool want = inside(p);
        inside_samples += want;
        if (in_span != want) {
            char buf[128];
            std::snprintf(buf, sizeof buf, "t=%.17g: spans say %s, the model %s; ", t, in_span ? "inside" : "outside",
                          want ? "inside" : "outside");
            f.add(buf + ray);
        }
    }

    for (const rt::Span& s : spans) {
        for (int k = 0; k < 2; ++k) {
            const rt::SpanEnd& e = k == 0 ? s.in : s.out;
            if (!std::isfinite(e.t)) {
                f.add("infinite span end of a bounded solid; " + ray);
                continue;
            }
            const rt::Vec3 p = o + d * e.t;
            const double off = surface(p);
            if (!(off < 1e-7)) {
                char buf[120];
                std::snprintf(buf, sizeof buf, "span end t=%.17g is off the surface by %.3g; ", e.t, off);
                f.add(buf + ray);
            }
            rt::Vec3 n = g.normal(e.node, e.face, p);
            if (e.flip) n = -n;
            if (!(std::fabs(length(n) - 1) < 1e-9)) f.add("normal not unit at " + fmt(p) + "; " + ray);
            const double dn = dot(n, d);
            if (k == 0 ? dn > 1e-9 : dn < -1e-9)
                f.add(std::string(k == 0 ? "entry" : "exit") + " normal faces the wrong way along the ray at " + fmt(p) +
                      "; " + ray);
            normal_check(p, n, [&](const std::string& why) { f.add(why + " at " + fmt(p) + " n=" + fmt(n) + "; " + ray); });
        }
    }
}

}  // namespace rt_test
