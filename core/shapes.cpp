// Inside intervals, normals and bounds of the primitives, and the compiler from the
// plain Scene into flat arrays. Spans cover the whole line (negative t included) so
// that CSG can tell where a ray starts.
#include "shapes.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <unordered_map>

#include "csg.h"
#include "model.h"
#include "roots.h"
#include "world.h"

namespace rt {
namespace {

constexpr double kInf = HUGE_VAL;

template <class Out>
[[gnu::always_inline]] inline void sphere_spans(const SphereG& s, std::uint32_t node, const Vec3& o, const Vec3& d, Out& out) {
    Vec3 oc = o - s.c;
    double b = dot(oc, d);
    double e = dot(oc, oc) - s.r2;
    double disc = b * b - e;
    if (disc < 0) return;
    double q = std::sqrt(disc);
    out.push_back({{-b - q, node, 0, false}, {-b + q, node, 0, false}});
}

template <class Out>
[[gnu::always_inline]] inline void tetra_spans(const TetraG& s, std::uint32_t node, const Vec3& o, const Vec3& d, Out& out) {
    double t0 = -kInf, t1 = kInf;
    std::uint8_t f0 = 0, f1 = 0;
    for (std::uint8_t i = 0; i < 4; ++i) {
        double dist = dot(s.n[i], o) + s.d[i];
        double dn = dot(s.n[i], d);
        if (dn == 0) {
            if (dist > 0) return;
            continue;
        }
        double t = -dist / dn;
        if (dn < 0) {
            if (t > t0) t0 = t, f0 = i;
        } else {
            if (t < t1) t1 = t, f1 = i;
        }
        if (t0 > t1) return;  // the interval only shrinks
    }
    out.push_back({{t0, node, f0, false}, {t1, node, f1, false}});
}

// Faces: 0 = cap at e1, 1 = cap at e2, 2 = side.
template <class Out>
[[gnu::always_inline]] inline void cylinder_spans(const CylinderG& s, std::uint32_t node, const Vec3& o, const Vec3& d, Out& out) {
    Vec3 w = o - s.e1;
    double wa = dot(w, s.a), da = dot(d, s.a);
    Vec3 wp = w - s.a * wa, dp = d - s.a * da;
    double A = dot(dp, dp), B = dot(wp, dp), C = dot(wp, wp) - s.r * s.r;
    double t0, t1;
    std::uint8_t f0 = 2, f1 = 2;
    if (A < 1e-24) {
        if (C > 0) return;
        t0 = -kInf, t1 = kInf;
    } else {
        double disc = B * B - A * C;
        if (disc < 0) return;
        double q = std::sqrt(disc);
        // Numerically stable pair of roots.
        double k = B >= 0 ? -(B + q) : -(B - q);
        double ra = k / A, rb = k != 0 ? C / k : 0.0;
        if (k == 0) ra = rb = 0;
        t0 = std::min(ra, rb), t1 = std::max(ra, rb);
    }
    // Between the caps: 0 <= wa + t da <= len.
    if (da == 0) {
        if (wa < 0 || wa > s.len) return;
    } else {
        double ta = -wa / da, tb = (s.len - wa) / da;
        std::uint8_t fa = 0, fb = 1;
        if (ta > tb) std::swap(ta, tb), std::swap(fa, fb);
        if (ta > t0) t0 = ta, f0 = fa;
        if (tb < t1) t1 = tb, f1 = fb;
    }
    if (t0 <= t1) out.push_back({{t0, node, f0, false}, {t1, node, f1, false}});
}

// Faces: 2 k (+1 on the high side) for axis k.
template <class Out>
[[gnu::always_inline]] inline void box_spans(const BoxG& s, std::uint32_t node, const Vec3& o, const Vec3& d, Out& out) {
    double t0 = -kInf, t1 = kInf;
    std::uint8_t f0 = 0, f1 = 0;
    for (std::uint8_t k = 0; k < 3; ++k) {
        if (d[k] == 0) {
            if (o[k] < s.lo[k] || o[k] > s.hi[k]) return;
            continue;
        }
        double ta = (s.lo[k] - o[k]) / d[k], tb = (s.hi[k] - o[k]) / d[k];
        std::uint8_t fa = std::uint8_t(2 * k), fb = std::uint8_t(2 * k + 1);
        if (ta > tb) std::swap(ta, tb), std::swap(fa, fb);
        if (ta > t0) t0 = ta, f0 = fa;
        if (tb < t1) t1 = tb, f1 = fb;
    }
    if (t0 <= t1) out.push_back({{t0, node, f0, false}, {t1, node, f1, false}});
}

// Faces as the cylinder's: 0 = cap at e1, 1 = cap at e2, 2 = side. Inside the double
// cone through the side where A t^2 + 2 B t + C <= 0; between the caps only the
// frustum's own nappe is (the apex is at a cap or beyond), and a frustum is convex:
// one span at most.
template <class Out>
[[gnu::always_inline]] inline void cone_spans(const ConeG& s, std::uint32_t node, const Vec3& o, const Vec3& d, Out& out) {
    Vec3 w = o - s.e1;
    double wa = dot(w, s.a), da = dot(d, s.a);
    Vec3 wp = w - s.a * wa, dp = d - s.a * da;
    double rw = s.r1 + s.k * wa;
    double A = dot(dp, dp) - s.k * s.k * da * da, B = dot(wp, dp) - s.k * rw * da, C = dot(wp, wp) - rw * rw;
    // The side's pieces: [p0, p1], and [p2, p3] when the line leaves and comes back.
    double p0 = -kInf, p1 = kInf, p2 = kInf, p3 = kInf;
    if (A == 0) {
        if (B == 0) {
            if (C > 0) return;
        } else {
            const double t = -C / (2 * B);
            if (B > 0) p1 = t; else p0 = t;
        }
    } else {
        double disc = B * B - A * C;
        if (disc < 0) {
            if (A > 0) return;  // (A < 0: inside along the whole line)
        } else {
            double q = std::sqrt(disc);
            double kq = B >= 0 ? -(B + q) : -(B - q);
            double ra = kq / A, rb = kq != 0 ? C / kq : 0.0;
            if (kq == 0) ra = rb = 0;
            if (ra > rb) std::swap(ra, rb);
            if (A > 0) p0 = ra, p1 = rb;
            else p1 = ra, p2 = rb;
        }
    }
    // Between the caps: 0 <= wa + t da <= len.
    double c0 = -kInf, c1 = kInf;
    std::uint8_t fc0 = 0, fc1 = 1;
    if (da == 0) {
        if (wa < 0 || wa > s.len) return;
    } else {
        c0 = -wa / da, c1 = (s.len - wa) / da;
        if (c0 > c1) std::swap(c0, c1), std::swap(fc0, fc1);
    }
    double t0, t1;
    std::uint8_t f0, f1;
    auto clip = [&](double a, double b, double& x, double& y, std::uint8_t& fx, std::uint8_t& fy) {
        x = a, fx = 2, y = b, fy = 2;
        if (c0 > x) x = c0, fx = fc0;
        if (c1 < y) y = c1, fy = fc1;
        return x <= y;
    };
    const bool first = clip(p0, p1, t0, t1, f0, f1);
    double u0 = 0, u1 = 0;
    std::uint8_t g0 = 0, g1 = 0;
    const bool second = p2 != kInf && clip(p2, p3, u0, u1, g0, g1);
    if (first && second) {  // (only by rounding, at an apex on a cap): the hull
        t1 = u1, f1 = g1;
    } else if (second) {
        t0 = u0, t1 = u1, f0 = g0, f1 = g1;
    } else if (!first) {
        return;
    }
    out.push_back({{t0, node, f0, false}, {t1, node, f1, false}});
}

// The solid's own inside test, (R - rho)^2 + z^2 < r^2. The quartic's zero set also
// holds the inner 'lemon' of a spindle torus (minor > major), which is no boundary
// of the solid, so the pieces between roots are classified with this instead.
double torus_inside(const TorusG& s, const Vec3& p) {
    double rho = std::sqrt(p.x * p.x + p.y * p.y);
    double a = s.R - rho;
    return a * a + p.z * p.z - s.r * s.r;
}

// (Out of line: large, and rare; the callers stay small.)
template <class Out>
[[gnu::noinline]] void torus_spans(const TorusG& s, std::uint32_t node, const Vec3& o, const Vec3& d, Out& out) {
    // Local frame, origin moved to the point of the line nearest the centre so that the
    // quartic is well conditioned.
    Vec3 lo = s.frame.to_local(o - s.c), ld = s.frame.to_local(d);
    double tc = -dot(lo, ld);
    Vec3 p0 = lo + ld * tc;
    double bound = s.R + s.r;
    double h2 = bound * bound - dot(p0, p0);
    if (h2 < 0) return;
    double h = std::sqrt(h2) * (1 + 1e-9) + 1e-12;
    double alpha = dot(p0, ld);  // ~0, kept for exactness
    double beta = dot(p0, p0) + s.R * s.R - s.r * s.r;
    double dxy = ld.x * ld.x + ld.y * ld.y;
    double exy = 2 * (p0.x * ld.x + p0.y * ld.y);
    double fxy = p0.x * p0.x + p0.y * p0.y;
    double k = 4 * s.R * s.R;
    double c[5] = {beta * beta - k * fxy, 4 * alpha * beta - k * exy, 4 * alpha * alpha + 2 * beta - k * dxy,
                   4 * alpha, 1};
    double roots[4];
    int n = solve_quartic(c, -h, h, roots);
    // Classify the pieces between roots by the sign of f at their middles; this copes
    // with tangent (double) roots.
    double edges[6];
    int m = 0;
    edges[m++] = -h;
    for (int i = 0; i < n; ++i) edges[m++] = roots[i];
    edges[m++] = h;
    bool open = false;
    double start = 0;
    for (int i = 0; i + 1 < m; ++i) {
        double mid = 0.5 * (edges[i] + edges[i + 1]);
        bool inside = torus_inside(s, p0 + ld * mid) < 0;
        if (inside && !open) open = true, start = edges[i];
        if (!inside && open) {
            open = false;
            out.push_back({{start + tc, node, 0, false}, {edges[i] + tc, node, 0, false}});
        }
    }
    if (open) out.push_back({{start + tc, node, 0, false}, {h + tc, node, 0, false}});
}

// At most N spans, without touching the heap: a primitive gives two at most (a torus).
template <int N>
struct SmallSpans {
    Span v[N];
    int n = 0;
    void push_back(const Span& s) { v[n++] = s; }
    std::size_t size() const { return std::size_t(n); }
    const Span& operator[](std::size_t i) const { return v[i]; }
    const Span* begin() const { return v; }
    const Span* end() const { return v + n; }
};

// The one span of a sphere, tetrahedron or cylinder, if the line meets it.
struct OneSpan {
    Span s;
    bool got = false;
    void push_back(const Span& x) { s = x, got = true; }
    const Span* get() const { return got ? &s : nullptr; }
};

Aabb sphere_bounds(const SphereG& s) {
    Aabb b;
    b.lo = s.c - Vec3{s.r, s.r, s.r};
    b.hi = s.c + Vec3{s.r, s.r, s.r};
    return b;
}

}  // namespace

template <class Out>
void Geometry::leaf_spans(std::uint32_t n, const Vec3& o, const Vec3& d, Out& out) const {
    const Node& node = nodes[n];
    switch (node.kind) {
        case NodeKind::Sphere: sphere_spans(spheres[node.index], n, o, d, out); return;
        case NodeKind::Tetra: tetra_spans(tetras[node.index], n, o, d, out); return;
        case NodeKind::Cylinder: cylinder_spans(cylinders[node.index], n, o, d, out); return;
        case NodeKind::Torus: torus_spans(tori[node.index], n, o, d, out); return;
        case NodeKind::Box: box_spans(boxes[node.index], n, o, d, out); return;
        case NodeKind::Cone: cone_spans(cones[node.index], n, o, d, out); return;
        case NodeKind::Xform: {
            // The child's spans along the line taken into its space, where the direction
            // is made unit again: t there is t here times that length.
            // (Multiplied by the inverse length: three divisions were a third of the walk.)
            const XformG& x = xforms[node.index];
            Vec3 ld = x.inst.to_model(d);
            const double inv = 1 / length(ld);
            ld = ld * inv;
            SmallSpans<2> s;
            leaf_spans(x.child, x.inst.point_to_model(o), ld, s);
            for (Span sp : s) {
                sp.in.t *= inv, sp.out.t *= inv;
                sp.in.node = sp.out.node = n;
                out.push_back(sp);
            }
            return;
        }
        case NodeKind::Instance:  // (spans() has them: they are never operands)
        case NodeKind::Csg:
        case NodeKind::Mesh: return;
    }
}

// leaf_spans for a node known not to be a torus (nor a CSG), inline.
template <class Out>
inline void Geometry::one_span(const Node& node, std::uint32_t n, const Vec3& o, const Vec3& d, Out& out) const {
    switch (node.kind) {
        case NodeKind::Sphere: sphere_spans(spheres[node.index], n, o, d, out); return;
        case NodeKind::Tetra: tetra_spans(tetras[node.index], n, o, d, out); return;
        case NodeKind::Cylinder: cylinder_spans(cylinders[node.index], n, o, d, out); return;
        case NodeKind::Box: box_spans(boxes[node.index], n, o, d, out); return;
        case NodeKind::Cone: cone_spans(cones[node.index], n, o, d, out); return;
        case NodeKind::Torus:
        case NodeKind::Xform:
        case NodeKind::Instance:
        case NodeKind::Csg:
        case NodeKind::Mesh: return;
    }
}

// Whether a node's solid gives at most one span (not a torus, which may give two; nor
// a placed primitive, which may be a torus; nor a CSG).
inline bool one_span_kind(NodeKind k) {
    return k != NodeKind::Torus && k != NodeKind::Xform && k != NodeKind::Csg && k != NodeKind::Instance;
}

// A CSG of two primitives (l, r: its operands' nodes) neither of them a torus: one span
// a side, and no lists to walk.
template <class Out>
inline void Geometry::single_csg_spans(const CsgG& c, const Node& l, const Node& r, const Vec3& o, const Vec3& d,
                                       Out& out) const {
    OneSpan a, b;
    one_span(l, c.left, o, d, a);
    if (!a.got && c.type != CsgType::Union) return;
    one_span(r, c.right, o, d, b);
    combine_single_spans(c.type, a.get(), b.get(), out);
}

template <class Out>
void Geometry::simple_csg_spans(const CsgG& c, const Vec3& o, const Vec3& d, Out& out) const {
    const Node &l = nodes[c.left], &r = nodes[c.right];
    if (one_span_kind(l.kind) && one_span_kind(r.kind)) return single_csg_spans(c, l, r, o, d, out);
    SmallSpans<2> a, b;
    leaf_spans(c.left, o, d, a);
    if (a.n == 0 && c.type != CsgType::Union) return;
    leaf_spans(c.right, o, d, b);
    combine_span_lists(c.type, a, b, out);
}

void Geometry::spans(std::uint32_t n, const Vec3& o, const Vec3& d, std::vector<Span>& out, SpanScratch& scratch,
                     std::size_t depth) const {
    const Node& node = nodes[n];
    switch (node.kind) {
        case NodeKind::Sphere:
        case NodeKind::Tetra:
        case NodeKind::Cylinder:
        case NodeKind::Torus:
        case NodeKind::Box:
        case NodeKind::Cone:
        case NodeKind::Xform:
        case NodeKind::Mesh: leaf_spans(n, o, d, out); return;
        case NodeKind::Instance: {
            // The definition's spans along the line in its space (t there is t here
            // times the direction's length there).
            const InstanceG& x = instances[node.index];
            Vec3 ld = x.inst.to_model(d);
            const double inv = 1 / length(ld);
            ld = ld * inv;
            std::vector<Span>& a = scratch.at(2 * depth);
            spans(x.root, x.inst.point_to_model(o), ld, a, scratch, depth + 1);
            for (Span sp : a) {
                sp.in.t *= inv, sp.out.t *= inv;
                out.push_back(sp);
            }
            return;
        }
        case NodeKind::Csg: {
            const CsgG& c = csgs[node.index];
            std::vector<Span>& a = scratch.at(2 * depth);
            spans(c.left, o, d, a, scratch, depth + 1);
            // An empty left side decides U's and I's and C's result without the right.
            if (a.empty() && c.type != CsgType::Union) return;
            std::vector<Span>& b = scratch.at(2 * depth + 1);
            spans(c.right, o, d, b, scratch, depth + 1);
            combine_spans(c.type, a, b, out);
            return;
        }
    }
}

Vec3 Geometry::normal(std::uint32_t n, std::uint8_t face, const Vec3& p) const {
    const Node& node = nodes[n];
    switch (node.kind) {
        case NodeKind::Sphere: return normalize(p - spheres[node.index].c);
        case NodeKind::Tetra: return tetras[node.index].n[face & 3];
        case NodeKind::Cylinder: {
            const CylinderG& s = cylinders[node.index];
            if (face == 0) return -s.a;
            if (face == 1) return s.a;
            Vec3 w = p - s.e1;
            Vec3 r = normalize(w - s.a * dot(w, s.a));
            return r;
        }
        case NodeKind::Torus: {
            const TorusG& s = tori[node.index];
            Vec3 l = s.frame.to_local(p - s.c);
            Vec3 ring{l.x, l.y, 0};
            double rl = length(ring);
            Vec3 q = rl > 0 ? l - ring * (s.R / rl) : Vec3{0, 0, l.z};
            return s.frame.to_world(normalize(q));
        }
        case NodeKind::Box: {
            Vec3 n{0, 0, 0};
            n[face >> 1 & 3] = face & 1 ? 1 : -1;
            return n;
        }
        case NodeKind::Cone: {
            const ConeG& s = cones[node.index];
            if (face == 0) return -s.a;
            if (face == 1) return s.a;
            Vec3 w = p - s.e1;
            Vec3 r = w - s.a * dot(w, s.a);
            double rl = length(r);
            // (At the apex itself, along the axis, away from the cone.)
            if (!(rl > 0)) return s.k > 0 ? -s.a : s.a;
            return normalize(r / rl - s.a * s.k);
        }
        case NodeKind::Xform: {
            const XformG& x = xforms[node.index];
            return normalize(x.inst.normal_to_world(normal(x.child, face, x.inst.point_to_model(p))));
        }
        case NodeKind::Instance:
        case NodeKind::Csg:
        case NodeKind::Mesh: break;
    }
    return {};
}

Vec3 Geometry::surface_normal(std::uint32_t obj, const SpanEnd& e, const Vec3& p) const {
    const Node& node = nodes[object_node[obj]];
    if (node.kind == NodeKind::Mesh) return mesh_normal(meshes[node.index], e, p);
    if (node.kind == NodeKind::Instance) {
        const InstanceG& x = instances[node.index];
        Vec3 n = normalize(x.inst.normal_to_world(normal(e.node, e.face, x.inst.point_to_model(p))));
        return e.flip ? -n : n;
    }
    Vec3 n = normal(e.node, e.face, p);
    if (e.flip) n = -n;
    return n;
}

bool Geometry::mesh_hit(const MeshG& m, const Vec3& o, const Vec3& d, double tmin, SpanEnd& out) const {
    if (!m.accel) return false;
    const TriRay r = TriRay::make(m.instance.point_to_model(o), m.instance.to_model(d));
    TriHit h;
    if (!m.accel->nearest(r, tmin, HUGE_VAL, h)) return false;
    Vec3 c[3];
    m.accel->corners(h.slot, c);
    out = {h.t, h.slot, 0, dot(cross(c[1] - c[0], c[2] - c[0]), r.d) > 0};
    return true;
}

Vec3 Geometry::mesh_normal(const MeshG& m, const SpanEnd& e, const Vec3& p) const {
    Vec3 c[3];
    m.accel->corners(e.node, c);
    const Vec3 e1 = c[1] - c[0], e2 = c[2] - c[0];
    const Vec3 flat = cross(e1, e2);
    Vec3 n = flat;
    if (m.smooth) {
        // The corners' normals weighted by the point's barycentric coordinates.
        const std::uint32_t* v = &m.model->data().triangles[3 * std::size_t(m.accel->ids[e.node])];
        const std::vector<float>& vn = m.model->vertex_normals();
        const Vec3 q = m.instance.point_to_model(p) - c[0];
        const double d00 = dot(e1, e1), d01 = dot(e1, e2), d11 = dot(e2, e2), d20 = dot(q, e1), d21 = dot(q, e2);
        const double den = d00 * d11 - d01 * d01;
        const double b1 = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
        const double b2 = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - b1);
        const double w[3] = {1 - b1 - b2, b1, b2};
        Vec3 s;
        for (int k = 0; k < 3; ++k) s += Vec3{vn[3 * v[k]], vn[3 * v[k] + 1], vn[3 * v[k] + 2]} * w[k];
        // Normals given the other way round from the triangles' winding are turned to
        // agree with them (the flip below goes by the winding).
        if (dot(s, flat) < 0) s = -s;
        if (length2(s) > 0 && finite(s)) n = s;
    }
    n = normalize(m.instance.normal_to_world(n));
    return e.flip ? -n : n;
}

