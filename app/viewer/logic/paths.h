// Parts of a file's path as the viewer names files: the name without its folder, and
// without its extension.
#pragma once

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

}  // namespace rtview
