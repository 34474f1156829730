// One model of the bounded primitives for the property tests (shapes, CSG), written
// from each shape's definition (docs/rendering.md §7) rather than from core/shapes.cpp,
// so that the spans the core reports can be checked against it.
#pragma once

#include <algorithm>
#include <cmath>

#include "math.h"
#include "scene.h"

namespace rt_test {

// A sphere, tetrahedron, cylinder or torus. sd() is negative inside, zero on the
// surface, positive outside; for the sphere and torus it is the exact signed
// distance, for the tetrahedron and cylinder the largest signed distance to a
// bounding plane or tube.
struct Prim {
    enum Kind { Sph, Tet, Cyl, Tor } kind = Sph;
    rt::Vec3 c;              // sphere centre, torus centre
    double r = 1;            // sphere radius, cylinder radius, torus minor
    rt::Vec3 v[4];           // tetrahedron corners
    rt::Vec3 e1, e2;         // cylinder ends
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
        }
    }
};

}  // namespace rt_test
