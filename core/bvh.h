// Bounding volume hierarchy over boxes, built with a binned surface area heuristic and
// stored as one flat array of 32-byte nodes (float bounds, padded outward so that the
// float box test never misses what the double-precision shapes would hit).
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

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
    float pad[3];         // slack in t for rounding the origin to float
#if defined(__SSE2__)
    __m128 o4, inv4, pad4;  // x, y, z, z (the last lane repeats z so reductions can use all four)
#endif
    static BvhRay make(const Vec3& origin, const Vec3& dir) {
        BvhRay r;
        for (int i = 0; i < 3; ++i) {
            r.o[i] = float(origin[i]);
            // A zero component gets a huge finite inverse instead of infinity, so the
            // slab products stay numbers (0 * inf would be NaN).
            double inv = dir[i] != 0 ? 1.0 / dir[i] : (std::signbit(dir[i]) ? -1e30 : 1e30);
            inv = inv > 1e30 ? 1e30 : (inv < -1e30 ? -1e30 : inv);
            r.inv[i] = float(inv);
            // Rounding the origin to float moves the ray by up to |o| * 2^-24 on each
            // axis; widening each slab by that much (in t) keeps the test conservative.
            r.pad[i] = float((std::fabs(origin[i]) * 1.2e-7 + 1e-30) * std::fabs(inv));
            bool neg = std::signbit(dir[i]);
            r.near[i] = neg ? 3 + i : i;
            r.far[i] = neg ? i : 3 + i;
        }
#if defined(__SSE2__)
        r.o4 = _mm_setr_ps(r.o[0], r.o[1], r.o[2], r.o[2]);
        r.inv4 = _mm_setr_ps(r.inv[0], r.inv[1], r.inv[2], r.inv[2]);
        r.pad4 = _mm_setr_ps(r.pad[0], r.pad[1], r.pad[2], r.pad[2]);
#endif
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
#if defined(__SSE2__)
        // lo = (lx, ly, lz, lz), hi = (hx, hy, hz, hz)
        __m128 a = _mm_loadu_ps(n.b);      // lx ly lz hx
        __m128 b = _mm_loadu_ps(n.b + 2);  // lz hx hy hz
        __m128 lo = _mm_shuffle_ps(a, a, _MM_SHUFFLE(2, 2, 1, 0));
        __m128 hi = _mm_shuffle_ps(b, b, _MM_SHUFFLE(3, 3, 2, 1));
        __m128 t1 = _mm_mul_ps(_mm_sub_ps(lo, r.o4), r.inv4);
        __m128 t2 = _mm_mul_ps(_mm_sub_ps(hi, r.o4), r.inv4);
        __m128 near = _mm_sub_ps(_mm_min_ps(t1, t2), r.pad4), far = _mm_add_ps(_mm_max_ps(t1, t2), r.pad4);
        near = _mm_max_ps(near, _mm_shuffle_ps(near, near, _MM_SHUFFLE(2, 3, 0, 1)));
        near = _mm_max_ps(near, _mm_shuffle_ps(near, near, _MM_SHUFFLE(1, 0, 3, 2)));
        far = _mm_min_ps(far, _mm_shuffle_ps(far, far, _MM_SHUFFLE(2, 3, 0, 1)));
        far = _mm_min_ps(far, _mm_shuffle_ps(far, far, _MM_SHUFFLE(1, 0, 3, 2)));
        float t0 = _mm_cvtss_f32(near), t1s = _mm_cvtss_f32(far);
        t0 = t0 > 0.f ? t0 : 0.f;
        t1s = t1s < tmax ? t1s : tmax;
        // A few ulps for the rounding of the products themselves.
        return t0 <= t1s * 1.000001f ? t0 : INFINITY;
#else
        const float* b = n.b;
        float x0 = (b[r.near[0]] - r.o[0]) * r.inv[0] - r.pad[0], x1 = (b[r.far[0]] - r.o[0]) * r.inv[0] + r.pad[0];
        float y0 = (b[r.near[1]] - r.o[1]) * r.inv[1] - r.pad[1], y1 = (b[r.far[1]] - r.o[1]) * r.inv[1] + r.pad[1];
        float z0 = (b[r.near[2]] - r.o[2]) * r.inv[2] - r.pad[2], z1 = (b[r.far[2]] - r.o[2]) * r.inv[2] + r.pad[2];
        float t0 = x0 > 0.f ? x0 : 0.f;
        t0 = y0 > t0 ? y0 : t0;
        t0 = z0 > t0 ? z0 : t0;
        float t1 = x1 < tmax ? x1 : tmax;
        t1 = y1 < t1 ? y1 : t1;
        t1 = z1 < t1 ? z1 : t1;
        return t0 <= t1 * 1.000001f ? t0 : INFINITY;
#endif
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
