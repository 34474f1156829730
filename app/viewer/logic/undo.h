// Undo/redo history of edits (not of whole documents): each step holds what one edit
// changed and knows its size, and the history keeps at most a byte budget of them,
// dropping the oldest first. A step bigger than the whole budget is not kept at all.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <utility>

namespace rtview {

template <class Step>
class UndoHistory {
public:
    explicit UndoHistory(std::size_t budget_bytes = 64u << 20, std::size_t max_steps = 10000)
        : budget_(budget_bytes), max_steps_(max_steps < 1 ? 1 : max_steps) {}

    // Records an edit just made. A new edit forgets the redo branch.
    void push(Step step, std::size_t bytes) {
        ++changes_;
        redo_.clear();
        redo_bytes_ = 0;
        undo_.push_back({std::move(step), bytes});
        undo_bytes_ += bytes;
        trim();
    }
    // The step to take back (then on the redo side), or null.
    const Step* undo() { return move_last(undo_, undo_bytes_, redo_, redo_bytes_); }
    // The step to do again (then on the undo side), or null.
    const Step* redo() { return move_last(redo_, redo_bytes_, undo_, undo_bytes_); }
    // The step the k-th undo() (redo()) from now would return (k = 0: the next), or
    // null: for listing the history without taking anything back.
    const Step* peek_undo(std::size_t k) const { return k < undo_.size() ? &undo_[undo_.size() - 1 - k].first : nullptr; }
    const Step* peek_redo(std::size_t k) const { return k < redo_.size() ? &redo_[redo_.size() - 1 - k].first : nullptr; }
    bool can_undo() const { return !undo_.empty(); }
    bool can_redo() const { return !redo_.empty(); }
    std::size_t undo_size() const { return undo_.size(); }
    // Counts pushes, undos, redos and clears: what the next undo() would take back
    // is the same while it stays the same.
    std::uint64_t changes() const { return changes_; }
    // Bytes held by all steps (undo and redo side).
    std::size_t bytes() const { return undo_bytes_ + redo_bytes_; }
    std::size_t budget() const { return budget_; }
    void set_budget(std::size_t b) {
        budget_ = b;
        trim();
    }
    void clear() {
        ++changes_;
        undo_.clear();
        redo_.clear();
        undo_bytes_ = redo_bytes_ = 0;
    }

private:
    using Steps = std::deque<std::pair<Step, std::size_t>>;
    // The last step of `from` moved to the end of `to`, with its bytes.
    const Step* move_last(Steps& from, std::size_t& from_bytes, Steps& to, std::size_t& to_bytes) {
        if (from.empty()) return nullptr;
        ++changes_;
        from_bytes -= from.back().second;
        to_bytes += from.back().second;
        to.push_back(std::move(from.back()));
        from.pop_back();
        return &to.back().first;
    }
    void trim() {
        while (!undo_.empty() && (bytes() > budget_ || undo_.size() > max_steps_)) {
            undo_bytes_ -= undo_.front().second;
            undo_.pop_front();
        }
    }

    std::size_t budget_, max_steps_;
    Steps undo_, redo_;
    std::size_t undo_bytes_ = 0, redo_bytes_ = 0;
    std::uint64_t changes_ = 0;
};

}  // namespace rtview
