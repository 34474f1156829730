// Tests for app/args (the option parser of all three programs): what a table accepts
// and refuses, with the messages the programs print, and the --help columns.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "arg_table.h"

namespace {

struct Parsed {
    bool flag = false, stop = false;
    std::string value;
    std::vector<std::string> positional;
};

rtargs::Table table(Parsed& p) {
    rtargs::Table t;
    t.options = {
        rtargs::flag_option("-f, --flag", "a flag", [&p] { p.flag = true; }),
        rtargs::value_option("--value", "V", "a value", "takes a value\ncontinued",
                             [&p](const std::string& name, const std::string& v) {
                                 if (v == "bad") return rt::Status::error(name + " refuses 'bad'", rt::kExitUsage);
                                 p.value = v;
                                 return rt::Status();
                             }),
        rtargs::flag_option("--stop", "stops", [&p] { p.stop = true; }, true),
    };
    t.positional = [&p](const std::string& a) {
        p.positional.push_back(a);
        return rt::Status();
    };
    return t;
}

rt::Status parse(std::vector<const char*> args, Parsed& p, bool shows_value = true) {
    args.insert(args.begin(), "prog");
    rtargs::Table t = table(p);
    t.unknown_shows_value = shows_value;
    return rtargs::parse(t, int(args.size()), args.data());
}

}  // namespace

TEST_CASE("args: both value forms, both names of a flag, '--' and '-' as arguments") {
    Parsed p;
    REQUIRE(parse({"-f", "--value", "-x", "a", "-", "--", "--flag"}, p).ok());
    CHECK(p.flag);
    CHECK(p.value == "-x");  // the next word is the value, whatever it looks like
    CHECK(p.positional == std::vector<std::string>{"a", "-", "--flag"});
    Parsed q;
    REQUIRE(parse({"--value=", "--flag"}, q).ok());
    CHECK(q.value.empty());
    CHECK(q.flag);
}

TEST_CASE("args: errors name the option as the programs print them, exit code 2") {
    Parsed p;
    const rt::Status missing = parse({"--value"}, p);
    CHECK(missing.message() == "option '--value' needs a value");
    CHECK(missing.exit_code() == rt::kExitUsage);
    CHECK(parse({"--flag=1"}, p).message() == "option '--flag' takes no value");
    CHECK(parse({"--frob=1"}, p).message() == "unknown option '--frob=1'");
    CHECK(parse({"--frob=1"}, p, false).message() == "unknown option '--frob'");
    CHECK(parse({"-x"}, p).message() == "unknown option '-x'");
    CHECK(parse({"--value=bad"}, p).message() == "--value refuses 'bad'");
}

TEST_CASE("args: a stopping flag ends the parse before later errors") {
    Parsed p;
    CHECK(parse({"--stop", "--frob"}, p).ok());
    CHECK(p.stop);
    CHECK_FALSE(parse({"--frob", "--stop"}, p).ok());
}

TEST_CASE("args: help lines put descriptions and their continuations at the column") {
    Parsed p;
    rtargs::Table t = table(p);
    t.help_column = 14;
    CHECK(rtargs::help_lines(t) == "  -f, --flag  a flag\n"
                                   "  --value V   takes a value\n"
                                   "              continued\n"
                                   "  --stop      stops\n");
    t.help_column = 8;  // a label longer than the column still gets one space
    CHECK(rtargs::help_lines(t).rfind("  -f, --flag a flag\n", 0) == 0);
}

TEST_CASE("args: numbers are whole decimal tokens") {
    for (const char* s : {"0", "12", "+5", "-7"}) CHECK_MESSAGE(rtargs::is_integer_token(s), s);
    for (const char* s : {"", "+", "-", " 12", "12 ", "0x10", "1e3", "1.0", "++1"})
        CHECK_MESSAGE(!rtargs::is_integer_token(s), s);
    for (const char* s : {"2", "0.5", ".5", "5.", "-1e3", "1E+2"}) CHECK_MESSAGE(rtargs::is_decimal_token(s), s);
    for (const char* s : {"", ".", "e3", "1e", "inf", "nan", "0x1p3", " 1", "1 "})
        CHECK_MESSAGE(!rtargs::is_decimal_token(s), s);
    CHECK(rtargs::integer_in("16384", 1, 16384) == 16384L);
    CHECK_FALSE(rtargs::integer_in("16385", 1, 16384));
    CHECK_FALSE(rtargs::integer_in("99999999999999999999", 1, 16384));
    CHECK(rtargs::decimal("-0.25") == -0.25);
    CHECK_FALSE(rtargs::decimal("1e400"));  // not finite
}
