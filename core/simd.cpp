// Run-time choice of the kernels' instruction set (see simd.h).
#include "simd.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rt {

bool isa_supported(Isa isa) {
    if (isa == Isa::Sse2) return true;
#if RT_HAVE_AVX2_KERNELS
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}

namespace {
Isa initial_isa() {
    Isa best = isa_supported(Isa::Avx2) ? Isa::Avx2 : Isa::Sse2;
    const char* forced = std::getenv("RT_ISA");
    if (!forced || !*forced) return best;
    if (std::strcmp(forced, "sse2") == 0) return Isa::Sse2;
    if (std::strcmp(forced, "avx2") == 0 && isa_supported(Isa::Avx2)) return Isa::Avx2;
    std::fprintf(stderr, "warning: RT_ISA=%s is not a path this processor runs (sse2%s); using %s\n", forced,
                 isa_supported(Isa::Avx2) ? ", avx2" : "", isa_name(best));
    return best;
}
}  // namespace

namespace detail {
std::atomic<bool> g_avx2{initial_isa() == Isa::Avx2};
}

Isa active_isa() { return avx2_active() ? Isa::Avx2 : Isa::Sse2; }

bool set_isa(Isa isa) {
    if (!isa_supported(isa)) return false;
    detail::g_avx2.store(isa == Isa::Avx2);
    return true;
}

const char* isa_name(Isa isa) { return isa == Isa::Avx2 ? "avx2" : "sse2"; }

}  // namespace rt
