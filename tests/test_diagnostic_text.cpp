// Tests of core/diagnostic_text.cpp: which bytes are escaped in messages, which files
// are recognised as UTF-16/32, and the cap on printed diagnostics. Expected strings
// are written out by hand.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "diagnostic_text.h"

using namespace rt;
using namespace std::string_literals;

TEST_CASE("escape_text keeps printable UTF-8 and tabs, escapes everything else as \\xNN") {
    CHECK(escape_text("plain ASCII, tab\there") == "plain ASCII, tab\there");
    CHECK(escape_text("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80") == "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80");
    CHECK(escape_text("caf\xE9") == "caf\\xe9");                        // Latin-1
    CHECK(escape_text("a\x1B[2Jb") == "a\\x1b[2Jb");                    // terminal escape
    CHECK(escape_text("nul\0x"s) == "nul\\x00x");
    CHECK(escape_text("line\nbreak\r") == "line\\x0abreak\\x0d");
    CHECK(escape_text("del\x7F") == "del\\x7f");
    CHECK(escape_text("c1\xC2\x9B" "31m") == "c1\\xc2\\x9b31m");        // C1 CSI
    CHECK(escape_text("overlong\xC0\xAF") == "overlong\\xc0\\xaf");
    CHECK(escape_text("surrogate\xED\xA0\x80") == "surrogate\\xed\\xa0\\x80");
    CHECK(escape_text("cut\xE2\x82") == "cut\\xe2\\x82");              // truncated sequence
    CHECK(escape_text("big\xF4\x90\x80\x80") == "big\\xf4\\x90\\x80\\x80");  // above U+10FFFF
}

TEST_CASE("encoding_problem recognises UTF-16 and UTF-32, with or without a mark") {
    CHECK(encoding_problem("thing { }\nend\n") == "");
    CHECK(encoding_problem("") == "");
    CHECK(encoding_problem("a\0b"s) == "");  // a stray NUL is the parser's business
    CHECK(encoding_problem("\xEF\xBB\xBFthing") == "");  // UTF-8 mark
    const std::string le = "t\0h\0i\0n\0g\0 \0{\0 \0}\0\n\0"s, be = "\0t\0h\0i\0n\0g\0 \0{\0 \0}\0\n"s;
    CHECK(encoding_problem("\xFF\xFE"s + le).find("UTF-16") != std::string::npos);
    CHECK(encoding_problem("\xFE\xFF"s + be).find("byte-order mark") != std::string::npos);
    CHECK(encoding_problem(le).find("every other position") != std::string::npos);
    CHECK(encoding_problem(be).find("UTF-16") != std::string::npos);
    CHECK(encoding_problem("\xFF\xFE\0\0t\0\0\0"s).find("UTF-32") != std::string::npos);
}

TEST_CASE("diagnostics_report shows at most N of each kind, then how many more") {
    std::vector<Diagnostic> d;
    for (int i = 1; i <= 25; ++i) d.push_back({Diagnostic::Severity::Warning, i, 1, "w\xE9"});
    for (int i = 1; i <= 3; ++i) d.push_back({Diagnostic::Severity::Error, i, 2, "e"});
    const std::string r = diagnostics_report("f.txt", d, 20);
    std::size_t lines = 0;
    for (char c : r) lines += c == '\n';
    CHECK(lines == 20 + 3 + 1);
    CHECK(r.find("f.txt:1:1: warning: w\\xe9\n") == 0);
    CHECK(r.find("f.txt:21:1") == std::string::npos);
    CHECK(r.find("f.txt:3:2: error: e\n") != std::string::npos);
    CHECK(r.find("f.txt: 5 more warnings not shown\n") != std::string::npos);
    CHECK(diagnostics_report("f.txt", d, 20, true).find("too many errors; stopped reading") != std::string::npos);
}
