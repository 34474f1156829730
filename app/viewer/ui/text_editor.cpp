// The scene text editor widget (see text_editor.h). Text sits on a grid of columns:
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

ImU32 kind_colour(TokenKind k) {
    switch (k) {
    case TokenKind::Section: return IM_COL32(255, 160, 80, 255);
    case TokenKind::Object: return IM_COL32(100, 190, 255, 255);
    case TokenKind::Key: return IM_COL32(200, 160, 255, 255);
    case TokenKind::Number: return IM_COL32(150, 225, 150, 255);
    case TokenKind::Comment: return IM_COL32(130, 140, 130, 255);
    case TokenKind::Brace: return IM_COL32(210, 210, 210, 255);
    case TokenKind::Text: break;
    }
    return ImGui::GetColorU32(ImGuiCol_Text);
}

constexpr ImU32 kErrorCol = IM_COL32(255, 107, 107, 255);
constexpr ImU32 kWarnCol = IM_COL32(255, 204, 90, 255);
constexpr ImU32 kErrorLineBg = IM_COL32(255, 80, 80, 40);
constexpr ImU32 kMatchBg = IM_COL32(255, 210, 60, 70);
constexpr ImU32 kCurrentLineBg = IM_COL32(255, 255, 255, 14);

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

// Whether the printable ASCII characters of `font` at `size` are all `char_w` wide.
bool fixed_width(const ImFont* font, float size, float char_w) {
    const float scale = size / font->FontSize;
    for (ImWchar c = 32; c < 127; ++c)
        if (std::fabs(font->GetCharAdvance(c) * scale - char_w) > 0.01f * char_w) return false;
    return true;
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

// ---------------------------------------------------------------------------------
// Wrap geometry (in wrap mode a line takes ceil(width / wrap_cols) rows)

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

// ---------------------------------------------------------------------------------
// Input

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
        case Key::Tab: buf_.insert("  "); break;
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
        buf_.insert(std::string_view(typed).substr(i, n));
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

// ---------------------------------------------------------------------------------
// Find and go-to bar

void TextEditor::find_next(bool forward) {
    const std::string needle = find_field_.line(0);
    TextRange sel = buf_.selection();
    auto r = buf_.find(needle, forward ? sel.end : sel.begin, forward, match_case_);
    if (r) {
        buf_.select(*r);
        scroll_request_ = true;
        scroll_centre_ = true;
        find_status_.clear();
    } else {
        find_status_ = needle.empty() ? "" : "no match";
    }
}

void TextEditor::handle_field_key(const KeyEvent& e) {
    using M = TextBuffer::Move;
    TextBuffer& f = mode_ == Mode::Find ? find_field_ : goto_field_;
    ++stats_.keys;
    if (e.ctrl) {
        switch (e.key) {
        case Key::A: f.select_all(); break;
        case Key::C:
            if (f.has_selection()) ImGui::SetClipboardText(f.selected_text().c_str());
            break;
        case Key::V:
            if (const char* clip = ImGui::GetClipboardText()) {
                std::string s(clip);
                s = s.substr(0, s.find_first_of("\r\n"));
                field_chars(s);
            }
            break;
        case Key::F: open_find(); break;
        case Key::G: open_goto(); break;
        default: break;
        }
        return;
    }
    switch (e.key) {
    case Key::Left: f.move(M::Left, e.shift); break;
    case Key::Right: f.move(M::Right, e.shift); break;
    case Key::Home: f.move(M::DocStart, e.shift); break;
    case Key::End: f.move(M::DocEnd, e.shift); break;
    case Key::Backspace: f.backspace(); break;
    case Key::Delete: f.erase_forward(); break;
    case Key::Up:
    case Key::Down:
        if (mode_ == Mode::Find) find_next(e.key == Key::Down);
        break;
    case Key::Enter:
        if (mode_ == Mode::Find) {
            find_next(!e.shift);
        } else {
            int line = parse_line_number(goto_field_.line(0));
            buf_.goto_line(std::max(1, line));
            scroll_request_ = true;
            scroll_centre_ = true;
            goto_open_ = false;
            mode_ = Mode::Text;
        }
        break;
    case Key::Escape:
    case Key::Tab:
        // Back to the text; Escape also closes the bar.
        if (e.key == Key::Escape) find_open_ = goto_open_ = false;
        mode_ = Mode::Text;
        break;
    default: break;
    }
}

void TextEditor::field_chars(const std::string& typed) {
    TextBuffer& f = mode_ == Mode::Find ? find_field_ : goto_field_;
    std::string s;
    for (char c : typed) {
        if (mode_ == Mode::Goto && (c < '0' || c > '9')) continue;
        if (c != '\n' && c != '\r') s += c;
    }
    if (!s.empty()) f.insert(s);
}

// A one-line field drawn like an ImGui input; returns true when clicked.
bool TextEditor::draw_field(const char* id, TextBuffer& f, float width, bool active) {
    const ImGuiStyle& st = ImGui::GetStyle();
    ImVec2 p = ImGui::GetCursorScreenPos();
    ImVec2 sz(width, ImGui::GetFrameHeight());
    ImGui::InvisibleButton(id, sz);
    bool clicked = ImGui::IsItemClicked();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->AddRectFilled(p, ImVec2(p.x + sz.x, p.y + sz.y), ImGui::GetColorU32(ImGuiCol_FrameBg), st.FrameRounding);
    if (active)
        dl->AddRect(p, ImVec2(p.x + sz.x, p.y + sz.y), ImGui::GetColorU32(ImGuiCol_NavHighlight), st.FrameRounding);
    const std::string& t = f.line(0);
    // Keep the cursor in view when the text is wider than the field.
    float tx = p.x + st.FramePadding.x, ty = p.y + st.FramePadding.y;
    float avail = sz.x - 2 * st.FramePadding.x;
    float cx = float(f.display_col(0, f.cursor().col)) * char_w_;
    float shift = std::max(0.f, cx - avail + char_w_);
    dl->PushClipRect(p, ImVec2(p.x + sz.x, p.y + sz.y), true);
    if (f.has_selection()) {
        TextRange r = f.selection();
        dl->AddRectFilled(ImVec2(tx - shift + float(f.display_col(0, r.begin.col)) * char_w_, ty),
                          ImVec2(tx - shift + float(f.display_col(0, r.end.col)) * char_w_, ty + ImGui::GetFontSize()),
                          ImGui::GetColorU32(ImGuiCol_TextSelectedBg));
    }
    // Only the columns in view: a pasted line may be megabytes long, and ImGui reserves
    // vertices for every character it is given.
    const int first = f.col_at_display(0, std::max(0, int(shift / char_w_) - 1));
    const int last = f.col_at_display(0, int((shift + avail) / char_w_) + 2);
    dl->AddText(ImVec2(tx - shift + float(f.display_col(0, first)) * char_w_, ty), ImGui::GetColorU32(ImGuiCol_Text),
                t.c_str() + first, t.c_str() + std::max(first, last));
    if (active) dl->AddLine(ImVec2(tx - shift + cx, ty), ImVec2(tx - shift + cx, ty + ImGui::GetFontSize()), ImGui::GetColorU32(ImGuiCol_Text));
    dl->PopClipRect();
    return clicked;
}

void TextEditor::draw_bar() {
    const ImGuiStyle& st = ImGui::GetStyle();
    if (find_open_) {
        ImGui::AlignTextToFramePadding();
        ImGui::TextUnformatted("Find");
        ImGui::SameLine();
        auto bw = [&](const char* s) { return ImGui::CalcTextSize(s).x + st.FramePadding.x * 2 + st.ItemSpacing.x; };
        float rest = bw("<") + bw(">") + bw("Aa") + bw("x") +
                     (find_status_.empty() ? 0 : ImGui::CalcTextSize(find_status_.c_str()).x + st.ItemSpacing.x);
        float w = std::max(6 * char_w_, ImGui::GetContentRegionAvail().x - rest);
        if (draw_field("##find", find_field_, w, focused_ && mode_ == Mode::Find)) {
            mode_ = Mode::Find;
            want_focus_ = true;
        }
        ImGui::SameLine();
        if (ImGui::Button("<")) find_next(false);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Previous match (Shift+Enter)");
        ImGui::SameLine();
        if (ImGui::Button(">")) find_next(true);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Next match (Enter)");
        ImGui::SameLine();
        ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(match_case_ ? ImGuiCol_ButtonActive : ImGuiCol_Button));
        if (ImGui::Button("Aa")) match_case_ = !match_case_;
        ImGui::PopStyleColor();
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Match case");
        ImGui::SameLine();
        if (ImGui::Button("x")) {
            find_open_ = false;
            mode_ = Mode::Text;
        }
        if (!find_status_.empty()) {
            ImGui::SameLine();
            ImGui::TextColored(ImVec4(1, 0.8f, 0.35f, 1), "%s", find_status_.c_str());
        }
    } else if (goto_open_) {
        ImGui::AlignTextToFramePadding();
        ImGui::Text("Go to line (1-%d)", buf_.line_count());
        ImGui::SameLine();
        if (draw_field("##goto", goto_field_, char_w_ * 10 + st.FramePadding.x * 2, focused_ && mode_ == Mode::Goto)) {
            mode_ = Mode::Goto;
            want_focus_ = true;
        }
        ImGui::SameLine();
        if (ImGui::Button("Go")) handle_field_key({Key::Enter, false, false});
        ImGui::SameLine();
        if (ImGui::Button("x")) {
            goto_open_ = false;
            mode_ = Mode::Text;
        }
    }
}

