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

TEST_CASE("check_encoding recognises UTF-16 and UTF-32, with or without a mark") {
    CHECK(check_encoding("thing { }\nend\n").ok());
    CHECK(check_encoding("").ok());
    CHECK(check_encoding("a\0b"s).ok());  // a stray NUL is the parser's business
    CHECK(check_encoding("\xEF\xBB\xBFthing").ok());  // UTF-8 mark
    const std::string le = "t\0h\0i\0n\0g\0 \0{\0 \0}\0\n\0"s, be = "\0t\0h\0i\0n\0g\0 \0{\0 \0}\0\n"s;
    CHECK(check_encoding("\xFF\xFE"s + le).message().find("UTF-16") != std::string::npos);
    CHECK(check_encoding("\xFE\xFF"s + be).message().find("byte-order mark") != std::string::npos);
    CHECK(check_encoding(le).message().find("every other position") != std::string::npos);
    CHECK(check_encoding(be).message().find("UTF-16") != std::string::npos);
    CHECK(check_encoding("\xFF\xFE\0\0t\0\0\0"s).message().find("UTF-32") != std::string::npos);
    CHECK(check_encoding(le).exit_code() == kExitScene);
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

TEST_CASE("a parse result's status: ok with warnings, else the report a program prints and exit code 1") {
    const std::string camera = "camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }\n"
                               "picture_size { x_max 8 y_max 6 }\nend\n";
    const ParseResult good = parse_scene(camera);
    REQUIRE(good.ok());
    CHECK(good.status("s.txt").ok());

    const ParseResult bad = parse_scene("thing { sphere { radius x } }\n" + camera);
    const Status st = bad.status("s.txt");
    CHECK_FALSE(st.ok());
    CHECK(st.exit_code() == kExitScene);
    CHECK(st.message() == "s.txt:1:25: error: expected a number after 'radius', got 'x'\n");

    // One bad item a line: 25 errors. Read with the cap at 20 the parser stops and the
    // report says so; with a higher cap it reads on, and 5 are left out of the report.
    std::string many;
    for (int i = 0; i < 25; ++i) many += "thing { sphere { radius x } }\n";
    ParseOptions capped;
    capped.max_errors = 20;
    const std::string stopped = parse_scene(many + camera, capped).status("s.txt").message();
    CHECK(stopped.find("s.txt:20:25: error:") != std::string::npos);
    CHECK(stopped.find("s.txt:21:") == std::string::npos);
    CHECK(stopped.find("s.txt: too many errors; stopped reading\n") != std::string::npos);
    ParseOptions roomy;
    roomy.max_errors = 30;
    const std::string all = parse_scene(many + camera, roomy).status("s.txt").message();
    CHECK(all.find("s.txt: 5 more errors not shown\n") != std::string::npos);
    CHECK(all.find("stopped reading") == std::string::npos);

    ParseOptions cancel;
    cancel.progress = [](std::size_t, std::size_t) { return false; };
    const Status cancelled = parse_scene(std::string(3 << 20, ' ') + camera, cancel).status("s.txt");
    CHECK(cancelled.exit_code() == kExitUsage);
    CHECK(cancelled.message() == "s.txt: reading was cancelled\n");
}
