// The recent-files list, kept in $XDG_CONFIG_HOME/raytracer-view/recent.txt (or
// ~/.config/...), one absolute path per line, most recent first.
#pragma once

#include <string>
#include <vector>

#include "status.h"

namespace rtview {

class RecentFiles {
public:
    static constexpr std::size_t kMax = 10;

    // `file` empty: the default location from the environment (may stay empty if
    // neither XDG_CONFIG_HOME nor HOME is set; the list then lives in memory only).
    explicit RecentFiles(std::string file = {});
    static std::string default_path();

    const std::vector<std::string>& paths() const { return paths_; }
    // Moves `path` (made absolute) to the front and saves; success, or why saving
    // failed (the list in memory is changed either way).
    rt::Status add(const std::string& path);
    rt::Status remove(const std::string& path);
    void load();

private:
    rt::Status save() const;
    std::string file_;
    std::vector<std::string> paths_;
};

// Writes a file of the viewer's configuration folder atomically, creating the folder
// first. An empty `file` (no configuration folder known) writes nothing.
rt::Status save_config_file(const std::string& file, const std::string& text);

// `path` made absolute against the current directory (not resolving links).
std::string absolute_path(const std::string& path);

}  // namespace rtview
