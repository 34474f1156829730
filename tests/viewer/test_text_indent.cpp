// The scene text editor's indentation: the unit a text uses (tabs, or 2, 3 or 4
// spaces), Enter after `{` and between `{` and `}`, a `}` typed on a blank line, each
// against the text written out by hand; undo takes each back as one step.
#include <doctest/doctest.h>

#include <string>

#include "text_buffer.h"

using namespace rtview;

TEST_CASE("indent: the unit is the text's own: tabs, or its commonest step of spaces") {
    CHECK(TextBuffer("thing {\n\tsphere {\n\t\tradius 1\n\t}\n}\n").indent_unit() == "\t");
    CHECK(TextBuffer("thing {\n    sphere {\n        radius 1\n    }\n}\n").indent_unit() == "    ");
    CHECK(TextBuffer("thing {\n   sphere {\n      radius 1\n   }\n}\n").indent_unit() == "   ");
    CHECK(TextBuffer("thing {\n  sphere {\n    radius 1\n  }\n}\n").indent_unit() == "  ");
    // Nothing indented: two spaces, as the viewer writes new blocks.
    CHECK(TextBuffer("camera { }\nend\n").indent_unit() == "  ");
    CHECK(TextBuffer("").indent_unit() == "  ");
    // A continuation line aligned far in and blank lines do not outvote the blocks.
    CHECK(TextBuffer("a {\n    b {\n        c 1\n\n        d 2 3\n                   4\n    }\n    e {\n        f\n    }\n}\n")
              .indent_unit() == "    ");
    // Mostly tabs with a stray space-indented line: tabs.
    CHECK(TextBuffer("a {\n\tb\n\tc\n  d\n}\n").indent_unit() == "\t");
}

TEST_CASE("indent: Enter keeps the line's indentation and adds a level after `{`") {
    TextBuffer b("thing {\n\tsphere {\n\t\tradius 1\n\t}\n}\n");
    b.set_cursor({2, 10});  // after "radius 1"
    b.newline();
    CHECK(b.text() == "thing {\n\tsphere {\n\t\tradius 1\n\t\t\n\t}\n}\n");
    CHECK(b.cursor() == TextPos{3, 2});
    b.set_cursor({1, 9});  // after "sphere {"
    b.newline();
    CHECK(b.line(2) == "\t\t");
    CHECK(b.cursor() == TextPos{2, 2});
    // A comment after the brace: still a block's first line.
    TextBuffer c("thing {  // the objects\n  sphere { }\n}\n");
    c.set_cursor({0, 23});
    c.newline();
    CHECK(c.line(1) == "  ");
    // Not after a `{` that is not last: the line's indentation only.
    TextBuffer d("    sphere { radius 1 }\n");
    d.set_cursor({0, 23});
    d.newline();
    CHECK(d.text() == "    sphere { radius 1 }\n    \n");
    CHECK(d.indent_unit() == "    ");
}

TEST_CASE("indent: Enter between `{` and `}` puts the `}` on a line of its own") {
    TextBuffer b("  light {\n    lamp {  }\n  }\n");
    b.set_cursor({1, 10});  // after "lamp {"
    b.newline();
    CHECK(b.text() == "  light {\n    lamp {\n      \n    }\n  }\n");
    CHECK(b.cursor() == TextPos{2, 6});
    b.insert("size 1");
    CHECK(b.line(2) == "      size 1");
    // One undo step each.
    REQUIRE(b.undo());
    REQUIRE(b.undo());
    CHECK(b.text() == "  light {\n    lamp {  }\n  }\n");
}

TEST_CASE("indent: a `}` typed on a blank line takes one level away") {
    SUBCASE("spaces") {
        TextBuffer b("thing {\n  sphere {\n    radius 1\n");
        b.set_cursor({2, 12});
        b.newline();  // "    "
        b.type("}");
        CHECK(b.line(3) == "  }");
        CHECK(b.cursor() == TextPos{3, 3});
        b.newline();
        b.type("}");
        CHECK(b.text() == "thing {\n  sphere {\n    radius 1\n  }\n}\n");
        REQUIRE(b.undo());
        CHECK(b.line(4) == "  ");
    }
    SUBCASE("tabs") {
        TextBuffer b("a {\n\tb {\n\t\tc\n\t\t");
        b.set_cursor({3, 2});
        b.type("}");
        CHECK(b.line(3) == "\t}");
    }
    SUBCASE("spaces off the grid go back to the previous multiple of the unit") {
        TextBuffer b("a {\n    b\n      ");
        b.set_cursor({2, 6});
        b.type("}");
        CHECK(b.line(2) == "    }");
    }
    SUBCASE("not on a line with text before the cursor, nor at its start") {
        TextBuffer b("a {\n    b");
        b.set_cursor({1, 5});
        b.type("}");
        CHECK(b.line(1) == "    b}");
        TextBuffer c("a {\n");
        c.set_cursor({1, 0});
        c.type("}");
        CHECK(c.text() == "a {\n}");
        // Other characters are typed as they are.
        TextBuffer d("    ");
        d.set_cursor({0, 4});
        d.type("x");
        CHECK(d.text() == "    x");
    }
}
