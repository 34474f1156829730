// The scene text editor's model, without GL or ImGui: the text as a vector of lines,
// the cursor and selection, edits recorded for undo, find and go to line (the colouring
// of one line: syntax_colours.h). A keystroke rewrites only the lines it changes; one
// that adds or joins lines also moves the later lines' strings along the vector, and
// the offset of a later line is counted again from the changed one when it is next
// asked for.
#pragma once

#include <cstddef>
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syntax_colours.h"

namespace rtview {

// A place in the text: 0-based line, byte column inside that line.
struct TextPos {
    int line = 0;
    int col = 0;
    bool operator==(const TextPos& o) const { return line == o.line && col == o.col; }
    bool operator!=(const TextPos& o) const { return !(*this == o); }
    bool operator<(const TextPos& o) const { return line < o.line || (line == o.line && col < o.col); }
    bool operator<=(const TextPos& o) const { return !(o < *this); }
};

struct TextRange {
    TextPos begin, end;  // begin <= end
    bool empty() const { return begin == end; }
};

// The buffer's record of one replacement, in lines and columns, with what it replaced and
// the cursors: enough to apply it again or take it back.
// `removed` started at `at`; after the edit `inserted` starts there.
struct BufferEdit {
    TextPos at;
    std::string removed, inserted;
    TextPos cursor_before, anchor_before;  // restored by undo
    TextPos cursor_after;                  // restored by redo
    std::size_t offset = 0;                // byte offset of `at` (in the edit log only)
};

// The number typed into "go to line": its digits (anything else is skipped), at most
// INT_MAX however many there are; 0 for none.
int parse_line_number(std::string_view typed);

// The unit of indentation of a text given line by line (`line(i)` for i < count; the
// first `max_lines` are looked at): a tab when more indented lines begin with a tab
// than with a space, else the commonest step (1 to 8 spaces) from a line to a more
// indented one after it; two spaces when the text says nothing.
template <class LineAt>
std::string detect_indent_unit(int count, LineAt line, int max_lines = 4000);
std::string indent_unit_from(int tab_lines, int space_lines, const int (&steps)[9]);

// ---- the buffer ----------------------------------------------------------------
class TextBuffer {
public:
    TextBuffer();
    explicit TextBuffer(std::string_view text) { set_text(text); }

    // Replaces everything; forgets the undo history; cursor to the start.
    void set_text(std::string_view text);
    // The whole text (lines joined by '\n'): O(size), for saving and parsing.
    std::string text() const;

    int line_count() const { return int(lines_.size()); }
    const std::string& line(int i) const { return lines_[std::size_t(i)]; }
    std::size_t size() const { return size_; }  // bytes of text(), newlines included
    // Increases with every change of the text.
    std::uint64_t version() const { return version_; }

    // Byte offset in text() <-> position. The line start index is kept up to date
    // lazily from the first changed line, so a query near the edit is cheap.
    std::size_t offset_of(TextPos p) const;
    TextPos pos_of(std::size_t offset) const;
    TextPos clamp(TextPos p) const;
    TextPos end_pos() const { return {line_count() - 1, int(lines_.back().size())}; }

    // ---- cursor and selection -------------------------------------------------
    TextPos cursor() const { return cursor_; }
    TextPos anchor() const { return anchor_; }
    bool has_selection() const { return cursor_ != anchor_; }
    TextRange selection() const;
    std::string selected_text() const;
    std::string text_in(TextRange r) const;
    // Moves the cursor; `extend` keeps the anchor (Shift), else the selection collapses.
    void set_cursor(TextPos p, bool extend = false);
    void select(TextRange r);  // anchor at begin, cursor at end
    void select_all();
    void select_word_at(TextPos p);

    enum class Move { Left, Right, WordLeft, WordRight, Up, Down, Home, End, PageUp, PageDown, DocStart, DocEnd };
    // Left/Right step over whole UTF-8 characters; Up/Down keep the column the cursor
    // had before the vertical run (in display columns, a tab counting 4); Home goes to
    // the first non-blank, then to column 0. `page` is lines per page.
    void move(Move m, bool extend, int page = 20);

    // ---- editing (each call is one undoable edit; typing merges) ---------------
    // Replaces the selection (or inserts at the cursor).
    void insert(std::string_view s);
    // Enter: keeps the current line's indentation, one level more after a `{` (the
    // text before the cursor ending in one, a // comment aside); between `{` and `}`
    // the `}` goes to a line of its own below, at the first line's indentation.
    void newline();
    // A typed character: `}` on a line blank up to the cursor takes one level of its
    // indentation away; anything else is insert().
    void type(std::string_view s);
    // The text's unit of indentation (detect_indent_unit of its first lines).
    std::string indent_unit() const;
    void backspace();
    void erase_forward();
    // Replaces `r` with `s`, cursor after it. The primitive every edit goes through.
    void replace(TextRange r, std::string_view s);
    // The same by byte offsets (an edit computed on text(), e.g. from scene_edits).
    void replace_bytes(std::size_t offset, std::size_t length, std::string_view s);
    // A replacement made elsewhere, in a copy of the text that this buffer follows (the
    // document's panel edits, undo and redo): not an edit of the buffer's own, so not
    // logged, and the undo history goes as with set_text(). The cursor and the anchor
    // keep their places in the text around it. Costs what the lines it touches cost.
    void follow_replacement(std::size_t offset, std::size_t length, std::string_view s);

