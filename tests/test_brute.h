// The brute-force reference for BVH tests: every object of a compiled Geometry tried
// in file order, so a tree's answer (built, refitted) can be checked against it.
#pragma once

#include <cmath>
#include <cstdint>

#include "math.h"
#include "shapes.h"

namespace rt_test {

struct Hit {
    bool hit = false;
    std::uint32_t obj = 0;
    double t = HUGE_VAL;
};

// Nearest hit with t > kDelta, ties to the lower index (the file order, as
// World::nearest).
inline Hit brute_nearest(const rt::Geometry& g, const rt::Vec3& o, const rt::Vec3& d) {
    Hit h;
    rt::SpanScratch scratch;
    for (std::uint32_t i = 0; i < g.object_node.size(); ++i) {
        rt::SpanEnd e;
        if (g.hit(i, o, d, rt::kDelta, e, scratch) && e.t < h.t) h = {true, i, e.t};
    }
    return h;
}

}  // namespace rt_test
