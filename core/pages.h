// Page faults taken ahead of time: a big buffer about to be written can have its
// first-touch faults (most of the cost of filling fresh memory) taken on two threads
// at once, before one thread writes it.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <system_error>
#include <thread>

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

// The same with the upper half on another thread (when one can be had).
inline void populate_pages_on_two_threads(const void* p, std::size_t n) {
    const std::size_t half = n / 2;
    const void* upper = static_cast<const char*>(p) + half;
    std::thread t;
    try {
        t = std::thread([=] { populate_pages(upper, n - half); });
    } catch (const std::system_error&) {
    }
    populate_pages(p, t.joinable() ? half : n);
    if (t.joinable()) t.join();
}

}  // namespace rt
