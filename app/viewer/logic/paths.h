// Parts of a file's path as the viewer names files: the name without its folder, and
// without its extension; a file as a scene names it.
#pragma once

#include <filesystem>
#include <string>

namespace rtview {

// "scenes/a.txt" -> "a.txt"
inline std::string base_name(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// "a.txt" -> "a" (a leading dot is part of the name: ".txt" stays)
inline std::string stem_of(const std::string& name) {
    const std::size_t dot = name.find_last_of('.');
    return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

// `file` as a scene at `scene_path` names it (a mesh's model, a material's texture):
// from the scene's folder when it is in it (the scene and its files then move
// together), else by its absolute path; an unsaved scene (`scene_path` empty) names it
// by its absolute path.
inline std::string scene_file_name(const std::string& file, const std::string& scene_path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path abs = fs::absolute(file, ec).lexically_normal();
    if (ec) return file;
    if (scene_path.empty()) return abs.string();
    const fs::path parent = fs::path(scene_path).parent_path();
    fs::path folder = fs::absolute(parent.empty() ? fs::path(".") : parent, ec).lexically_normal();
    if (ec) return abs.string();
    if (!folder.has_filename()) folder = folder.parent_path();  // "/a/b/" -> "/a/b"
    const fs::path rel = abs.lexically_relative(folder);
    if (!rel.empty() && *rel.begin() != ".." && rel != ".") return rel.string();
    return abs.string();
}

}  // namespace rtview
