// Text replacements (see text_replacement.h).
#include "text_replacement.h"

#include <algorithm>

namespace rtview {

TextReplacement TextReplacement::apply(std::string& s) const {
    TextReplacement back = inverse(s);
    s.replace(back.offset, back.text.size(), text);
    return back;
}

TextReplacement TextReplacement::inverse(const std::string& before) const {
    const std::size_t off = std::min(offset, before.size());
    const std::size_t len = std::min(length, before.size() - off);
    return {off, text.size(), before.substr(off, len)};
}

TextReplacement diff_texts(const std::string& a, const std::string& b) {
    std::size_t p = 0, n = std::min(a.size(), b.size());
    while (p < n && a[p] == b[p]) ++p;
    std::size_t s = 0;
    while (s < n - p && a[a.size() - 1 - s] == b[b.size() - 1 - s]) ++s;
    return {p, a.size() - p - s, b.substr(p, b.size() - p - s)};
}

}  // namespace rtview
