// The editor model (see text_buffer.h; the colouring of a line: syntax_colours.cpp;
// find and go to line: text_buffer_find.cpp). Lines are std::strings in a vector: an
// edit rewrites the lines it touches and moves the vector's tail (a memmove of small
// handles, not of the text); offsets and the widest line are kept up to date lazily.
#include "text_buffer.h"

#include <algorithm>
#include <cctype>
#include <utility>

namespace rtview {

// Buffer

namespace {

bool continuation(char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; }

// Position just after `s` inserted at `at`.
TextPos end_after(TextPos at, std::string_view s) {
    std::size_t nl = s.rfind('\n');
    if (nl == std::string_view::npos) return {at.line, at.col + int(s.size())};
    return {at.line + int(std::count(s.begin(), s.end(), '\n')), int(s.size() - nl - 1)};
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\n'; }

// 0 blank, 1 word, 2 other: what Ctrl+Left/Right skip over.
int char_class(char c) {
    if (is_space(c)) return 0;
    unsigned char u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '_' || c == '.' || c == '-' || c == '+' || u >= 0x80) return 1;
    return 2;
}

int line_end_col(const std::string& l) {
    return int(l.size()) - (!l.empty() && l.back() == '\r' ? 1 : 0);
}

}  // namespace

TextBuffer::TextBuffer() { set_text({}); }

int TextBuffer::width_of(std::string_view s) {
    int w = 0;
    for (char c : s) {
        if (c == '\t') w += 4;
        else if (c != '\r' && !continuation(c)) ++w;
    }
    return w;
}

void TextBuffer::set_text(std::string_view text) {
    lines_.clear();
    widths_.clear();
    // The line starts are indexed here, in the pass that splits the lines, not by the
    // first edit (a first key in a 99 MB text would pay a pass over its 2.8M lines).
    starts_.clear();
    // (Sized first: a 28 MB text has 1.75M lines, and the three lists grown a line at
    // a time copied themselves twenty times over.)
    const std::size_t lines = std::size_t(std::count(text.begin(), text.end(), '\n')) + 1;
    lines_.reserve(lines);
    widths_.reserve(lines);
    starts_.reserve(lines);
    std::size_t i = 0;
    for (;;) {
        std::size_t nl = text.find('\n', i);
        std::string_view l = text.substr(i, nl == std::string_view::npos ? std::string_view::npos : nl - i);
        lines_.emplace_back(l);
        widths_.push_back(width_of(l));
        starts_.push_back(i);
        if (nl == std::string_view::npos) break;
        i = nl + 1;
    }
    size_ = text.size();
    max_dirty_ = true;
    starts_valid_ = int(starts_.size());
    cursor_ = anchor_ = {};
    want_dcol_ = -1;
    undo_.clear();
    redo_.clear();
    last_ = LastKind::None;
    merge_ok_ = false;
    log_.clear();
    shifts_.clear();
    shifts_.push_back({0, -1, line_count()});  // everything replaced
    ++version_;
}

std::string TextBuffer::text() const {
    std::string out;
    out.reserve(size_);
    for (std::size_t i = 0; i < lines_.size(); ++i) {
        if (i) out += '\n';
        out += lines_[i];
    }
    return out;
}

void TextBuffer::touch_lines(int from) {
    starts_valid_ = std::min(starts_valid_, from + 1);
}

std::size_t TextBuffer::offset_of(TextPos p) const {
    p = clamp(p);
    if (starts_.size() != lines_.size()) {
        starts_.resize(lines_.size());
        starts_valid_ = std::min(starts_valid_, int(lines_.size()));
    }
    if (starts_valid_ == 0) {
        starts_[0] = 0;
        starts_valid_ = 1;
    }
    for (int i = starts_valid_; i <= p.line; ++i) starts_[std::size_t(i)] = starts_[std::size_t(i - 1)] + lines_[std::size_t(i - 1)].size() + 1;
    starts_valid_ = std::max(starts_valid_, p.line + 1);
    return starts_[std::size_t(p.line)] + std::size_t(p.col);
}

TextPos TextBuffer::pos_of(std::size_t offset) const {
    offset = std::min(offset, size_);
    offset_of(end_pos());  // the whole index (used for occasional whole-text edits)
    auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
    int line = int(it - starts_.begin()) - 1;
    return {line, int(offset - starts_[std::size_t(line)])};
}

TextPos TextBuffer::clamp(TextPos p) const {
    if (p.line < 0) return {0, 0};
    if (p.line >= line_count()) return end_pos();
    p.col = std::clamp(p.col, 0, int(lines_[std::size_t(p.line)].size()));
    return p;
}

TextRange TextBuffer::selection() const {
    return cursor_ < anchor_ ? TextRange{cursor_, anchor_} : TextRange{anchor_, cursor_};
}

std::string TextBuffer::text_in(TextRange r) const {
    r.begin = clamp(r.begin);
    r.end = clamp(r.end);
    if (r.end < r.begin) std::swap(r.begin, r.end);
    if (r.begin.line == r.end.line)
        return lines_[std::size_t(r.begin.line)].substr(std::size_t(r.begin.col), std::size_t(r.end.col - r.begin.col));
    std::string out = lines_[std::size_t(r.begin.line)].substr(std::size_t(r.begin.col));
    for (int l = r.begin.line + 1; l < r.end.line; ++l) {
        out += '\n';
        out += lines_[std::size_t(l)];
    }
    out += '\n';
    out += lines_[std::size_t(r.end.line)].substr(0, std::size_t(r.end.col));
    return out;
}

std::string TextBuffer::selected_text() const { return text_in(selection()); }

void TextBuffer::set_cursor(TextPos p, bool extend) {
    cursor_ = clamp(p);
    if (!extend) anchor_ = cursor_;
    want_dcol_ = -1;
    merge_ok_ = false;
}

void TextBuffer::select(TextRange r) {
    anchor_ = clamp(r.begin);
    cursor_ = clamp(r.end);
    want_dcol_ = -1;
    merge_ok_ = false;
}

void TextBuffer::select_all() { select({{0, 0}, end_pos()}); }

void TextBuffer::select_word_at(TextPos p) {
    p = clamp(p);
    const std::string& l = lines_[std::size_t(p.line)];
    if (l.empty()) return set_cursor(p);
    int c = std::min(p.col, int(l.size()) - 1);
    int cls = char_class(l[std::size_t(c)]);
    int b = c, e = c;
    while (b > 0 && char_class(l[std::size_t(b - 1)]) == cls) --b;
    while (e < int(l.size()) && char_class(l[std::size_t(e)]) == cls) ++e;
    select({{p.line, b}, {p.line, e}});
}

int TextBuffer::display_col(int line, int col) const {
    const std::string& l = lines_[std::size_t(line)];
    return width_of(std::string_view(l).substr(0, std::size_t(std::clamp(col, 0, int(l.size())))));
}

int TextBuffer::col_at_display(int line, int dcol) const {
    const std::string& l = lines_[std::size_t(line)];
    int w = 0, end = line_end_col(l);
    for (int i = 0; i < end; ++i) {
        char c = l[std::size_t(i)];
        if (continuation(c)) continue;
        int cw = c == '\t' ? 4 : 1;
        if (dcol < w + (cw + 1) / 2) return i;
        w += cw;
    }
    return end;
}

int TextBuffer::max_display_width() const {
    if (max_dirty_) {
        max_width_ = widths_.empty() ? 0 : *std::max_element(widths_.begin(), widths_.end());
        max_dirty_ = false;
    }
    return max_width_;
}

TextPos TextBuffer::word_left(TextPos p) const {
    if (p.col == 0) return p.line > 0 ? TextPos{p.line - 1, line_end_col(lines_[std::size_t(p.line - 1)])} : p;
    const std::string& l = lines_[std::size_t(p.line)];
    while (p.col > 0 && char_class(l[std::size_t(p.col - 1)]) == 0) --p.col;
    if (p.col > 0) {
        int cls = char_class(l[std::size_t(p.col - 1)]);
        while (p.col > 0 && char_class(l[std::size_t(p.col - 1)]) == cls) --p.col;
    }
    return p;
}

TextPos TextBuffer::word_right(TextPos p) const {
    const std::string& l = lines_[std::size_t(p.line)];
    int end = line_end_col(l);
    if (p.col >= end) return p.line + 1 < line_count() ? TextPos{p.line + 1, 0} : p;
    int cls = char_class(l[std::size_t(p.col)]);
    while (p.col < end && char_class(l[std::size_t(p.col)]) == cls) ++p.col;
    while (p.col < end && char_class(l[std::size_t(p.col)]) == 0) ++p.col;
    return p;
}

void TextBuffer::move(Move m, bool extend, int page) {
    // With a selection and no Shift, Left/Right collapse to its edge.
    if (!extend && has_selection() && (m == Move::Left || m == Move::Right)) {
        TextRange r = selection();
        return set_cursor(m == Move::Left ? r.begin : r.end);
    }
    TextPos p = cursor_;
    const std::string* l = &lines_[std::size_t(p.line)];
    int keep_dcol = -1;
    switch (m) {
    case Move::Left:
        if (p.col > 0) {
            do --p.col;
            while (p.col > 0 && continuation((*l)[std::size_t(p.col)]));
        } else if (p.line > 0) {
            --p.line;
            p.col = line_end_col(lines_[std::size_t(p.line)]);
        }
        break;
    case Move::Right:
        if (p.col < line_end_col(*l)) {
            do ++p.col;
            while (p.col < int(l->size()) && continuation((*l)[std::size_t(p.col)]));
        } else if (p.line + 1 < line_count()) {
            ++p.line;
            p.col = 0;
        }
        break;
    case Move::WordLeft: p = word_left(p); break;
    case Move::WordRight: p = word_right(p); break;
    case Move::Up:
    case Move::Down:
    case Move::PageUp:
    case Move::PageDown: {
        keep_dcol = want_dcol_ >= 0 ? want_dcol_ : display_col(p.line, p.col);
        int step = (m == Move::Up || m == Move::Down) ? 1 : std::max(1, page);
        int dir = (m == Move::Up || m == Move::PageUp) ? -1 : 1;
        int target = std::clamp(p.line + dir * step, 0, line_count() - 1);
        if (target == p.line) {
            // First or last line: go to its start or end, like other editors.
            p.col = dir < 0 ? 0 : line_end_col(*l);
            keep_dcol = -1;
        } else {
            p.line = target;
            p.col = col_at_display(target, keep_dcol);
        }
        break;
    }
    case Move::Home: {
        int first = 0;
        while (first < int(l->size()) && ((*l)[std::size_t(first)] == ' ' || (*l)[std::size_t(first)] == '\t')) ++first;
        p.col = p.col == first ? 0 : first;
        break;
    }
    case Move::End: p.col = line_end_col(*l); break;
    case Move::DocStart: p = {0, 0}; break;
    case Move::DocEnd: p = end_pos(); break;
    }
    set_cursor(p, extend);
    want_dcol_ = keep_dcol;
}

TextPos TextBuffer::apply(TextPos at, TextPos end, std::string_view s, std::string* removed) {
    at = clamp(at);
    end = clamp(end);
    if (end < at) std::swap(at, end);
    // Near the previous edit the line index is still valid: this costs little.
    if (logging_) last_offset_ = offset_of(at);
    std::size_t removed_bytes = 0;
    if (removed) *removed = text_in({at, end});
    {
        if (at.line == end.line) removed_bytes = std::size_t(end.col - at.col);
        else {
            removed_bytes = lines_[std::size_t(at.line)].size() - std::size_t(at.col) + 1 + std::size_t(end.col);
            for (int l = at.line + 1; l < end.line; ++l) removed_bytes += lines_[std::size_t(l)].size() + 1;
        }
    }
    // Did the edit remove a line as wide as the widest? Then that may shrink.
    bool had_max = false;
    if (!max_dirty_)
        for (int l = at.line; l <= end.line; ++l) had_max = had_max || widths_[std::size_t(l)] >= max_width_;

    std::vector<std::string_view> pieces;
    for (std::size_t i = 0;;) {
        std::size_t nl = s.find('\n', i);
        pieces.push_back(s.substr(i, nl == std::string_view::npos ? std::string_view::npos : nl - i));
        if (nl == std::string_view::npos) break;
        i = nl + 1;
    }
    const std::string& last_line = lines_[std::size_t(end.line)];
    std::string suffix = last_line.substr(std::size_t(end.col));
    std::string first = lines_[std::size_t(at.line)].substr(0, std::size_t(at.col));
    std::vector<std::string> fresh;
    fresh.reserve(pieces.size());
    first += pieces[0];
    fresh.push_back(std::move(first));
    for (std::size_t k = 1; k < pieces.size(); ++k) fresh.emplace_back(pieces[k]);
    TextPos after{at.line + int(pieces.size()) - 1, int(fresh.back().size())};
    fresh.back() += suffix;

    const std::size_t old_n = std::size_t(end.line - at.line + 1), new_n = fresh.size();
    const std::size_t base = std::size_t(at.line);
    const std::size_t common = std::min(old_n, new_n);
    for (std::size_t k = 0; k < common; ++k) {
        lines_[base + k] = std::move(fresh[k]);
        widths_[base + k] = width_of(lines_[base + k]);
    }
    if (old_n > new_n) {
        lines_.erase(lines_.begin() + std::ptrdiff_t(base + common), lines_.begin() + std::ptrdiff_t(base + old_n));
        widths_.erase(widths_.begin() + std::ptrdiff_t(base + common), widths_.begin() + std::ptrdiff_t(base + old_n));
    } else if (new_n > old_n) {
        lines_.insert(lines_.begin() + std::ptrdiff_t(base + common), std::make_move_iterator(fresh.begin() + std::ptrdiff_t(common)),
                      std::make_move_iterator(fresh.end()));
        std::vector<int> w;
        for (std::size_t k = common; k < new_n; ++k) w.push_back(width_of(lines_[base + k]));
        widths_.insert(widths_.begin() + std::ptrdiff_t(base + common), w.begin(), w.end());
    }
    if (!max_dirty_) {
        int new_max = 0;
        for (std::size_t k = 0; k < new_n; ++k) new_max = std::max(new_max, widths_[base + k]);
        if (new_max >= max_width_) max_width_ = new_max;
        else if (had_max) max_dirty_ = true;
    }
    size_ = size_ - removed_bytes + s.size();
    touch_lines(at.line);
    if (starts_.size() > lines_.size()) starts_.resize(lines_.size());
    shifts_.push_back({at.line, int(old_n), int(new_n)});
    ++version_;
    return after;
}

void TextBuffer::record(BufferEdit e, bool mergeable_insert, bool mergeable_erase) {
    redo_.clear();
    if (logging_) {
        e.offset = last_offset_;
        log_.push_back(e);
    }
    if (merge_ok_ && !undo_.empty()) {
        BufferEdit& last = undo_.back();
        if (mergeable_insert && last_ == LastKind::Insert && last.removed.empty() &&
            end_after(last.at, last.inserted) == e.at &&
            // A space after a word starts a new step: undo takes back a word at a time.
            !(e.inserted == " " && !last.inserted.empty() && last.inserted.back() != ' ')) {
            last.inserted += e.inserted;
            last.cursor_after = e.cursor_after;
            return;
        }
        if (mergeable_erase && last_ == LastKind::Erase && last.inserted.empty()) {
            if (end_after(e.at, e.removed) == last.at) {  // backspace run
                last.at = e.at;
                last.removed = e.removed + last.removed;
                last.cursor_after = e.cursor_after;
                return;
            }
            if (e.at == last.at) {  // Delete run
                last.removed += e.removed;
                last.cursor_after = e.cursor_after;
                return;
            }
        }
    }
    undo_.push_back(std::move(e));
    last_ = mergeable_insert ? LastKind::Insert : mergeable_erase ? LastKind::Erase : LastKind::None;
    merge_ok_ = mergeable_insert || mergeable_erase;
}

void TextBuffer::replace(TextRange r, std::string_view s) {
    r.begin = clamp(r.begin);
    r.end = clamp(r.end);
    if (r.end < r.begin) std::swap(r.begin, r.end);
    replace_range(r, s, false, false);
}

void TextBuffer::replace_range(TextRange r, std::string_view s, bool typing, bool may_merge) {
    BufferEdit e;
    e.cursor_before = cursor_;
    e.anchor_before = anchor_;
    e.at = r.begin;
    e.inserted = std::string(s);
    TextPos after = apply(r.begin, r.end, s, &e.removed);
    cursor_ = anchor_ = after;
    want_dcol_ = -1;
    e.cursor_after = after;
    if (!may_merge) merge_ok_ = false;
    record(std::move(e), typing, false);
}

void TextBuffer::replace_bytes(std::size_t offset, std::size_t length, std::string_view s) {
    offset = std::min(offset, size_);
    length = std::min(length, size_ - offset);
    replace({pos_of(offset), pos_of(offset + length)}, s);
}

void TextBuffer::follow_replacement(std::size_t offset, std::size_t length, std::string_view s) {
    offset = std::min(offset, size_);
    length = std::min(length, size_ - offset);
    // A place after the replaced bytes moves with them; one inside stays, within the new ones.
    auto moved = [&](std::size_t at) {
        return at <= offset ? at : at >= offset + length ? at - length + s.size() : std::min(at, offset + s.size());
    };
    const std::size_t cursor = moved(offset_of(cursor_)), anchor = moved(offset_of(anchor_));
    apply(pos_of(offset), pos_of(offset + length), s, nullptr);
    cursor_ = pos_of(cursor);
    anchor_ = pos_of(anchor);
    want_dcol_ = -1;
    undo_.clear();
    redo_.clear();
    last_ = LastKind::None;
    merge_ok_ = false;
}

void TextBuffer::insert(std::string_view s) {
    if (s.empty() && !has_selection()) return;
    bool typing = !has_selection() && s.size() <= 4 && s.find('\n') == std::string_view::npos;
    replace_range(selection(), s, typing, true);
}

void TextBuffer::backspace() { erase_toward(Move::Left); }

void TextBuffer::erase_forward() { erase_toward(Move::Right); }

void TextBuffer::erase_toward(Move step) {
    if (has_selection()) {
        merge_ok_ = false;
        insert({});
        merge_ok_ = false;
        return;
    }
    const bool merge = merge_ok_;
    const TextPos at = cursor_;
    move(step, false);
    const TextPos other = cursor_;
    cursor_ = anchor_ = at;
    if (other == at) return;
    const TextPos begin = std::min(at, other), end = std::max(at, other);
    BufferEdit e;
    e.cursor_before = at;
    e.anchor_before = at;
    e.at = begin;
    apply(begin, end, {}, &e.removed);
    cursor_ = anchor_ = begin;
    e.cursor_after = begin;
    merge_ok_ = merge;
    const bool one_line = e.removed.find('\n') == std::string::npos;
    record(std::move(e), false, one_line);
}

bool TextBuffer::undo() {
    if (undo_.empty()) return false;
    BufferEdit e = std::move(undo_.back());
    undo_.pop_back();
    apply(e.at, end_after(e.at, e.inserted), e.removed, nullptr);
    if (logging_) log_.push_back({e.at, e.inserted, e.removed, {}, {}, {}, last_offset_});
    cursor_ = e.cursor_before;
    anchor_ = e.anchor_before;
    want_dcol_ = -1;
    merge_ok_ = false;
    redo_.push_back(std::move(e));
    return true;
}

bool TextBuffer::redo() {
    if (redo_.empty()) return false;
    BufferEdit e = std::move(redo_.back());
    redo_.pop_back();
    apply(e.at, end_after(e.at, e.removed), e.inserted, nullptr);
    if (logging_) log_.push_back({e.at, e.removed, e.inserted, {}, {}, {}, last_offset_});
    cursor_ = anchor_ = e.cursor_after;
    want_dcol_ = -1;
    merge_ok_ = false;
    undo_.push_back(std::move(e));
    return true;
}

std::vector<BufferEdit> TextBuffer::take_edits() {
    std::vector<BufferEdit> out;
    out.swap(log_);
    return out;
}

}  // namespace rtview
