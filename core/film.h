// Float accumulation buffer: per-pixel colour sums and sample counts, plus a preview
// layer that coarse passes fill until the first full-resolution sample arrives, and
// for adaptive anti-aliasing the sums of squares that tell how a pixel's samples spread.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "huge_pages.h"
#include "math.h"

namespace rt {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  // linear colour, 3 floats per pixel, top row first
    Colour at(int x, int y) const {
        const float* p = &rgb[3 * (std::size_t(y) * width + x)];
        return {p[0], p[1], p[2]};
    }
};

// The original's output rounding (docs/rendering.md §9): truncation, clamped to 0..255; NaN gives 0.
// (Written as clamps of 255 c, which compile to min/max instead of branches.)
inline std::uint8_t to_byte(double c) {
    double v = 255.0 * c;
    v = v > 0 ? v : 0;  // also NaN
    v = v < 255 ? v : 255;
    return static_cast<std::uint8_t>(static_cast<int>(v));
}

// A zero-filled array of numbers. A big one is mapped straight from the system, so
// its pages are zero without anyone writing them, and touched first by the threads
// that fill them: not all up front by the one that allocates it. (calloc would do so
// only while the allocator hands big blocks back to the system; a program that keeps
// freed memory for reuse gets them memset.) Small ones come from calloc.
template <class T>
class ZeroedArray {
    static_assert(std::is_arithmetic_v<T>, "all-zero bytes must mean the value 0");
    static constexpr std::size_t kMapBytes = std::size_t(1) << 20;
    static constexpr std::size_t kHugeBytes = kHugePageBytes;

public:
    ZeroedArray() = default;
    explicit ZeroedArray(std::size_t n) { reset(n); }
    ZeroedArray(const ZeroedArray&) = delete;
    ZeroedArray& operator=(const ZeroedArray&) = delete;
    ~ZeroedArray() { release(); }

    // n zeros; the old contents are dropped.
    void reset(std::size_t n) {
        release();
        if (n == 0) return;
        if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
        const std::size_t bytes = n * sizeof(T);
        if (bytes >= kMapBytes) {
            mapped_bytes_ = map_size(bytes);
            p_ = static_cast<T*>(map(mapped_bytes_));
        } else {
            p_ = static_cast<T*>(std::calloc(n, sizeof(T)));
            if (!p_) throw std::bad_alloc();
        }
        n_ = n;
    }
    void swap(ZeroedArray& o) noexcept {
        std::swap(p_, o.p_);
        std::swap(n_, o.n_);
        std::swap(mapped_bytes_, o.mapped_bytes_);
    }
    // Takes over the memory of `from` (which is left empty) as n elements of T: for
    // results made in place of the numbers they came from, without fresh pages.
    template <class U>
    void adopt(ZeroedArray<U>& from, std::size_t n) {
        static_assert(alignof(T) <= alignof(U), "the memory must be aligned for T");
        if (n > from.n_ * sizeof(U) / sizeof(T)) throw std::length_error("ZeroedArray::adopt: too many elements");
        release();
        p_ = reinterpret_cast<T*>(from.p_);
        n_ = p_ ? n : 0;
        mapped_bytes_ = from.mapped_bytes_;
        from.p_ = nullptr;
        from.n_ = 0;
        from.mapped_bytes_ = 0;
    }
    std::size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
    T* data() { return p_; }
    const T* data() const { return p_; }
    T& operator[](std::size_t i) { return p_[i]; }
    const T& operator[](std::size_t i) const { return p_[i]; }
    T* begin() { return p_; }
    T* end() { return p_ + n_; }
    const T* begin() const { return p_; }
    const T* end() const { return p_ + n_; }

private:
    template <class>
    friend class ZeroedArray;
    // The length mapped for `bytes`: from kHugeBytes on, whole huge pages, so that
    // the last part is one huge page too (faulted at once) instead of up to 511 small
    // ones; what lies past `bytes` is never written, and the kernel does not tell
    // the two apart when it backs the page.
    static std::size_t map_size(std::size_t bytes) {
        if (bytes < kHugeBytes) return bytes;
        if (bytes > std::size_t(-1) - kHugeBytes) throw std::bad_alloc();
        return (bytes + kHugeBytes - 1) & ~(kHugeBytes - 1);
    }
    // Zeroed pages for `bytes`. From kHugeBytes on, they start on a huge-page boundary
    // and the kernel is asked to back them with huge pages: a film is read and written
    // row by row of tiles, each row on pages of its own, and in small pages the address
    // translations missed on nearly every row (a film at 1280x720 spans 4,000 of them).
    static void* map(std::size_t bytes) {
        const std::size_t span = bytes >= kHugeBytes ? bytes + kHugeBytes : bytes;
        void* p = ::mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        if (span == bytes) return p;
        // The mapping from the first boundary on, the pages around it given back.
        const std::uintptr_t base = reinterpret_cast<std::uintptr_t>(p);
        const std::uintptr_t start = (base + kHugeBytes - 1) & ~std::uintptr_t(kHugeBytes - 1);
        const std::uintptr_t page = std::uintptr_t(::sysconf(_SC_PAGESIZE));
        const std::uintptr_t end = start + ((bytes + page - 1) & ~(page - 1));
        if (start > base) ::munmap(p, start - base);
        if (base + span > end) ::munmap(reinterpret_cast<void*>(end), base + span - end);
        advise_huge_pages(reinterpret_cast<void*>(start), bytes, kHugeBytes);  // advice: small pages if refused
        return reinterpret_cast<void*>(start);
    }
    void release() {
        if (mapped_bytes_) ::munmap(p_, mapped_bytes_);
        else std::free(p_);
        p_ = nullptr;
        n_ = 0;
        mapped_bytes_ = 0;
    }
    T* p_ = nullptr;
    std::size_t n_ = 0;
    std::size_t mapped_bytes_ = 0;  // 0: from calloc
};

