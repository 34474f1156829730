// The file browser's folder listing, typed paths and completion (see file_browser.h).
#include "file_browser.h"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace rtview {
namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

std::string home() {
    const char* h = std::getenv("HOME");
    return h && *h ? h : "/";
}

// "~" and "~/x" as the shell reads them.
std::string expand_home(const std::string& typed) {
    if (typed == "~") return home();
    if (typed.rfind("~/", 0) == 0) return home() + typed.substr(1);
    return typed;
}

// Folders first, then by name, case-insensitively (then exactly, for a stable order).
bool before(const FileEntry& a, const FileEntry& b) {
    if (a.folder != b.folder) return a.folder;
    const std::string la = lower(a.name), lb = lower(b.name);
    return la != lb ? la < lb : a.name < b.name;
}

}  // namespace

FileBrowser::FileBrowser(std::vector<std::string> extensions, const std::string& folder)
    : extensions_(std::move(extensions)) {
    for (std::string& e : extensions_) e = lower(e);
    std::error_code ec;
    const std::string start = folder.empty() ? fs::current_path(ec).string() : folder;
    if (!go(start) && !go(home())) go("/");
}

bool FileBrowser::admits(const std::string& name) const {
    if (show_all_ || extensions_.empty()) return true;
    const std::string l = lower(name);
    for (const std::string& e : extensions_)
        if (l.size() > e.size() && l.compare(l.size() - e.size(), e.size(), e) == 0) return true;
    return false;
}

std::vector<FileEntry> FileBrowser::list(const std::string& folder, bool& truncated, std::string& error) const {
    std::vector<FileEntry> out;
    truncated = false;
    std::error_code ec;
    fs::directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec);
    if (ec) {
        error = "cannot list " + folder + ": " + ec.message();
        return out;
    }
    for (; it != fs::directory_iterator(); it.increment(ec)) {
        if (ec) break;
        const std::string name = it->path().filename().string();
        if (!show_hidden_ && !name.empty() && name[0] == '.') continue;
        std::error_code sec;
        const fs::file_status st = it->status(sec);  // follows symlinks; a loop is an error here
        FileEntry e;
        e.name = name;
        e.folder = !sec && fs::is_directory(st);
        if (!e.folder && !admits(name)) continue;
        e.readable = !sec && ::access(it->path().c_str(), e.folder ? (R_OK | X_OK) : R_OK) == 0;
        if (!e.folder && !sec && fs::is_regular_file(st)) e.size = it->file_size(sec);
        if (out.size() >= kMaxEntries) {
            truncated = true;
            break;
        }
        out.push_back(std::move(e));
    }
    std::sort(out.begin(), out.end(), before);
    return out;
}

bool FileBrowser::go(const std::string& path) {
    const std::string target = resolve(path);
    std::error_code ec;
    if (!fs::is_directory(target, ec)) {
        error_ = target + " is not a folder";
        return false;
    }
    bool truncated = false;
    std::string error;
    std::vector<FileEntry> entries = list(target, truncated, error);
    if (!error.empty()) {
        error_ = error;
        return false;
    }
    folder_ = target;
    entries_ = std::move(entries);
    truncated_ = truncated;
    error_.clear();
    return true;
}

void FileBrowser::refresh() {
    if (!folder_.empty()) go(folder_);
}

void FileBrowser::set_show_all(bool all) {
    if (all == show_all_) return;
    show_all_ = all;
    refresh();
}

void FileBrowser::set_show_hidden(bool hidden) {
    if (hidden == show_hidden_) return;
    show_hidden_ = hidden;
    refresh();
}

std::string FileBrowser::resolve(const std::string& typed) const {
    std::string t = expand_home(typed);
    fs::path p = t.empty() ? fs::path(folder_) : fs::path(t);
    if (p.is_relative()) p = fs::path(folder_.empty() ? "/" : folder_) / p;
    std::string s = p.lexically_normal().string();
    if (s.size() > 1 && s.back() == '/') s.pop_back();
    return s;
}

std::string FileBrowser::complete(const std::string& typed, std::vector<std::string>* candidates) const {
    if (candidates) candidates->clear();
    const std::size_t slash = typed.find_last_of('/');
    const std::string dir_part = slash == std::string::npos ? std::string() : typed.substr(0, slash + 1);
    const std::string stem = slash == std::string::npos ? typed : typed.substr(slash + 1);
    // The folder the last part is in: listed afresh (it may not be the one shown).
    const std::string folder = dir_part.empty() ? folder_ : resolve(dir_part == "/" ? "/" : dir_part);
    bool truncated = false;
    std::string error;
    const std::vector<FileEntry> entries = list(folder, truncated, error);
    std::vector<const FileEntry*> matches;
    for (const FileEntry& e : entries)
        if (e.name.compare(0, stem.size(), stem) == 0) matches.push_back(&e);
    if (matches.empty()) return typed;
    std::string common = matches.front()->name;
    for (const FileEntry* e : matches) {
        std::size_t n = 0;
        while (n < common.size() && n < e->name.size() && common[n] == e->name[n]) ++n;
        common.resize(n);
    }
    if (matches.size() == 1 && matches.front()->folder) common += '/';
    if (candidates && matches.size() > 1)
        for (const FileEntry* e : matches) candidates->push_back(e->name + (e->folder ? "/" : ""));
    return dir_part + common;
}

}  // namespace rtview
