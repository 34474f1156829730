// Compiled geometry: the bounded shapes as flat arrays, each able to report the
// intervals (spans) of the ray's line that lie inside it. CSG nodes combine their
// operands' spans (csg.cpp); top-level objects sit in a BVH (bvh.h).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "bvh.h"
#include "chunked.h"
#include "math.h"
#include "scene.h"
#include "simd.h"
#include "triangles.h"

namespace rt {

// 1.5e-5 world units: the original's surface tolerance.
constexpr double kDelta = 1.5e-5;

enum class NodeKind : std::uint8_t { Sphere, Tetra, Cylinder, Torus, Csg, Mesh, Box, Cone, Xform, Instance };

struct SphereG {
    Vec3 c;
    double r, r2;
};
// Inside where dot(n[i], p) + d[i] <= 0 for all four faces.
struct TetraG {
    Vec3 n[4];
    double d[4];
};
struct CylinderG {
    Vec3 e1, a;  // first end centre, unit axis toward the second
    double len, r;
};
struct TorusG {
    Vec3 c;
    Frame frame;  // frame.w is the axis
    double R, r;
};
// Faces: 2 k + 0 the low side on axis k, 2 k + 1 the high side.
struct BoxG {
    Vec3 lo, hi;
};
// A frustum: radius r1 at e1, r1 + k z at z along the unit axis a, up to len (k: the
// change of radius per unit of length). Faces as the cylinder's.
struct ConeG {
    Vec3 e1, a;
    double len, r1, r2, k;
};
// A primitive placed by a transform (its own and its CSGs', composed): the child node,
// always the next one, holds the shape as written; rays are taken into its space, so
// the shape stays exact (a scaled sphere is an ellipsoid), normals back by the
// inverse transpose. The span ends it reports name this node.
struct XformG {
    MeshInstance inst;  // object -> world (l, position) and world -> object (m)
    std::uint32_t child = 0;
    std::uint32_t unused = 0;  // (no padding of unknown bytes: records compare by memcmp)
};
// A placement of a defined object (a top-level object only): the definition's nodes,
// built once for every placement in its own space from `root`, seen through `inst`.
// The span ends it reports name the definition's nodes, so their normals are taken
// back by the object's (Geometry::surface_normal).
struct InstanceG {
    MeshInstance inst;
    std::uint32_t root = 0;
    std::uint32_t unused = 0;
};
struct CsgG {
    CsgType type;
    std::uint32_t left, right;  // node indices
    bool simple = false;        // both operands are primitives: at most 2 spans each
};

// A mesh block: a model's triangles (shared with every mesh naming the same file)
// placed by its transform. A mesh is a surface, not a solid: its "spans" are single
// crossings, found by mesh_hit(); its SpanEnd's `node` is the triangle's slot in the
// model's TriangleAccel and `flip` says that the triangle faces along the ray (so its
// normal is turned toward the ray: both sides are lit alike).
struct MeshG {
    MeshInstance instance;
    std::shared_ptr<const MeshModel> model;  // null: no model was read (nothing to hit)
    const TriangleAccel* accel = nullptr;  // model->accel()
    bool smooth = false;
    bool opaque = true;  // its material lets no light through: a shadow ray may stop at any hit
};

struct Node {
    NodeKind kind;
    std::uint32_t index;  // into the array for its kind
};

// One end of an inside interval: where it is and which surface made it, so that the
// normal there can be found. `flip` is set for surfaces of a subtracted operand.
struct SpanEnd {
    double t;
    std::uint32_t node;
    std::uint8_t face;
    bool flip;
};
struct Span {
    SpanEnd in, out;
};

// Scratch space for CSG span lists, reused between rays (one per thread).
// Sized up front for the deepest CSG the parser accepts, so references into it stay
// valid while deeper levels are in use.
struct SpanScratch {
    std::vector<std::vector<Span>> levels;
    SpanScratch() : levels(2 * (Limits::max_csg_depth + 4)) {}
    std::vector<Span>& at(std::size_t slot) {
        std::vector<Span>& v = levels[slot];
        v.clear();
        return v;
    }
};

// The arrays are shared by copies (chunked.h): the structure whole (no edit in place
// changes it), the records and boxes in chunks, so that moving an object in a copy
// copies only the few chunks its records are in.
struct Geometry {
    Chunked<SphereG> spheres;
    Chunked<TetraG> tetras;
    Chunked<CylinderG> cylinders;
    Chunked<TorusG> tori;
    Chunked<BoxG> boxes;
    Chunked<ConeG> cones;
    Chunked<XformG> xforms;
    Chunked<InstanceG> instances;
    Shared<CsgG> csgs;
    Shared<MeshG> meshes;  // instances of models (their triangles shared, not copied)
    Shared<Node> nodes;
    Shared<std::uint32_t> object_node;  // top-level object -> node
    // Objects [0, sphere_prefix) are spheres with node i = object i = sphere i, so that
    // hit() finds them without the two lookups (a scene of spheres is one prefix).
    std::uint32_t sphere_prefix = 0;
    Chunked<Aabb> object_bounds;
    Bvh bvh;                             // over top-level objects