namespace {
// A tetrahedron's corners recovered from its face planes (corner i is opposite face
// i+1), boxed with a little room.
Aabb tetra_bounds(const TetraG& t) {
    Aabb b;
    for (int skip = 0; skip < 4; ++skip) {
        int f[3], k = 0;
        for (int i = 0; i < 4; ++i)
            if (i != skip) f[k++] = i;
        Vec3 n0 = t.n[f[0]], n1 = t.n[f[1]], n2 = t.n[f[2]];
        double det = dot(n0, cross(n1, n2));
        Vec3 p = (cross(n1, n2) * -t.d[f[0]] + cross(n2, n0) * -t.d[f[1]] + cross(n0, n1) * -t.d[f[2]]) / det;
        b.grow(p);
    }
    Vec3 pad = (b.hi - b.lo) * 1e-9 + Vec3{1e-9, 1e-9, 1e-9};
    b.lo -= pad;
    b.hi += pad;
    return b;
}

// A transformed sphere's (an ellipsoid's) box exactly: its centre placed, and on axis
// i the radius times the length of row i of the linear part.
Aabb ellipsoid_bounds(const XformG& x, const SphereG& sp) {
    const Vec3 c = x.inst.point_to_world(sp.c);
    Vec3 ext;
    for (int i = 0; i < 3; ++i)
        ext[i] = sp.r * std::sqrt(x.inst.l[i][0] * x.inst.l[i][0] + x.inst.l[i][1] * x.inst.l[i][1] +
                                  x.inst.l[i][2] * x.inst.l[i][2]);
    double m = 0;
    for (int i = 0; i < 3; ++i) m = std::max({m, std::fabs(c[i]) + ext[i]});
    ext += Vec3{1, 1, 1} * (m * 1e-9 + 1e-300);
    Aabb b;
    b.lo = c - ext;
    b.hi = c + ext;
    return b;
}
}  // namespace

