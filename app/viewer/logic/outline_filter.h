// The outline's filter: which objects' rows match a typed text. A whole number is an
// object's number (1 for the first); anything else is looked for in the rows' labels,
// case aside. The labels are read a slice at a time (scan()), so that a scene of a
// million objects never holds up a frame: the matches grow while the user watches.
#pragma once

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rtview {

class OutlineFilter {
public:
    // The text typed, the scene's version and its number of objects: a change of any
    // starts the search over.
    void set(const std::string& text, std::uint64_t version, std::size_t count) {
        std::string t = trimmed_lower(text);
        if (t == text_ && version == version_ && count == count_) return;
        text_ = std::move(t);
        version_ = version;
        count_ = count;
        matches_.clear();
        next_ = 0;
        number_ = !text_.empty() && std::all_of(text_.begin(), text_.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (number_) {
            // (At most 19 digits are a number at all; more name no object.)
            const std::size_t n = text_.size() <= 18 ? std::stoull(text_) : 0;
            if (n >= 1 && n <= count_) matches_.push_back(n - 1);
            next_ = count_;
        }
    }
    bool active() const { return !text_.empty(); }
    // Reads labels (label(k): object k's row) from where the last call stopped until
    // `seconds` have passed (checked every 256 labels) or all are read; true when done.
    template <class Label>
    bool scan(double seconds, Label&& label) {
        const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
        while (next_ < count_) {
            const std::size_t end = std::min(count_, next_ + 256);
            for (; next_ < end; ++next_)
                if (contains_lower(label(next_), text_)) matches_.push_back(next_);
            if (std::chrono::steady_clock::now() >= until) break;
        }
        return done();
    }
    bool done() const { return next_ >= count_; }
    // How much of the scene has been read, 0..1.
    double fraction() const { return count_ == 0 ? 1.0 : double(next_) / double(count_); }
    // The matching objects' indices (0 for the first), in order.
    const std::vector<std::size_t>& matches() const { return matches_; }

private:
    static std::string trimmed_lower(const std::string& s) {
        std::size_t a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
        std::string t = a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
        for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
        return t;
    }
    static bool contains_lower(const std::string& hay, const std::string& needle) {
        return std::search(hay.begin(), hay.end(), needle.begin(), needle.end(), [](char a, char b) {
                   return char(std::tolower(static_cast<unsigned char>(a))) == b;
               }) != hay.end();
    }
    std::string text_;
    std::uint64_t version_ = 0;
    std::size_t count_ = 0, next_ = 0;
    bool number_ = false;
    std::vector<std::size_t> matches_;
};

}  // namespace rtview
