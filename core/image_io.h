// Image and text output. Every write goes to a temporary file in the same folder,
// is flushed and synced, then renamed over the target: a failed or interrupted write
// leaves any existing file untouched and no temporary file behind. The rules for
// links, read-only files and other users' files are those of check_writable().
#pragma once

#include <atomic>
#include <cstdint>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "film.h"
#include "status.h"

namespace rt {

enum class ImageFormat { Unknown, Ppm, Png, Pfm, Exr };
// .pfm and .exr hold floats (New:): the film's linear values, written by write_image.
inline bool is_float_format(ImageFormat f) { return f == ImageFormat::Pfm || f == ImageFormat::Exr; }
ImageFormat format_from_path(const std::string& path);

// 8-bit RGB bytes of an image, with the original's rounding.
std::vector<std::uint8_t> to_rgb8(const Image& img);

// Success, or why not (exit code kExitUsage: an I/O error). By the path's extension:
// PPM and PNG with the original's byte rounding, PFM and EXR with the floats.
Status write_image(const std::string& path, const Image& img);
// The encoded files (image_float.cpp).
std::string encode_pfm(const Image& img);
Status encode_exr(const Image& img, std::string& out);
Status write_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb);
Status write_rgb8(const std::string& path, int width, int height, const std::uint8_t* rgb, std::size_t size);
// How the new file exists while it is written: under a temporary name beside the target
// (".NAME.XXXXXX", removed on failure or interrupt_writes()), or, where the file system
// allows (Linux O_TMPFILE; else as TempName), with no name at all until it is complete,
// so that even a SIGKILL in the middle of the write leaves nothing behind.
enum class WhileWriting { TempName, NoName };
Status write_file_atomic(const std::string& path, const std::string& data,
                         WhileWriting how = WhileWriting::TempName);
// The same for data in several pieces, written one after the other.
Status write_file_atomic(const std::string& path, std::initializer_list<std::string_view> parts,
                         WhileWriting how = WhileWriting::TempName);
// Success if write_file_atomic(path, ...) can be expected to succeed, else the
// system's reason (checked before a long render, so that it fails at once). The rules, the
// same for both: a symbolic link is followed to its end (a dangling link creates its
// target; a loop fails with ELOOP); a folder is refused (EISDIR); a file we may not
// write to (a read-only OUT) is refused with EACCES, as the shell's `>` does, except
// for root, who may replace any file; a replaced file keeps its mode, and its owner
// and group as far as the system allows (root keeps another user's file theirs); a
// file in a sticky folder (/tmp) that belongs to someone else is refused (EPERM);
// devices and FIFOs are written in place. The folder must accept a new file: this
// creates and removes a temporary file there.
Status check_writable(const std::string& path);

// For signal handlers (both async-signal-safe). interrupt_writes() makes every write
// in progress, and every later one, stop, remove its temporary file and fail with
// "interrupted"; it returns true if a temporary file exists right now, in which case
// the process must let the write clean up rather than end at once.
bool interrupt_writes();
// Undoes interrupt_writes() (for tests).
void reset_write_interrupt();

// What a reader that must stay responsive (the viewer's loader) asks of read_file.
struct ReadControl {
    const std::atomic<bool>* cancel = nullptr;  // once set, the read ends: "cancelled"
    // After each piece read: bytes so far, of `total` (0 when unknown: a pipe).
    std::function<void(std::uint64_t done, std::uint64_t total)> progress;
    // Only a regular file or a FIFO, never blocking: a folder, a device or a socket
    // fails at once, a FIFO is waited for in polls that see `cancel`, and a regular file
    // that changes while it is read fails ("changed while it was read") rather than
    // arrive half old, half new.
    bool strict = false;
    // Room left beyond a regular file's bytes, as a share of its size: a text edited in
    // place (the viewer's) then grows by that much without being moved (a 100 MB move
    // and its fresh pages' faults on the edit that first makes the text longer).
    double spare_share = 0;
};

// Reads a whole file (file_read.cpp). Refuses files over max_bytes.
Status read_file(const std::string& path, std::string& out, std::size_t max_bytes,
                 const ReadControl* control = nullptr);

// The extension of a path's last component, with its dot, in lower case ("" if none):
// what picks an image format or a model reader.
std::string lower_extension(const std::string& path);

// A file's bytes, for big files read once: growing it leaves the new bytes unwritten
// until the read fills them, where a std::string would zero them first (one more pass
// over a 100+ MB scene on one thread).
class FileText {
public:
    std::string_view view() const { return {data_.get(), size_}; }
    std::size_t size() const { return size_; }
    char* data() { return data_.get(); }
    char& operator[](std::size_t i) { return data_[i]; }
    void clear() { size_ = 0; }
    void reserve(std::size_t n) {
        if (n <= capacity_) return;
        std::unique_ptr<char[]> grown(new char[n]);  // (not value-initialised: no zero fill)
        if (size_ > 0) std::memcpy(grown.get(), data_.get(), size_);
        data_ = std::move(grown);
        capacity_ = n;
    }
    void resize(std::size_t n) {
        reserve(n);
        size_ = n;
    }

private:
    std::unique_ptr<char[]> data_;
    std::size_t size_ = 0, capacity_ = 0;
};
Status read_file(const std::string& path, FileText& out, std::size_t max_bytes,
                 const ReadControl* control = nullptr);

// Reads a binary (P6) or ASCII (P3) PPM.
Status read_ppm(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgb);

}  // namespace rt
