// Tests for the shared arrays of core/chunked.h: a copy shares every chunk, a write
// copies only its own chunk and never shows in the other array, and random sequences
// of operations on copies agree with plain vectors.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "chunked.h"
#include "test_random.h"

using namespace rt;
using rt_test::Rng;

namespace {

template <class A>
std::vector<std::uint64_t> contents(const A& a) {
    std::vector<std::uint64_t> v;
    for (std::size_t i = 0; i < a.size(); ++i) v.push_back(a[i]);
    return v;
}

}  // namespace

TEST_CASE("chunked: a copy shares every chunk; a write copies only its chunk and leaves the other array alone") {
    using A = Chunked<std::uint64_t>;
    const std::size_t n = 10 * A::kChunk + 17;
    A a;
    a.reserve(n);
    for (std::size_t i = 0; i < n; ++i) a.push_back(i * 3);
    REQUIRE(a.flat() != nullptr);  // one block: read as one
    A b = a;
    for (std::size_t c = 0; c < a.chunk_count(); ++c) CHECK(b.shares_chunk(a, c));
    const std::size_t i = 4 * A::kChunk + 5;
    b.write(i) = 7;
    CHECK(a[i] == i * 3);
    CHECK(b[i] == 7);
    for (std::size_t c = 0; c < a.chunk_count(); ++c) CHECK(b.shares_chunk(a, c) == (c != 4));
    CHECK(a.flat() != nullptr);
    CHECK(b.flat() == nullptr);  // its chunk 4 lies elsewhere now
    // Writing the same chunk again copies nothing more.
    const std::uint64_t* chunk4 = b.chunk(4);
    b.write(i + 1) = 8;
    CHECK(b.chunk(4) == chunk4);
    CHECK(a[i + 1] == (i + 1) * 3);
    // compact() puts the chunks back in one block.
    b.compact();
    CHECK(b.flat() != nullptr);
    CHECK(b[i] == 7);
    CHECK(b[i + 1] == 8);
    CHECK(b[n - 1] == (n - 1) * 3);
    // Once no other array holds a part of the block, it is this one's again: no copy.
    A c = a;
    a = A();
    const std::uint64_t* chunk2 = c.chunk(2);
    c.write(2 * A::kChunk) = 9;
    CHECK(c.chunk(2) == chunk2);
    CHECK(c.flat() != nullptr);
}

TEST_CASE("chunked: random pushes, writes, copies and resizes agree with vectors") {
    using A = Chunked<std::uint64_t>;
    Rng rng(41);
    std::vector<A> arrays(4);
    std::vector<std::vector<std::uint64_t>> want(4);
    for (int step = 0; step < 4000; ++step) {
        const std::size_t k = rng.index(arrays.size());
        A& a = arrays[k];
        std::vector<std::uint64_t>& w = want[k];
        switch (rng.index(6)) {
            case 0:
            case 1:
                for (std::size_t r = rng.index(3 * A::kChunk); r > 0; --r) {
                    w.push_back(rng.g());
                    a.push_back(w.back());
                }
                break;
            case 2:
                for (int r = 0; r < 20 && !w.empty(); ++r) {
                    const std::size_t i = rng.index(w.size());
                    w[i] = rng.g();
                    a.write(i) = w[i];
                }
                break;
            case 3: {  // a copy from another array
                const std::size_t from = rng.index(arrays.size());
                arrays[k] = arrays[from];
                want[k] = want[from];
                break;
            }
            case 4: {
                const std::size_t n = rng.index(w.size() + A::kChunk);
                w.resize(n);
                a.resize(n);
                break;
            }
            default:
                if (rng.uni() < 0.5) a.compact();
                else a.reserve(w.size() + rng.index(2 * A::kChunk));
                break;
        }
        for (std::size_t j = 0; j < arrays.size(); ++j) REQUIRE(contents(arrays[j]) == want[j]);
    }
}

TEST_CASE("shared arrays: a copy shares the whole array; a write copies it first") {
    Shared<std::uint32_t> a;
    for (std::uint32_t i = 0; i < 100; ++i) a.push_back(i);
    Shared<std::uint32_t> b = a;
    CHECK(b.shares(a));
    CHECK(b.data() == a.data());
    b.write(10) = 1000;
    CHECK(!b.shares(a));
    CHECK(a[10] == 10);
    CHECK(b[10] == 1000);
    const std::uint32_t* own = b.data();
    b.write(11) = 1001;  // b's own now: no copy
    CHECK(b.data() == own);
}
