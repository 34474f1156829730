// CSG on interval lists: walk the boundaries of both operands in order, track whether
// the ray is inside each, and emit the intervals where the combined solid holds.
// Surfaces taken from the subtracted operand of a difference face the other way.
// A template so that short lists can live on the stack (see shapes.cpp).
#pragma once

#include <cmath>

#include "shapes.h"

namespace rt {

// A, B: ascending span lists with size() and operator[]; Out: has push_back.
template <class A, class B, class Out>
void combine_span_lists(CsgType type, const A& a, const B& b, Out& out) {
    auto holds = [type](bool ia, bool ib) {
        switch (type) {
            case CsgType::Union: return ia || ib;
            case CsgType::Intersection: return ia && ib;
            case CsgType::Difference: return ia && !ib;
        }
        return false;
    };
    std::size_t i = 0, j = 0;
    bool in_a = false, in_b = false;  // inside a (resp. b) at the current position
    bool inside = false;
    SpanEnd start{};
    const std::size_t na = a.size() * 2, nb = b.size() * 2;
    while (i < na || j < nb) {
        // The next boundary: the k-th boundary of a list is span k/2's in (even) or out (odd).
        double ta = i < na ? (i & 1 ? a[i / 2].out.t : a[i / 2].in.t) : HUGE_VAL;
        double tb = j < nb ? (j & 1 ? b[j / 2].out.t : b[j / 2].in.t) : HUGE_VAL;
        SpanEnd e;
        if (ta <= tb) {
            e = i & 1 ? a[i / 2].out : a[i / 2].in;
            in_a = !(i & 1);
            ++i;
        } else {
            e = j & 1 ? b[j / 2].out : b[j / 2].in;
            in_b = !(j & 1);
            ++j;
            if (type == CsgType::Difference) e.flip = !e.flip;
        }
        bool now = holds(in_a, in_b);
        if (now && !inside) {
            start = e;
        } else if (!now && inside) {
            // Coincident boundaries leave empty intervals: they are no surface.
            if (e.t > start.t) out.push_back({start, e});
        }
        inside = now;
    }
    if (inside) out.push_back({start, SpanEnd{HUGE_VAL, start.node, start.face, start.flip}});
}

}  // namespace rt
