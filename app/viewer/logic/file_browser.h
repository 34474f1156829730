// The file browser behind Open, Save As, Save Image and Render to file: a folder's
// entries (folders first, then the files the filter admits), a typed path completed
// with Tab as a shell does, and the path a typed text stands for. Debian 12 packages
// no file dialog library; this one lists folders with std::filesystem only, never
// opens a file, and stops at a bounded number of entries, so a huge folder, a FIFO
// or a symlink loop cannot hang the UI.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rtview {

struct FileEntry {
    std::string name;
    bool folder = false;
    bool readable = true;  // a folder that can be listed, a file that can be read
    std::uintmax_t size = 0;
};

class FileBrowser {
public:
    // `extensions`: the files listed (".txt"; empty: all files); `folder`: where to
    // start (empty: the current directory).
    FileBrowser(std::vector<std::string> extensions, const std::string& folder);

    const std::string& folder() const { return folder_; }
    // Lists `path` (relative to the current folder, "~" for home) if it is a folder
    // that can be read; false, with error() saying why, if not.
    bool go(const std::string& path);
    bool up() { return go(".."); }
    void refresh();

    const std::vector<FileEntry>& entries() const { return entries_; }
    bool truncated() const { return truncated_; }  // more entries than kMaxEntries
    const std::string& error() const { return error_; }

    // Admitted by the filter (folders always are).
    bool admits(const std::string& name) const;
    void set_show_all(bool all);
    bool show_all() const { return show_all_; }
    void set_show_hidden(bool hidden);

    // The absolute path a typed text stands for (relative to the folder; "~"
    // expanded), normalised.
    std::string resolve(const std::string& typed) const;
    // Tab on a typed text: the longest completion shared by the names that start
    // with its last part (a folder gets its "/"); `candidates` receives those names
    // when there is more than one. Unchanged text if nothing matches.
    std::string complete(const std::string& typed, std::vector<std::string>* candidates = nullptr) const;

    static constexpr std::size_t kMaxEntries = 20000;

private:
    std::vector<FileEntry> list(const std::string& folder, bool& truncated, std::string& error) const;

    std::vector<std::string> extensions_;
    std::string folder_;
    std::vector<FileEntry> entries_;
    bool truncated_ = false;
    bool show_all_ = false, show_hidden_ = false;
    std::string error_;
};

}  // namespace rtview
