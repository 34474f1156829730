// Scene text -> Scene, or diagnostics with line and column. Never prints, never exits.
// Accepts every file the 2013 program accepts, with the changes marked New: in the
// format spec (self-delimiting braces, // anywhere, whole-token numbers, required
// camera keys, clear errors).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "scene.h"

namespace rt {

struct Diagnostic {
    enum class Severity { Error, Warning } severity = Severity::Error;
    int line = 0;  // 1-based
    int col = 0;   // 1-based byte column
    std::string message;
    bool is_error() const { return severity == Severity::Error; }
};

struct ParseResult {
    Scene scene;
    std::vector<Diagnostic> diagnostics;  // errors and warnings, in file order
    bool ok() const {
        for (const auto& d : diagnostics)
            if (d.is_error()) return false;
        return true;
    }
};

struct ParseOptions {
    int max_errors = 20;  // stop collecting after this many errors
};

ParseResult parse_scene(std::string_view text, const ParseOptions& options = {});

// "FILE:LINE:COL: error: MESSAGE"
std::string format_diagnostic(const std::string& file, const Diagnostic& d);

}  // namespace rt
