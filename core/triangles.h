// A model's triangles compiled for tracing: a BVH over them (the same wide nodes and
// walks as the scene's objects, built in less memory per item), its leaves' triangles
// stored four to a block (one or two blocks a leaf) in the order the leaves come, and
// the watertight ray-triangle test of Woop, Benthin and Wald (JCGT 2013) over a block
// at once. One TriangleAccel serves every mesh block that names the model: a mesh
// instance (MeshInstance) takes the ray into the model's space and back.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "bvh.h"
#include "math.h"
#include "model.h"

namespace rt {

// Up to four triangles, a lane each: corner k's coordinate a at v[3 k + a][lane].
struct alignas(16) TriBlock {
    float v[9][4];
};

// A ray set up for the watertight test (in the model's space): its origin, the axis
// of its direction's largest component (kz) and the two others, and the shear that
// takes the direction to that axis.
struct TriRay {
    Vec3 o, d;
    int kx, ky, kz;
    double sx, sy, sz;
    double ox, oy, oz;  // o's kx, ky and kz coordinates
    static TriRay make(const Vec3& o, const Vec3& d);
};

// The nearest hit of a ray on a model's triangles: its distance and the triangle
// (its slot: 4 * block + lane).
struct TriHit {
    double t;
    std::uint32_t slot;
};

struct TriangleAccel {
    Bvh bvh;  // leaves hold [first, first + count): slots of one or two blocks (first = 4 * block)
    std::vector<TriBlock> blocks;
    std::vector<std::uint32_t> ids;  // per slot, the triangle's index in the model

    static TriangleAccel build(const MeshData& m, int threads = 0);

    // The nearest triangle the line o + t d meets with tmin < t < tmax (ties: the
    // lower slot); false if none.
    bool nearest(const TriRay& r, double tmin, double tmax, TriHit& hit) const;
    // Whether a triangle lies on it with tmin < t < tmax (t: the first one found).
    bool any(const TriRay& r, double tmin, double tmax, double& t) const;

    // nearest() for n rays (n <= kPacket) at once: hits[i] and found[i] are what
    // nearest(rays[i], tmin, tmax, ...) gives, bit for bit. On the AVX2 path the rays
    // walk the 8-wide tree together: a node is fetched once for all of them, and where
    // they share an origin (camera rays) a frustum test of the node's eight boxes against
    // the whole packet skips the children no ray of it can enter before any ray is
    // tested. Each ray then takes the children its own box test (the single-ray walk's)
    // lets through, and its own nearest hit, ties to the lower slot, so that the order
    // of the leaves cannot change an answer.
    static constexpr int kPacket = 32;
    void nearest_packet(const TriRay* rays, int n, double tmin, double tmax, TriHit* hits, bool* found) const;
    // nearest_packet() for rays whose nearest() this thread asks next (camera rays about
    // to be shaded, in order): their answers are kept, and nearest() on exactly one of
    // these rays (the same origin, direction, tmin and tmax, bit for bit) returns the
    // kept answer instead of walking. forget_prepared() drops what is kept (before the
    // accel may go away). Up to kPrepared accels at once per thread; more are not kept.
    // (With hits and found given, the answers are copied there too; false if nothing
    // was prepared: too many rays or accels, or rays of different origins.)
    static constexpr int kPrepared = 4;
    bool prepare(const TriRay* rays, int n, double tmin, double tmax, TriHit* hits = nullptr,
                 bool* found = nullptr) const;
    static void forget_prepared();

    // any() for n rays (n <= kPacket) at once, each with its own tmax: hit[i] is what
    // any(rays[i], tmin, tmax[i], t[i]) returns, and t[i] is set where it is true (a
    // hit on the segment, not necessarily the one any() would meet first). The rays
    // walk the 8-wide tree together as in nearest_packet(), their origins may differ.
    void any_packet(const TriRay* rays, int n, double tmin, const double* tmax, bool* hit, double* t) const;
    // prepare() for any(): shadow rays about to be asked of an opaque mesh (whose
    // callers read only whether a ray is blocked). Dropped by forget_prepared().
    static constexpr int kPreparedAny = 8;
    void prepare_any(const TriRay* rays, int n, double tmin, const double* tmax) const;

    // The triangle's corners in the model's space.
    void corners(std::uint32_t slot, Vec3 c[3]) const;
    std::size_t memory_bytes() const;
};

// The watertight test of lane `lane` of a block: t of the hit (the line's parameter)
// when the line crosses the triangle (its edges and corners included), else NaN.
// Exposed for the tests; nearest() and any() use it or its four-lane form.
double tri_intersect(const TriRay& r, const TriBlock& b, int lane);

// A mesh block's placement of a model: x_world = L x_model + position, with
// L = R(z) R(y) R(x) S; M = L^-1 takes world vectors into the model's space (normals
// go back by M^T).
struct MeshInstance {
    double m[3][3];  // world -> model
    double l[3][3];  // model -> world
    Vec3 position;
    static MeshInstance make(const Vec3& position, const Vec3& scale, const Vec3& rotation_degrees);
    Vec3 to_model(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    Vec3 point_to_model(const Vec3& p) const { return to_model(p - position); }
    Vec3 normal_to_world(const Vec3& n) const {
        return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z, m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
                m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
    }
    Vec3 point_to_world(const Vec3& p) const {
        return Vec3{l[0][0] * p.x + l[0][1] * p.y + l[0][2] * p.z, l[1][0] * p.x + l[1][1] * p.y + l[1][2] * p.z,
                    l[2][0] * p.x + l[2][1] * p.y + l[2][2] * p.z} +
               position;
    }
    // The world box of a model box (its eight corners placed), padded for rounding.
    Aabb world_bounds(const Aabb& model) const;
};

// a then b: the map p -> a(b(p)) (a placement inside a placed frame).
MeshInstance compose(const MeshInstance& a, const MeshInstance& b);

}  // namespace rt
