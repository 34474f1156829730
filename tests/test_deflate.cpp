// Tests for core/deflate.cpp, the PNG encoder's DEFLATE writer: whatever it is given
// (nothing, one byte, runs, repeats of a pixel, noise, symbols so skewed that their
// Huffman codes must be cut to 15 bits, several blocks, two writers one after the
// other), zlib's inflate reads back exactly the bytes; and the code lengths it builds
// are complete prefix codes within the limit.
#include <doctest/doctest.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "deflate.h"

using namespace rt;

namespace {

// The raw DEFLATE data inflated by zlib (which checks every code and block); `n` is
// the expected size. Fails the test if zlib objects.
std::vector<std::uint8_t> inflate_raw(const std::string& data, std::size_t n) {
    z_stream z{};
    REQUIRE(inflateInit2(&z, -15) == Z_OK);
    std::vector<std::uint8_t> out(n + 16);
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z.avail_in = uInt(data.size());
    z.next_out = out.data();
    z.avail_out = uInt(out.size());
    const int rc = inflate(&z, Z_FINISH);
    CHECK(rc == Z_STREAM_END);
    CHECK(z.avail_in == 0);  // nothing after the final block
    out.resize(z.total_out);
    inflateEnd(&z);
    return out;
}

std::string compress(const std::vector<std::uint8_t>& in, std::size_t block) {
    std::string out;
    DeflateWriter w(out);
    std::size_t at = 0;
    do {
        const std::size_t n = std::min(block, in.size() - at);
        w.block(in.data() + at, n, at + n >= in.size());
        at += n;
    } while (at < in.size());
    w.finish(true);
    return out;
}

// Symbol counts in Fibonacci proportion: a Huffman tree as deep as there are symbols.
std::vector<std::uint8_t> fibonacci_bytes(int symbols, std::mt19937& rng) {
    std::vector<std::uint8_t> v;
    std::uint64_t a = 1, b = 1;
    for (int s = 0; s < symbols; ++s, b = a + b, a = b - a) v.insert(v.end(), std::size_t(a), std::uint8_t(s * 7));
    std::shuffle(v.begin(), v.end(), rng);
    return v;
}

}  // namespace

TEST_CASE("deflate: zlib reads back exactly what was written, for every kind of data") {
    std::mt19937 rng(11);
    std::vector<std::vector<std::uint8_t>> inputs;
    inputs.push_back({});
    inputs.push_back({42});
    inputs.push_back(std::vector<std::uint8_t>(1 << 20, 0));  // one long run
    std::vector<std::uint8_t> noise(300000), pixels, mixed, fib = fibonacci_bytes(27, rng);
    for (auto& b : noise) b = std::uint8_t(rng());
    for (int i = 0; i < 200000; ++i) pixels.push_back(std::uint8_t(i % 3 * 50 + i / 3000));  // pixel repeats
    for (int i = 0; i < 400000; ++i) mixed.push_back(std::uint8_t(i % 1000 < 300 ? 0 : i % 1000 < 600 ? rng() % 4 : rng()));
    inputs.push_back(noise);
    inputs.push_back(pixels);
    inputs.push_back(mixed);
    inputs.push_back(fib);
    for (const auto& in : inputs)
        for (std::size_t block : {std::size_t(1) << 17, std::size_t(1000), std::size_t(7)}) {
            if (block == 7 && in.size() > 50000) continue;
            CAPTURE(in.size());
            CAPTURE(block);
            const std::string out = compress(in, block);
            CHECK(inflate_raw(out, in.size()) == in);
        }
    // Runs and pixel repeats cost next to nothing.
    CHECK(compress(inputs[2], 1 << 17).size() < 3000);
    CHECK(compress(pixels, 1 << 17).size() < pixels.size() / 20);
}

TEST_CASE("deflate: a writer ended with a sync flush can be followed by another writer's blocks") {
    std::vector<std::uint8_t> a(5000), b(7000);
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = std::uint8_t(i * i % 13);
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = std::uint8_t(i % 256);
    std::string first, second;
    DeflateWriter wa(first), wb(second);
    wa.block(a.data(), a.size(), false);
    wa.finish(false);
    wb.block(b.data(), b.size(), true);
    wb.finish(true);
    std::vector<std::uint8_t> both = a;
    both.insert(both.end(), b.begin(), b.end());
    CHECK(inflate_raw(first + second, both.size()) == both);
}

TEST_CASE("deflate: Huffman code lengths are complete prefix codes within the limit") {
    std::mt19937 rng(3);
    for (int trial = 0; trial < 200; ++trial) {
        const int n = trial % 2 ? 286 : 19, limit = n == 19 ? 7 : 15;
        std::vector<std::uint32_t> freq(static_cast<std::size_t>(n));
        const int kind = trial % 4;
        std::uint32_t a = 1, b = 1;
        for (auto& f : freq) {
            // Random counts, many zeros, or Fibonacci counts (a tree as deep as n).
            f = kind == 0 ? rng() % 1000 : kind == 1 ? (rng() % 4 == 0 ? rng() % 50 : 0) : a;
            b = a + b, a = b - a;
            if (a > (1u << 30)) a = b = 1;
        }
        if (trial == 4) std::fill(freq.begin(), freq.end(), 0u), freq[5] = 9;  // a single symbol
        std::vector<std::uint8_t> len(static_cast<std::size_t>(n));
        huffman_code_lengths(freq.data(), n, limit, len.data());
        double kraft = 0;
        int coded = 0;
        for (int i = 0; i < n; ++i) {
            CAPTURE(trial);
            CHECK(len[i] <= limit);
            CHECK((freq[i] > 0) <= (len[i] > 0));  // every symbol used has a code
            if (len[i]) kraft += std::ldexp(1.0, -len[i]), ++coded;
            for (int j = 0; j < n; ++j)
                if (freq[i] > freq[j] && len[j] > 0) CHECK(len[i] <= len[j]);  // more frequent, no longer
        }
        CHECK(coded >= 2);
        CHECK(kraft == 1.0);  // complete: no code left over, none overlapping
    }
}

TEST_CASE("deflate: adler32_update gives zlib's Adler-32 for any length, start and bytes") {
    std::mt19937 rng(17);
    std::vector<std::uint8_t> data(40000);
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t n = trial < 40 ? std::size_t(trial) : rng() % data.size();
        const bool extreme = trial % 5 == 0;  // all 255: the sums' largest values
        for (std::size_t i = 0; i < n; ++i) data[i] = extreme ? 255 : std::uint8_t(rng());
        const std::uint32_t start = trial % 3 == 0 ? 1u : std::uint32_t(rng() % 65521) | std::uint32_t(rng() % 65521) << 16;
        CAPTURE(n);
        CAPTURE(start);
        CHECK(adler32_update(start, data.data(), n) == std::uint32_t(adler32(start, data.data(), uInt(n))));
    }
}
