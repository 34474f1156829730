// The scene text editor widget (see text_editor.h): its state, wrap geometry and
// input (the find and go-to bar: text_editor_bar.cpp; drawing: text_editor_draw.cpp). Text sits on a grid of columns:
// a column is one character, a tab four. It is drawn in the fixed-width font
// (fonts.h); should that face not be fixed-width after all, each character is drawn
// in its own column, so the caret, selection and clicks still match what is shown.
#include "text_editor.h"

#include <imgui_internal.h>  // WantTextInputNextFrame, FocusWindow: 1.86 has no public way

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fonts.h"
#include "probe.h"

namespace rtview {

namespace {


void append_utf8(std::string& s, unsigned c) {
    if (c < 0x80) s += char(c);
    else if (c < 0x800) {
        s += char(0xC0 | (c >> 6));
        s += char(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
        if (c >= 0xD800 && c < 0xE000) return;  // a lone surrogate is no character
        s += char(0xE0 | (c >> 12));
        s += char(0x80 | ((c >> 6) & 0x3F));
        s += char(0x80 | (c & 0x3F));
    } else if (c < 0x110000) {
        s += char(0xF0 | (c >> 18));
        s += char(0x80 | ((c >> 12) & 0x3F));
        s += char(0x80 | ((c >> 6) & 0x3F));
        s += char(0x80 | (c & 0x3F));
    }
}

// ImGui key index of a Key: the backend's key map for named keys; letters follow
// 'A' in the key map (GLFW, SDL scancodes and the Win32 virtual keys all keep A..Z
// contiguous).
int imgui_index(TextEditor::Key k) {
    const ImGuiIO& io = ImGui::GetIO();
    using K = TextEditor::Key;
    switch (k) {
    case K::Left: return io.KeyMap[ImGuiKey_LeftArrow];
    case K::Right: return io.KeyMap[ImGuiKey_RightArrow];
    case K::Up: return io.KeyMap[ImGuiKey_UpArrow];
    case K::Down: return io.KeyMap[ImGuiKey_DownArrow];
    case K::Home: return io.KeyMap[ImGuiKey_Home];
    case K::End: return io.KeyMap[ImGuiKey_End];
    case K::PageUp: return io.KeyMap[ImGuiKey_PageUp];
    case K::PageDown: return io.KeyMap[ImGuiKey_PageDown];
    case K::Backspace: return io.KeyMap[ImGuiKey_Backspace];
    case K::Delete: return io.KeyMap[ImGuiKey_Delete];
    case K::Enter: return io.KeyMap[ImGuiKey_Enter];
    case K::Tab: return io.KeyMap[ImGuiKey_Tab];
    case K::Escape: return io.KeyMap[ImGuiKey_Escape];
    case K::A: return io.KeyMap[ImGuiKey_A];
    case K::C: return io.KeyMap[ImGuiKey_C];
    case K::V: return io.KeyMap[ImGuiKey_V];
    case K::X: return io.KeyMap[ImGuiKey_X];
    case K::Y: return io.KeyMap[ImGuiKey_Y];
    case K::Z: return io.KeyMap[ImGuiKey_Z];
    case K::F: return io.KeyMap[ImGuiKey_A] < 0 ? -1 : io.KeyMap[ImGuiKey_A] + ('F' - 'A');
    case K::G: return io.KeyMap[ImGuiKey_A] < 0 ? -1 : io.KeyMap[ImGuiKey_A] + ('G' - 'A');
    }
    return -1;
}

}  // namespace

TextEditor::TextEditor() = default;

void TextEditor::push_key(Key k, bool shift, bool ctrl) {
    external_keys_ = true;
    if (queue_.size() < 1024) queue_.push_back({k, shift, ctrl});
}

void TextEditor::push_char(unsigned codepoint) {
    external_chars_ = true;
    if (queue_.size() < 1024) queue_.push_back({Key::A, false, false, codepoint});
}

void TextEditor::set_text(std::string_view text) {
    TextPos keep = buf_.cursor();
    buf_.set_text(text);
    buf_.set_cursor(buf_.clamp(keep));
    buf_.clear_line_shifts();
}

void TextEditor::start_over(std::string_view text) {
    set_text(text);
    buf_.set_cursor({0, 0});
    scroll_request_ = true;
    scroll_centre_ = false;
}

void TextEditor::set_marks(std::vector<LineMark> marks) {
    std::stable_sort(marks.begin(), marks.end(), [](const LineMark& a, const LineMark& b) { return a.line < b.line; });
    marks_ = std::move(marks);
}

// Marks follow the lines they are on until the next check replaces them.
void TextEditor::shift_marks() {
    for (const TextBuffer::LineShift& s : buf_.line_shifts()) {
        if (s.removed < 0) continue;  // a whole new text: the host sets new marks
        int delta = s.added - s.removed;
        if (delta == 0) continue;
        for (LineMark& m : marks_) {
            int l = m.line - 1;
            if (l >= s.first + s.removed) m.line += delta;
            else if (l >= s.first + s.added) m.line = s.first + s.added;  // its line went: the last that stayed
        }
    }
    buf_.clear_line_shifts();
}

void TextEditor::show(TextPos p) {
    buf_.set_cursor(p);
    scroll_request_ = true;
    scroll_centre_ = true;
    want_focus_ = true;
}

void TextEditor::open_find() {
    find_open_ = true;
    goto_open_ = false;
    mode_ = Mode::Find;
    want_focus_ = true;
    if (buf_.has_selection() && buf_.selection().begin.line == buf_.selection().end.line)
        find_field_.set_text(buf_.selected_text());
    find_field_.select_all();  // typing replaces the last search
}

void TextEditor::open_goto() {
    goto_open_ = true;
    find_open_ = false;
    mode_ = Mode::Goto;
    want_focus_ = true;
    goto_field_.set_text(std::to_string(buf_.cursor().line + 1));
    goto_field_.select_all();
}

// --- Wrap geometry (in wrap mode a line takes ceil(width / wrap_cols) rows)

int TextEditor::rows_of(int line) const {
    if (!wrap_) return 1;
    int w = buf_.display_width(line);
    return w <= wrap_cols_ ? 1 : (w + wrap_cols_ - 1) / wrap_cols_;
}

int TextEditor::row_of_line(int line) const {
    if (!wrap_) return line;
    int row = 0;
    for (int l = 0; l < line; ++l) row += rows_of(l);
    return row;
}

int TextEditor::line_at_row(int row, int& row_in_line) const {
    if (!wrap_) {
        int l = std::clamp(row, 0, buf_.line_count() - 1);
        row_in_line = 0;
        return l;
    }
    int r = 0;
    for (int l = 0; l < buf_.line_count(); ++l) {
        int n = rows_of(l);
        if (row < r + n) {
            row_in_line = std::max(0, row - r);
            return l;
        }
        r += n;
    }
    int last = buf_.line_count() - 1;
    row_in_line = rows_of(last) - 1;
    return last;
}

TextPos TextEditor::pos_at(const ImVec2& m, const ImVec2& origin) const {
    int row = int(std::floor((m.y - origin.y) / line_h_));
    if (row < 0) return {0, 0};
    int sub = 0;
    int line = line_at_row(row, sub);
    int dcol = int(std::lround((m.x - origin.x) / char_w_));
    dcol = std::max(0, dcol);
    if (wrap_) dcol = std::min(dcol, wrap_cols_) + sub * wrap_cols_;
    return {line, buf_.col_at_display(line, dcol)};
}

// --- Input

void TextEditor::gather_keys() {
    if (external_keys_) return;  // the host's queue has them, in order
    const ImGuiIO& io = ImGui::GetIO();
    static const Key all[] = {Key::Left,   Key::Right, Key::Up,  Key::Down, Key::Home, Key::End, Key::PageUp,
                              Key::PageDown, Key::Backspace, Key::Delete, Key::Enter, Key::Tab, Key::Escape,
                              Key::A,      Key::C,     Key::V,   Key::X,    Key::Y,    Key::Z,   Key::F,  Key::G};
    for (Key k : all) {
        int idx = imgui_index(k);
        if (idx < 0 || idx >= int(IM_ARRAYSIZE(io.KeysDown))) continue;
        if (ImGui::IsKeyPressed(idx, true)) queue_.push_back({k, io.KeyShift, io.KeyCtrl});
    }
}

void TextEditor::handle_key(const KeyEvent& e) {
    if (e.ch) {
        std::string s;
        if (e.ch >= 32 && e.ch != 127) append_utf8(s, e.ch);
        return insert_typed(s);
    }
    if (mode_ != Mode::Text) return handle_field_key(e);
    using M = TextBuffer::Move;
    const int page = std::max(1, int(view_h_ / line_h_) - 1);
    bool moved = true;
    if (e.ctrl) {
        switch (e.key) {
        case Key::A: buf_.select_all(); break;
        case Key::C:
        case Key::X:
            if (buf_.has_selection()) {
                ImGui::SetClipboardText(buf_.selected_text().c_str());
                if (e.key == Key::X) buf_.insert({});
            }
            break;
        case Key::V:
            if (const char* clip = ImGui::GetClipboardText()) {
                // One undo step, newlines as the file has them.
                std::string s(clip);
                s.erase(std::remove(s.begin(), s.end(), '\r'), s.end());
                buf_.break_merge();
                buf_.insert(s);
                buf_.break_merge();
            }
            break;
        case Key::Z:
            if (e.shift ? !buf_.redo() : !buf_.undo()) passed_undo_ = e.shift ? -1 : 1;
            break;
        case Key::Y:
            if (!buf_.redo()) passed_undo_ = -1;
            break;
        case Key::F: open_find(); break;
        case Key::G: open_goto(); break;
        case Key::Left: buf_.move(M::WordLeft, e.shift); break;
        case Key::Right: buf_.move(M::WordRight, e.shift); break;
        case Key::Home: buf_.move(M::DocStart, e.shift); break;
        case Key::End: buf_.move(M::DocEnd, e.shift); break;
        case Key::Up: scroll_by_lines_ -= 1; moved = false; break;
        case Key::Down: scroll_by_lines_ += 1; moved = false; break;
        default: moved = false; break;  // Ctrl+Enter and the like belong to the host
        }
    } else {
        switch (e.key) {
        case Key::Left: buf_.move(M::Left, e.shift); break;
        case Key::Right: buf_.move(M::Right, e.shift); break;
        case Key::Up: buf_.move(M::Up, e.shift); break;
        case Key::Down: buf_.move(M::Down, e.shift); break;
        case Key::Home: buf_.move(M::Home, e.shift); break;
        case Key::End: buf_.move(M::End, e.shift); break;
        case Key::PageUp: buf_.move(M::PageUp, e.shift, page); break;
        case Key::PageDown: buf_.move(M::PageDown, e.shift, page); break;
        case Key::Backspace: buf_.backspace(); break;
        case Key::Delete: buf_.erase_forward(); break;
        case Key::Enter: buf_.newline(); break;
        case Key::Tab: buf_.insert(buf_.indent_unit()); break;  // the file's own unit
        case Key::Escape:
            // Leaves the editor; the text stays as typed.
            focused_ = false;
            ImGui::FocusWindow(nullptr);
            moved = false;
            break;
        default: moved = false; break;
        }
    }
    ++stats_.keys;
    if (moved) scroll_request_ = true;
}

void TextEditor::handle_chars() {
    ImGuiIO& io = ImGui::GetIO();
    if (external_chars_) {
        io.InputQueueCharacters.resize(0);  // the host's queue has them, in order
        return;
    }
    // Ctrl+letter is a shortcut, but AltGr (Ctrl+Alt) types characters on many layouts.
    bool shortcut = io.KeyCtrl && !io.KeyAlt;
    std::string typed;
    for (ImWchar c : io.InputQueueCharacters) {
        if (shortcut || c < 32 || c == 127) continue;  // Enter, Tab and Backspace come as keys
        append_utf8(typed, c);
    }
    io.InputQueueCharacters.resize(0);
    insert_typed(typed);
}

void TextEditor::insert_typed(const std::string& typed) {
    if (typed.empty()) return;
    if (mode_ != Mode::Text) return field_chars(typed);
    // Characters one at a time, so typing merges into word-sized undo steps.
    std::size_t i = 0;
    while (i < typed.size()) {
        std::size_t n = 1;
        while (i + n < typed.size() && (static_cast<unsigned char>(typed[i + n]) & 0xC0) == 0x80) ++n;
        buf_.type(std::string_view(typed).substr(i, n));  // (a `}` on a blank line: one level less)
        i += n;
        ++stats_.chars;
    }
    scroll_request_ = true;
}

void TextEditor::handle_mouse(const ImVec2& origin, float gutter_x1, bool hovered) {
    ImGuiIO& io = ImGui::GetIO();
    ImVec2 m = io.MousePos;
    if (hovered && ImGui::IsMouseClicked(0)) {
        want_focus_ = true;
        if (m.x < gutter_x1) {
            // Click on a line number: select the line.
            TextPos p = pos_at({origin.x, m.y}, origin);
            mode_ = Mode::Text;
        buf_.select({{p.line, 0}, p.line + 1 < buf_.line_count() ? TextPos{p.line + 1, 0} : TextPos{p.line, int(buf_.line(p.line).size())}});
            selecting_ = false;
        } else if (ImGui::IsMouseDoubleClicked(0)) {
            mode_ = Mode::Text;
            buf_.select_word_at(pos_at(m, origin));
            selecting_ = false;
        } else {
            mode_ = Mode::Text;
            buf_.set_cursor(pos_at(m, origin), io.KeyShift);
            selecting_ = true;
        }
    }
    if (selecting_) {
        if (ImGui::IsMouseDown(0)) {
            TextPos p = pos_at(m, origin);
            if (p != buf_.cursor()) {
                buf_.set_cursor(p, true);
                scroll_request_ = true;
            }
        } else {
            selecting_ = false;
        }
    }
}

}  // namespace rtview