Aabb Geometry::bounds(std::uint32_t n) const {
    const Node& node = nodes[n];
    switch (node.kind) {
        case NodeKind::Sphere: return sphere_bounds(spheres[node.index]);
        case NodeKind::Tetra: return tetra_bounds(tetras[node.index]);
        case NodeKind::Cylinder: {
            const CylinderG& s = cylinders[node.index];
            Vec3 e2 = s.e1 + s.a * s.len;
            Vec3 ext{s.r * std::sqrt(std::max(0.0, 1 - s.a.x * s.a.x)), s.r * std::sqrt(std::max(0.0, 1 - s.a.y * s.a.y)),
                     s.r * std::sqrt(std::max(0.0, 1 - s.a.z * s.a.z))};
            Aabb b;
            b.grow(s.e1 - ext);
            b.grow(s.e1 + ext);
            b.grow(e2 - ext);
            b.grow(e2 + ext);
            return b;
        }
        case NodeKind::Torus: {
            const TorusG& s = tori[node.index];
            Vec3 a = s.frame.w;
            Vec3 ext{s.R * std::sqrt(std::max(0.0, 1 - a.x * a.x)) + s.r, s.R * std::sqrt(std::max(0.0, 1 - a.y * a.y)) + s.r,
                     s.R * std::sqrt(std::max(0.0, 1 - a.z * a.z)) + s.r};
            Aabb b;
            b.lo = s.c - ext;
            b.hi = s.c + ext;
            return b;
        }
        case NodeKind::Box: {
            const BoxG& s = boxes[node.index];
            Aabb b;
            b.lo = s.lo;
            b.hi = s.hi;
            return b;
        }
        case NodeKind::Cone: {
            const ConeG& s = cones[node.index];
            Vec3 e2 = s.e1 + s.a * s.len;
            Vec3 u{std::sqrt(std::max(0.0, 1 - s.a.x * s.a.x)), std::sqrt(std::max(0.0, 1 - s.a.y * s.a.y)),
                   std::sqrt(std::max(0.0, 1 - s.a.z * s.a.z))};
            Aabb b;
            b.grow(s.e1 - u * s.r1);
            b.grow(s.e1 + u * s.r1);
            b.grow(e2 - u * s.r2);
            b.grow(e2 + u * s.r2);
            return b;
        }
        case NodeKind::Instance: {
            const InstanceG& x = instances[node.index];
            return x.inst.world_bounds(bounds(x.root));
        }
        case NodeKind::Xform: {
            const XformG& x = xforms[node.index];
            const Node& child = nodes[x.child];
            if (child.kind != NodeKind::Sphere) return x.inst.world_bounds(bounds(x.child));
            return ellipsoid_bounds(x, spheres[child.index]);
        }
        case NodeKind::Mesh: {
            const MeshG& m = meshes[node.index];
            return m.model ? m.instance.world_bounds(m.model->bounds()) : Aabb();
        }
        case NodeKind::Csg: {
            const CsgG& c = csgs[node.index];
            Aabb l = bounds(c.left);
            if (c.type == CsgType::Difference) return l;
            Aabb r = bounds(c.right);
            if (c.type == CsgType::Intersection) return intersect(l, r);
            l.grow(r);
            return l;
        }
    }
    return {};
}

