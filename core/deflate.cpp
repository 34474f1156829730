// The fast DEFLATE encoder (deflate.h). A block is coded in two passes: the first
// finds the repeats and counts the symbols, the second writes them with Huffman codes
// built from those counts (lengths limited to 15 bits as the format requires, the
// literal/length code's by the method of the JPEG standard's Annex K.3). Distances
// are only ever 1 and 3, so their code is fixed: two codes of one bit each.
#include "deflate.h"

#include <algorithm>
#include <cstring>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rt {

namespace {

constexpr int kLitCodes = 286;  // 256 literals, end of block, 29 lengths
constexpr int kEndOfBlock = 256;
constexpr int kClCodes = 19;  // the code of the code lengths
constexpr std::uint32_t kRepeat = 1u << 31, kPixelBack = 1u << 9;
constexpr unsigned kMaxRepeat = 258;

// RFC 1951 3.2.5: the lengths 3..258 as 29 codes (from 257) with extra bits.
constexpr unsigned kLengthBase[29] = {3,  4,  5,  6,  7,  8,  9,  10, 11,  13,  15,  17,  19,  23, 27,
                                      31, 35, 43, 51, 59, 67, 83, 99, 115, 131, 163, 195, 227, 258};
constexpr unsigned kLengthExtra[29] = {0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2,
                                       2, 3, 3, 3, 3, 4, 4, 4, 4, 5, 5, 5, 5, 0};
// RFC 1951 3.2.7: the order in which the code lengths' own code lengths are sent.
constexpr int kClOrder[kClCodes] = {16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15};

// Length -> its code's index (0..28).
struct LengthCodes {
    std::uint8_t index[kMaxRepeat + 1] = {};
    LengthCodes() {
        for (int c = 0; c < 29; ++c)
            for (unsigned l = kLengthBase[c]; l < (c == 28 ? 259 : kLengthBase[c + 1]); ++l) index[l] = std::uint8_t(c);
    }
};
const LengthCodes& length_codes() {
    static const LengthCodes table;
    return table;
}

// How many bytes from in[i] on repeat the bytes d back (at most 258, within [0, n)).
unsigned repeat(const std::uint8_t* in, std::size_t i, std::size_t n, std::size_t d) {
    const std::size_t most = std::min<std::size_t>(kMaxRepeat, n - i);
    std::size_t k = 0;
#if defined(__GNUC__) && defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    for (; k + 8 <= most; k += 8) {
        std::uint64_t a, b;
        std::memcpy(&a, in + i + k, 8);
        std::memcpy(&b, in + i + k - d, 8);
        if (a != b) return unsigned(k + std::size_t(__builtin_ctzll(a ^ b)) / 8);
    }
#endif
    while (k < most && in[i + k] == in[i + k - d]) ++k;
    return unsigned(k);
}

}  // namespace

void huffman_code_lengths(const std::uint32_t* freq, int n, int limit, std::uint8_t* lengths) {
    std::fill(lengths, lengths + n, std::uint8_t(0));
    std::pair<std::uint32_t, int> sym[kLitCodes];
    int m = 0;
    for (int i = 0; i < n; ++i)
        if (freq[i]) sym[m++] = {freq[i], i};
    if (m < 2) {
        // One symbol (or none): two codes of one bit, the second never used.
        const int s = m ? sym[0].second : 0;
        lengths[s] = lengths[s == 0 ? 1 : 0] = 1;
        return;
    }
    std::sort(sym, sym + m);
    // The tree, from two queues in increasing weight: the leaves, and the nodes made.
    std::uint64_t weight[2 * kLitCodes];
    int parent[2 * kLitCodes], depth[2 * kLitCodes];
    for (int k = 0; k < m; ++k) weight[k] = sym[k].first;
    int leaf = 0, node = m, next = m;
    auto lightest = [&] { return leaf < m && (node >= next || weight[leaf] <= weight[node]) ? leaf++ : node++; };
    for (; next < 2 * m - 1; ++next) {
        const int a = lightest(), b = lightest();
        weight[next] = weight[a] + weight[b];
        parent[a] = parent[b] = next;
    }
    depth[2 * m - 2] = 0;
    for (int k = 2 * m - 3; k >= 0; --k) depth[k] = depth[parent[k]] + 1;
    int count[kLitCodes] = {};
    int longest = 0;
    for (int k = 0; k < m; ++k) ++count[depth[k]], longest = std::max(longest, depth[k]);
    // Too long: move codes up, keeping the code complete (JPEG, Annex K.3).
    for (int i = longest; i > limit; --i)
        while (count[i] > 0) {
            int j = i - 2;
            while (count[j] == 0) --j;
            count[i] -= 2, count[i - 1] += 1, count[j + 1] += 2, count[j] -= 1;
        }
    // The shortest lengths to the most frequent symbols.
    int k = m - 1;
    for (int len = 1; len <= limit; ++len)
        for (int c = 0; c < count[len]; ++c) lengths[sym[k--].second] = std::uint8_t(len);
}

