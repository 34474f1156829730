// The text editor's model: edits against a plain std::string reference, undo/redo
// byte for byte, offsets, cursor moves, find, go to line and line colouring.
#include <doctest/doctest.h>

#include <algorithm>
#include <climits>

#include <random>
#include <string>

#include "text_buffer.h"

using namespace rtview;

namespace {

// Reference offset of a (line, col) in a plain string, counted by hand.
std::size_t ref_offset(const std::string& s, TextPos p) {
    std::size_t off = 0;
    for (int l = 0; l < p.line; ++l) off = s.find('\n', off) + 1;
    return off + std::size_t(p.col);
}

std::string spans_as_text(std::string_view line) {
    std::vector<TokenSpan> spans;
    tokenise_scene_line(line, spans);
    std::string out;
    for (const TokenSpan& s : spans) {
        static const char* const names[] = {"text", "section", "object", "key", "number", "comment", "brace"};
        out += std::string(names[int(s.kind)]) + ":" + std::string(line.substr(std::size_t(s.begin), std::size_t(s.end - s.begin))) + " ";
    }
    return out;
}

}  // namespace

TEST_CASE("text buffer: set_text and text() round-trip byte for byte, lines split at newlines") {
    for (std::string t : {"", "\n", "a", "a\n", "\n\nb", "thing {\r\n  sphere { }\r\n}\r\n", "x\ny\nz"}) {
        TextBuffer b(t);
        CHECK(b.text() == t);
        CHECK(b.size() == t.size());
        CHECK(b.line_count() == 1 + int(std::count(t.begin(), t.end(), '\n')));
    }
    TextBuffer b("ab\ncd\n");
    CHECK(b.line(0) == "ab");
    CHECK(b.line(1) == "cd");
    CHECK(b.line(2) == "");
}

TEST_CASE("text buffer: random replacements agree with std::string, and undo/redo restore every step") {
    std::mt19937 rng(15);
    std::string ref = "thing {\n  sphere { position 1 2 3 radius 0.5 }\n}\nend\n";
    TextBuffer b(ref);
    b.set_logging(true);
    std::string mirror = ref;  // follows the edit log
    auto replay = [&] {
        for (const BufferEdit& e : b.take_edits()) {
            REQUIRE(mirror.compare(e.offset, e.removed.size(), e.removed) == 0);
            mirror.replace(e.offset, e.removed.size(), e.inserted);
        }
        REQUIRE(mirror == b.text());
    };
    std::vector<std::string> history{ref};
    const char* const pieces[] = {"", "x", "\n", "ab\ncd", "{ }", "\n\n", "é", "  // c\n"};
    for (int step = 0; step < 400; ++step) {
        std::size_t a = rng() % (ref.size() + 1);
        std::size_t len = rng() % 6;
        len = std::min(len, ref.size() - a);
        std::string ins = pieces[rng() % 8];
        TextPos pa = b.pos_of(a), pe = b.pos_of(a + len);
        REQUIRE(ref_offset(ref, pa) == a);
        REQUIRE(b.offset_of(pe) == a + len);
        b.replace({pa, pe}, ins);
        ref.replace(a, len, ins);
        REQUIRE(b.text() == ref);
        REQUIRE(b.size() == ref.size());
        CHECK(b.offset_of(b.cursor()) == a + ins.size());
        history.push_back(ref);
        if (step % 50 == 0) replay();
    }
    replay();
    // Each replace() is its own step: undo walks back through every state.
    for (std::size_t k = history.size() - 1; k > 0; --k) {
        REQUIRE(b.undo());
        REQUIRE(b.text() == history[k - 1]);
    }
    CHECK_FALSE(b.undo());
    replay();
    for (std::size_t k = 1; k < history.size(); ++k) {
        REQUIRE(b.redo());
        REQUIRE(b.text() == history[k]);
    }
    CHECK_FALSE(b.redo());
    replay();
}

TEST_CASE("text buffer: typing merges into one undo step per word; backspace runs merge; a move breaks it") {
    TextBuffer b("radius 1\n");
    b.set_cursor({0, 8});
    for (char c : std::string("5 and"))
        b.insert(std::string(1, c));
    CHECK(b.line(0) == "radius 15 and");
    REQUIRE(b.undo());
    CHECK(b.line(0) == "radius 15");  // " and" was the second step (the space started it)
    REQUIRE(b.undo());
    CHECK(b.line(0) == "radius 1");
    CHECK(b.cursor() == TextPos{0, 8});
    CHECK_FALSE(b.undo());

    b.set_text("position 1 2 3");
    b.set_cursor({0, 14});
    b.backspace();
    b.backspace();
    b.set_cursor({0, 0});
    b.erase_forward();
    CHECK(b.text() == "osition 1 2");
    REQUIRE(b.undo());
    CHECK(b.text() == "position 1 2");
    REQUIRE(b.undo());
    CHECK(b.text() == "position 1 2 3");
    CHECK(b.cursor() == TextPos{0, 14});
}

