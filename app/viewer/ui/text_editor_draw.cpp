// Drawing the text editor (see text_editor.h): scrolling, the rows with their syntax
// colours, selection and find matches, and the gutter with line numbers and marks.
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

// Whether the printable ASCII characters of `font` at `size` are all `char_w` wide.
bool fixed_width(const ImFont* font, float size, float char_w) {
    const float scale = size / font->FontSize;
    for (ImWchar c = 32; c < 127; ++c)
        if (std::fabs(font->GetCharAdvance(c) * scale - char_w) > 0.01f * char_w) return false;
    return true;
}

}  // namespace

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
        // Back to the left: the cursor half a view in (or the line's start in view, when
        // the cursor is that near it), so that what it follows, a find's match or a word
        // typed, shows whole.
        float margin = 4 * char_w_;
        if (x < sx) ImGui::SetScrollX(std::max(0.f, x - view_w_ / 2));
        else if (x + char_w_ > sx + view_w_) ImGui::SetScrollX(x + margin - view_w_);
    }
}

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
        probe("editor_bar", find_open_   ? "find " + find_field_.line(0) + (find_status_.empty() ? "" : " (" + find_status_ + ")")
                            : goto_open_ ? "goto " + goto_field_.line(0)
                                         : std::string("none"));
    }
    // The keys go where the user last clicked: a frame round the text says it has them
    // (with the caret, which only then is drawn).
    const ImRect text_rect = ImGui::GetCurrentWindow()->Rect();
    ImGui::EndChild();
    if (focused_) {
        const float t = std::max(1.f, std::floor(ImGui::GetFontSize() / 8));
        ImGui::GetWindowDrawList()->AddRect(ImVec2(text_rect.Min.x + t / 2, text_rect.Min.y + t / 2),
                                            ImVec2(text_rect.Max.x - t / 2, text_rect.Max.y - t / 2),
                                            ImGui::GetColorU32(ImGuiCol_NavHighlight), 0, 0, t);
    }
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
