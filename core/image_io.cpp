// PPM and PNG encoding (PNG in png.cpp), atomic file writes (temporary file + fsync +
// rename) and the small readers the tools and tests need.
#include "image_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <string_view>
#include <system_error>

#include "png.h"

namespace rt {
namespace {

// Set by interrupt_writes() (from a signal handler); g_pending counts the temporary
// files that exist. Lock-free atomics, so both are safe to touch in a handler.
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_pending{0};
constexpr int kInterrupted = -1;  // an "errno" for an interrupted write

std::string errno_text(int err) { return std::strerror(err); }

// I/O failures are usage errors for the programs (exit status 2).
Status io_error(std::string message) { return Status::error(std::move(message), kExitUsage); }
Status io_status(std::string message) { return message.empty() ? Status() : io_error(std::move(message)); }

// Writes all of `size` bytes, retrying short writes and signals; errno on failure.
int write_all(int fd, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, data, size);
        if (n < 0) {
            if (errno == EINTR) continue;
            return errno;
        }
        data += n;
        size -= std::size_t(n);
    }
    return 0;
}

// The process umask, read without changing it: umask(2) can only be queried by
// setting it, which would race with other threads creating files.
mode_t current_umask() {
    std::ifstream status("/proc/self/status");
    std::string key;
    while (status >> key) {
        if (key == "Umask:") {
            std::string value;
            status >> value;
            return mode_t(std::strtoul(value.c_str(), nullptr, 8) & 0777);
        }
    }
    return 022;  // the usual default, if /proc is unavailable
}

// An interruptible write checks for interrupt_writes() between pieces of a few MiB,
// so that a signal stops even a picture of hundreds of MiB within a fraction of a second.
int write_parts(int fd, std::initializer_list<std::string_view> parts, bool interruptible = false) {
    constexpr std::size_t kPiece = std::size_t(4) << 20;
    for (std::string_view part : parts) {
        for (std::size_t at = 0; at < part.size(); at += kPiece) {
            if (interruptible && g_interrupted.load()) return kInterrupted;
            const std::size_t n = std::min(kPiece, part.size() - at);
            if (int err = write_all(fd, part.data() + at, n)) return err;
        }
    }
    return interruptible && g_interrupted.load() ? kInterrupted : 0;
}

// Targets that are not regular files (a terminal, a pipe, /dev/null) cannot be
// replaced by a rename and have no contents to protect: write straight into them.
std::string write_in_place(const std::string& path, std::initializer_list<std::string_view> parts) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) return errno_text(errno);
    int err = write_parts(fd, parts);
    if (::close(fd) != 0 && err == 0) err = errno;
    return err ? errno_text(err) : std::string();
}

std::string ppm_header(int width, int height) {
    return "P6\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
}

// A PPM header field: skips whitespace and '#' comments, then reads digits.
bool ppm_number(const std::string& s, std::size_t& i, long& value) {
    for (;;) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        if (i < s.size() && s[i] == '#') {
            while (i < s.size() && s[i] != '\n') ++i;
            continue;
        }
        break;
    }
    if (i >= s.size() || !std::isdigit(static_cast<unsigned char>(s[i]))) return false;
    value = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
        value = value * 10 + (s[i++] - '0');
        if (value > 1L << 30) return false;
    }
    return true;
}


// What a write to a path really writes to: symbolic links followed to their end.
struct Target {
    std::string path;  // the final target (may not exist yet)
    std::string dir;   // its folder, with the trailing '/', or "" for the current one
    std::string name;
    bool exists = false;
    struct stat st {};
};

// Follows `path` through symbolic links, as open() would, but also through a
// dangling one (whose target is then created, as the shell's `>` does). 0 or errno.
int resolve_target(const std::string& path, Target& t) {
    std::string p = path;
    for (int hops = 0;; ++hops) {
        struct stat st;
        if (::lstat(p.c_str(), &st) != 0) {
            if (errno != ENOENT) return errno;
            t.exists = false;
            break;
        }
        if (!S_ISLNK(st.st_mode)) {
            t.exists = true;
            t.st = st;
            break;
        }
        if (hops >= 40) return ELOOP;  // the kernel's own limit
        std::string link(PATH_MAX, '\0');
        const ssize_t n = ::readlink(p.c_str(), link.data(), link.size());
        if (n < 0) return errno;
        if (std::size_t(n) >= link.size()) return ENAMETOOLONG;
        link.resize(std::size_t(n));
        const std::size_t slash = p.find_last_of('/');
        p = link[0] == '/' || slash == std::string::npos ? link : p.substr(0, slash + 1) + link;
        if (p.size() >= PATH_MAX) return ENAMETOOLONG;
    }
    const std::size_t slash = p.find_last_of('/');
    t.dir = slash == std::string::npos ? std::string() : p.substr(0, slash + 1);
    t.name = slash == std::string::npos ? p : p.substr(slash + 1);
    t.path = std::move(p);
    if (t.name.empty()) return EISDIR;  // "folder/"
    return 0;
}