TEST_CASE("text buffer: newline keeps indentation, backspace joins lines, selection is replaced") {
    TextBuffer b("  sphere {\n  }");
    b.set_cursor({0, 10});
    b.newline();  // (after a `{`: one level more, text_indent's tests)
    CHECK(b.text() == "  sphere {\n    \n  }");
    CHECK(b.cursor() == TextPos{1, 4});
    b.insert("radius 2");
    b.newline();  // the line's own indentation
    CHECK(b.text() == "  sphere {\n    radius 2\n    \n  }");
    REQUIRE(b.undo());
    b.set_cursor({2, 0});
    b.backspace();
    CHECK(b.text() == "  sphere {\n    radius 2  }");
    b.select({{1, 4}, {1, 10}});
    CHECK(b.selected_text() == "radius");
    b.insert("size");
    CHECK(b.text() == "  sphere {\n    size 2  }");
    // CRLF files stay CRLF.
    TextBuffer c("a {\r\nb\r\n");
    c.set_cursor({0, 1});
    c.newline();
    CHECK(c.text() == "a\r\n {\r\nb\r\n");
}

TEST_CASE("text buffer: offsets and positions agree with a hand count after edits far from each other") {
    std::string ref;
    for (int i = 0; i < 2000; ++i) ref += "line " + std::to_string(i) + "\n";
    TextBuffer b(ref);
    b.replace({{1500, 0}, {1500, 0}}, "new\n");
    ref.insert(ref_offset(ref, {1500, 0}), "new\n");
    b.replace({{10, 2}, {12, 1}}, "X");
    ref.replace(ref_offset(ref, {10, 2}), ref_offset(ref, {12, 1}) - ref_offset(ref, {10, 2}), "X");
    REQUIRE(b.text() == ref);
    for (int l : {0, 5, 10, 11, 999, 1498, 1499, 1500, b.line_count() - 1}) {
        CHECK(b.offset_of({l, 0}) == ref_offset(ref, {l, 0}));
        CHECK(b.pos_of(ref_offset(ref, {l, 1})) == TextPos{l, std::min(1, int(b.line(l).size()))});
    }
    CHECK(b.pos_of(ref.size()) == b.end_pos());
}

TEST_CASE("text buffer: cursor moves over UTF-8, words, lines, keeping the column across short lines") {
    TextBuffer b("héllo wörld\nab\nlong line here\n\tx");
    b.set_cursor({0, 0});
    b.move(TextBuffer::Move::Right, false);
    b.move(TextBuffer::Move::Right, false);
    CHECK(b.cursor() == TextPos{0, 3});  // é is two bytes
    b.move(TextBuffer::Move::Left, false);
    CHECK(b.cursor() == TextPos{0, 1});
    b.move(TextBuffer::Move::WordRight, false);
    CHECK(b.cursor() == TextPos{0, 7});  // start of wörld
    b.move(TextBuffer::Move::WordLeft, false);
    CHECK(b.cursor() == TextPos{0, 0});
    b.set_cursor({0, 11});  // display column 9 ("héllo wör" ends at byte 11)
    CHECK(b.display_col(0, 11) == 9);
    b.move(TextBuffer::Move::Down, false);
    CHECK(b.cursor() == TextPos{1, 2});  // short line: its end
    b.move(TextBuffer::Move::Down, false);
    CHECK(b.cursor() == TextPos{2, 9});  // back to display column 9
    b.move(TextBuffer::Move::Down, false);
    CHECK(b.cursor() == TextPos{3, 2});  // tab counts 4: column 9 is past "\tx"'s end
    b.move(TextBuffer::Move::Home, false);
    CHECK(b.cursor() == TextPos{3, 1});  // first non-blank
    b.move(TextBuffer::Move::Home, false);
    CHECK(b.cursor() == TextPos{3, 0});
    b.move(TextBuffer::Move::Left, true);
    CHECK(b.selected_text() == "\n");
    b.move(TextBuffer::Move::DocStart, true);
    CHECK(b.selection().begin == TextPos{0, 0});
    CHECK(b.selection().end == TextPos{3, 0});
    b.move(TextBuffer::Move::PageDown, false, 2);
    CHECK(b.cursor().line == 2);
}

