// What the stores of models and textures (ModelStore, TextureStore) keep of each file
// read: by resolved path, the file version read (FileId), and either what was made of
// it, held weakly (kept only while something else holds it), or the reading's error.
// A stat() per file then tells whether a scene parsed again may reuse them.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "file_id.h"

namespace rt {

template <class T, class Error>
class FileCache {
public:
    // What the cache holds for `path` as of version `id`: true with `error` set for a
    // failed reading of that version; true with `value` set when its result is still
    // held; false otherwise (read the file).
    bool find(const std::string& path, const FileId& id, std::shared_ptr<const T>& value, Error& error) {
        std::lock_guard<std::mutex> lock(mutex_);
        auto it = entries_.find(path);
        if (it == entries_.end() || !id.known() || it->second.id != id) return false;
        if (it->second.failed) {
            error = it->second.error;
            return true;
        }
        value = it->second.value.lock();
        return bool(value);
    }
    // Records the reading of `path` (version `id`): `value`, or `error` when it is null.
    // Unless `keep`, the entry is not kept (a file whose stat says nothing of what it
    // would give). Entries of results nobody holds any more are dropped meanwhile.
    void store(const std::string& path, const FileId& id, const std::shared_ptr<const T>& value, const Error& error,
               bool keep) {
        std::lock_guard<std::mutex> lock(mutex_);
        for (auto it = entries_.begin(); it != entries_.end();)
            it = !it->second.failed && it->second.value.expired() ? entries_.erase(it) : std::next(it);
        if (!keep) return;
        Entry& e = entries_[path];
        e.id = id;
        e.value = value;
        e.failed = !value;
        e.error = value ? Error{} : error;
    }

private:
    struct Entry {
        FileId id;
        std::weak_ptr<const T> value;
        Error error{};  // the last reading's, when it failed
        bool failed = false;
    };
    std::mutex mutex_;
    std::map<std::string, Entry> entries_;
};

}  // namespace rt
