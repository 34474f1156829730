// An array kept in fixed-size chunks that copies of it share: copying one copies its
// table of chunks, not its elements, and writing an element first copies that
// element's chunk if another array still holds it (copy on write). A world made from
// another by a one-object edit shares every chunk but the few the edit wrote.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstring>
#include <functional>
#include <iterator>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#include "huge_pages.h"

namespace rt {

namespace detail {
// Chunks of about 64 KB: a one-element write copies that much, and a million
// elements need a table of a thousand or so chunks (which stays in the L1 cache).
constexpr unsigned chunk_shift(std::size_t element_bytes) {
    unsigned s = 6;
    while (s < 16 && (std::size_t(2) << s) * element_bytes <= 65536) ++s;
    return s;
}
}  // namespace detail

template <class T>
class Chunked {
    static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>,
                  "chunks are copied and freed as bytes");

public:
    static constexpr unsigned kShift = detail::chunk_shift(sizeof(T));
    static constexpr std::size_t kChunk = std::size_t(1) << kShift;
    static constexpr std::size_t kMask = kChunk - 1;

    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    // An array whose chunks lie one after the other (made in one block by reserve(), and
    // none copied since) is read as one: no load of its chunk's address.
    const T& operator[](std::size_t i) const { return flat_ ? flat_[i] : table_[i >> kShift][i & kMask]; }
    const T& back() const { return (*this)[size_ - 1]; }
    // All the elements, contiguous, or null when the chunks are apart.
    const T* flat() const { return flat_; }
    // The chunk table, for hot loops that keep it in a register (where flat() is null).
    T* const* table() const { return table_.data(); }

    // Element i for writing: its chunk is copied first when another array shares it.
    T& write(std::size_t i) { return write_chunk(i >> kShift)[i & kMask]; }

    // Room for n elements, in one block where the array is empty or is one block of its
    // own (whose chunks the array then reads as one; pages of a block never written
    // cost address space only).
    void reserve(std::size_t n) {
        if (n <= capacity()) return;
        if (owners_.empty() || (flat_ && unique(0))) return into_block(n);
        table_.reserve((n + kMask) >> kShift);
        owners_.reserve((n + kMask) >> kShift);
    }
    void push_back(const T& v) {
        if (size_ == capacity()) grow();
        else if (!unique(size_ >> kShift)) copy_chunk(size_ >> kShift);
        new (table_[size_ >> kShift] + (size_ & kMask)) T(v);
        ++size_;
    }
    // n elements; the new ones are T().
    void resize(std::size_t n) {
        if (n < size_) size_ = n;
        reserve(n);
        while (size_ < n) push_back(T());
    }
    void clear() {
        owners_.clear();
        table_.clear();
        size_ = last_capacity_ = block_refs_ = 0;
        block_ = {nullptr, nullptr};
        flat_ = nullptr;
    }
    // The elements in one block of their size, shared with no other array: read as
    // one again after writes copied chunks apart.
    void compact() {
        if (size_ == 0) return clear();
        into_block(size_);
    }
    void shrink_to_fit() {
        if (!flat_ || capacity() > size_) compact();
    }

    // The elements by chunks, for passes over all of them: chunk c holds elements
    // [c kChunk, c kChunk + chunk_size(c)) contiguously.
    std::size_t chunk_count() const { return (size_ + kMask) >> kShift; }
    std::size_t chunk_size(std::size_t c) const {
        const std::size_t left = size_ - (c << kShift);
        return left < kChunk ? left : kChunk;
    }
    const T* chunk(std::size_t c) const { return table_[c]; }
    T* write_chunk(std::size_t c) {
        if (!unique(c)) copy_chunk(c);
        return table_[c];
    }
    // Whether chunk c is the very same (shared) chunk in both arrays.
    bool shares_chunk(const Chunked& o, std::size_t c) const {
        return c < chunk_count() && c < o.chunk_count() && table_[c] == o.table_[c];
    }

    // Bytes of the chunks this array holds (shared or not).
    std::size_t memory_bytes() const {
        std::size_t b = table_.capacity() * sizeof(T*) + owners_.capacity() * sizeof(std::shared_ptr<T>);
        for (std::size_t c = 0; c < owners_.size(); ++c) b += chunk_capacity(c) * sizeof(T);
        return b;
    }

    std::vector<T> to_vector() const {
        std::vector<T> v;
        v.reserve(size_);
        for (std::size_t c = 0; c < chunk_count(); ++c) v.insert(v.end(), chunk(c), chunk(c) + chunk_size(c));
        return v;
    }