    bool can_undo() const { return !undo_.empty(); }
    bool can_redo() const { return !redo_.empty(); }
    bool undo();
    bool redo();
    // The next edit starts a new undo step even if it would merge (a click, a pause).
    void break_merge() { merge_ok_ = false; }

    // With logging on, every applied edit (undo and redo as edits of their own) is
    // kept, oldest first, with its byte offset in the text as it was just before it,
    // for a host that mirrors the text in a std::string: replaying
    // `s.replace(e.offset, e.removed.size(), e.inserted)` in order keeps s == text().
    // take_edits() empties the list. set_text() is not an edit: it clears the list.
    void set_logging(bool on) { logging_ = on; }
    std::vector<BufferEdit> take_edits();

    // Lines [first, first+removed) were replaced by `added` lines by the last edit;
    // for markers attached to lines (diagnostics) that should follow the text.
    struct LineShift {
        int first = 0, removed = 0, added = 0;
    };
    const std::vector<LineShift>& line_shifts() const { return shifts_; }
    void clear_line_shifts() { shifts_.clear(); }

    // ---- find and go to line --------------------------------------------------
    // Next match of `needle` (no newlines) starting at `from` (forward) or ending
    // before it (backward), wrapping around the end. Empty needle: nothing.
    std::optional<TextRange> find(std::string_view needle, TextPos from, bool forward, bool match_case) const;
    // All matches in one line (for highlighting the visible ones).
    void find_in_line(int line, std::string_view needle, bool match_case, std::vector<TextRange>& out) const;
    // How many matches of `needle` the text has, and which of them (1-based) begins at
    // `at` (0: none does). Counts up to `limit` matches, then stops (`more` says so).
    struct MatchCount {
        int total = 0, index = 0;
        bool more = false;
    };
    MatchCount count_matches(std::string_view needle, bool match_case, TextPos at, int limit) const;
    // 1-based line number, clamped; selects nothing, cursor to the line's first column.
    void goto_line(int line1);

    // Display columns of a line prefix (tabs count 4, a UTF-8 character counts 1).
    int display_col(int line, int col) const;
    // The byte column whose display column is nearest `dcol` (not past the line).
    int col_at_display(int line, int dcol) const;
    // Widest line in display columns (kept incrementally).
    int max_display_width() const;
    int display_width(int line) const { return widths_[std::size_t(line)]; }

private:
    // Deletes the selection, or one character in the direction of `step` (Left or
    // Right), as one undoable edit that merges with typing.
    void erase_toward(Move step);
    // Replaces the ordered range `r` with `s` as one undo step, the cursor after it;
    // `typing` lets the next keystrokes join the step, `may_merge` lets it join the
    // previous one.
    void replace_range(TextRange r, std::string_view s, bool typing, bool may_merge);
    // Where Ctrl+Left and Ctrl+Right go from `p`: over blanks, then one run of word
    // or punctuation characters; across a line end from a line's start or end.
    TextPos word_left(TextPos p) const;
    TextPos word_right(TextPos p) const;
    TextPos apply(TextPos at, TextPos end, std::string_view s, std::string* removed);
    void record(BufferEdit e, bool mergeable_insert, bool mergeable_erase);
    void touch_lines(int from);
    static int width_of(std::string_view s);

    std::vector<std::string> lines_;
    std::vector<int> widths_;  // display width of each line
    mutable int max_width_ = 0;
    mutable bool max_dirty_ = false;
    std::size_t size_ = 0;
    std::uint64_t version_ = 0;
    // Line start offsets, valid for lines [0, starts_valid_).
    mutable std::vector<std::size_t> starts_;
    mutable int starts_valid_ = 0;

    TextPos cursor_, anchor_;
    int want_dcol_ = -1;  // column kept across Up/Down runs

    std::vector<BufferEdit> undo_, redo_;
    enum class LastKind { None, Insert, Erase } last_ = LastKind::None;
    bool merge_ok_ = false;
    bool logging_ = false;
    std::vector<BufferEdit> log_;
    std::size_t last_offset_ = 0;  // of the last apply(), when logging
    std::vector<LineShift> shifts_;
};

template <class LineAt>
std::string detect_indent_unit(int count, LineAt line, int max_lines) {
    int tabs = 0, spaces = 0, steps[9] = {};
    int prev = 0;
    for (int i = 0; i < count && i < max_lines; ++i) {
        const std::string_view l = line(i);
        std::size_t n = 0;
        while (n < l.size() && l[n] == ' ') ++n;
        const bool tab = n < l.size() && l[n] == '\t';
        if (l.find_first_not_of(" \t\r") == std::string_view::npos) continue;  // blank: says nothing
        if (tab) {
            ++tabs;
            continue;
        }
        if (n > 0) ++spaces;
        if (int(n) > prev) ++steps[std::min<std::size_t>(n - std::size_t(prev), 8)];
        prev = int(n);
    }
    return indent_unit_from(tabs, spaces, steps);
}

}  // namespace rtview