TEST_CASE("text buffer: find goes forward and backward, wraps, matches case on request; goto clamps") {
    TextBuffer b("Sphere a\nsphere b sphere\nnone\n");
    auto r = b.find("sphere", {0, 0}, true, true);
    REQUIRE(r);
    CHECK(r->begin == TextPos{1, 0});
    r = b.find("sphere", {1, 1}, true, true);
    REQUIRE(r);
    CHECK(r->begin == TextPos{1, 9});
    r = b.find("sphere", {1, 10}, true, true);  // wraps to the first match
    REQUIRE(r);
    CHECK(r->begin == TextPos{1, 0});
    r = b.find("sphere", {1, 10}, true, false);
    REQUIRE(r);
    CHECK(r->begin == TextPos{0, 0});  // case-insensitive wraps to line 0
    r = b.find("sphere", {1, 9}, false, true);
    REQUIRE(r);
    CHECK(r->begin == TextPos{1, 0});
    r = b.find("sphere", {1, 0}, false, true);  // backward wraps to the last
    REQUIRE(r);
    CHECK(r->begin == TextPos{1, 9});
    CHECK_FALSE(b.find("cube", {0, 0}, true, true));
    CHECK_FALSE(b.find("", {0, 0}, true, true));
    TextBuffer one("x");
    r = one.find("x", {0, 1}, true, true);  // the only match, found by wrapping
    REQUIRE(r);
    CHECK(r->begin == TextPos{0, 0});
    b.goto_line(3);
    CHECK(b.cursor() == TextPos{2, 0});
    b.goto_line(99);
    CHECK(b.cursor() == TextPos{3, 0});
    b.goto_line(-5);
    CHECK(b.cursor() == TextPos{0, 0});
}

TEST_CASE("text buffer: find after partial matches, of matches that overlap, and of a needle longer than lines") {
    // A search that restarts after a partial match must still see "aab" in "aaab".
    TextBuffer b("aaab abab\nababab\nAAAB\n");
    auto r = b.find("aab", {0, 0}, true, true);
    REQUIRE(r);
    CHECK(r->begin == TextPos{0, 1});
    r = b.find("aab", {0, 2}, true, false);  // case-insensitive: line 2's "AAB"
    REQUIRE(r);
    CHECK(r->begin == TextPos{2, 1});
    // Matches do not overlap: "abab" in "ababab" once, at 0.
    r = b.find("abab", {1, 1}, true, true);
    REQUIRE(r);
    CHECK(r->begin == TextPos{0, 5});
    r = b.find("abab", {0, 6}, true, true);
    REQUIRE(r);
    CHECK(r->begin == TextPos{1, 0});
    CHECK_FALSE(b.find(std::string(100, 'a'), {0, 0}, true, true));
}

TEST_CASE("go to line: the digits of what was typed, at most INT_MAX") {
    CHECK(parse_line_number("42") == 42);
    CHECK(parse_line_number("\x01" "4\xff" "2\x1b") == 42);  // control and invalid UTF-8 skipped
    CHECK(parse_line_number("") == 0);
    CHECK(parse_line_number("abc") == 0);
    CHECK(parse_line_number("-7") == 7);
    CHECK(parse_line_number(std::string(std::size_t(10) << 20, '9')) == INT_MAX);
    CHECK(parse_line_number("2147483648") == INT_MAX);
    CHECK(parse_line_number("2147483647") == INT_MAX);
    CHECK(parse_line_number("2147483646") == 2147483646);
}

TEST_CASE("text buffer: widest line follows edits, and line shifts report inserted lines") {
    TextBuffer b("ab\nabcdef\nabc");
    CHECK(b.max_display_width() == 6);
    b.replace({{1, 0}, {1, 6}}, "x");
    CHECK(b.max_display_width() == 3);
    b.clear_line_shifts();
    b.replace({{0, 0}, {0, 0}}, "1\n2\n");
    REQUIRE(b.line_shifts().size() == 1);
    CHECK(b.line_shifts()[0].first == 0);
    CHECK(b.line_shifts()[0].removed == 1);
    CHECK(b.line_shifts()[0].added == 3);
}

TEST_CASE("text buffer: the edit log replays onto a copy of the text, undo included") {
    std::string mirror = "thing {\n}\n";
    TextBuffer b(mirror);
    b.set_logging(true);
    b.set_cursor({0, 7});
    b.newline();
    b.insert("sphere { }");
    b.undo();
    b.insert("torus { }");
    b.select({{0, 0}, {0, 5}});
    b.insert("light");
    for (const BufferEdit& e : b.take_edits()) {
        // Offsets are those of the text before each edit: replay in order.
        REQUIRE(e.offset == ref_offset(mirror, e.at));
        REQUIRE(mirror.compare(e.offset, e.removed.size(), e.removed) == 0);
        mirror.replace(e.offset, e.removed.size(), e.inserted);
    }
    CHECK(mirror == b.text());
    CHECK(mirror == "light {\n  torus { }\n}\n");  // (indented after the `{`)
    CHECK(b.take_edits().empty());
}

