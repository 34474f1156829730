// The text editor's find and go-to bar (see text_editor.h).
#include "text_editor.h"

#include <imgui_internal.h>  // WantTextInputNextFrame, FocusWindow: 1.86 has no public way

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fonts.h"
#include "probe.h"

namespace rtview {

void TextEditor::find_next(bool forward) {
    const std::string needle = find_field_.line(0);
    TextRange sel = buf_.selection();
    auto r = buf_.find(needle, forward ? sel.end : sel.begin, forward, match_case_);
    if (r) {
        buf_.select(*r);
        scroll_request_ = true;
        scroll_centre_ = true;
        // "3 of 12": counted over the whole text, which for a very large one could hold
        // up the frame; it then stops at a limit ("3 of 5000+") or, past 200,000
        // lines, is not counted.
        find_status_.clear();
        if (buf_.line_count() <= 200000) {
            const TextBuffer::MatchCount c = buf_.count_matches(needle, match_case_, r->begin, 5000);
            find_status_ = (c.index > 0 ? std::to_string(c.index) : std::string("?")) + " of " + std::to_string(c.total) +
                           (c.more ? "+" : "");
        }
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
            const bool none = find_status_ == "no match";
            ImGui::TextColored(none ? ImVec4(1, 0.8f, 0.35f, 1) : ImGui::GetStyleColorVec4(ImGuiCol_Text), "%s",
                               find_status_.c_str());
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

}  // namespace rtview
