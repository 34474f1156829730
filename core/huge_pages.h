// Huge pages for big buffers: a buffer of many megabytes written for the first time
// takes a page fault every 4 KB, and on virtual machines a fault costs much more than
// the write (the 1M-sphere grid's compile spent more time in faults than in its own
// code). Backed by 2 MB pages it takes one fault per 2 MB and fewer TLB misses after.
#pragma once

#include <sys/mman.h>

#include <cstddef>
#include <cstdint>

namespace rt {

constexpr std::size_t kHugePageBytes = std::size_t(2) << 20;  // x86-64's huge page

// Asks the system to back the whole 2 MB pages inside [p, p + n) with huge pages (a
// hint: nothing changes where it cannot, or when n is under min_bytes: by default 4 MB,
// where an unaligned buffer is sure to hold a whole one). Call it before the buffer is
// first written.
inline void advise_huge_pages(const void* p, std::size_t n, std::size_t min_bytes = 2 * kHugePageBytes) {
#if defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t kHuge = kHugePageBytes;
    if (n < min_bytes) return;
    const std::uintptr_t b = (std::uintptr_t(p) + kHuge - 1) & ~(kHuge - 1);
    const std::uintptr_t e = (std::uintptr_t(p) + n) & ~(kHuge - 1);
    if (e > b) ::madvise(reinterpret_cast<void*>(b), e - b, MADV_HUGEPAGE);
#else
    (void)p;
    (void)n;
    (void)min_bytes;
#endif
}

}  // namespace rt
