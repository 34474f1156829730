// Scene text -> Scene, or diagnostics with line and column. Never prints, never exits.
// Accepts every file the 2013 program accepts, with the changes marked New: in the
// format spec (self-delimiting braces, // anywhere, whole-token numbers, required
// camera keys, clear errors).
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "model.h"
#include "scene.h"
#include "status.h"
#include "texture.h"

namespace rt {

struct Diagnostic {
    enum class Severity { Error, Warning } severity = Severity::Error;
    int line = 0;  // 1-based
    int col = 0;   // 1-based byte column
    std::string message;
    // New: a problem in an included file: that file's path (as the including file names
    // it, from the scene's folder), and where it was included, innermost first (file ""
    // for the scene file itself, whose name the caller knows). Empty for the scene file.
    struct Site {
        std::string file;
        int line = 0, col = 0;
    };
    std::string file{};
    std::vector<Site> included_from{};
    bool is_error() const { return severity == Severity::Error; }
};

constexpr int kDefaultMaxErrors = 20;

struct ParseResult {
    Scene scene;
    std::vector<Diagnostic> diagnostics;  // errors and warnings, in file order
    bool cancelled = false;               // the progress callback stopped the parse
    std::size_t objects_read_ahead = 0;   // of scene.objects, those read by helper threads
    int max_errors = kDefaultMaxErrors;   // the ParseOptions::max_errors it was read with
    bool ok() const {
        if (cancelled) return false;
        for (const auto& d : diagnostics)
            if (d.is_error()) return false;
        return true;
    }
    // ok(), as the Status a program returns: on failure the diagnostics as printed
    // for `file` (diagnostics_report: at most `max_shown` of each kind, then a note
    // if the parser stopped at max_errors) and the exit code of a bad scene; a
    // cancelled parse says so. The diagnostics themselves stay above, for a list.
    Status status(const std::string& file, int max_shown = kDefaultMaxErrors) const;
};

struct ParseOptions {
    int max_errors = kDefaultMaxErrors;  // stop collecting after this many errors
    // A big file's thing sections are read in pieces on up to this many threads (0: all
    // the processor's), each piece starting at an item. The result, diagnostics
    // included, is exactly that of reading the file in one go: a piece is used only if
    // the one-go reading reaches its start at an item of a thing section, and only the
    // items it read without any diagnostic.
    int threads = 0;
    std::size_t min_piece_bytes = std::size_t(1) << 22;  // smaller files: one thread
    // A helper hands its objects over in chunks of this many (at least 1), which the
    // main reading moves into the scene while the helper reads on.
    std::size_t chunk_objects = 4096;
    // Called on the calling thread about every MB of text with the bytes read so far
    // and the objects made so far; returning false cancels the parse (the result is
    // then `cancelled`, and not ok).
    std::function<bool(std::size_t bytes, std::size_t objects)> progress;
    // The folder a mesh's `file` is relative to: the scene file's own ("" = the current
    // folder, for text that comes from no file).
    std::string base_dir;
    // New: the scene file itself, when the text is read from one ("" = none): an include
    // of it is then a cycle from the first include on.
    std::string scene_file;
    // Where models are read and kept between parses (the viewer keeps one for its
    // document); null: read for this parse alone. Each file is read once per parse
    // however many meshes name it.
    ModelStore* models = nullptr;
    // False: mesh files are not read (their blocks are checked, their `model` stays null).
    bool read_models = true;
    // New: where the materials' textures are decoded and kept between parses, as
    // `models` (null: the textures() of `models` when that is given, else for this parse
    // alone); each file is read once per parse however many materials name it.
    TextureStore* textures = nullptr;
    // False: texture files are not read (the names are checked, texture_image stays
    // null). Nor are they when read_models is false: callers that check a scene's
    // text alone read no files at all.
    bool read_textures = true;
};

ParseResult parse_scene(std::string_view text, const ParseOptions& options = {});

// "FILE:LINE:COL: error: MESSAGE", with " (included from FILE:LINE:COL, from ...)" for a
// problem in an included file.
std::string format_diagnostic(const std::string& file, const Diagnostic& d);

}  // namespace rt