TEST_CASE("text buffer: following replacements made elsewhere keeps the text, the cursor's place, no log") {
    std::mt19937 rng(11);
    std::string ref = "camera { position 0 0 5 }\nthing {\n  sphere { radius 1 }\n}\nend\n";
    TextBuffer b(ref);
    b.set_logging(true);
    b.insert("// ");  // an edit of the buffer's own: in its log and undo history
    ref.insert(0, "// ");
    CHECK(b.can_undo());
    (void)b.take_edits();
    for (int k = 0; k < 300; ++k) {
        const std::size_t cursor = b.offset_of(b.cursor());
        const std::size_t pos = rng() % (ref.size() + 1);
        const std::size_t len = std::min<std::size_t>(rng() % 12, ref.size() - pos);
        static const char* const kTexts[] = {"", "x", "\n", "radius 2\n  ", "}\n\n{", "\r\n"};
        const std::string text = kTexts[rng() % 6];
        b.follow_replacement(pos, len, text);
        ref.replace(pos, len, text);
        REQUIRE(b.text() == ref);
        REQUIRE(b.size() == ref.size());
        // The cursor keeps its place: moved with what came before it, kept inside the
        // replaced bytes (within the new ones).
        const std::size_t want = cursor <= pos ? cursor : cursor >= pos + len ? cursor - len + text.size()
                                                                               : std::min(cursor, pos + text.size());
        REQUIRE(b.offset_of(b.cursor()) == want);
        REQUIRE(b.cursor() == b.anchor());
        if (k % 50 == 0) b.set_cursor(b.pos_of(ref.size() / 2));
    }
    // Not the buffer's own edits: nothing to carry back, and its undo steps are gone
    // (their places may not hold).
    CHECK(b.take_edits().empty());
    CHECK_FALSE(b.can_undo());
    // Far past the end: clamped, as replace_bytes does.
    b.follow_replacement(ref.size() + 100, 5, "tail");
    CHECK(b.text() == ref + "tail");
}

TEST_CASE("scene line colouring: sections, objects, keys, numbers, comments, braces") {
    CHECK(spans_as_text("thing { sphere { position 1 -2.5 3e2 radius .5 } // glass {") ==
          "section:thing brace:{ object:sphere brace:{ key:position number:1 number:-2.5 number:3e2 key:radius "
          "number:.5 brace:} comment:// glass { ");
    CHECK(spans_as_text("  material 1 { colour 1 1 x }") ==
          "key:material number:1 brace:{ key:colour number:1 number:1 brace:} ");
    // Not numbers in the format: partial tokens, a lone sign, inf; `//x` is a comment too.
    CHECK(spans_as_text("1e 5x - inf 1.5.2 //x") == "comment://x ");
    CHECK(spans_as_text("lamp{size") == "object:lamp brace:{ key:size ");
    CHECK(is_scene_number("5."));
    CHECK(is_scene_number("+2"));
    CHECK_FALSE(is_scene_number("."));
    CHECK_FALSE(is_scene_number("1e+"));
}

TEST_CASE("text buffer: matches counted, which one the cursor's is, and a limit") {
    TextBuffer b("Sphere a\nsphere b sphere\nnone\nsphere");
    auto c = b.count_matches("sphere", true, {1, 9}, 100);
    CHECK(c.total == 3);
    CHECK(c.index == 2);  // (1,0), (1,9), (3,0)
    CHECK_FALSE(c.more);
    c = b.count_matches("sphere", false, {0, 0}, 100);  // any case: line 0's too, first
    CHECK(c.total == 4);
    CHECK(c.index == 1);
    c = b.count_matches("sphere", true, {0, 3}, 100);  // not at a match
    CHECK(c.index == 0);
    c = b.count_matches("sphere", false, {3, 0}, 2);
    CHECK(c.total == 2);
    CHECK(c.more);
    CHECK(c.index == 0);  // the fourth, past the limit
    CHECK(b.count_matches("", true, {0, 0}, 100).total == 0);
    // Brute force over a text of repeats: every match is counted once.
    std::string text;
    int expected = 0;
    for (int i = 0; i < 50; ++i) {
        text += (i % 3 == 0 ? "ab ab\n" : "xb\n");
        expected += i % 3 == 0 ? 2 : 0;
    }
    TextBuffer many(text);
    CHECK(many.count_matches("ab", true, {0, 3}, 1000).total == expected);
    CHECK(many.count_matches("ab", true, {0, 3}, 1000).index == 2);
}