// Why an existing regular file may not be replaced (see check_writable), or 0.
int replace_problem(const Target& t) {
    if (!t.exists) return 0;
    const uid_t me = ::geteuid();
    if (me == 0) return 0;
    // A read-only file stays: replacing it by a rename would silently defeat that.
    if (::faccessat(AT_FDCWD, t.path.c_str(), W_OK, AT_EACCESS) != 0) return errno;
    // The rename would fail at the end (sticky folder, someone else's file); say so now.
    struct stat ds;
    if (::stat(t.dir.empty() ? "." : t.dir.c_str(), &ds) == 0 && (ds.st_mode & S_ISVTX) && t.st.st_uid != me &&
        ds.st_uid != me)
        return EPERM;
    return 0;
}

// Best effort: the new file gets the old one's owner and group (root can give any;
// others only a group they belong to). A failure leaves them ours, as for a new file.
void keep_owner(int fd, const struct stat& old) {
    struct stat now;
    if (::fstat(fd, &now) != 0) return;
    if (now.st_uid != old.st_uid || now.st_gid != old.st_gid) {
        if (::fchown(fd, old.st_uid, old.st_gid) != 0 && now.st_gid != old.st_gid) {
            [[maybe_unused]] int ignored = ::fchown(fd, uid_t(-1), old.st_gid);
        }
    }
}

// The temporary file next to the target: ".NAME.XXXXXX", with NAME shortened so that
// the whole stays within NAME_MAX (a target name of 248..255 bytes is legal). Removed
// by the destructor unless renamed; counted in g_pending while it exists.
struct TempFile {
    std::string name;
    int fd = -1;
    int err = 0;

    explicit TempFile(const Target& t, WhileWriting how = WhileWriting::TempName) {
        g_pending.fetch_add(1);  // before the interrupt check (see interrupt_writes)
        if (g_interrupted.load()) {
            err = kInterrupted;
            name_gone_ = true;
            return;
        }
        constexpr std::size_t kSuffix = 8;  // "." in front, ".XXXXXX" behind
        name = t.dir + "." + t.name.substr(0, std::min(t.name.size(), std::size_t(NAME_MAX) - kSuffix)) + ".XXXXXX";
        if (how == WhileWriting::NoName) {
            fd = ::open(t.dir.empty() ? "." : t.dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600);
            if (fd >= 0) {
                unnamed_ = true;
                name_gone_ = true;  // nothing to remove until name() gives it one
                return;
            }
            // A file system without O_TMPFILE says so in one of these: a named one then.
            if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) {
                err = errno;
                name_gone_ = true;
                return;
            }
        }
        fd = ::mkostemp(name.data(), O_CLOEXEC);
        if (fd < 0) {
            err = errno;
            name_gone_ = true;  // nothing was created: the name is only the template
        }
    }
    ~TempFile() {
        if (fd >= 0) ::close(fd);
        if (!name_gone_) ::unlink(name.c_str());
        g_pending.fetch_sub(1);
    }
    TempFile(const TempFile&) = delete;
    TempFile& operator=(const TempFile&) = delete;

    std::string error() const { return err == kInterrupted ? std::string("interrupted") : errno_text(err); }
    int close() {
        const int r = ::close(fd);
        fd = -1;
        return r != 0 ? errno : 0;
    }
    void renamed() { name_gone_ = true; }
    // A complete unnamed file gets its temporary name (for the rename over the target);
    // 0 or errno. (A named one has it already.)
    int name_it() {
        if (!unnamed_) return 0;
        const std::string proc = "/proc/self/fd/" + std::to_string(fd);
        static std::atomic<unsigned> counter{0};
        for (int attempt = 0; attempt < 100; ++attempt) {
            char suffix[8];
            const unsigned r = unsigned(::getpid()) * 2654435761u + counter.fetch_add(1) * 40503u + unsigned(attempt);
            std::snprintf(suffix, sizeof suffix, "%06x", r & 0xffffffu);
            std::string n = name.substr(0, name.size() - 6) + suffix;
            if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, n.c_str(), AT_SYMLINK_FOLLOW) == 0) {
                name = std::move(n);
                unnamed_ = false;
                name_gone_ = false;
                return 0;
            }
            if (errno != EEXIST) return errno;
        }
        return EEXIST;
    }

