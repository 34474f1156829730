// The command-line parser all three programs share (raytracer, raytracer-mpi and the
// two viewer binaries): each program declares one table of options, from which both
// the parsing and the option lines of --help come, plus the number-token checks.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "status.h"

namespace rtargs {

// One option. A flag has no `value` (null); an option with a value has a set() that
// takes it. Errors are returned as messages, which the caller prefixes with its name.
struct Option {
    const char* names;   // as --help shows them: "--width", "-v, --verbose"
    const char* value;   // --help's placeholder ("N", "SEC"), or null for a flag
    const char* needs;   // what "option 'NAME' needs ..." says when the value is missing
    std::string help;    // description; '\n' starts a continuation line
    std::function<rt::Status(const std::string& name, const std::string& value)> set;  // null for a flag
    std::function<void()> on_flag;
    bool stops = false;  // parsing ends after this flag (--help, --version)
};

using Setter = std::function<rt::Status(const std::string& name, const std::string& value)>;

// An option with a value, and a flag.
inline Option value_option(const char* names, const char* value, const char* needs, std::string help, Setter set) {
    return Option{names, value, needs, std::move(help), std::move(set), nullptr, false};
}
inline Option flag_option(const char* names, std::string help, std::function<void()> on_flag, bool stops = false) {
    return Option{names, nullptr, nullptr, std::move(help), nullptr, std::move(on_flag), stops};
}

struct Table {
    std::vector<Option> options;
    // Arguments that are not options (after "--", "-" and anything not starting with
    // '-'), in order.
    std::function<rt::Status(const std::string& arg)> positional;
    int help_column = 21;             // where the descriptions start in --help
    bool unknown_shows_value = true;  // "unknown option '--x=1'" rather than '--x'
};

// Parses argv[1..argc): `--opt VALUE` and `--opt=VALUE`, "--" ends the options. On
// the first error returns it (exit code kExitUsage); on a `stops` flag returns success
// at once.
rt::Status parse(const Table& table, int argc, const char* const* argv);

// The option lines of --help: "  NAMES VALUE" and the description at help_column.
std::string help_lines(const Table& table);

// Numbers on the command line are whole decimal tokens, as in scene files: no leading
// or trailing spaces, no hex, no "inf" or "nan" (strtol and strtod would accept " 12",
// "0x10" and "0x1p3"). An optional sign, then digits.
bool is_integer_token(const std::string& s);
// Digits with an optional point and exponent: "2", "-0.5", "1e3".
bool is_decimal_token(const std::string& s);
// The token's value if it is an integer token in [lo, hi].
std::optional<long> integer_in(const std::string& s, long lo, long hi);
// The token's value if it is a decimal token with a finite value.
std::optional<double> decimal(const std::string& s);

}  // namespace rtargs