// ---------------------------------------------------------------------------------
// Scrolling

void TextEditor::scroll_to_cursor(bool centre) {
    TextPos c = buf_.cursor();
    int dcol = buf_.display_col(c.line, c.col);
    int row = row_of_line(c.line);
    if (wrap_) {
        int sub = std::min(dcol / wrap_cols_, rows_of(c.line) - 1);
        row += sub;
        dcol -= sub * wrap_cols_;
    }
    float y = float(row) * line_h_, x = float(dcol) * char_w_;
    float sy = ImGui::GetScrollY(), sx = ImGui::GetScrollX();
    if (centre && (y < sy || y + line_h_ > sy + view_h_)) ImGui::SetScrollY(std::max(0.f, y - view_h_ / 2));
    else if (y < sy) ImGui::SetScrollY(y);
    else if (y + line_h_ > sy + view_h_) ImGui::SetScrollY(y + line_h_ - view_h_);
    if (!wrap_) {
        float margin = 4 * char_w_;
        if (x < sx) ImGui::SetScrollX(std::max(0.f, x - margin));
        else if (x + char_w_ > sx + view_w_) ImGui::SetScrollX(x + margin - view_w_);
    }
}

// ---------------------------------------------------------------------------------
// Drawing

// What drawing the rows needs of this frame's geometry.
struct TextEditor::Frame {
    ImDrawList* dl = nullptr;
    ImFont* font = nullptr;
    float fs = 0;
    bool fixed_width = true;  // every character of the font as wide as "M"
    int digits = 0;                 // of the largest line number
    float mark_w = 0, gutter_w = 0;  // the gutter: mark column, then numbers
    ImRect inner;                   // the text child without its scrollbars
    ImVec2 text_origin;             // where column 0 of line 0 is, scrolled
    float scroll_y = 0;
    int first_dcol = 0, last_dcol = 0;  // unwrapped: the visible display columns
    TextRange sel;
    TextPos cur;
};