private:
    bool name_gone_ = false;
    bool unnamed_ = false;
};
}  // namespace

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

ImageFormat format_from_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".ppm") return ImageFormat::Ppm;
    if (ext == ".png") return ImageFormat::Png;
    if (ext == ".pfm") return ImageFormat::Pfm;
    if (ext == ".exr") return ImageFormat::Exr;
    return ImageFormat::Unknown;
}

std::vector<std::uint8_t> to_rgb8(const Image& img) {
    std::vector<std::uint8_t> out(img.rgb.size());
    for (std::size_t i = 0; i < img.rgb.size(); ++i) out[i] = to_byte(img.rgb[i]);
    return out;
}

Status write_image(const std::string& path, const Image& img) {
    const ImageFormat f = format_from_path(path);
    if (!is_float_format(f)) return write_rgb8(path, img.width, img.height, to_rgb8(img));
    if (img.width < 1 || img.height < 1 || img.rgb.size() != std::size_t(img.width) * std::size_t(img.height) * 3)
        return io_error("internal error: the image data does not match its size");
    if (f == ImageFormat::Pfm) return write_file_atomic(path, encode_pfm(img));
    std::string exr;
    if (const Status st = encode_exr(img, exr); !st) return st;
    return write_file_atomic(path, exr);
}

Status write_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
    return write_rgb8(path, width, height, rgb.data(), rgb.size());
}

Status write_rgb8(const std::string& path, int width, int height, const std::uint8_t* rgb, std::size_t size) {
    if (width < 1 || height < 1 || size != std::size_t(width) * std::size_t(height) * 3)
        return io_error("internal error: the image data does not match its size");
    switch (format_from_path(path)) {
        case ImageFormat::Ppm:
            return write_file_atomic(path, {ppm_header(width, height),
                                            {reinterpret_cast<const char*>(rgb), size}});
        case ImageFormat::Png: {
            std::string png;
            if (!encode_png(rgb, width, height, png)) return io_error("PNG encoding failed");
            return write_file_atomic(path, png);
        }
        case ImageFormat::Pfm:
        case ImageFormat::Exr:
            // Bytes have lost the floats: callers with a film write it (write_image).
            return io_error("internal error: .pfm and .exr are written from the film's floats");
        case ImageFormat::Unknown:
            break;
    }
    return io_error("unknown image format: the file name must end in .ppm, .png, .pfm or .exr");
}

Status write_file_atomic(const std::string& path, const std::string& data, WhileWriting how) {
    return write_file_atomic(path, {std::string_view(data)}, how);
}

