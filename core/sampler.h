// The random numbers of a pixel's samples (docs/rendering.md §11): for the lens and the
// sphere lights (the New: `aperture` and `radius` keys). Sample s of pixel (x, y) takes its points from an
// Owen-scrambled Sobol sequence, shuffled and scrambled per pixel and per dimension
// (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020): the samples of one pixel
// are stratified over the lens disc and over each light, neighbouring pixels use
// unrelated patterns, and every point depends only on (x, y, s, dimension), never on
// the thread, the tile order or the MPI rank that traces it.
#pragma once

#include <cmath>
#include <cstdint>

namespace rt {

// Which sample of which pixel a camera ray is.
struct PixelSample {
    int x = 0, y = 0;
    int s = 0;
};

namespace sampling {

inline std::uint32_t reverse_bits(std::uint32_t v) {
    v = __builtin_bswap32(v);  // the bytes reversed, then the bits within each
    v = ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    return ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
}

// A nested scramble of a 32-bit integer: bit k of the result is bit k of x flipped by a
// function of x's bits below k, the function chosen by the seed (x + seed, times an odd
// number taken from the seed's high half; both keep the low bits' dependence on low bits
// only). Applied to a reversed fraction, it is an Owen scramble: each bit flipped by a
// hash of the bits above it. One multiplication where Laine and Karras' hash takes four,
// for the same stratification and about the same error (bench/README.md, "Realism,
// round 4").
inline std::uint32_t nested_scramble(std::uint32_t x, std::uint32_t seed) { return (x + seed) * ((seed >> 16) | 1u); }

inline std::uint32_t hash(std::uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

inline std::uint32_t combine(std::uint32_t seed, std::uint32_t v) { return hash(seed ^ (v + 0x9e3779b9u + (seed << 6))); }

// The first two Sobol dimensions of index i, as 32-bit fractions.
inline std::uint32_t sobol0(std::uint32_t i) { return reverse_bits(i); }
// Sobol dimension 1 is linear over GF(2) in the index's bits: the sum (xor) of one
// column per set bit, column k being (I + S)^k of the top bit (S: a shift right).
inline std::uint32_t sobol1_slow(std::uint32_t i) {
    std::uint32_t r = 0;
    for (std::uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
        if (i & 1) r ^= v;
    return r;
}
// The same, bit-reversed: bit j is the sum of the index's bits k whose binomial C(k, j)
// is odd, i.e. (Lucas) whose bit set holds j's: the superset sum over the five bits of
// a bit's number, one shift a bit.
inline std::uint32_t sobol1_reversed(std::uint32_t i) {
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0F0F0F0Fu;
    i ^= (i >> 8) & 0x00FF00FFu;
    i ^= (i >> 16) & 0x0000FFFFu;
    return i;
}
inline std::uint32_t sobol1(std::uint32_t i) { return reverse_bits(sobol1_reversed(i)); }

inline double fraction(std::uint32_t v) { return double(v) * (1.0 / 4294967296.0); }

// cos and sin of the angle 2 pi v, for v in [0, 1], within 1e-13: a quarter turn is
// taken out (v's nearest multiple of 1/4), and what is left (at most pi / 4) goes
// through the Taylor series to x^13 and x^14. Plain products and sums, so that the
// AVX2 path (shade_avx2.cpp) gets the same bits four at a time; std::sin and std::cos
// would cost a library call each for more precision than a sample needs.
constexpr double kTurnSin[7] = {1.0, -1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880, -1.0 / 39916800,
                                1.0 / 6227020800};
constexpr double kTurnCos[8] = {1.0, -1.0 / 2, 1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800,
                                1.0 / 479001600, -1.0 / 87178291200};
constexpr double kTwoPi = 6.283185307179586476925;
inline void cos_sin_turn(double v, double& c, double& s) {
    const double q = std::nearbyint(v * 4);
    const double x = (v - q * 0.25) * kTwoPi, x2 = x * x;
    double ps = kTurnSin[6], pc = kTurnCos[7];
    for (int i = 5; i >= 0; --i) ps = kTurnSin[i] + x2 * ps;
    for (int i = 6; i >= 0; --i) pc = kTurnCos[i] + x2 * pc;
    const double sx = x * ps;
    const int quarter = int(q) & 3;
    c = quarter & 1 ? sx : pc;
    s = quarter & 1 ? pc : sx;
    if (quarter == 1 || quarter == 2) c = -c;
    if (quarter >= 2) s = -s;
}

}  // namespace sampling

// The 2D points of one camera ray's path: next() gives dimension 0, 1, 2, ... in turn
// (the lens first, then one per sphere light met on the path, in the tracer's order).
class PathSampler {
public:
    PathSampler() = default;
    explicit PathSampler(const PixelSample& p) : PathSampler(p, row_hash(p.y)) {}
    // The same with row = row_hash(p.y), for callers that make many of one row.
    PathSampler(const PixelSample& p, std::uint32_t row)
        : pixel_(sampling::hash(std::uint32_t(p.x) * 0x8da6b343u ^ row)),
          rindex_(sampling::reverse_bits(std::uint32_t(p.s))) {}
    static std::uint32_t row_hash(int y) { return sampling::hash(std::uint32_t(y) + 0x68e31da4u); }
    // A point of [0, 1)^2: Sobol dimensions 0 and 1 of the shuffled index, each
    // Owen-scrambled. (Sobol dimension 0 is the bit reversal of the index, so its
    // scramble needs no reversal of its own: reverse(nested(reverse(reverse(i)))); the
    // scramble of dimension 1 starts from its reversal, sobol1_reversed().)
    void next(double& u, double& v) {
        using namespace sampling;
        const std::uint32_t seed = take_seed();
        const std::uint32_t i = reverse_bits(nested_scramble(rindex_, seed));  // shuffled
        u = fraction(reverse_bits(nested_scramble(i, seed ^ kSeedU)));
        v = fraction(reverse_bits(nested_scramble(sobol1_reversed(i), seed ^ kSeedV)));
    }
    // next()'s parts, for the AVX2 path that draws four samplers' points at once: the
    // next dimension's seed (one hash a dimension), what dimension d's seed hashes
    // (pixel() ^ d kGolden), the next dimension, the reversed sample number.
    std::uint32_t take_seed() { return sampling::hash(pixel_ ^ (dim_++ * kGolden)); }
    std::uint32_t pixel() const { return pixel_; }
    std::uint32_t dimension() const { return dim_; }
    void skip(std::uint32_t n) { dim_ += n; }
    std::uint32_t reversed_index() const { return rindex_; }
    static constexpr std::uint32_t kSeedU = 0xa511e9b3u, kSeedV = 0x63d83595u, kGolden = 0x9e3779b9u;

private:
    std::uint32_t pixel_ = 0, rindex_ = 0, dim_ = 0;
};

}  // namespace rt
