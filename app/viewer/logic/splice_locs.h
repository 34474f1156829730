// Source positions as the document's structural edits move them (document_splice.cpp,
// one edit; document_splice_group.cpp, several as one pass): the parser's lines and
// columns after a text, their order, and where those after a replacement go.
#pragma once

#include <string_view>
#include <variant>
#include <vector>

#include "scene.h"
#include "scene_text.h"

namespace rtview {

// The line and column (the parser's: LF, CR LF and a lone CR end a line; columns count
// bytes from 1) after `text`, which starts at `at`.
inline rt::SourceLoc loc_after(rt::SourceLoc at, std::string_view text) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '\n' || c == '\r') {
            if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
            ++at.line;
            at.col = 1;
        } else {
            ++at.col;
        }
    }
    return at;
}

inline bool before(const rt::SourceLoc& a, const rt::SourceLoc& b) {
    return a.line < b.line || (a.line == b.line && a.col < b.col);
}

// Where the source positions after a replacement go: those from the end of the text
// it removed on move to the end of the text it inserted.
struct LocShift {
    rt::SourceLoc old_end, new_end;
    bool none() const { return old_end.line == new_end.line && old_end.col == new_end.col; }
    void operator()(rt::SourceLoc& l) const {
        if (l.line <= 0 || before(l, old_end)) return;
        if (l.line == old_end.line) {
            l.col = new_end.col + (l.col - old_end.col);
            l.line = new_end.line;
        } else {
            l.line += new_end.line - old_end.line;
        }
    }
    void operator()(rt::Object& o) const {
        (*this)(o.loc);
        if (rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
            for (rt::Object& k : g->operands) (*this)(k);
    }
};

inline std::vector<TextSpan>& spans_of(SceneLayout& l, ItemList list) {
    return list == ItemList::Object ? l.objects : list == ItemList::Plane ? l.planes : l.lights;
}
inline const std::vector<TextSpan>& spans_of(const SceneLayout& l, ItemList list) {
    return list == ItemList::Object ? l.objects : list == ItemList::Plane ? l.planes : l.lights;
}

}  // namespace rtview
