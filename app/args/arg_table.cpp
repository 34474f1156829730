// The shared table-driven command-line parser (arg_table.h).
#include "arg_table.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace rtargs {

namespace {

// Whether `name` is one of the option's spellings ("-h, --help" has two).
bool has_name(const Option& o, const std::string& name) {
    const std::string names = o.names;
    std::size_t start = 0;
    for (;;) {
        const std::size_t end = names.find(", ", start);
        if (names.compare(start, end == std::string::npos ? std::string::npos : end - start, name) == 0) return true;
        if (end == std::string::npos) return false;
        start = end + 2;
    }
}

const Option* find(const Table& table, const std::string& name) {
    for (const Option& o : table.options)
        if (has_name(o, name)) return &o;
    return nullptr;
}

rt::Status usage(const std::string& message) { return rt::Status::error(message, rt::kExitUsage); }

}  // namespace

rt::Status parse(const Table& table, int argc, const char* const* argv) {
    bool only_positional = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (only_positional || a.size() < 2 || a[0] != '-') {
            if (rt::Status st = table.positional(a); !st) return st;
            continue;
        }
        if (a == "--") {
            only_positional = true;
            continue;
        }
        std::string name = a, value;
        bool inline_value = false;
        if (auto eq = a.find('='); a.rfind("--", 0) == 0 && eq != std::string::npos) {
            name = a.substr(0, eq);
            value = a.substr(eq + 1);
            inline_value = true;
        }
        const Option* o = find(table, name);
        if (!o) return usage("unknown option '" + (table.unknown_shows_value ? a : name) + "'");
        if (!o->value) {
            if (inline_value) return usage("option '" + name + "' takes no value");
            if (o->on_flag) o->on_flag();
            if (o->stops) return {};
            continue;
        }
        if (!inline_value) {
            if (i + 1 >= argc) return usage("option '" + name + "' needs " + o->needs);
            value = argv[++i];
        }
        if (rt::Status st = o->set(name, value); !st) return st;
    }
    return {};
}

std::string help_lines(const Table& table) {
    const std::size_t column = std::size_t(table.help_column);
    std::string s;
    for (const Option& o : table.options) {
        std::string line = std::string("  ") + o.names + (o.value ? std::string(" ") + o.value : "");
        line.resize(std::max(line.size() + 1, column), ' ');
        for (const char* p = o.help.c_str(); *p; ++p) {
            line += *p;
            if (*p == '\n') line.append(column, ' ');
        }
        s += line + "\n";
    }
    return s;
}

bool is_integer_token(const std::string& s) {
    std::size_t i = s.size() > 1 && (s[0] == '+' || s[0] == '-') ? 1 : 0;
    if (i == s.size()) return false;
    for (; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') return false;
    return true;
}

bool is_decimal_token(const std::string& s) {
    std::size_t i = 0, n = s.size();
    auto digits = [&] {
        std::size_t k = 0;
        while (i < n && s[i] >= '0' && s[i] <= '9') ++i, ++k;
        return k;
    };
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    std::size_t mantissa = digits();
    if (i < n && s[i] == '.') ++i, mantissa += digits();
    if (mantissa == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        ++i;
        if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
        if (digits() == 0) return false;
    }
    return i == n;
}

std::optional<long> integer_in(const std::string& s, long lo, long hi) {
    if (!is_integer_token(s)) return std::nullopt;
    errno = 0;
    const long v = std::strtol(s.c_str(), nullptr, 10);
    if (errno == ERANGE || v < lo || v > hi) return std::nullopt;
    return v;
}

std::optional<double> decimal(const std::string& s) {
    if (!is_decimal_token(s)) return std::nullopt;
    const double v = std::strtod(s.c_str(), nullptr);
    if (!std::isfinite(v)) return std::nullopt;
    return v;
}

}  // namespace rtargs