namespace {

// The canonical codes of RFC 1951 3.2.2 for the lengths, bit-reversed (the format
// sends a code's bits from its first, the writer fills from the lowest).
void canonical_codes(const std::uint8_t* lengths, int n, std::uint16_t* codes) {
    int count[16] = {}, next[16] = {};
    for (int i = 0; i < n; ++i) ++count[lengths[i]];
    count[0] = 0;
    for (int b = 1, code = 0; b < 16; ++b) next[b] = code = (code + count[b - 1]) << 1;
    for (int i = 0; i < n; ++i) {
        if (!lengths[i]) continue;
        unsigned v = unsigned(next[lengths[i]]++), r = 0;
        for (int b = 0; b < lengths[i]; ++b, v >>= 1) r = (r << 1) | (v & 1);
        codes[i] = std::uint16_t(r);
    }
}

// The code lengths of a block header as RFC 1951 3.2.7 sends them: each symbol (0-15
// a length, 16 the last length again 3-6 times, 17 and 18 zeros 3-10 and 11-138 times)
// with its extra bits' value, as symbol | value << 8.
int run_length_code(const std::uint8_t* all, int n, std::uint16_t* out, std::uint32_t* freq) {
    int m = 0;
    auto add = [&](int sym, int value) { out[m++] = std::uint16_t(sym | value << 8), ++freq[sym]; };
    for (int i = 0; i < n;) {
        const int v = all[i];
        int run = 1;
        while (i + run < n && all[i + run] == v) ++run;
        i += run;
        if (v == 0) {
            for (; run >= 11; run -= std::min(run, 138)) add(18, std::min(run, 138) - 11);
            if (run >= 3) add(17, run - 3), run = 0;
        } else {
            add(v, 0), --run;
            for (; run >= 3; run -= std::min(run, 6)) add(16, std::min(run, 6) - 3);
        }
        for (; run > 0; --run) add(v, 0);
    }
    return m;
}

}  // namespace

struct DeflateWriter::Codes {
    std::uint8_t length[kLitCodes];
    std::uint16_t code[kLitCodes] = {};
};

// The three bytes at p, as one number (p[3] must be readable too).
inline std::uint32_t three(const std::uint8_t* p) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    return v & 0xffffff;
#else
    return std::uint32_t(p[0]) | p[1] << 8 | p[2] << 16;
#endif
}

void DeflateWriter::tokenize(const std::uint8_t* in, std::size_t n, std::uint32_t* freq) {
    const LengthCodes& lc = length_codes();
    std::uint32_t* t = tokens_.room(n + 1);
    for (std::size_t i = 0; i < n;) {
        // A repeat is worth a token from three bytes on: compare three at once.
        unsigned best = 0;
        std::uint32_t back = 0;
        if (i >= 3 && i + 4 <= n) {
            const std::uint32_t here = three(in + i);
            if (here == three(in + i - 1)) best = repeat(in, i, n, 1);
            if (here == three(in + i - 3)) {
                const unsigned r = repeat(in, i, n, 3);
                if (r > best) best = r, back = kPixelBack;
            }
        }
        if (best >= 3) {
            *t++ = kRepeat | back | best;
            ++freq[257 + lc.index[best]];
            i += best;
        } else {
            *t++ = in[i];
            ++freq[in[i]];
            ++i;
        }
    }
    token_count_ = std::size_t(t - tokens_.data.get());
}

void DeflateWriter::header(const std::uint8_t* lit_lengths, int lit_count, bool last) {
    put(last ? 1 : 0, 1);
    put(2, 2);  // dynamic Huffman codes
    // Both codes' lengths in one run: the literals and lengths, then the distances 1
    // (code 0) and 3 (code 2) with one bit each; distance 2 (code 1) never comes.
    std::uint8_t all[kLitCodes + 3];
    std::copy(lit_lengths, lit_lengths + lit_count, all);
    all[lit_count] = 1, all[lit_count + 1] = 0, all[lit_count + 2] = 1;
    std::uint16_t symbols[kLitCodes + 3];
    std::uint32_t freq[kClCodes] = {};
    const int m = run_length_code(all, lit_count + 3, symbols, freq);
    std::uint8_t cl_length[kClCodes];
    std::uint16_t cl_code[kClCodes] = {};
    huffman_code_lengths(freq, kClCodes, 7, cl_length);
    canonical_codes(cl_length, kClCodes, cl_code);
    int hclen = kClCodes;
    while (hclen > 4 && cl_length[kClOrder[hclen - 1]] == 0) --hclen;
    put(unsigned(lit_count - 257), 5);
    put(3 - 1, 5);
    put(unsigned(hclen - 4), 4);
    for (int k = 0; k < hclen; ++k) put(cl_length[kClOrder[k]], 3);
    constexpr unsigned kExtraBits[3] = {2, 3, 7};  // of symbols 16, 17, 18
    for (int k = 0; k < m; ++k) {
        const int sym = symbols[k] & 0xff;
        put(cl_code[sym], cl_length[sym]);
        if (sym >= 16) put(unsigned(symbols[k] >> 8), kExtraBits[sym - 16]);
    }
}

