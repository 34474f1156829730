// Printing what came out of a scene file, safely: bytes that are not printable UTF-8
// are escaped (\xNN), so a binary, Latin-1 or UTF-16 file cannot send raw bytes to a
// terminal; a UTF-16 file is recognised and reported as such; and the diagnostics of
// a file are printed the same way (capped) by every program.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scene_parser.h"
#include "status.h"

namespace rt {

// `s` with every byte that is not part of printable UTF-8 (control characters, DEL,
// C1 controls, invalid or overlong sequences) written as \xNN. Tabs are kept.
std::string escape_text(std::string_view s);

// Whether `text` may be a scene file; it fails, saying why, with the exit code of a bad
// scene when it looks like UTF-16 or UTF-32 (a byte-order mark, or NUL bytes in
// every other position).
Status check_encoding(std::string_view text);

// The lines a program prints for a file's diagnostics ("FILE:LINE:COL: error: ...",
// escaped, each ending in '\n'): at most `max_shown` errors and `max_shown` warnings,
// then how many were left out. `stopped_early`: the parser gave up collecting errors.
std::string diagnostics_report(const std::string& path, const std::vector<Diagnostic>& diagnostics,
                               int max_shown, bool stopped_early = false);

}  // namespace rt
