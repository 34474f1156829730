// The scene text editor's indentation (see text_buffer.h): Enter keeps a line's
// indentation and adds a level after `{`, a `}` typed on a blank line takes one away,
// in the unit the text itself uses (a tab, or so many spaces).
#include "text_buffer.h"

namespace rtview {

namespace {

bool blank_char(char c) { return c == ' ' || c == '\t'; }

// Whether the text before the cursor ends in `{` (a // comment after it aside).
bool opens_block(std::string_view before) {
    if (std::size_t c = before.find("//"); c != std::string_view::npos) before = before.substr(0, c);
    while (!before.empty() && (blank_char(before.back()) || before.back() == '\r')) before.remove_suffix(1);
    return !before.empty() && before.back() == '{';
}

}  // namespace

std::string indent_unit_from(int tab_lines, int space_lines, const int (&steps)[9]) {
    if (tab_lines > space_lines) return "\t";
    int best = 0;
    for (int k = 1; k <= 8; ++k)
        if (steps[k] > (best ? steps[best] : 0)) best = k;
    return std::string(best ? std::size_t(best) : 2, ' ');
}

std::string TextBuffer::indent_unit() const {
    return detect_indent_unit(line_count(), [this](int i) { return std::string_view(line(i)); });
}

void TextBuffer::newline() {
    const std::string& l = lines_[std::size_t(cursor_.line)];
    const std::string eol = (!l.empty() && l.back() == '\r') ? "\r\n" : "\n";
    TextRange r = selection();
    const std::string& first = lines_[std::size_t(r.begin.line)];
    std::size_t indent = 0;
    while (indent < first.size() && int(indent) < r.begin.col && blank_char(first[indent])) ++indent;
    const std::string ind = first.substr(0, indent);
    const bool opens = opens_block(std::string_view(first).substr(0, std::size_t(r.begin.col)));
    // `{|}`: the blanks before the `}` go, and it moves to a line of its own.
    const std::string& last = lines_[std::size_t(r.end.line)];
    std::size_t skip = std::size_t(r.end.col);
    while (skip < last.size() && blank_char(last[skip])) ++skip;
    const bool closes = opens && skip < last.size() && last[skip] == '}';
    const std::string unit = opens ? indent_unit() : std::string();
    std::string s = eol + ind + unit;
    merge_ok_ = false;
    if (closes) {
        r.end.col = int(skip);
        replace(r, s + eol + ind);
        set_cursor({r.begin.line + 1, int(ind.size() + unit.size())});
    } else {
        insert(s);
    }
    merge_ok_ = false;
}

void TextBuffer::type(std::string_view s) {
    if (s != "}" || has_selection()) return insert(s);
    const std::string& l = lines_[std::size_t(cursor_.line)];
    const std::size_t col = std::size_t(cursor_.col);
    if (col == 0 || col > l.size()) return insert(s);
    for (std::size_t k = 0; k < col; ++k)
        if (!blank_char(l[k])) return insert(s);
    // One level less: a tab, or the spaces back to the previous multiple of the unit.
    std::size_t cut = 1;
    if (l[col - 1] == ' ') {
        const std::string unit = indent_unit();
        const std::size_t width = unit == "\t" ? 4 : unit.size();
        std::size_t n = 0;
        while (n < col && l[col - 1 - n] == ' ') ++n;
        cut = std::min(n, (n - 1) % width + 1);
    }
    merge_ok_ = false;
    replace({{cursor_.line, int(col - cut)}, cursor_}, "}");
}

}  // namespace rtview
