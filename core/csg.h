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
        // The next boundary: the k-th boundary of a list is span k/2's in (even) or out (odd);
        // a exhausted, b's; b exhausted, a's (whatever the values, +inf and NaN included).
        SpanEnd e;
        if (i < na && (j >= nb || (i & 1 ? a[i / 2].out.t : a[i / 2].in.t) <= (j & 1 ? b[j / 2].out.t : b[j / 2].in.t))) {
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

// The same for at most one span a side (null: none), as a decision tree: the boundaries
// are met in the order combine_span_lists meets them (a's first on equal t) and the
// same spans come out, bit for bit. Both lists end outside, so nothing stays open.
template <class Out>
void combine_single_spans(CsgType type, const Span* a, const Span* b, Out& out) {
    auto emit = [&out](const SpanEnd& s, const SpanEnd& e) {
        if (e.t > s.t) out.push_back({s, e});
    };
    if (!a || !b) {
        if (a && type != CsgType::Intersection) emit(a->in, a->out);
        if (b && type == CsgType::Union) emit(b->in, b->out);
        return;
    }
    const SpanEnd &a0 = a->in, &a1 = a->out;
    SpanEnd b0 = b->in, b1 = b->out;
    switch (type) {
        case CsgType::Difference:
            b0.flip = !b0.flip;
            b1.flip = !b1.flip;
            if (a0.t <= b0.t) {  // a0 opens
                if (a1.t <= b0.t) return emit(a0, a1);
                emit(a0, b0);                     // b0 closes
                if (!(a1.t <= b1.t)) emit(b1, a1);  // b1 opens, a1 closes
            } else if (a0.t <= b1.t) {  // b0, then a0 inside b
                if (!(a1.t <= b1.t)) emit(b1, a1);
            } else {  // b0, b1, then a0 opens and a1 closes
                emit(a0, a1);
            }
            return;
        case CsgType::Intersection:
            if (a0.t <= b0.t) {
                if (a1.t <= b0.t) return;
                emit(b0, a1.t <= b1.t ? a1 : b1);
            } else if (a0.t <= b1.t) {
                emit(a0, a1.t <= b1.t ? a1 : b1);
            }
            return;
        case CsgType::Union:
            if (a0.t <= b0.t) {
                if (a1.t <= b0.t) {
                    emit(a0, a1);
                    emit(b0, b1);
                } else {
                    emit(a0, a1.t <= b1.t ? b1 : a1);
                }
            } else if (a0.t <= b1.t) {
                emit(b0, a1.t <= b1.t ? b1 : a1);
            } else {
                emit(b0, b1);
                emit(a0, a1);
            }
            return;
    }
}

}  // namespace rt