namespace {
// Takes an object's spans as they come (ascending) and keeps the first entry (or exit)
// beyond tmin, so that no list of them need be kept.
struct FirstEnd {
    bool entry;
    double tmin;
    SpanEnd& out;
    bool found = false;
    void push_back(const Span& s) {
        const SpanEnd& e = entry ? s.in : s.out;
        if (!found && e.t > tmin) out = e, found = true;
    }
};
}  // namespace

template <class Sink>
[[gnu::noinline]] bool Geometry::first_end(std::uint32_t obj, const Vec3& o, const Vec3& d, SpanScratch& scratch, Sink&& sink) const {
    std::uint32_t n = object_node[obj];
    const Node& node = nodes[n];
    if (node.kind != NodeKind::Csg && node.kind != NodeKind::Instance) {
        leaf_spans(n, o, d, sink);
    } else if (node.kind == NodeKind::Csg && csgs[node.index].simple) {
        // Both operands primitives: no lists on the heap.
        simple_csg_spans(csgs[node.index], o, d, sink);
    } else {
        std::vector<Span>& sp = scratch.at(0);
        spans(n, o, d, sp, scratch, 1);
        for (const Span& s : sp) sink.push_back(s);
    }
    return sink.found;
}

bool Geometry::hit_general(std::uint32_t obj, const Vec3& o, const Vec3& d, double tmin, SpanEnd& out,
                           SpanScratch& scratch) const {
    const std::uint32_t n = object_node[obj];
    const Node& node = nodes[n];
    if (node.kind == NodeKind::Tetra || node.kind == NodeKind::Cylinder || node.kind == NodeKind::Box ||
        node.kind == NodeKind::Cone) {
        // One span at most: first_end()'s answer without its call and second lookup.
        OneSpan a;
        one_span(node, n, o, d, a);
        if (!a.got || !(a.s.in.t > tmin)) return false;
        out = a.s.in;
        return true;
    }
    if (node.kind == NodeKind::Mesh) return mesh_hit(meshes[node.index], o, d, tmin, out);
    if (node.kind == NodeKind::Csg) {
        // The common CSG (two operands of one span each) here, with a small frame.
        const CsgG& c = csgs[node.index];
        const Node &l = nodes[c.left], &r = nodes[c.right];
        if (c.simple && one_span_kind(l.kind) && one_span_kind(r.kind)) {
            OneSpan a, b;
            one_span(l, c.left, o, d, a);
            if (c.type != CsgType::Union) {
                // What I and C keep lies within a's span (entries at or before a's exit):
                // with a behind tmin, or missed, there is nothing to enter.
                if (!a.got || a.s.out.t <= tmin) return false;
            }
            one_span(r, c.right, o, d, b);
            FirstEnd sink{true, tmin, out};
            combine_single_spans(c.type, a.get(), b.get(), sink);
            return sink.found;
        }
    }
    return first_end(obj, o, d, scratch, FirstEnd{true, tmin, out});
}

