// Reading whole files: scenes (100+ MB for a million objects), pictures for the tools.
// One reader for the command line and the viewer; the viewer adds a cancel flag, a
// progress report and the refusals that keep its loader from blocking (ReadControl).
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "image_io.h"
#include "pages.h"
#include "parallel.h"

namespace rt {
namespace {

Status read_error(std::string message) { return Status::error(std::move(message), kExitUsage); }

// Up to n bytes at `at` (fewer only at the end of the file); -1 with errno on error.
ssize_t pread_full(int fd, char* p, std::size_t n, off_t at) {
    std::size_t got = 0;
    while (got < n) {
        const ssize_t r = ::pread(fd, p + got, n - got, at + off_t(got));
        if (r < 0) {
            if (errno == EINTR) continue;
            return -1;
        }
        if (r == 0) break;
        got += std::size_t(r);
    }
    return ssize_t(got);
}

// Waits up to 50 ms for a FIFO to have data or its writer's end: until a writer has
// come, poll reports nothing (not even a hang-up), and a read would say end of file.
// False: nothing yet, ask again (after a look at the cancel flag).
bool fifo_ready(int fd) {
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, 50);
    return !(ready == 0 || (ready < 0 && errno == EINTR));
}

// Whether the file still has the size and time it had when it was opened.
bool unchanged(int fd, const struct stat& st) {
    struct stat now {};
    return ::fstat(fd, &now) == 0 && now.st_size == st.st_size && now.st_mtim.tv_sec == st.st_mtim.tv_sec &&
           now.st_mtim.tv_nsec == st.st_mtim.tv_nsec;
}

// A big regular file read in two halves at once, the second on another of the process
// pool's threads (copying from the page cache is most of a read's time). `size`
// becomes `total` when both halves were read whole; it stays 0 when the caller's loop
// is to read the file instead (the file is no longer as big).
template <class Buffer>
Status read_halves(int fd, std::size_t total, Buffer& out, std::size_t& size) {
    const std::size_t half = total / 2;
    ssize_t second = -1;
    int second_errno = 0;
    ssize_t first = -1;
    int first_errno = 0;
    two_ways(true, [&](int part) {
        if (part == 0) {
            first = pread_full(fd, &out[0], half, 0);
            if (first < 0) first_errno = errno;
        } else {
            second = pread_full(fd, &out[half], total - half, off_t(half));
            if (second < 0) second_errno = errno;
        }
    });
    if (first < 0) return read_error(std::strerror(first_errno));
    if (second < 0) return read_error(std::strerror(second_errno));
    if (std::size_t(first) == half && std::size_t(second) == total - half &&
        ::lseek(fd, off_t(total), SEEK_SET) == off_t(total))
        size = total;
    else if (::lseek(fd, 0, SEEK_SET) != 0)
        return read_error(std::strerror(errno));
    return {};
}

std::string too_big(std::size_t max_bytes) {
    return "the file is larger than " + std::to_string(max_bytes) + " bytes";
}

// What kind of file `st` is allowed to be; a message when it is not.
std::string refusal(const struct stat& st, std::size_t max_bytes, const ReadControl* control) {
    if (S_ISDIR(st.st_mode)) return control && control->strict ? "a folder, not a scene file" : std::strerror(EISDIR);
    if (control && control->strict && !S_ISREG(st.st_mode) && !S_ISFIFO(st.st_mode))
        return "not a regular file or a pipe (a device or a socket)";
    if (S_ISREG(st.st_mode) && std::uint64_t(st.st_size) > max_bytes) return too_big(max_bytes);
    return {};
}

// read_file into a std::string or a FileText.
template <class Buffer>
Status read_into(const std::string& path, Buffer& out, std::size_t max_bytes, const ReadControl* control) {
    const bool strict = control && control->strict;
    // Strict: not blocking on open, since a FIFO with no writer would hold the reader
    // (and its cancel flag) for ever.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | (strict ? O_NONBLOCK : 0));
    if (fd < 0) return read_error(std::strerror(errno));
    auto fail = [&](std::string msg) {
        ::close(fd);
        out.clear();
        return read_error(std::move(msg));
    };
    const std::string changing = "the file changed while it was read (is another program still writing it?)";
    struct stat st;
    if (::fstat(fd, &st) != 0) return fail(std::strerror(errno));
    if (std::string why = refusal(st, max_bytes, control); !why.empty()) return fail(why);
    const bool regular = S_ISREG(st.st_mode), fifo = S_ISFIFO(st.st_mode);
    if (strict && !fifo) ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    auto cancelled = [&] { return control && control->cancel && control->cancel->load(); };
    auto report = [&](std::size_t done) {
        if (control && control->progress) control->progress(done, regular ? std::uint64_t(st.st_size) : 0);
    };
    // Read straight into `out` (a scene can be 100+ MB: no second copy through a
    // buffer), but to the end of the file rather than trusting st_size: pipes and /proc
    // files have none, and a file may grow while it is read. One byte more than the
    // size lets the read that finds the end need no bigger buffer.
    const std::size_t limit = max_bytes == std::size_t(-1) ? max_bytes : max_bytes + 1;
    std::size_t size = 0;
    out.clear();
    const std::size_t spare =
        control && regular ? std::size_t(double(st.st_size) * std::clamp(control->spare_share, 0.0, 1.0)) : 0;
    const std::size_t first =
        std::min(limit, regular && st.st_size > 0 ? std::size_t(st.st_size) + 1 + spare : std::size_t(65536));
    const bool big = regular && std::size_t(st.st_size) >= (std::size_t(8) << 20) && first > std::size_t(st.st_size);
    if (big) {
        // The first-touch faults (most of the cost of filling fresh pages) taken on two
        // threads; else a std::string's zero fill in resize() would take them all on
        // this one, and a FileText's read would take them as it goes.
        out.reserve(first);
        populate_pages_on_two_threads(out.data(), first);
    }
    out.resize(first);
    if (big) {
        if (Status s = read_halves(fd, std::size_t(st.st_size), out, size); !s) return fail(s.message());
        if (size > 0) report(size);
    }
    // Then on from the size, for a file that grew (one that shrank is read again in one
    // go), and every file the halves did not read. Reads of at most 4 MB, so that a
    // cancel is seen and progress reported as a big file arrives.
    constexpr std::size_t kPiece = std::size_t(4) << 20;
    for (;;) {
        if (cancelled()) return fail("cancelled");
        if (strict && fifo && !fifo_ready(fd)) continue;
        if (size == out.size()) out.resize(std::min(limit, std::max(out.size() * 2, std::size_t(65536))));
        const ssize_t n = ::read(fd, &out[size], std::min(kPiece, out.size() - size));
        if (n < 0) {
            if (errno == EINTR || errno == EAGAIN) continue;
            return fail(std::strerror(errno));
        }
        if (n == 0) break;
        size += std::size_t(n);
        if (size > max_bytes) return fail(too_big(max_bytes));
        // Strict: a regular file's size is known, and one another program is still
        // writing (it grows, shrinks or is rewritten meanwhile) could be read half old,
        // half new.
        if (strict && regular && size > std::size_t(st.st_size)) return fail(changing);
        report(size);
    }
    if (strict && regular && (size != std::size_t(st.st_size) || !unchanged(fd, st))) return fail(changing);
    out.resize(size);
    ::close(fd);
    return {};
}

}  // namespace

Status read_file(const std::string& path, std::string& out, std::size_t max_bytes, const ReadControl* control) {
    return read_into(path, out, max_bytes, control);
}

Status read_file(const std::string& path, FileText& out, std::size_t max_bytes, const ReadControl* control) {
    return read_into(path, out, max_bytes, control);
}

}  // namespace rt
