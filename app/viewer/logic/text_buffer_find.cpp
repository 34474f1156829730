// The editor model's find and go to line (see text_buffer.h): matches within a line
// (Knuth-Morris-Pratt), the next or previous one with wrap-around, their count, and a
// typed line number.
#include "text_buffer.h"

#include <algorithm>
#include <cctype>
#include <climits>

namespace rtview {

namespace {

bool equal_chars(char a, char b, bool match_case) {
    if (match_case) return a == b;
    return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
}

}  // namespace

void TextBuffer::find_in_line(int line, std::string_view needle, bool match_case, std::vector<TextRange>& out) const {
    if (needle.empty() || line < 0 || line >= line_count()) return;
    const std::string& l = lines_[std::size_t(line)];
    // Most lines are shorter than the needle (a pasted one may be megabytes long).
    if (l.size() < needle.size()) return;
    auto same = [match_case](char a, char b) { return equal_chars(a, b, match_case); };
    // Knuth-Morris-Pratt: linear in the line and the needle, where a plain search can
    // take their product ("aaa...ab" in a line of "a"s).
    const std::size_t m = needle.size();
    std::vector<std::size_t> border(m + 1, 0);
    for (std::size_t i = 1, k = 0; i < m; ++i) {
        while (k > 0 && !same(needle[i], needle[k])) k = border[k];
        if (same(needle[i], needle[k])) ++k;
        border[i + 1] = k;
    }
    for (std::size_t i = 0, k = 0; i < l.size(); ++i) {
        while (k > 0 && !same(l[i], needle[k])) k = border[k];
        if (same(l[i], needle[k])) ++k;
        if (k == m) {
            const int c = int(i + 1 - m);
            out.push_back({{line, c}, {line, c + int(m)}});
            k = 0;  // matches do not overlap
        }
    }
}

std::optional<TextRange> TextBuffer::find(std::string_view needle, TextPos from, bool forward, bool match_case) const {
    if (needle.empty() || needle.find('\n') != std::string_view::npos) return std::nullopt;
    from = clamp(from);
    const int n = line_count();
    std::vector<TextRange> hits;
    // Visit from.line, the others in order, and from.line again for the wrapped part.
    for (int k = 0; k <= n; ++k) {
        int line = forward ? (from.line + k) % n : ((from.line - k) % n + n) % n;
        hits.clear();
        find_in_line(line, needle, match_case, hits);
        if (hits.empty()) continue;
        if (forward) {
            for (const TextRange& h : hits)
                if (k == n ? h.begin < from : (k > 0 || from <= h.begin)) return h;
        } else {
            for (auto it = hits.rbegin(); it != hits.rend(); ++it)
                if (k == n ? from < it->end : (k > 0 || it->end <= from)) return *it;
        }
    }
    return std::nullopt;
}

TextBuffer::MatchCount TextBuffer::count_matches(std::string_view needle, bool match_case, TextPos at, int limit) const {
    MatchCount c;
    if (needle.empty() || needle.find('\n') != std::string_view::npos) return c;
    std::vector<TextRange> hits;
    for (int line = 0; line < line_count(); ++line) {
        hits.clear();
        find_in_line(line, needle, match_case, hits);
        for (const TextRange& h : hits) {
            if (c.total == limit) {
                c.more = true;
                return c;
            }
            ++c.total;
            if (h.begin == at) c.index = c.total;
        }
    }
    return c;
}

int parse_line_number(std::string_view typed) {
    // Digits only (the field takes nothing else); a number too big for an int is the
    // last line anyway.
    long long n = 0;
    bool any = false;
    for (char c : typed) {
        if (c < '0' || c > '9') continue;
        any = true;
        n = std::min<long long>(n * 10 + (c - '0'), INT_MAX);
    }
    return any ? int(n) : 0;
}

void TextBuffer::goto_line(int line1) {
    int l = std::clamp(line1 - 1, 0, line_count() - 1);
    set_cursor({l, 0});
}

}  // namespace rtview