#if RT_HAVE_AVX2_KERNELS
RT_TARGET_AVX2 unsigned Geometry::sphere_entries4(const std::uint32_t ids[4], const Vec3& o, const Vec3& d, double tmin,
                                                  double t[4]) const {
    static_assert(sizeof(SphereG) == 5 * sizeof(double), "a sphere is five doubles: c, r, r2");
    // Each sphere's y, z, r, r2 in one load, turned into a vector per field; x apart.
    const SphereG &s0 = spheres[ids[0]], &s1 = spheres[ids[1]], &s2 = spheres[ids[2]], &s3 = spheres[ids[3]];
    const __m256d q0 = _mm256_loadu_pd(&s0.c.y), q1 = _mm256_loadu_pd(&s1.c.y), q2 = _mm256_loadu_pd(&s2.c.y),
                  q3 = _mm256_loadu_pd(&s3.c.y);
    const __m256d u01 = _mm256_unpacklo_pd(q0, q1), v01 = _mm256_unpackhi_pd(q0, q1);  // y0 y1 r0 r1, z0 z1 r20 r21
    const __m256d u23 = _mm256_unpacklo_pd(q2, q3), v23 = _mm256_unpackhi_pd(q2, q3);
    const __m256d cy = _mm256_permute2f128_pd(u01, u23, 0x20), cz = _mm256_permute2f128_pd(v01, v23, 0x20);
    const __m256d r2 = _mm256_permute2f128_pd(v01, v23, 0x31);
    const __m256d cx = _mm256_set_pd(s3.c.x, s2.c.x, s1.c.x, s0.c.x);
    const __m256d ox = _mm256_sub_pd(_mm256_set1_pd(o.x), cx), oy = _mm256_sub_pd(_mm256_set1_pd(o.y), cy),
                  oz = _mm256_sub_pd(_mm256_set1_pd(o.z), cz);
    // hit(): b = dot(oc, d), disc = b b - (dot(oc, oc) - r2), t = -b - sqrt(disc), summed
    // in dot()'s order. A negative disc gives a NaN t, which fails t > tmin as hit() does.
    const __m256d b = _mm256_add_pd(
        _mm256_add_pd(_mm256_mul_pd(ox, _mm256_set1_pd(d.x)), _mm256_mul_pd(oy, _mm256_set1_pd(d.y))),
        _mm256_mul_pd(oz, _mm256_set1_pd(d.z)));
    const __m256d e =
        _mm256_sub_pd(_mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ox, ox), _mm256_mul_pd(oy, oy)), _mm256_mul_pd(oz, oz)), r2);
    const __m256d disc = _mm256_sub_pd(_mm256_mul_pd(b, b), e);
    const __m256d tt = _mm256_sub_pd(_mm256_xor_pd(b, _mm256_set1_pd(-0.0)), _mm256_sqrt_pd(disc));
    _mm256_storeu_pd(t, tt);
    return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(tt, _mm256_set1_pd(tmin), _CMP_GT_OQ)));
}
#endif