bool TextEditor::draw(const char* id, const ImVec2& size_arg) {
    const std::uint64_t version0 = buf_.version();
    stats_ = {};
    const int frame = ImGui::GetFrameCount();
    // Keys queued while the editor was not drawn (another tab) were not meant for it.
    if (last_drawn_frame_ < frame - 1) queue_.clear();
    last_drawn_frame_ = frame;

    ImGui::PushFont(mono_font());
    Frame f;
    f.font = ImGui::GetFont();
    f.fs = ImGui::GetFontSize();
    char_w_ = f.font->CalcTextSizeA(f.fs, FLT_MAX, 0, "M").x;
    f.fixed_width = fixed_width(f.font, f.fs, char_w_);
    line_h_ = std::floor(f.fs + 2);
    f.digits = int(std::to_string(buf_.line_count()).size());
    f.mark_w = char_w_ * 2;
    f.gutter_w = f.mark_w + char_w_ * float(std::max(f.digits, 3)) + char_w_;

    // An outer child holds the bar and the text, so focus on either is the editor's.
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::BeginChild(id, size_arg, false, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoNavInputs);
    ImGuiWindow* outer = ImGui::GetCurrentWindow();
    if (want_focus_) {
        ImGui::FocusWindow(outer);
        want_focus_ = false;
    }
    focused_ = ImGui::IsWindowFocused(ImGuiFocusedFlags_ChildWindows);
    take_input();  // before drawing, so the frame shows its result
    if (find_open_ || goto_open_) draw_bar();

    ImGui::PushStyleColor(ImGuiCol_ChildBg, ImGui::GetStyleColorVec4(ImGuiCol_FrameBg));
    ImGui::BeginChild("text", ImVec2(0, 0), true,
                      ImGuiWindowFlags_HorizontalScrollbar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoNavInputs);
    lay_out_text(f);
    draw_rows(f);
    {
        // Where the text grid is on the screen: scripts click on characters by it.
        char grid[160];
        std::snprintf(grid, sizeof grid, "%.2f %.2f %.3f %.3f %d %s", f.text_origin.x, f.text_origin.y, char_w_, line_h_,
                      f.fixed_width ? 1 : 0, wrap_ ? "wrap" : "nowrap");
        probe("editor_grid", grid);
        probe("editor_cursor", std::to_string(f.cur.line + 1) + " " + std::to_string(f.cur.col + 1) +
                                   (focused_ ? " focused" : ""));
    }
    ImGui::EndChild();
    ImGui::PopStyleColor();
    ImGui::EndChild();
    ImGui::PopStyleVar();
    ImGui::PopFont();
    return buf_.version() != version0;
}

