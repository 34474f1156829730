// The scene text editor widget: draws a TextBuffer with ImGui (line numbers, syntax
// colours, diagnostics in the gutter, find and go-to bars, optional wrap) and turns
// keys, characters and the mouse into buffer edits. Only the visible lines are
// coloured and drawn, so the cost of a frame does not grow with the file.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <imgui.h>

#include "text_buffer.h"

namespace rtview {

// A diagnostic attached to a line (1-based, as the parser reports them).
struct LineMark {
    int line = 1;
    bool error = true;  // else a warning
    std::string message;
};

class TextEditor {
public:
    // Keys the editor acts on. A host whose input reaches ImGui once a frame (so a
    // press and release between two frames would vanish) feeds them with push_key()
    // from its key callback instead; after the first push_key() the editor stops
    // polling ImGui for these keys. Either way they are handled in arrival order.
    enum class Key { Left, Right, Up, Down, Home, End, PageUp, PageDown, Backspace, Delete, Enter, Tab, Escape, A, C, V, X, Y, Z, F, G };
    void push_key(Key k, bool shift, bool ctrl);
    // Characters from the same host queue (keeps their order with the keys); after
    // the first push_char() the editor stops reading ImGui's character queue.
    void push_char(unsigned codepoint);

    TextEditor();

    TextBuffer& buffer() { return buf_; }
    const TextBuffer& buffer() const { return buf_; }
    // Replaces the text (a reload, an undo of the document): keeps the cursor's line
    // and the scroll position where they still exist.
    void set_text(std::string_view text);
    // Another document's text: the cursor at its start, scrolled to the top.
    void start_over(std::string_view text);
    std::string text() const { return buf_.text(); }

    // Draws the editor filling `size` (ImGui sizes: 0 = available, < 0 = available
    // minus). Returns true when the user changed the text during this call.
    bool draw(const char* id, const ImVec2& size);

    void set_marks(std::vector<LineMark> marks);
    // The marks as they are now: they move with inserted and deleted lines.
    const std::vector<LineMark>& marks() const { return marks_; }
    void set_wrap(bool on) { wrap_ = on; }
    bool wrap() const { return wrap_; }

    bool focused() const { return focused_; }
    // An undo (+1) or redo (-1) asked of the text when it had no step to take (its
    // history starts again where the document changed the text): the host's to make.
    int take_passed_undo() { return std::exchange(passed_undo_, 0); }
    void focus() { want_focus_ = true; }
    // Cursor to `p`, scrolled into view (centred when it was out of view), focused.
    void show(TextPos p);
    void open_find();
    void open_goto();

    // What the last draw() did (tests and benchmarks).
    struct Stats {
        int first_line = 0, last_line = -1;  // lines drawn
        int keys = 0, chars = 0;             // handled
    };
    const Stats& stats() const { return stats_; }

private:
    struct KeyEvent {
        Key key;
        bool shift, ctrl;
        unsigned ch = 0;  // a character instead of a key
    };
    void gather_keys();
    void handle_key(const KeyEvent& e);
    void handle_chars();
    void insert_typed(const std::string& typed);
    void handle_mouse(const ImVec2& text_origin, float gutter_x1, bool hovered);
    void handle_field_key(const KeyEvent& e);
    void field_chars(const std::string& typed);
    void find_next(bool forward);
    void draw_bar();
    // Parts of draw(): the queued keys and characters (when focused), the text area's
    // geometry and scrolling, the visible rows, a line's gutter, one row.
    struct Frame;
    void take_input();
    void lay_out_text(Frame& f);
    void draw_rows(const Frame& f);
    void draw_gutter(const Frame& f, int line, float line_y0, const LineMark* mark, const std::string& tip);
    void draw_row(const Frame& f, int line, int r, float y, const std::vector<TextRange>& matches);
    bool draw_field(const char* id, TextBuffer& f, float width, bool active);
    void scroll_to_cursor(bool centre);
    void shift_marks();
    // Wrap geometry: rows of a line, the first row of a line, the line at a row.
    int rows_of(int line) const;
    int row_of_line(int line) const;
    int line_at_row(int row, int& row_in_line) const;
    TextPos pos_at(const ImVec2& mouse, const ImVec2& text_origin) const;

    TextBuffer buf_;
    std::vector<LineMark> marks_;  // sorted by line
    std::vector<TokenSpan> spans_;
    bool wrap_ = false;
    int wrap_cols_ = 80;
    float char_w_ = 7, line_h_ = 13;
    float view_w_ = 0, view_h_ = 0;

    bool focused_ = false, want_focus_ = false;
    int passed_undo_ = 0;
    bool external_keys_ = false, external_chars_ = false;
    std::vector<KeyEvent> queue_;
    int last_drawn_frame_ = -10;
    bool scroll_request_ = false, scroll_centre_ = false;
    bool selecting_ = false;  // mouse drag in progress

    // Where typing goes. The find and go-to fields are drawn and edited here (not
    // ImGui InputTexts), so a key typed right after Ctrl+F lands in the field
    // instead of in a frame where neither has the keyboard.
    enum class Mode { Text, Find, Goto } mode_ = Mode::Text;
    bool find_open_ = false, goto_open_ = false, match_case_ = false;
    TextBuffer find_field_, goto_field_;
    std::string find_status_;
    float scroll_by_lines_ = 0;

    Stats stats_;
};

}  // namespace rtview