    class const_iterator {
    public:
        using iterator_category = std::forward_iterator_tag;
        using value_type = T;
        using difference_type = std::ptrdiff_t;
        using pointer = const T*;
        using reference = const T&;
        const_iterator(const Chunked* a, std::size_t i) : a_(a), i_(i) {}
        const T& operator*() const { return (*a_)[i_]; }
        const T* operator->() const { return &(*a_)[i_]; }
        const_iterator& operator++() {
            ++i_;
            return *this;
        }
        bool operator==(const const_iterator& o) const { return i_ == o.i_; }
        bool operator!=(const const_iterator& o) const { return i_ != o.i_; }

    private:
        const Chunked* a_;
        std::size_t i_;
    };
    const_iterator begin() const { return {this, 0}; }
    const_iterator end() const { return {this, size_}; }

private:
    // The elements moved into a new block of room n (>= size_), every chunk of it this
    // array's.
    void into_block(std::size_t n) {
        Chunked old = std::move(*this);
        clear();
        T* block = static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(alignof(T))));
        advise_huge_pages(block, n * sizeof(T));
        std::shared_ptr<T> whole(block, [](T* q) { ::operator delete(q, std::align_val_t(alignof(T))); });
        const std::size_t chunks = (n + kMask) >> kShift;
        owners_.reserve(chunks);
        table_.reserve(chunks);
        for (std::size_t c = 0; c < chunks; ++c) {
            owners_.emplace_back(whole, block + (c << kShift));
            table_.push_back(block + (c << kShift));
        }
        block_ = {block, block + n};
        block_refs_ = chunks;
        last_capacity_ = n - ((chunks - 1) << kShift);
        flat_ = block;
        for (std::size_t c = 0; c < old.chunk_count(); ++c)
            std::memcpy(static_cast<void*>(block + (c << kShift)), old.chunk(c), old.chunk_size(c) * sizeof(T));
        size_ = old.size_;
    }
    static std::shared_ptr<T> allocate(std::size_t n) {
        T* p = static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(alignof(T))));
        return std::shared_ptr<T>(p, [](T* q) { ::operator delete(q, std::align_val_t(alignof(T))); });
    }
    bool in_block(std::size_t c) const {
        return !std::less<const T*>()(table_[c], block_.first) && std::less<const T*>()(table_[c], block_.second);
    }
    // Whether no other array holds chunk c (then it may be written in place): a chunk of
    // its own held once, or a chunk of the block while no other array holds any part of
    // it. Only this array could make another holder, so the answer cannot turn false
    // meanwhile; the fence orders the writes after the other holders' last reads, which
    // came before their release.
    bool unique(std::size_t c) const {
        const long want = in_block(c) ? long(block_refs_) : 1;
        if (owners_[c].use_count() != want) return false;
        std::atomic_thread_fence(std::memory_order_acquire);
        return true;
    }
    std::size_t chunk_capacity(std::size_t c) const { return c + 1 < owners_.size() ? kChunk : last_capacity_; }
    std::size_t capacity() const { return owners_.empty() ? 0 : ((owners_.size() - 1) << kShift) + last_capacity_; }
    // Chunk c is now `fresh`, a chunk of its own.
    void replace(std::size_t c, std::shared_ptr<T> fresh) {
        if (in_block(c)) --block_refs_;
        table_[c] = fresh.get();
        owners_[c] = std::move(fresh);
        flat_ = owners_.size() == 1 ? table_[0] : nullptr;
    }
    void reallocate_last(std::size_t capacity) {
        const std::size_t c = owners_.size() - 1;
        std::shared_ptr<T> fresh = allocate(capacity);
        std::memcpy(static_cast<void*>(fresh.get()), table_[c], (c < chunk_count() ? chunk_size(c) : 0) * sizeof(T));
        replace(c, std::move(fresh));
        last_capacity_ = capacity;
    }
    // Room for one more element: the last chunk grows (by doubling, up to a chunk) or a
    // new one starts.
    void grow() {
        if (!owners_.empty() && last_capacity_ < kChunk) {
            const std::size_t want = last_capacity_ * 2;
            reallocate_last(want < kChunk ? want : kChunk);
            return;
        }
        const std::size_t capacity = owners_.empty() ? 8 : kChunk;
        owners_.push_back(allocate(capacity));
        table_.push_back(owners_.back().get());
        last_capacity_ = capacity;
        flat_ = owners_.size() == 1 ? table_[0] : nullptr;
    }
    void copy_chunk(std::size_t c) {
        std::shared_ptr<T> fresh = allocate(chunk_capacity(c));
        std::memcpy(static_cast<void*>(fresh.get()), table_[c], (c < chunk_count() ? chunk_size(c) : 0) * sizeof(T));
        replace(c, std::move(fresh));
    }

    std::vector<std::shared_ptr<T>> owners_;
    std::vector<T*> table_;  // owners_[c].get(), kept apart so that reads touch only this
    std::size_t size_ = 0;
    std::size_t last_capacity_ = 0;  // of the last chunk (a whole chunk's, or less)
    // The block reserve() made, [first, second), and how many of owners_ are its chunks.
    std::pair<T*, T*> block_{nullptr, nullptr};
    std::size_t block_refs_ = 0;
    T* flat_ = nullptr;  // see flat()
};

