// Page faults taken ahead of time: a big buffer about to be written can have its
// first-touch faults (most of the cost of filling fresh memory) taken on two threads
// at once, before one thread writes it. And big scratch buffers of pages of their own,
// handed back to the system when freed.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <new>

#include "huge_pages.h"
#include "parallel.h"

namespace rt {

// Takes the first-touch faults of the whole pages in [p, p + n) now; the contents stay
// as they are. A hint: nothing happens where the system cannot do it.
inline void populate_pages(const void* p, std::size_t n) {
#if defined(MADV_POPULATE_WRITE)
    const std::uintptr_t page = std::uintptr_t(::sysconf(_SC_PAGESIZE));
    const std::uintptr_t b = (std::uintptr_t(p) + page - 1) & ~(page - 1), e = (std::uintptr_t(p) + n) & ~(page - 1);
    if (e > b) ::madvise(reinterpret_cast<void*>(b), e - b, MADV_POPULATE_WRITE);
#else
    (void)p;
    (void)n;
#endif
}

// The same with the upper half on another of the process pool's threads, in huge
// pages where the system has them.
inline void populate_pages_on_two_threads(const void* p, std::size_t n) {
    advise_huge_pages(p, n);
    const std::size_t half = n / 2;
    two_ways(true, [=](int part) {
        if (part == 0) populate_pages(p, half);
        else populate_pages(static_cast<const char*>(p) + half, n - half);
    });
}

// Scratch bytes in pages of their own (an anonymous mapping), handed back to the
// system when the buffer goes: the raytracer keeps freed heap memory for its next
// phase (app/raytracer.cpp), which would keep a big model's scratch (its file's text,
// the BVH build's records) resident beside everything that comes after it.
class PageBuffer {
public:
    PageBuffer() = default;
    // n bytes, zero; throws std::bad_alloc when they cannot be had.
    explicit PageBuffer(std::size_t n) : size_(n) {
        if (n == 0) return;
        void* p = ::mmap(nullptr, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) throw std::bad_alloc();
        data_ = static_cast<char*>(p);
    }
    PageBuffer(PageBuffer&& o) noexcept : data_(o.data_), size_(o.size_) { o.data_ = nullptr, o.size_ = 0; }
    PageBuffer& operator=(PageBuffer&& o) noexcept {
        if (this != &o) {
            reset();
            data_ = o.data_, size_ = o.size_;
            o.data_ = nullptr, o.size_ = 0;
        }
        return *this;
    }
    PageBuffer(const PageBuffer&) = delete;
    PageBuffer& operator=(const PageBuffer&) = delete;
    ~PageBuffer() { reset(); }

    char* data() const { return data_; }
    std::size_t size() const { return size_; }
    // Drops the bytes past the first n (n <= size()), handing back their whole pages.
    void shrink(std::size_t n) {
        if (n >= size_) return;
        const std::size_t page = std::size_t(::sysconf(_SC_PAGESIZE));
        const std::size_t keep = (n + page - 1) / page * page, mapped = (size_ + page - 1) / page * page;
        if (keep < mapped) ::munmap(data_ + keep, mapped - keep);
        size_ = n;
        if (n == 0) data_ = nullptr;
    }
    void reset() {
        if (data_) ::munmap(data_, size_);
        data_ = nullptr, size_ = 0;
    }

private:
    char* data_ = nullptr;
    std::size_t size_ = 0;
};

}  // namespace rt