void TextEditor::take_input() {
    if (!focused_) {
        queue_.clear();
        return;
    }
    gather_keys();
    std::vector<KeyEvent> keys;
    keys.swap(queue_);
    for (const KeyEvent& e : keys) handle_key(e);
    if (focused_) handle_chars();
    // Keep the host's shortcuts (Space, F, R ...) away while typing here.
    ImGui::CaptureKeyboardFromApp(true);
    GImGui->WantTextInputNextFrame = 1;
}

void TextEditor::lay_out_text(Frame& f) {
    ImGuiIO& io = ImGui::GetIO();
    ImGuiWindow* win = ImGui::GetCurrentWindow();
    f.inner = win->InnerRect;  // without scrollbars
    view_w_ = std::max(1.f, f.inner.GetWidth() - f.gutter_w);
    view_h_ = std::max(1.f, f.inner.GetHeight());
    wrap_cols_ = std::max(8, int(view_w_ / char_w_) - 1);
    if (scroll_by_lines_ != 0) {
        ImGui::SetScrollY(std::max(0.f, ImGui::GetScrollY() + scroll_by_lines_ * line_h_));
        scroll_by_lines_ = 0;
    }
    const float scroll_x = wrap_ ? 0 : ImGui::GetScrollX();
    f.scroll_y = ImGui::GetScrollY();
    f.text_origin = ImVec2(f.inner.Min.x + f.gutter_w - scroll_x, f.inner.Min.y - f.scroll_y);
    const bool hovered = ImGui::IsWindowHovered() && f.inner.Contains(io.MousePos);
    handle_mouse(f.text_origin, f.inner.Min.x + f.gutter_w, hovered);
    if (hovered && io.MousePos.x >= f.inner.Min.x + f.gutter_w) ImGui::SetMouseCursor(ImGuiMouseCursor_TextInput);
    shift_marks();

    // The content size: the scrollbars come from it.
    int total_rows = buf_.line_count();
    if (wrap_) total_rows = row_of_line(buf_.line_count());
    float content_w = wrap_ ? view_w_ : float(buf_.max_display_width() + 2) * char_w_;
    ImGui::SetCursorPos(ImVec2(0, 0));
    ImGui::Dummy(ImVec2(f.gutter_w + content_w, float(total_rows) * line_h_ + line_h_));
    if (scroll_request_) {
        scroll_to_cursor(scroll_centre_);
        scroll_request_ = scroll_centre_ = false;
    }
    f.dl = ImGui::GetWindowDrawList();
    f.first_dcol = wrap_ ? 0 : int(scroll_x / char_w_);
    f.last_dcol = f.first_dcol + int(view_w_ / char_w_) + 2;
    f.sel = buf_.selection();
    f.cur = buf_.cursor();
}

