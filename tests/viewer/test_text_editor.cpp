// The text editor widget driven frame by frame in a window-less ImGui context: no
// lost keys, typing, find, go to line, marks that follow their lines, and drawing
// only the visible lines of a large text, fields that take a 10 MB paste.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "bounded_input.h"
#include "imgui_harness.h"
#include "text_editor.h"

namespace doctest {
template <>
struct StringMaker<rtview::TextPos> {
    static String convert(const rtview::TextPos& p) {
        return (std::to_string(p.line) + ":" + std::to_string(p.col)).c_str();
    }
};
}  // namespace doctest

using namespace rtview;
using rtview_test::ImGuiHarness;

namespace {

std::string numbered_lines(int n) {
    std::string s;
    for (int i = 1; i <= n; ++i) s += "sphere { position " + std::to_string(i) + " 0 0 radius 1 }\n";
    return s;
}

struct Fixture {
    ImGuiHarness h;
    TextEditor ed;
    bool changed = false;
    std::function<void()> body = [this] { changed = ed.draw("editor", ImVec2(0, 0)) || changed; };
    void frame() { h.frame(body); }
    void focus() {
        h.click(ImVec2(200, 20), body);  // first line of text
        REQUIRE(ed.focused());
    }
};

// The most vertices a draw list of the last frame has room for: ImGui reserves room
// for every character it is given to draw, also those it then clips away.
std::size_t vertex_room() {
    std::size_t most = 0;
    if (const ImDrawData* d = ImGui::GetDrawData())
        for (int i = 0; i < d->CmdListsCount; ++i) most = std::max(most, std::size_t(d->CmdLists[i]->VtxBuffer.Capacity));
    return most;
}

}  // namespace

TEST_CASE("text editor: five quick Down presses all arrive, from the host's queue or one a frame") {
    Fixture f;
    f.ed.set_text(numbered_lines(50));
    f.frame();
    f.focus();
    REQUIRE(f.ed.buffer().cursor().line == 0);
    // Polled: each press seen for one frame.
    for (int i = 0; i < 5; ++i) f.h.tap(ImGuiHarness::kDown, false, false, f.body);
    CHECK(f.ed.buffer().cursor().line == 5);
    // Queued by the host: five presses (and releases) between two frames.
    for (int i = 0; i < 5; ++i) f.ed.push_key(TextEditor::Key::Down, false, false);
    f.frame();
    CHECK(f.ed.buffer().cursor().line == 10);
    CHECK(f.ed.stats().keys == 5);
}

TEST_CASE("text editor: typing, Enter, Backspace and undo change the text; Escape leaves the editor") {
    Fixture f;
    f.ed.set_text("thing {\n}\n");
    f.frame();
    f.focus();
    f.ed.buffer().set_cursor({0, 7});
    f.ed.push_key(TextEditor::Key::Enter, false, false);
    f.frame();
    f.changed = false;
    f.h.type("sphere { }x");
    f.frame();
    CHECK(f.changed);
    f.ed.push_key(TextEditor::Key::Backspace, false, false);
    f.frame();
    CHECK(f.ed.text() == "thing {\n  sphere { }\n}\n");  // (Enter after `{`: one level in)
    // Five undo steps: "sphere", " {", " }x" (a space after a word starts a step),
    // the Backspace, the Enter.
    for (int i = 0; i < 5; ++i) f.ed.push_key(TextEditor::Key::Z, false, true);
    f.frame();
    CHECK(f.ed.text() == "thing {\n}\n");
    // The editor holds the keyboard while focused, so the host's shortcuts stay away.
    f.frame();
    CHECK(ImGui::GetIO().WantCaptureKeyboard);
    CHECK(ImGui::GetIO().WantTextInput);
    f.ed.push_key(TextEditor::Key::Escape, false, false);
    f.frame();
    CHECK_FALSE(f.ed.focused());
    f.h.type("lost?");
    f.frame();
    CHECK(f.ed.text() == "thing {\n}\n");
}

TEST_CASE("text editor: Ctrl+F finds and selects the next match, Enter again the one after; Ctrl+G goes to a line") {
    Fixture f;
    f.ed.set_text("lamp { }\nspotlight { }\nlamp { size 2 }\n");
    f.frame();
    f.focus();
    using K = TextEditor::Key;
    // Polled keys: Ctrl+F, then the search typed in the very next frame goes to the
    // field (an ImGui InputText would take two frames to get the keyboard).
    ImGuiIO& io = ImGui::GetIO();
    io.KeyCtrl = true;
    io.KeysDown['F'] = true;
    f.frame();
    io.KeysDown['F'] = false;
    io.KeyCtrl = false;
    f.h.type("lamp");
    f.frame();
    CHECK(f.ed.text() == "lamp { }\nspotlight { }\nlamp { size 2 }\n");  // not typed into the text
    f.h.tap(ImGuiHarness::kEnter, false, false, f.body);
    CHECK(f.ed.buffer().selection().begin == TextPos{2, 0});  // the match after the cursor's
    f.h.tap(ImGuiHarness::kEnter, false, false, f.body);
    CHECK(f.ed.buffer().selection().begin == TextPos{0, 0});  // wrapped
    CHECK(f.ed.buffer().selected_text() == "lamp");
    f.h.tap(ImGuiHarness::kEnter, false, true, f.body);  // Shift+Enter: previous
    CHECK(f.ed.buffer().selection().begin == TextPos{2, 0});

    // Queued keys: Ctrl+G, a line number, Enter, all between two frames.
    f.ed.push_key(K::G, false, true);
    f.frame();
    f.ed.push_char('2');  // replaces the current line number, which the bar opens selected
    f.ed.push_key(K::Enter, false, false);
    f.ed.push_char('x');
    f.frame();
    CHECK(f.ed.buffer().cursor() == TextPos{1, 1});
    CHECK(f.ed.buffer().line(1) == "xspotlight { }");  // back in the text after going
}

