// A scene file read as the command line reads it, for the benchmark tools: its meshes
// from the scene's folder; a file that cannot be read or does not parse is reported in
// the usual `file:line:col: error: ...` form under the tool's name.
#pragma once

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "image_io.h"
#include "scene.h"
#include "model.h"
#include "scene_parser.h"

namespace bench {

// A camera moved along a circle about the z axis (the scene format's worlds are z-up)
// through its centre: what an orbit drag does.
inline rt::Camera orbited(const rt::Camera& c, double angle) {
    rt::Camera out = c;
    const rt::Vec3 d = c.position - c.centre;
    const double cs = std::cos(angle), sn = std::sin(angle);
    out.position = c.centre + rt::Vec3{cs * d.x - sn * d.y, sn * d.x + cs * d.y, d.z};
    return out;
}

// The scene at `path`, or nothing with the reason printed and `exit_code` set (2: the
// file cannot be read, 1: it does not parse).
inline std::optional<rt::Scene> read_scene(const char* tool, const std::string& path, int& exit_code) {
    std::string text;
    if (std::string err = rt::read_file(path, text, rt::Limits::max_file_size).message(); !err.empty()) {
        std::fprintf(stderr, "%s: cannot read %s: %s\n", tool, path.c_str(), err.c_str());
        exit_code = 2;
        return std::nullopt;
    }
    rt::ParseOptions options;
    options.base_dir = rt::folder_of(path);
    rt::ParseResult parsed = rt::parse_scene(text, options);
    if (!parsed.ok()) {
        for (const auto& d : parsed.diagnostics) std::fprintf(stderr, "%s\n", rt::format_diagnostic(path, d).c_str());
        exit_code = 1;
        return std::nullopt;
    }
    return std::move(parsed.scene);
}

}  // namespace bench