void TextEditor::draw_rows(const Frame& f) {
    const int first_row = std::max(0, int(f.scroll_y / line_h_));
    const int rows_visible = int(view_h_ / line_h_) + 2;
    int sub0 = 0;
    int line = line_at_row(first_row, sub0);
    std::vector<TextRange> matches;
    auto mark_it = marks_.begin();

    stats_.first_line = line;
    const ImRect& inner = f.inner;
    float y = inner.Min.y + float(first_row) * line_h_ - f.scroll_y;
    for (int drawn = 0; drawn < rows_visible && line < buf_.line_count(); ++line) {
        const std::string& text = buf_.line(line);
        const int nrows = rows_of(line);
        const float line_y0 = y - float(sub0) * line_h_;
        // Marks on this line.
        while (mark_it != marks_.end() && mark_it->line - 1 < line) ++mark_it;
        const LineMark* mark = nullptr;
        std::string tip;
        for (auto it = mark_it; it != marks_.end() && it->line - 1 == line; ++it) {
            if (!mark || (it->error && !mark->error)) mark = &*it;
            if (!tip.empty()) tip += '\n';
            tip += std::string(it->error ? "error: " : "warning: ") + it->message;
        }
        draw_gutter(f, line, line_y0, mark, tip);
        f.dl->PushClipRect(ImVec2(inner.Min.x + f.gutter_w, inner.Min.y), inner.Max, true);
        // Whole-line backgrounds.
        ImVec2 bg0(inner.Min.x + f.gutter_w, line_y0), bg1(inner.Max.x, line_y0 + float(nrows) * line_h_);
        if (mark && mark->error) f.dl->AddRectFilled(bg0, bg1, kErrorLineBg);
        else if (line == f.cur.line && focused_) f.dl->AddRectFilled(bg0, bg1, kCurrentLineBg);

        matches.clear();
        if (find_open_ && !find_field_.line(0).empty()) buf_.find_in_line(line, find_field_.line(0), match_case_, matches);
        tokenise_scene_line(text, spans_);
        for (int r = sub0; r < nrows && drawn < rows_visible; ++r, ++drawn, y += line_h_)
            draw_row(f, line, r, y, matches);
        f.dl->PopClipRect();
        sub0 = 0;
        stats_.last_line = line;
    }
}

// The line's number and mark (the gutter does not scroll sideways), with the mark's
// messages as its tooltip.
void TextEditor::draw_gutter(const Frame& f, int line, float line_y0, const LineMark* mark, const std::string& tip) {
    const ImRect& inner = f.inner;
    char num[32];
    std::snprintf(num, sizeof num, "%*d", std::clamp(f.digits, 3, 10), line + 1);
    ImU32 col = line == f.cur.line ? ImGui::GetColorU32(ImGuiCol_Text) : ImGui::GetColorU32(ImGuiCol_TextDisabled);
    f.dl->AddText(ImVec2(inner.Min.x + f.mark_w, line_y0), col, num);
    if (!mark) return;
    ImVec2 c(inner.Min.x + f.mark_w * 0.5f, line_y0 + line_h_ * 0.5f);
    f.dl->AddCircleFilled(c, std::min(f.mark_w, line_h_) * 0.3f, mark->error ? kErrorCol : kWarnCol);
    ImRect hit(ImVec2(inner.Min.x, line_y0), ImVec2(inner.Min.x + f.gutter_w, line_y0 + line_h_));
    if (ImGui::IsWindowHovered() && hit.Contains(ImGui::GetIO().MousePos)) ImGui::SetTooltip("%s", tip.c_str());
}