// An array that copies share whole: for tables an edit never writes (the shapes'
// structure, the BVH's items), read as fast as a std::vector. Writing one that
// another array holds copies it first.
template <class T>
class Shared {
public:
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    const T& operator[](std::size_t i) const { return data_[i]; }
    const T& back() const { return data_[size_ - 1]; }
    const T* data() const { return data_; }
    const T* begin() const { return data_; }
    const T* end() const { return data_ + size_; }
    T& write(std::size_t i) {
        std::vector<T>& v = own();
        sync();
        return v[i];
    }
    void push_back(const T& v) {
        own().push_back(v);
        sync();
    }
    void reserve(std::size_t n) {
        std::vector<T>& v = own();
        if (n > v.capacity()) {
            v.reserve(n);
            advise_huge_pages(v.data() + v.size(), (v.capacity() - v.size()) * sizeof(T));
        }
        sync();
    }
    void resize(std::size_t n) {
        own().resize(n);
        sync();
    }
    void clear() {
        v_ = nullptr;
        sync();
    }
    void shrink_to_fit() {
        own().shrink_to_fit();
        sync();
    }
    std::size_t memory_bytes() const { return v_ ? v_->capacity() * sizeof(T) : 0; }
    std::vector<T> to_vector() const { return v_ ? *v_ : std::vector<T>(); }
    bool shares(const Shared& o) const { return v_ == o.v_; }

private:
    std::vector<T>& own() {
        if (!v_) v_ = std::make_shared<std::vector<T>>();
        else if (v_.use_count() != 1) v_ = std::make_shared<std::vector<T>>(*v_);
        else std::atomic_thread_fence(std::memory_order_acquire);
        return *v_;
    }
    void sync() {
        data_ = v_ ? v_->data() : nullptr;
        size_ = v_ ? v_->size() : 0;
    }
    std::shared_ptr<std::vector<T>> v_;
    T* data_ = nullptr;
    std::size_t size_ = 0;
};

// Whether two arrays hold the same bytes (for records without padding); chunks they
// share are not compared.
template <class T>
bool same_bits(const Chunked<T>& a, const Chunked<T>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t c = 0; c < a.chunk_count(); ++c)
        if (!a.shares_chunk(b, c) && std::memcmp(a.chunk(c), b.chunk(c), a.chunk_size(c) * sizeof(T)) != 0) return false;
    return true;
}

template <class T>
bool same_bits(const Shared<T>& a, const Shared<T>& b) {
    return a.size() == b.size() && (a.shares(b) || a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}
template <class T, class Eq>
bool same_items(const Shared<T>& a, const Shared<T>& b, Eq&& eq) {
    if (a.size() != b.size()) return false;
    if (a.shares(b)) return true;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (!eq(a[i], b[i])) return false;
    return true;
}

// Whether eq(a[i], b[i]) holds for every i (for records with padding); chunks the
// arrays share are not compared.
template <class T, class Eq>
bool same_items(const Chunked<T>& a, const Chunked<T>& b, Eq&& eq) {
    if (a.size() != b.size()) return false;
    for (std::size_t c = 0; c < a.chunk_count(); ++c) {
        if (a.shares_chunk(b, c)) continue;
        const T *x = a.chunk(c), *y = b.chunk(c);
        for (std::size_t k = 0, e = a.chunk_size(c); k < e; ++k)
            if (!eq(x[k], y[k])) return false;
    }
    return true;
}

}  // namespace rt
