// PPM and PNG encoding, atomic file writes (temporary file + fsync + rename) and the
// small readers the tools and tests need. PNG bytes come from the packaged stb
// (libstb, which already holds the implementation: link `stb`, define nothing).
#include "image_io.h"

#include <fcntl.h>
#include <stb/stb_image_write.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <string_view>

namespace rt {
namespace {

std::string errno_text(int err) { return std::strerror(err); }

std::string lower_extension(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    const std::size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
    std::string ext = path.substr(dot);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

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

// Targets that are not regular files (a terminal, a pipe, /dev/null) cannot be
// replaced by a rename and have no contents to protect: write straight into them.
int write_parts(int fd, std::initializer_list<std::string_view> parts) {
    for (std::string_view part : parts)
        if (int err = write_all(fd, part.data(), part.size())) return err;
    return 0;
}

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

void append_bytes(void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
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

}  // namespace

ImageFormat format_from_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == ".ppm") return ImageFormat::Ppm;
    if (ext == ".png") return ImageFormat::Png;
    return ImageFormat::Unknown;
}

std::vector<std::uint8_t> to_rgb8(const Image& img) {
    std::vector<std::uint8_t> out(img.rgb.size());
    for (std::size_t i = 0; i < img.rgb.size(); ++i) out[i] = to_byte(img.rgb[i]);
    return out;
}

std::string write_image(const std::string& path, const Image& img) {
    return write_rgb8(path, img.width, img.height, to_rgb8(img));
}

std::string write_rgb8(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb) {
    return write_rgb8(path, width, height, rgb.data(), rgb.size());
}

std::string write_rgb8(const std::string& path, int width, int height, const std::uint8_t* rgb, std::size_t size) {
    if (width < 1 || height < 1 || size != std::size_t(width) * std::size_t(height) * 3)
        return "internal error: the image data does not match its size";
    switch (format_from_path(path)) {
        case ImageFormat::Ppm:
            return write_file_atomic(path, {ppm_header(width, height),
                                            {reinterpret_cast<const char*>(rgb), size}});
        case ImageFormat::Png: {
            if (std::size_t(width) * 3 > std::size_t(INT_MAX) / std::size_t(height))
                return "the picture is too large for a PNG file";
            std::string png;
            if (!stbi_write_png_to_func(append_bytes, &png, width, height, 3, rgb, width * 3))
                return "PNG encoding failed";
            return write_file_atomic(path, png);
        }
        case ImageFormat::Unknown:
            break;
    }
    return "unknown image format: the file name must end in .ppm or .png";
}

std::string write_file_atomic(const std::string& path, const std::string& data) {
    return write_file_atomic(path, {std::string_view(data)});
}

std::string write_file_atomic(const std::string& path_in, std::initializer_list<std::string_view> parts) {
    if (path_in.empty()) return "no file name given";
    // Replace what a symbolic link points to, not the link itself.
    std::string path = path_in;
    struct stat st;
    if (::lstat(path.c_str(), &st) == 0 && S_ISLNK(st.st_mode)) {
        if (char* real = ::realpath(path.c_str(), nullptr)) {
            path = real;
            std::free(real);
        }
    }
    const bool exists = ::stat(path.c_str(), &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) return errno_text(EISDIR);
    if (exists && !S_ISREG(st.st_mode)) return write_in_place(path, parts);

    // The temporary file must be in the target's folder: rename() is atomic only
    // within one file system.
    const std::size_t slash = path.find_last_of('/');
    const std::string dir = slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
    const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
    std::string tmp = dir + "." + name + ".XXXXXX";
    const int fd = ::mkostemp(tmp.data(), O_CLOEXEC);
    if (fd < 0) return errno_text(errno);

    // mkstemp makes the file 0600; give it the mode the file has now, or the mode
    // a newly created file would get.
    const mode_t mode = exists ? (st.st_mode & 07777) : (0666 & ~current_umask());
    int err = 0;
    if (::fchmod(fd, mode) != 0) err = errno;
    if (!err) err = write_parts(fd, parts);
    // Without fsync a crash soon after the rename can leave an empty file under the
    // target's name; fsync is also where some file systems first report a full disk.
    if (!err && ::fsync(fd) != 0) err = errno;
    if (::close(fd) != 0 && !err) err = errno;
    if (!err && ::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
    if (err) {
        ::unlink(tmp.c_str());
        return errno_text(err);
    }
    // Make the rename itself durable; the new file is already in place, so a
    // failure here is not worth reporting.
    const int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        ::fsync(dfd);
        ::close(dfd);
    }
    return {};
}

std::string read_file(const std::string& path, std::string& out, std::size_t max_bytes) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return errno_text(errno);
    auto fail = [&](std::string msg) {
        ::close(fd);
        out.clear();
        return msg;
    };
    auto too_big = [&] { return fail("the file is larger than " + std::to_string(max_bytes) + " bytes"); };
    struct stat st;
    if (::fstat(fd, &st) != 0) return fail(errno_text(errno));
    if (S_ISDIR(st.st_mode)) return fail(errno_text(EISDIR));
    if (S_ISREG(st.st_mode)) {
        if (std::size_t(st.st_size) > max_bytes) return too_big();
        out.reserve(std::size_t(st.st_size));
    }
    // Read to end of file rather than trusting st_size: pipes and /proc files have
    // none, and a file may grow while it is read.
    out.clear();
    char buf[65536];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0) {
            if (errno == EINTR) continue;
            return fail(errno_text(errno));
        }
        if (n == 0) break;
        if (out.size() + std::size_t(n) > max_bytes) return too_big();
        out.append(buf, std::size_t(n));
    }
    ::close(fd);
    return {};
}