struct Film {
    int width = 0, height = 0;
    ZeroedArray<float> sum;  // 3 per pixel
    ZeroedArray<std::uint32_t> count;
    // Coarse previews: the colour of each block's corner pixel (the block's one ray),
    // shown while count == 0; empty if no coarse passes. Blocks are 2x2 or larger, so
    // every corner has even coordinates: 3 floats for each pixel of even x and y only,
    // at preview_index() (a quarter of the film's size, and a row's corners side by side).
    ZeroedArray<float> preview;
    int preview_level = 0;  // block size of the last complete coarse pass; 0 = none
    // Adaptive anti-aliasing only (core/adaptive.h), else empty: per pixel, the sum over
    // its samples of the squared colour channels, each clamped to 0..1. Valid where
    // count >= 2 (for one sample it is the sum's own square).
    ZeroedArray<float> squares;
    // An id pass only (RenderPass::Ids), else empty: per pixel, what its ray hit first
    // (rt::pick_id), where count is 1.
    ZeroedArray<std::uint32_t> ids;

    void reset(int w, int h, bool with_preview = true) {
        width = w;
        height = h;
        sum.reset(std::size_t(w) * h * 3);
        count.reset(std::size_t(w) * h);
        preview.reset(with_preview ? preview_size(w, h) : 0);
        preview_level = 0;
        squares.reset(0);
        ids.reset(0);
    }
    // The floats of a preview layer for a w x h film.
    static std::size_t preview_size(int w, int h) {
        return std::size_t((w + 1) / 2) * std::size_t((h + 1) / 2) * 3;
    }
    // Where the preview colour of pixel (x, y), both even, begins.
    std::size_t preview_index(int x, int y) const {
        return 3 * (std::size_t(y >> 1) * std::size_t((width + 1) >> 1) + std::size_t(x >> 1));
    }
    // Pixel (x, y); idx = y * width + x.
    Colour pixel(int x, int y, std::size_t idx) const {
        std::uint32_t n = count[idx];
        if (n == 0) {
            if (preview_level == 0 || preview.empty()) return {};
            int mask = ~(preview_level - 1);
            const float* p = &preview[preview_index(x & mask, y & mask)];
            return {p[0], p[1], p[2]};
        }
        if (n == 1) return {sum[3 * idx], sum[3 * idx + 1], sum[3 * idx + 2]};
        double inv = 1.0 / n;
        return {sum[3 * idx] * inv, sum[3 * idx + 1] * inv, sum[3 * idx + 2] * inv};
    }
    // f(idx, colour) for every pixel of rows [y0, y1).
    template <class F>
    void for_each_pixel(int y0, int y1, F&& f) const {
        for (int y = y0; y < y1; ++y) {
            std::size_t idx = std::size_t(y) * width;
            for (int x = 0; x < width; ++x, ++idx) f(idx, pixel(x, y, idx));
        }
    }
    Image resolve() const {
        Image img;
        img.width = width;
        img.height = height;
        img.rgb.resize(std::size_t(width) * height * 3);
        for_each_pixel(0, height, [&](std::size_t i, const Colour& c) {
            img.rgb[3 * i] = float(c.x);
            img.rgb[3 * i + 1] = float(c.y);
            img.rgb[3 * i + 2] = float(c.z);
        });
        return img;
    }
};

}  // namespace rt