TEST_CASE("text editor: diagnostics marks follow inserted and deleted lines") {
    Fixture f;
    f.ed.set_text(numbered_lines(20));
    f.ed.set_marks({{10, true, "unknown key 'radus' in sphere"}, {3, false, "degenerate"}});
    REQUIRE(f.ed.marks()[0].line == 3);
    f.frame();
    f.focus();
    f.ed.buffer().set_cursor({4, 0});
    f.ed.push_key(TextEditor::Key::Enter, false, false);
    f.ed.push_key(TextEditor::Key::Enter, false, false);
    f.frame();
    CHECK(f.ed.marks()[0].line == 3);
    CHECK(f.ed.marks()[1].line == 12);
    f.ed.buffer().select({{0, 0}, {2, 0}});
    f.ed.push_key(TextEditor::Key::Delete, false, false);
    f.frame();
    CHECK(f.ed.marks()[0].line == 1);  // its line survived as the first
    CHECK(f.ed.marks()[1].line == 10);
}

TEST_CASE("text editor: a 100,000-line text draws only the lines in view, also after jumping to its end") {
    Fixture f;
    f.ed.set_text(numbered_lines(100000));
    f.frame();
    const TextEditor::Stats s = f.ed.stats();
    CHECK(s.first_line == 0);
    CHECK(s.last_line > 20);
    CHECK(s.last_line < 80);  // 700 px of 15 px lines
    f.ed.show({99990, 0});
    f.frame();
    f.frame();
    CHECK(f.ed.stats().first_line > 99900);
    CHECK(f.ed.stats().last_line == 100000);  // the empty last line after the final newline
    // Wrapped, a line as long as many rows is drawn as several rows.
    std::string long_line(20000, 'x');
    f.ed.set_text(long_line + "\nend\n");
    f.ed.set_wrap(true);
    f.ed.show({0, 0});
    f.frame();
    f.frame();
    CHECK(f.ed.stats().first_line == 0);
    CHECK(f.ed.stats().last_line == 0);  // the long line fills the view
}

TEST_CASE("text editor: find and go to line take a 10 MB paste with control characters and invalid UTF-8") {
    Fixture f;
    // A line where a plain search for the needle below takes (line x needle) steps.
    const std::string as(std::size_t(12) << 20, 'a');
    f.ed.set_text("lamp { }\n" + as + "\nend\n");
    f.frame();
    f.focus();
    const TextPos at = f.ed.buffer().cursor();
    using K = TextEditor::Key;
    f.ed.push_key(K::F, false, true);
    f.frame();
    const std::string half(std::size_t(5) << 20, 'a');
    const std::string needle = half + "\x01\x7f\xff\xfe\xc3\t" + half;  // 10 MB
    ImGui::SetClipboardText(needle.c_str());
    f.ed.push_key(K::V, false, true);
    f.ed.push_key(K::Enter, false, false);
    f.frame();
    CHECK(f.ed.buffer().cursor() == at);         // no match: the cursor stays
    CHECK(f.ed.text().size() == as.size() + 14);  // nothing typed into the text
    // The field drew the columns in view, not ten million characters.
    CHECK(vertex_room() < 1000000);

    // Go to line: ten million digits among control characters and invalid UTF-8 are a
    // line number past the end.
    f.ed.push_key(K::G, false, true);
    f.frame();
    std::string digits(std::size_t(10) << 20, '9');
    for (std::size_t k = 0; k < digits.size(); k += 4096) digits[k] = "\x01\xff\x1b\xc3"[k / 4096 % 4];
    ImGui::SetClipboardText(digits.c_str());
    f.ed.push_key(K::V, false, true);
    f.ed.push_key(K::Enter, false, false);
    f.frame();
    CHECK(f.ed.buffer().cursor().line == 3);  // the last line (empty, after "end\n")
    CHECK(vertex_room() < 1000000);
}

TEST_CASE("bounded_input: a 10 MB paste with control characters and invalid UTF-8 is cut to the field's bound") {
    ImGuiHarness h;
    std::string text(std::size_t(10) << 20, 'x');
    for (std::size_t k = 0; k < text.size(); k += 7) text[k] = "\x01\xff\x7f\xc3\xa9\n\xf0\x9f\x98\x80\x80"[k / 7 % 11];
    const std::string start = text.substr(0, 4096);
    auto body = [&] {
        if (h.frames() < 2) ImGui::SetKeyboardFocusHere();
        bounded_input("##path", "hint", text, 4096);
    };
    for (int i = 0; i < 3; ++i) h.frame(body);
    CHECK(vertex_room() < 1000000);
    CHECK(text == start);  // cut, and not edited: the bytes as they were
    // Typed into, then erased back past the bytes ImGui cannot read.
    h.type("more");
    h.frame(body);
    for (int i = 0; i < 40; ++i) h.tap(ImGuiHarness::kBackspace, false, false, body);
    h.tap(ImGuiHarness::kHome, false, false, body);
    for (int i = 0; i < 40; ++i) h.tap(ImGuiHarness::kDelete, false, false, body);
    CHECK(text.size() <= 4096);
    CHECK(text != start);
    CHECK(text.find("more") == std::string::npos);
}
