// The identity of a file version on disk: device, inode, size and modification time.
// Stores that keep what they read from a file (models, textures) compare it to tell
// whether the file changed since: an editor that saves by rename gives a new inode
// even within one tick of the clock, one that writes in place a new size or time.
#pragma once

#include <sys/stat.h>

#include <cstdint>
#include <string>

namespace rt {

struct FileId {
    std::uint64_t dev = 0, ino = 0;
    std::int64_t size = -1, mtime_ns = 0;  // size -1: unknown (no such file, or not read from one)

    bool known() const { return size >= 0; }
    bool operator==(const FileId& o) const {
        return dev == o.dev && ino == o.ino && size == o.size && mtime_ns == o.mtime_ns;
    }
    bool operator!=(const FileId& o) const { return !(*this == o); }

    static FileId of(const struct stat& st) {
        FileId id;
        id.dev = std::uint64_t(st.st_dev);
        id.ino = std::uint64_t(st.st_ino);
        id.size = std::int64_t(st.st_size);
        id.mtime_ns = std::int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
        return id;
    }
    // The file at `path` now (following links); unknown if it cannot be stat'ed.
    static FileId of(const std::string& path) {
        struct stat st;
        if (path.empty() || ::stat(path.c_str(), &st) != 0) return {};
        return of(st);
    }
    // Whether the file at `path` is still the version `read` was taken of: true also
    // when nothing was read from a file (`read` unknown) and when the file is gone
    // (what was read is kept).
    static bool unchanged(const std::string& path, const FileId& read) {
        if (!read.known()) return true;
        const FileId now = of(path);
        return !now.known() || now == read;
    }
};

}  // namespace rt