// Row `r` of `line` at height y: selection, find matches, the text in its token
// colours (spans_ holds the line's tokens) and the cursor.
void TextEditor::draw_row(const Frame& f, int line, int r, float y, const std::vector<TextRange>& matches) {
    const std::string& text = buf_.line(line);
    const int nrows = rows_of(line);
    // Byte range of the row (display columns [r*wc, (r+1)*wc)).
    int d0 = wrap_ ? r * wrap_cols_ : f.first_dcol;
    int d1 = wrap_ ? d0 + wrap_cols_ : f.last_dcol;
    int b0 = d0 == 0 ? 0 : buf_.col_at_display(line, d0);
    int b1 = r == nrows - 1 && wrap_ ? int(text.size()) : buf_.col_at_display(line, d1);
    if (!wrap_) {
        // Start on a whole character at or before the first visible column.
        while (b0 > 0 && buf_.display_col(line, b0) > d0) --b0;
        b1 = std::max(b1, b0);
        if (b1 < int(text.size())) ++b1;
    }
    const int row_d0 = buf_.display_col(line, b0);
    const float row_x = wrap_ ? f.inner.Min.x + f.gutter_w : f.text_origin.x + float(row_d0) * char_w_;
    auto x_of = [&](int col) { return row_x + float(buf_.display_col(line, std::clamp(col, b0, b1)) - row_d0) * char_w_; };
    ImDrawList* dl = f.dl;
    // Selection and find matches.
    const TextRange& sel = f.sel;
    if (sel.begin.line <= line && line <= sel.end.line && !sel.empty()) {
        int s0 = line == sel.begin.line ? sel.begin.col : 0;
        int s1 = line == sel.end.line ? sel.end.col : int(text.size());
        bool newline = line < sel.end.line && (r == nrows - 1);
        if (s1 >= b0 && s0 <= b1 && (s0 < s1 || newline)) {
            float x0 = x_of(std::max(s0, b0)), x1 = x_of(std::min(s1, b1)) + (newline ? char_w_ * 0.5f : 0);
            dl->AddRectFilled(ImVec2(x0, y), ImVec2(x1, y + line_h_), ImGui::GetColorU32(ImGuiCol_TextSelectedBg));
        }
    }
    for (const TextRange& mr : matches)
        if (mr.end.col > b0 && mr.begin.col < b1)
            dl->AddRectFilled(ImVec2(x_of(mr.begin.col), y), ImVec2(x_of(mr.end.col), y + line_h_), kMatchBg);
    // Text, span by span; the gaps between spans are plain text.
    auto draw_piece = [&](int a, int b, ImU32 col) {
        a = std::max(a, b0);
        b = std::min(b, b1);
        if (a >= b) return;
        if (f.fixed_width) return dl->AddText(f.font, f.fs, ImVec2(x_of(a), y + 1), col, text.data() + a, text.data() + b);
        for (int c = a; c < b;) {  // each character centred in its own column
            int n = 1;
            while (c + n < b && (static_cast<unsigned char>(text[std::size_t(c + n)]) & 0xC0) == 0x80) ++n;
            const char *s0 = text.data() + c, *s1 = s0 + n;
            const float w = f.font->CalcTextSizeA(f.fs, FLT_MAX, 0, s0, s1).x;
            dl->AddText(f.font, f.fs, ImVec2(x_of(c) + std::floor((char_w_ - w) / 2), y + 1), col, s0, s1);
            c += n;
        }
    };
    int at = b0;
    const ImU32 plain = kind_colour(TokenKind::Text);
    for (const TokenSpan& s : spans_) {
        if (s.end <= b0) continue;
        if (s.begin >= b1) break;
        draw_piece(at, s.begin, plain);
        draw_piece(s.begin, s.end, kind_colour(s.kind));
        at = std::max(at, s.end);
    }
    draw_piece(at, b1, plain);
    // Cursor.
    if (focused_ && line == f.cur.line) {
        int cd = buf_.display_col(line, f.cur.col);
        bool here = wrap_ ? (cd >= d0 && (cd < d0 + wrap_cols_ || r == nrows - 1)) : true;
        if (here) {
            float cx = wrap_ ? row_x + float(cd - d0) * char_w_ : f.text_origin.x + float(cd) * char_w_;
            dl->AddLine(ImVec2(cx, y), ImVec2(cx, y + line_h_), ImGui::GetColorU32(ImGuiCol_Text), 1.5f);
        }
    }
}

}  // namespace rtview
