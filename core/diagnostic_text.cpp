// Escaping and encoding checks for what is printed about scene files (diagnostic_text.h).
#include "diagnostic_text.h"

#include <algorithm>
#include <cstdio>

namespace rt {

namespace {

// Length of the valid, printable UTF-8 sequence at s[i], or 0.
std::size_t printable_utf8(std::string_view s, std::size_t i) {
    const auto b = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
    const unsigned char c = b(i);
    if (c == '\t' || (c >= 0x20 && c < 0x7F)) return 1;
    std::size_t n = 0;
    unsigned min = 0, cp = 0;
    if (c >= 0xC2 && c <= 0xDF) n = 2, cp = c & 0x1Fu, min = 0x80;
    else if (c >= 0xE0 && c <= 0xEF) n = 3, cp = c & 0x0Fu, min = 0x800;
    else if (c >= 0xF0 && c <= 0xF4) n = 4, cp = c & 0x07u, min = 0x10000;
    else return 0;
    if (i + n > s.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((b(i + k) & 0xC0) != 0x80) return 0;
        cp = (cp << 6) | (b(i + k) & 0x3Fu);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return 0;  // overlong, surrogate
    if (cp >= 0x80 && cp <= 0x9F) return 0;  // C1 controls: some terminals act on them
    return n;
}

}  // namespace

std::string escape_text(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    for (std::size_t i = 0; i < s.size();) {
        if (const std::size_t n = printable_utf8(s, i)) {
            out.append(s.substr(i, n));
            i += n;
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned char>(s[i]));
            out += hex;
            ++i;
        }
    }
    return out;
}

Status check_encoding(std::string_view text) {
    auto starts = [&](std::string_view bom) { return text.substr(0, bom.size()) == bom; };
    auto refuse = [](const char* why) { return Status::error(why, kExitScene); };
    using namespace std::string_view_literals;
    if (starts("\xFF\xFE\0\0"sv) || starts("\0\0\xFE\xFF"sv))
        return refuse("the file looks like UTF-32 (it starts with a UTF-32 byte-order mark); save it as UTF-8 or ASCII");
    if (starts("\xFF\xFE"sv) || starts("\xFE\xFF"sv))
        return refuse("the file looks like UTF-16 (it starts with a UTF-16 byte-order mark); save it as UTF-8 or ASCII");
    // Without a mark: ASCII text in UTF-16 has a NUL byte in every other position.
    const std::size_t n = std::min<std::size_t>(text.size(), 1024) & ~std::size_t(1);
    if (n >= 4) {
        std::size_t even = 0, odd = 0;
        for (std::size_t i = 0; i < n; i += 2) {
            even += text[i] == '\0';
            odd += text[i + 1] == '\0';
        }
        const std::size_t half = n / 2;
        if ((even * 10 >= half * 7 && odd * 10 < half) || (odd * 10 >= half * 7 && even * 10 < half))
            return refuse("the file looks like UTF-16 (a NUL byte in every other position); save it as UTF-8 or ASCII");
    }
    return {};
}

std::string diagnostics_report(const std::string& path, const std::vector<Diagnostic>& diagnostics, int max_shown,
                               bool stopped_early) {
    std::string out;
    int errors = 0, warnings = 0;
    for (const Diagnostic& d : diagnostics) {
        int& shown = d.is_error() ? errors : warnings;
        if (++shown <= max_shown) out += escape_text(format_diagnostic(path, d)) + "\n";
    }
    const std::string name = escape_text(path);
    if (errors > max_shown) out += name + ": " + std::to_string(errors - max_shown) + " more errors not shown\n";
    if (warnings > max_shown)
        out += name + ": " + std::to_string(warnings - max_shown) + " more warnings not shown\n";
    if (stopped_early) out += name + ": too many errors; stopped reading\n";
    return out;
}

}  // namespace rt