std::string read_ppm(const std::string& path, int& width, int& height, std::vector<std::uint8_t>& rgb) {
    std::string data;
    // A P3 file of the largest picture the format allows is about 3 GiB; tests and
    // tools compare far smaller ones.
    if (std::string err = read_file(path, data, std::size_t(1) << 30); !err.empty()) return err;
    if (data.size() < 2 || data[0] != 'P' || (data[1] != '3' && data[1] != '6'))
        return "not a PPM file (expected P3 or P6)";
    const bool binary = data[1] == '6';
    std::size_t i = 2;
    long w = 0, h = 0, maxval = 0;
    if (!ppm_number(data, i, w) || !ppm_number(data, i, h) || !ppm_number(data, i, maxval))
        return "malformed PPM header";
    if (w < 1 || h < 1 || w > 65536 || h > 65536 || maxval < 1 || maxval > 65535)
        return "unsupported PPM size or maximum value";
    const std::size_t samples = std::size_t(w) * std::size_t(h) * 3;
    // Every sample takes at least a byte of the file: check before allocating.
    if (samples > data.size() - i) return "PPM pixel data is truncated";
    std::vector<std::uint8_t> px(samples);
    // Samples are rescaled to 0..255, so only maxval 255 is lossless.
    auto scale = [&](long v) { return std::uint8_t((v * 255 + maxval / 2) / maxval); };
    if (binary) {
        // Exactly one whitespace byte separates the header from the raster.
        if (i >= data.size() || !std::isspace(static_cast<unsigned char>(data[i]))) return "malformed PPM header";
        ++i;
        const std::size_t bytes_per_sample = maxval > 255 ? 2 : 1;
        if (data.size() - i < samples * bytes_per_sample) return "PPM pixel data is truncated";
        for (std::size_t k = 0; k < samples; ++k) {
            long v = static_cast<unsigned char>(data[i + k * bytes_per_sample]);
            if (bytes_per_sample == 2) v = v * 256 + static_cast<unsigned char>(data[i + 2 * k + 1]);
            if (v > maxval) return "PPM sample larger than the maximum value";
            px[k] = scale(v);
        }
    } else {
        for (std::size_t k = 0; k < samples; ++k) {
            long v = 0;
            if (!ppm_number(data, i, v)) return "PPM pixel data is truncated or malformed";
            if (v > maxval) return "PPM sample larger than the maximum value";
            px[k] = scale(v);
        }
    }
    width = int(w);
    height = int(h);
    rgb = std::move(px);
    return {};
}

}  // namespace rt
