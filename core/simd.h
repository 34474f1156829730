// Which instruction set the wide kernels use, chosen at run time: the binary is built
// for SSE2 and carries AVX2 kernels (per-function target attributes, never FMA, so
// every path gives the same bits). RT_ISA=sse2 or RT_ISA=avx2 in the environment forces
// a path; set_isa() does the same for tests and benchmarks.
#pragma once

#include <atomic>

namespace rt {

enum class Isa { Sse2, Avx2 };

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__)) && defined(__SSE2__)
#define RT_HAVE_AVX2_KERNELS 1
#else
#define RT_HAVE_AVX2_KERNELS 0
#endif

// Whether this processor (and this build) can run the path.
bool isa_supported(Isa isa);
// The path in use: RT_ISA if set and supported, else the widest supported.
Isa active_isa();
// Forces a path; false (and no change) if it is not supported here. A BVH built
// before a change keeps its node width; compile the world again after switching.
bool set_isa(Isa isa);
const char* isa_name(Isa isa);

namespace detail {
extern std::atomic<bool> g_avx2;  // active_isa() == Isa::Avx2, read on every ray
}
inline bool avx2_active() { return detail::g_avx2.load(std::memory_order_relaxed); }

}  // namespace rt