bool Geometry::exit(std::uint32_t obj, const Vec3& o, const Vec3& d, SpanEnd& out, SpanScratch& scratch) const {
    const std::uint32_t n = object_node[obj];
    const Node& node = nodes[n];
    if (node.kind == NodeKind::Mesh) return mesh_hit(meshes[node.index], o, d, kDelta, out);
    if (one_span_kind(node.kind)) {
        // One span at most, as in hit_general().
        OneSpan a;
        one_span(node, n, o, d, a);
        if (!a.got || !(a.s.out.t > kDelta)) return false;
        out = a.s.out;
        return true;
    }
    return first_end(obj, o, d, scratch, FirstEnd{false, kDelta, out});
}

std::size_t Geometry::model_bytes() const {
    // Each model once, however many meshes show it.
    std::vector<const TriangleAccel*> seen;
    std::size_t bytes = 0;
    for (const MeshG& m : meshes) {
        if (!m.accel || std::find(seen.begin(), seen.end(), m.accel) != seen.end()) continue;
        seen.push_back(m.accel);
        bytes += m.accel->memory_bytes() + m.model->data().positions.capacity() * 4 +
                 m.model->data().normals.capacity() * 4 + m.model->data().triangles.capacity() * 4;
    }
    return bytes;
}

namespace {

MeshG mesh_g(const Mesh& s, const Object& obj) {
    const Material& material = obj.material;
    MeshG m;
    // (A mesh's transform is its translate only: its rotation and scale are its own.)
    m.instance = MeshInstance::make(obj.transform.set() ? s.position + obj.transform.get().translate : s.position,
                                    s.scale, s.rotation);
    m.model = s.model;
    if (m.model) {
        m.accel = &m.model->accel();
        if (s.smooth) m.model->vertex_normals();  // made now, not while tracing
    }
    m.smooth = s.smooth != 0;
    m.opaque = ShadeMaterial::from(material).refraction == 0;
    return m;
}

// Each definition built so far (each once, however many placements): its root node
// and that node's box in the definition's own space.
struct Definition {
    std::uint32_t root;
    Aabb box;
};
using Definitions = std::unordered_map<const Object*, Definition>;

std::uint32_t add_node(Geometry& g, const Object& obj, const MeshInstance* placed = nullptr,
                       Definitions* defs = nullptr);

// An instance's node: its transform, over its definition's root (built once per
// definition, whatever the number of placements).
std::uint32_t add_instance(Geometry& g, const Object& obj, const Instance& placed_def, Definitions* defs) {
    const Instance* in = &placed_def;
    std::uint32_t id = std::uint32_t(g.nodes.size());
    const Transform& t = obj.transform.get();
    InstanceG x;
    x.inst = MeshInstance::make(t.translate, t.scale, t.rotation);
    g.nodes.push_back({NodeKind::Instance, std::uint32_t(g.instances.size())});
    g.instances.push_back(x);
    if (!in->defined) {
        // (Not resolved: nothing to show. A sphere of radius 0 is never hit.)
        g.instances.write(g.instances.size() - 1).root = std::uint32_t(g.nodes.size());
        g.nodes.push_back({NodeKind::Sphere, std::uint32_t(g.spheres.size())});
        g.spheres.push_back({{0, 0, 0}, 0, 0});
        return id;
    }
    std::uint32_t root = 0;
    bool found = false;
    if (defs)
        if (auto it = defs->find(in->defined.get()); it != defs->end()) root = it->second.root, found = true;
    if (!found) {
        root = add_node(g, *in->defined, nullptr, defs);
        if (defs) defs->emplace(in->defined.get(), Definition{root, g.bounds(root)});
    }
    g.instances.write(g.instances.size() - 1).root = root;
    return id;
}

// A tetrahedron's face planes, each normal pointing away from the opposite corner.
TetraG tetra_g(const Tetrahedron& s) {
    TetraG t;
    for (int i = 0; i < 4; ++i) {
        const Vec3& a = s.v[i];
        const Vec3& b = s.v[(i + 1) % 4];
        const Vec3& c = s.v[(i + 2) % 4];
        const Vec3& opp = s.v[(i + 3) % 4];
        Vec3 n = normalize(cross(b - a, c - a));
        if (dot(n, opp - a) > 0) n = -n;
        t.n[i] = n;
        t.d[i] = -dot(n, a);
    }
    return t;
}

// `placed`: the transform of the CSGs around obj, composed (null: none).
std::uint32_t add_node(Geometry& g, const Object& obj, const MeshInstance* placed, Definitions* defs) {
    std::uint32_t id = std::uint32_t(g.nodes.size());
    if (const Instance* in = std::get_if<Instance>(&obj.shape)) return add_instance(g, obj, *in, defs);
    MeshInstance own;
    if (obj.transform.set() && !std::holds_alternative<Mesh>(obj.shape)) {
        const Transform& t = obj.transform.get();
        own = MeshInstance::make(t.translate, t.scale, t.rotation);
        if (placed) own = compose(*placed, own);
        placed = &own;
    }
    if (placed && !std::holds_alternative<Csg>(obj.shape) && !std::holds_alternative<Mesh>(obj.shape)) {
        // The primitive, as written, in the node after this one.
        g.nodes.push_back({NodeKind::Xform, std::uint32_t(g.xforms.size())});
        XformG x;
        x.inst = *placed;
        x.child = id + 1;
        g.xforms.push_back(x);
    }
    std::visit(
        [&](const auto& s) {
            using T = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<T, Sphere>) {
                g.nodes.push_back({NodeKind::Sphere, std::uint32_t(g.spheres.size())});
                g.spheres.push_back({s.position, s.radius, s.radius * s.radius});
            } else if constexpr (std::is_same_v<T, Tetrahedron>) {
                g.nodes.push_back({NodeKind::Tetra, std::uint32_t(g.tetras.size())});
                g.tetras.push_back(tetra_g(s));
            } else if constexpr (std::is_same_v<T, Cylinder>) {
                Vec3 axis = s.end2 - s.end1;
                g.nodes.push_back({NodeKind::Cylinder, std::uint32_t(g.cylinders.size())});
                g.cylinders.push_back({s.end1, normalize(axis), length(axis), std::fabs(s.radius)});
            } else if constexpr (std::is_same_v<T, Torus>) {
                g.nodes.push_back({NodeKind::Torus, std::uint32_t(g.tori.size())});
                g.tori.push_back({s.position, Frame::from_axis(s.direction), std::fabs(s.major), std::fabs(s.minor)});
            } else if constexpr (std::is_same_v<T, Box>) {
                g.nodes.push_back({NodeKind::Box, std::uint32_t(g.boxes.size())});
                const Vec3 &a = s.corner1, &b = s.corner2;
                g.boxes.push_back({{std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)},
                                   {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}});
            } else if constexpr (std::is_same_v<T, Cone>) {
                Vec3 axis = s.end2 - s.end1;
                const double len = length(axis), r1 = std::fabs(s.radius1), r2 = std::fabs(s.radius2);
                g.nodes.push_back({NodeKind::Cone, std::uint32_t(g.cones.size())});
                g.cones.push_back({s.end1, normalize(axis), len, r1, r2, (r2 - r1) / len});
            } else if constexpr (std::is_same_v<T, Mesh>) {
                g.nodes.push_back({NodeKind::Mesh, std::uint32_t(g.meshes.size())});
                g.meshes.push_back(mesh_g(s, obj));
            } else if constexpr (std::is_same_v<T, Instance>) {
                // (handled above)
            } else {
                g.nodes.push_back({NodeKind::Csg, std::uint32_t(g.csgs.size())});
                std::uint32_t ci = std::uint32_t(g.csgs.size());
                g.csgs.push_back({s.type, 0, 0});
                std::uint32_t l = add_node(g, s.operands[0], placed);
                std::uint32_t r = add_node(g, s.operands[1], placed);
                CsgG& c = g.csgs.write(ci);
                c.left = l;
                c.right = r;
                c.simple = g.nodes[l].kind != NodeKind::Csg && g.nodes[r].kind != NodeKind::Csg;
            }
        },
        obj.shape);
    return id;
}