    // Inside spans of node `n` along the whole line o + t d (d unit), ascending.
    void spans(std::uint32_t n, const Vec3& o, const Vec3& d, std::vector<Span>& out, SpanScratch& scratch,
               std::size_t depth = 0) const;
    // Outward unit normal of surface `face` of node `n` at p (not for meshes).
    [[nodiscard]] Vec3 normal(std::uint32_t n, std::uint8_t face, const Vec3& p) const;
    // The unit normal at p of the surface `e` of object `obj` that a ray hit: normal()
    // turned by e.flip, or for a mesh its triangle's (interpolated if smooth).
    [[nodiscard]] Vec3 surface_normal(std::uint32_t obj, const SpanEnd& e, const Vec3& p) const;
    Aabb bounds(std::uint32_t n) const;

    // Nearest entry into object `obj` with t > tmin; false if none.
    [[nodiscard]] bool hit(std::uint32_t obj, const Vec3& o, const Vec3& d, double tmin, SpanEnd& out, SpanScratch& s) const {
        return hit_inline(obj, o, d, tmin, out, s);
    }
    // The same, inlined whatever the compiler would choose: for the hottest loops only.
    [[nodiscard, gnu::always_inline]] bool hit_inline(std::uint32_t obj, const Vec3& o, const Vec3& d, double tmin,
                                                      SpanEnd& out, SpanScratch& s) const {
        // The common case, inline and without building a span.
        const SphereG* ps;
        std::uint32_t n;
        if (obj < sphere_prefix) {
            ps = &spheres[obj];
            n = obj;
        } else {
            n = object_node[obj];
            const Node& node = nodes[n];
            if (node.kind != NodeKind::Sphere) return hit_general(obj, o, d, tmin, out, s);
            ps = &spheres[node.index];
        }
        const SphereG& sp = *ps;
        Vec3 oc = o - sp.c;
        double b = dot(oc, d);
        double disc = b * b - (dot(oc, oc) - sp.r2);
        if (disc < 0) return false;
        double t = -b - std::sqrt(disc);
        if (!(t > tmin)) return false;
        out = {t, n, 0, false};
        return true;
    }
#if RT_HAVE_AVX2_KERNELS
    // hit() for four spheres of the prefix at once (AVX2; call only where it is active):
    // bit k set when the line enters sphere ids[k] at t[k] > tmin. The same double
    // operations lane for lane as hit(), so the same t, bit for bit.
    [[nodiscard]] unsigned sphere_entries4(const std::uint32_t ids[4], const Vec3& o, const Vec3& d, double tmin,
                                           double t[4]) const;
#endif
    [[nodiscard]] bool hit_general(std::uint32_t obj, const Vec3& o, const Vec3& d, double tmin, SpanEnd& out,
                                   SpanScratch& s) const;
    // hit(obj, o, d, 0.0, out, s) out of line, for shadow rays' tests of objects outside
    // the sphere prefix (mostly tetrahedra, cylinders and CSG, which they mostly miss).
    // The ray ends at `limit`: an opaque mesh stops at any triangle before it (out.t is
    // then that one's, not necessarily the nearest).
    [[nodiscard]] bool shadow_hit(std::uint32_t obj, const Vec3& o, const Vec3& d, double limit, SpanEnd& out,
                                  SpanScratch& s) const;
    // Where a ray inside object `obj` (or on its surface, going in) leaves it:
    // the first span end beyond kDelta; false if none.
    [[nodiscard]] bool exit(std::uint32_t obj, const Vec3& o, const Vec3& d, SpanEnd& out, SpanScratch& s) const;

    std::size_t model_bytes() const;  // the meshes' models, each once

private:
    bool mesh_hit(const MeshG& m, const Vec3& o, const Vec3& d, double tmin, SpanEnd& out) const;
    Vec3 mesh_normal(const MeshG& m, const SpanEnd& e, const Vec3& p) const;
    template <class Out>
    void leaf_spans(std::uint32_t n, const Vec3& o, const Vec3& d, Out& out) const;
    template <class Out>
    void one_span(const Node& node, std::uint32_t n, const Vec3& o, const Vec3& d, Out& out) const;
    template <class Out>
    void single_csg_spans(const CsgG& c, const Node& l, const Node& r, const Vec3& o, const Vec3& d, Out& out) const;
    template <class Out>
    void simple_csg_spans(const CsgG& c, const Vec3& o, const Vec3& d, Out& out) const;
    // Feeds the spans of object `obj` along the line, ascending, to sink.push_back()
    // (through `scratch` only for nested CSG); returns sink.found.
    template <class Sink>
    bool first_end(std::uint32_t obj, const Vec3& o, const Vec3& d, SpanScratch& scratch, Sink&& sink) const;
};

// The BVH is left empty when with_bvh is false (to compare with same_shapes first).
[[nodiscard]] Geometry build_geometry(const Scene& scene, bool with_bvh = true);
// Whether two geometries hold the same compiled shapes, bit for bit (their BVHs aside):
// then they render alike, and one's BVH serves the other.
[[nodiscard]] bool same_shapes(const Geometry& a, const Geometry& b);

// Combine two ascending span lists by a CSG operation.
void combine_spans(CsgType type, const std::vector<Span>& a, const std::vector<Span>& b, std::vector<Span>& out);

}  // namespace rt