void DeflateWriter::emit(const Codes& lit) {
    const LengthCodes& lc = length_codes();
    // A literal's code and length in one word: one load for the most frequent token.
    std::uint32_t literal[256];
    for (int k = 0; k < 256; ++k) literal[k] = lit.code[k] | std::uint32_t(lit.length[k]) << 16;
    for (const std::uint32_t* p = tokens_.data.get(), *end = p + token_count_; p < end; ++p) {
        const std::uint32_t t = *p;
        if (!(t & kRepeat)) {
            put(literal[t] & 0xffff, literal[t] >> 16);
            continue;
        }
        // The length's code, its extra bits and the distance's one bit, in one go.
        const unsigned len = t & 0x1ff, c = lc.index[len], s = 257 + c, code_bits = lit.length[s];
        const std::uint64_t extra = len - kLengthBase[c], far = (t & kPixelBack) ? 1 : 0;
        put(lit.code[s] | extra << code_bits | far << (code_bits + kLengthExtra[c]), code_bits + kLengthExtra[c] + 1);
    }
    put(lit.code[kEndOfBlock], lit.length[kEndOfBlock]);
}

void DeflateWriter::block(const std::uint8_t* in, std::size_t n, bool last) {
    std::uint32_t freq[kLitCodes] = {};
    tokenize(in, n, freq);
    freq[kEndOfBlock] = 1;
    Codes lit;
    huffman_code_lengths(freq, kLitCodes, 15, lit.length);
    canonical_codes(lit.length, kLitCodes, lit.code);
    int lit_count = kLitCodes;
    while (lit_count > 257 && lit.length[lit_count - 1] == 0) --lit_count;
    // Room for the worst case: a header of at most 600 bytes, 15 bits a literal.
    char* const start = at_ = bytes_.room(2 * n + 1024);
    header(lit.length, lit_count, last);
    emit(lit);
    out_.append(start, std::size_t(at_ - start));
}

void DeflateWriter::finish(bool after_last) {
    char* const start = at_ = bytes_.room(16);
    if (!after_last) {
        // An empty stored block: its header, then padding to a byte, then LEN 0, NLEN ~0.
        put(0, 3);
        put(0, (8 - count_ % 8) % 8);
        put(0xffff0000u, 32);
    }
    for (; count_ > 0; count_ = count_ > 8 ? count_ - 8 : 0, bits_ >>= 8) *at_++ = char(bits_ & 0xff);
    bits_ = 0;
    out_.append(start, std::size_t(at_ - start));
}

std::uint32_t adler32_update(std::uint32_t adler, const std::uint8_t* p, std::size_t n) {
    constexpr std::uint32_t kBase = 65521;
    std::uint64_t s1 = adler & 0xffff, s2 = adler >> 16;
#if defined(__SSE2__)
    // A block of k 16-byte chunks b: s2 += 16 k s1 + 16 (the sums of the chunks before
    // each) + sum (16 - i) b_i; s1 += sum b_i. Blocks of at most 5552 bytes keep the
    // 32-bit lanes from overflowing, as zlib's NMAX does.
    const __m128i zero = _mm_setzero_si128();
    const __m128i high = _mm_setr_epi16(16, 15, 14, 13, 12, 11, 10, 9), low = _mm_setr_epi16(8, 7, 6, 5, 4, 3, 2, 1);
    while (n >= 16) {
        const std::size_t k = std::min<std::size_t>(n, 5552) / 16;
        __m128i sums = zero, before = zero, weighted = zero;
        for (std::size_t j = 0; j < k; ++j, p += 16) {
            const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
            before = _mm_add_epi32(before, sums);
            sums = _mm_add_epi32(sums, _mm_sad_epu8(b, zero));
            weighted = _mm_add_epi32(weighted, _mm_madd_epi16(_mm_unpacklo_epi8(b, zero), high));
            weighted = _mm_add_epi32(weighted, _mm_madd_epi16(_mm_unpackhi_epi8(b, zero), low));
        }
        alignas(16) std::uint32_t a[4], c[4], w[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(a), sums);
        _mm_store_si128(reinterpret_cast<__m128i*>(c), before);
        _mm_store_si128(reinterpret_cast<__m128i*>(w), weighted);
        s2 += 16 * (k * s1 + std::uint64_t(c[0]) + c[2]) + std::uint64_t(w[0]) + w[1] + w[2] + w[3];
        s1 += std::uint64_t(a[0]) + a[2];
        s1 %= kBase, s2 %= kBase;
        n -= 16 * k;
    }
#endif
    for (; n > 0; --n) s1 += *p++, s2 += s1, s1 %= kBase, s2 %= kBase;
    return std::uint32_t(s2 << 16 | s1);
}

}  // namespace rt