// Adds the object's shapes, its CSG operands' included, to count[] by the variant's
// index.
void count_shapes(const Object& obj, std::size_t count[std::variant_size_v<Shape>]) {
    ++count[obj.shape.index()];
    if (const Csg* c = std::get_if<Csg>(&obj.shape))
        for (const Object& o : c->operands) count_shapes(o, count);
}

}  // namespace

Geometry build_geometry(const Scene& scene, bool with_bvh) {
    Geometry g;
    const std::vector<Object>& objects = scene.objects;
    const std::size_t n = objects.size();
    // Reserved up front (top-level shapes; CSG operands may grow them): grown by
    // doubling, a million spheres' arrays would be written about twice. A leading run
    // of spheres (all of many a big scene) is not counted first, a pass over every
    // object: the spheres are reserved for all objects (address space only, where the
    // run ends early), the other shapes counted from the first that is not a sphere.
    static_assert(std::is_same_v<std::variant_alternative_t<0, Shape>, Sphere> &&
                      std::is_same_v<std::variant_alternative_t<4, Shape>, Csg> &&
                      std::is_same_v<std::variant_alternative_t<5, Shape>, Mesh>,
                  "counted by the variant's index");
    // (A sphere with a transform is no plain sphere: it ends the prefix.)
    auto plain_sphere = [](const Object& o) { return o.shape.index() == 0 && !o.transform.set(); };
    const bool sphere_first = n > 0 && plain_sphere(objects[0]);
    std::size_t i = 0;
    if (sphere_first) {
        g.spheres.reserve(n);
        g.nodes.reserve(n);
    }
    g.object_node.reserve(n);
    g.object_bounds.reserve(n);
    // Each object's box is made while its shape record is still in the cache (a pass
    // of its own would read a million spheres' records and nodes again).
    Definitions defs;
    auto add = [&g, &defs](const Object& obj) {
        const std::uint32_t node = add_node(g, obj, nullptr, &defs);
        g.object_node.push_back(node);
        if (const Instance* in = std::get_if<Instance>(&obj.shape)) {
            // (Its definition's box, made once: Geometry::bounds() without walking it again.)
            if (auto it = defs.find(in->defined.get()); it != defs.end()) {
                g.object_bounds.push_back(g.instances[g.nodes[node].index].inst.world_bounds(it->second.box));
                return;
            }
        }
        g.object_bounds.push_back(g.bounds(node));
    };
    // The leading spheres: node i = object i = sphere i (Geometry::sphere_prefix).
    for (; i < n && plain_sphere(objects[i]); ++i) add(objects[i]);
    g.sphere_prefix = std::uint32_t(i);
    if (i < n) {
        // Every shape, CSG operands too: each array is then made in one block.
        std::size_t count[std::variant_size_v<Shape>] = {};
        for (std::size_t j = i; j < n; ++j) count_shapes(objects[j], count);
        g.spheres.reserve(i + count[0]);
        g.tetras.reserve(count[1]);
        g.cylinders.reserve(count[2]);
        g.tori.reserve(count[3]);
        g.csgs.reserve(count[4]);
        g.meshes.reserve(count[5]);
        g.boxes.reserve(count[6]);
        g.cones.reserve(count[7]);
        std::size_t nodes = i;
        for (std::size_t c : count) nodes += c;
        g.nodes.reserve(nodes);
        for (; i < n; ++i) add(objects[i]);
    }
    if (with_bvh) g.bvh.build(g.object_bounds);
    return g;
}