Status write_file_atomic(const std::string& path_in, std::initializer_list<std::string_view> parts, WhileWriting how) {
    if (path_in.empty()) return io_error("no file name given");
    Target t;
    if (int err = resolve_target(path_in, t)) return io_error(errno_text(err));
    if (t.exists && S_ISDIR(t.st.st_mode)) return io_error(errno_text(EISDIR));
    if (t.exists && !S_ISREG(t.st.st_mode)) return io_status(write_in_place(t.path, parts));
    if (int err = replace_problem(t)) return io_error(errno_text(err));

    TempFile tmp(t, how);
    if (tmp.fd < 0) return io_error(tmp.error());
    // mkstemp makes the file 0600; give it the mode the file has now, or the mode
    // a newly created file would get.
    const mode_t mode = t.exists ? (t.st.st_mode & 07777) : (0666 & ~current_umask());
    if (t.exists) keep_owner(tmp.fd, t.st);
    int err = 0;
    if (::fchmod(tmp.fd, mode) != 0) err = errno;
    if (!err) err = write_parts(tmp.fd, parts, true);
    // Without fsync a crash soon after the rename can leave an empty file under the
    // target's name; fsync is also where some file systems first report a full disk.
    if (!err && ::fsync(tmp.fd) != 0) err = errno;
    if (!err) err = tmp.name_it();
    if (!err) err = tmp.close();
    if (!err && g_interrupted.load()) err = kInterrupted;
    if (!err && ::rename(tmp.name.c_str(), t.path.c_str()) != 0) err = errno;
    if (err) return io_error(err == kInterrupted ? std::string("interrupted") : errno_text(err));
    tmp.renamed();
    // Make the rename itself durable; the new file is already in place, so a
    // failure here is not worth reporting.
    const int dfd = ::open(t.dir.empty() ? "." : t.dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return {};
}

Status check_writable(const std::string& path) {
    if (path.empty()) return io_error("no file name given");
    Target t;
    if (int err = resolve_target(path, t)) return io_error(errno_text(err));
    if (t.exists && S_ISDIR(t.st.st_mode)) return io_error(errno_text(EISDIR));
    if (t.exists && !S_ISREG(t.st.st_mode)) {
        // Not opened: a FIFO would block until somebody reads it.
        if (::faccessat(AT_FDCWD, t.path.c_str(), W_OK, AT_EACCESS) != 0) return io_error(errno_text(errno));
        return {};
    }
    if (int err = replace_problem(t)) return io_error(errno_text(err));
    TempFile probe(t);
    if (probe.fd < 0) return io_error(probe.error());
    return {};  // the probe's destructor removes it
}

bool interrupt_writes() {
    g_interrupted.store(true);
    return g_pending.load() > 0;
}

void reset_write_interrupt() { g_interrupted.store(false); }

Status read_ppm(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgb) {
    std::string data;
    // A P3 file of the largest picture the format allows is about 3 GiB; tests and
    // tools compare far smaller ones.
    if (Status st = read_file(path, data, std::size_t(1) << 30); !st) return st;
    if (data.size() < 2 || data[0] != 'P' || (data[1] != '3' && data[1] != '6'))
        return io_error("not a PPM file (expected P3 or P6)");
    const bool binary = data[1] == '6';
    std::size_t i = 2;
    long w = 0, h = 0, maxval = 0;
    if (!ppm_number(data, i, w) || !ppm_number(data, i, h) || !ppm_number(data, i, maxval))
        return io_error("malformed PPM header");
    if (w < 1 || h < 1 || w > 65536 || h > 65536 || maxval < 1 || maxval > 65535)
        return io_error("unsupported PPM size or maximum value");
    const std::size_t samples = std::size_t(w) * std::size_t(h) * 3;
    // Every sample takes at least a byte of the file: check before allocating.
    if (samples > data.size() - i) return io_error("PPM pixel data is truncated");
    std::vector<std::uint8_t> px(samples);
    // Samples are rescaled to 0..255, so only maxval 255 is lossless.
    auto scale = [&](long v) { return std::uint8_t((v * 255 + maxval / 2) / maxval); };
    if (binary) {
        // Exactly one whitespace byte separates the header from the raster.
        if (i >= data.size() || !std::isspace(static_cast<unsigned char>(data[i]))) return io_error("malformed PPM header");
        ++i;
        const std::size_t bytes_per_sample = maxval > 255 ? 2 : 1;
        if (data.size() - i < samples * bytes_per_sample) return io_error("PPM pixel data is truncated");
        for (std::size_t k = 0; k < samples; ++k) {
            long v = static_cast<unsigned char>(data[i + k * bytes_per_sample]);
            if (bytes_per_sample == 2) v = v * 256 + static_cast<unsigned char>(data[i + 2 * k + 1]);
            if (v > maxval) return io_error("PPM sample larger than the maximum value");
            px[k] = scale(v);
        }
    } else {
        for (std::size_t k = 0; k < samples; ++k) {
            long v = 0;
            if (!ppm_number(data, i, v)) return io_error("PPM pixel data is truncated or malformed");
            if (v > maxval) return io_error("PPM sample larger than the maximum value");
            px[k] = scale(v);
        }
    }
    width = int(w);
    height = int(h);
    rgb = std::move(px);
    return {};
}

}  // namespace rt
