// Bounding volume hierarchy over boxes, built with a binned surface area heuristic and
// stored as one flat array of 32-byte nodes (float bounds, padded outward so that the
// float box test never misses what the double-precision shapes would hit).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "math.h"

namespace rt {

struct BvhNode {
    float b[6];  // lo x, y, z then hi x, y, z
    std::uint32_t first;  // leaf: first index into Bvh::items; inner: right child (left is this + 1)
    std::uint32_t count;  // leaf: number of items (> 0); inner: 0
};
static_assert(sizeof(BvhNode) == 32, "BVH nodes are 32 bytes");

struct BvhRay {
    float o[3];
    float inv[3];
    int near[3], far[3];  // per axis, the index of the near and far slab in lo/hi order
    static BvhRay make(const Vec3& origin, const Vec3& dir) {
        BvhRay r;
        for (int i = 0; i < 3; ++i) {
            r.o[i] = float(origin[i]);
            double inv = 1.0 / dir[i];  // +-inf for a zero component is fine in the slab test
            r.inv[i] = float(inv);
            bool neg = dir[i] < 0;
            r.near[i] = neg ? 3 + i : i;
            r.far[i] = neg ? i : 3 + i;
        }
        return r;
    }
};

class Bvh {
public:
    std::vector<BvhNode> nodes;
    std::vector<std::uint32_t> items;  // item ids (indices of the boxes given to build)

    // Items with empty boxes are left out.
    void build(const std::vector<Aabb>& boxes);

    // Entry distance of the ray into node's box if it is within [0, tmax], else +inf.
    static inline float enter(const BvhNode& n, const BvhRay& r, float tmax) {
        const float* b = n.b;
        float x0 = (b[r.near[0]] - r.o[0]) * r.inv[0], x1 = (b[r.far[0]] - r.o[0]) * r.inv[0];
        float y0 = (b[r.near[1]] - r.o[1]) * r.inv[1], y1 = (b[r.far[1]] - r.o[1]) * r.inv[1];
        float z0 = (b[r.near[2]] - r.o[2]) * r.inv[2], z1 = (b[r.far[2]] - r.o[2]) * r.inv[2];
        // A NaN (0 * inf, a ray in a slab's plane) compares false and leaves the bound as it is.
        float t0 = x0 > 0.f ? x0 : 0.f;
        t0 = y0 > t0 ? y0 : t0;
        t0 = z0 > t0 ? z0 : t0;
        float t1 = x1 < tmax ? x1 : tmax;
        t1 = y1 < t1 ? y1 : t1;
        t1 = z1 < t1 ? z1 : t1;
        return t0 <= t1 ? t0 : INFINITY;
    }

    // Visit the items whose boxes the ray may enter before tmax, nearest box first.
    // `fn(item, tmax)` returns the new tmax (smaller to prune), or a negative value to stop.
    template <class Fn>
    void traverse(const Vec3& origin, const Vec3& dir, double tmax, Fn&& fn) const {
        if (nodes.empty()) return;
        BvhRay r = BvhRay::make(origin, dir);
        auto widen = [](double t) { return t == HUGE_VAL ? INFINITY : float(t * (1 + 1e-6) + 1e-6); };
        float ftmax = widen(tmax);
        struct Entry {
            std::uint32_t node;
            float t;
        };
        Entry stack[64];
        int sp = 0;
        std::uint32_t cur = 0;
        if (enter(nodes[0], r, ftmax) == INFINITY) return;
        for (;;) {
            const BvhNode& n = nodes[cur];
            if (n.count > 0) {
                for (std::uint32_t i = 0; i < n.count; ++i) {
                    double nt = fn(items[n.first + i], tmax);
                    if (nt < 0) return;
                    if (nt < tmax) {
                        tmax = nt;
                        ftmax = widen(tmax);
                    }
                }
            } else {
                std::uint32_t a = cur + 1, b = n.first;
                float ta = enter(nodes[a], r, ftmax), tb = enter(nodes[b], r, ftmax);
                if (ta > tb) {
                    std::swap(a, b);
                    std::swap(ta, tb);
                }
                if (ta != INFINITY) {
                    if (tb != INFINITY) {
                        if (sp < 64) {
                            stack[sp++] = {b, tb};
                        } else {
                            // Too deep for the stack: search that subtree now.
                            if (!traverse_from(b, r, tmax, fn)) return;
                            ftmax = widen(tmax);
                        }
                    }
                    cur = a;
                    continue;
                }
            }
            // Pop the next subtree still in reach.
            for (;;) {
                if (sp == 0) return;
                --sp;
                if (stack[sp].t <= ftmax) break;
            }
            cur = stack[sp].node;
        }
    }

    // Fallback for pathologically deep trees: plain recursion from one node.
    template <class Fn>
    bool traverse_from(std::uint32_t cur, const BvhRay& r, double& tmax, Fn& fn) const {
        float ftmax = tmax == HUGE_VAL ? INFINITY : float(tmax * (1 + 1e-6) + 1e-6);
        if (enter(nodes[cur], r, ftmax) == INFINITY) return true;
        const BvhNode& n = nodes[cur];
        if (n.count > 0) {
            for (std::uint32_t i = 0; i < n.count; ++i) {
                double nt = fn(items[n.first + i], tmax);
                if (nt < 0) return false;
                if (nt < tmax) tmax = nt;
            }
            return true;
        }
        return traverse_from(cur + 1, r, tmax, fn) && traverse_from(n.first, r, tmax, fn);
    }

    std::size_t memory_bytes() const { return nodes.capacity() * sizeof(BvhNode) + items.capacity() * 4; }
};

}  // namespace rt