bool same_shapes(const Geometry& a, const Geometry& b) {
    static_assert(sizeof(SphereG) == 5 * sizeof(double) && sizeof(TetraG) == 16 * sizeof(double) &&
                      sizeof(CylinderG) == 8 * sizeof(double) && sizeof(TorusG) == 14 * sizeof(double) &&
                      sizeof(BoxG) == 6 * sizeof(double) && sizeof(ConeG) == 10 * sizeof(double) &&
                      sizeof(XformG) == 22 * sizeof(double) && sizeof(InstanceG) == 22 * sizeof(double) &&
                      sizeof(Aabb) == 6 * sizeof(double),
                  "shape records are plain doubles");
    if (!same_bits(a.spheres, b.spheres) || !same_bits(a.tetras, b.tetras) || !same_bits(a.cylinders, b.cylinders) ||
        !same_bits(a.tori, b.tori) || !same_bits(a.boxes, b.boxes) || !same_bits(a.cones, b.cones) ||
        !same_bits(a.xforms, b.xforms) || !same_bits(a.instances, b.instances) ||
        !same_bits(a.object_node, b.object_node) ||
        !same_bits(a.object_bounds, b.object_bounds) || a.sphere_prefix != b.sphere_prefix)
        return false;
    if (a.meshes.size() != b.meshes.size()) return false;
    for (std::size_t i = 0; i < a.meshes.size(); ++i) {
        const MeshG &x = a.meshes[i], &y = b.meshes[i];
        if (std::memcmp(&x.instance, &y.instance, sizeof x.instance) != 0 || x.model != y.model ||
            x.smooth != y.smooth || x.opaque != y.opaque)
            return false;
    }
    return same_items(a.csgs, b.csgs,
                      [](const CsgG& x, const CsgG& y) {
                          return x.type == y.type && x.left == y.left && x.right == y.right && x.simple == y.simple;
                      }) &&
           same_items(a.nodes, b.nodes, [](const Node& x, const Node& y) { return x.kind == y.kind && x.index == y.index; });
}

// hit(obj, o, d, 0, out) for a shadow ray's test, out of line: every shape but a
// sphere straight to hit_general() (whose one-span shapes already skip first_end()).
bool Geometry::shadow_hit(std::uint32_t obj, const Vec3& o, const Vec3& d, double limit, SpanEnd& out,
                          SpanScratch& s) const {
    const Node& node = nodes[object_node[obj]];
    if (node.kind == NodeKind::Sphere) return hit(obj, o, d, 0.0, out, s);
    if (node.kind == NodeKind::Mesh && meshes[node.index].opaque) {
        const MeshG& m = meshes[node.index];
        if (!m.accel) return false;
        const TriRay r = TriRay::make(m.instance.point_to_model(o), m.instance.to_model(d));
        out = {0, 0, 0, false};
        return m.accel->any(r, 0.0, limit, out.t);
    }
    return hit_general(obj, o, d, 0.0, out, s);
}

}  // namespace rt
