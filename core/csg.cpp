// The heap-list instance of the CSG span combination (csg.h).
#include "csg.h"

namespace rt {

void combine_spans(CsgType type, const std::vector<Span>& a, const std::vector<Span>& b, std::vector<Span>& out) {
    combine_span_lists(type, a, b, out);
}

}  // namespace rt
