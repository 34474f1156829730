// A fast DEFLATE (RFC 1951) encoder for the filtered rows of the PNG encoder (png.cpp).
// It looks for repeats only one byte and one pixel (three bytes) back, which is where
// a filtered rendering repeats itself (flat and evenly shaded regions), and codes each
// block with Huffman codes made for it: several times faster than zlib's fastest
// setting on such data, and about as small.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>

namespace rt {

// Huffman code lengths for the n (at most 286) symbols' counts, none longer than `limit` (too long
// ones are moved up as the JPEG standard's Annex K.3 does); a symbol without a count
// gets 0. At least two symbols get a length, so the code is always complete.
void huffman_code_lengths(const std::uint32_t* freq, int n, int limit, std::uint8_t* lengths);

// The Adler-32 checksum a zlib stream ends with: `adler` (1 to start) continued over
// p[0, n). The same as zlib's adler32(), 16 bytes at a time with SSE2 where there is.
std::uint32_t adler32_update(std::uint32_t adler, const std::uint8_t* p, std::size_t n);

class DeflateWriter {
public:
    // Appends to `out`.
    explicit DeflateWriter(std::string& out) : out_(out) {}

    // One block holding in[0, n) (its repeats reach back only within it); `last`: the
    // stream's final block.
    void block(const std::uint8_t* in, std::size_t n, bool last);
    // Ends the data on a byte boundary: after the final block, with padding bits;
    // otherwise with an empty stored block (a sync flush), after which the blocks of
    // another writer (the next strip of the picture) can follow.
    void finish(bool after_last);

private:
    struct Codes;
    void tokenize(const std::uint8_t* in, std::size_t n, std::uint32_t* freq);
    void header(const std::uint8_t* lit_lengths, int lit_count, bool last);
    void emit(const Codes& lit);
    void put(std::uint64_t bits, unsigned n) {
        bits_ |= bits << count_;
        count_ += n;
        if (count_ >= 32) {
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
            const std::uint32_t low = std::uint32_t(bits_);
            std::memcpy(at_, &low, 4);
            at_ += 4;
#else
            for (int k = 0; k < 4; ++k) *at_++ = char(bits_ >> (8 * k));
#endif
            bits_ >>= 32;
            count_ -= 32;
        }
    }

    // Space that is not zeroed first (a std::vector or std::string would write every
    // byte of it once more).
    template <class T>
    struct Scratch {
        std::unique_ptr<T[]> data;
        std::size_t capacity = 0;
        T* room(std::size_t n) {
            if (n > capacity) data.reset(new T[n]), capacity = n;
            return data.get();
        }
    };

    std::string& out_;
    Scratch<char> bytes_;  // a block's output, then appended to out_
    char* at_ = nullptr;   // where put() writes, in bytes_
    std::uint64_t bits_ = 0;
    unsigned count_ = 0;
    // Literals (< 256) and repeats (bit 31, the length in bits 0-8, bit 9 set for a
    // pixel back rather than a byte).
    Scratch<std::uint32_t> tokens_;
    std::size_t token_count_ = 0;
};

}  // namespace rt
