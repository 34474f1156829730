// Undo/redo history of whole document states. Scenes are small next to the cost of a
// render, so storing complete states (not deltas) keeps undo trivially correct.
#pragma once

#include <cstddef>
#include <deque>
#include <optional>
#include <utility>

namespace rtview {

template <class State>
class UndoHistory {
public:
    explicit UndoHistory(std::size_t limit = 256) : limit_(limit < 1 ? 1 : limit) {}

    // Records the state as it was before an edit. A new edit forgets the redo branch.
    void push(State before) {
        undo_.push_back(std::move(before));
        if (undo_.size() > limit_) undo_.pop_front();
        redo_.clear();
    }
    // Returns the state to go back to and remembers `current` for redo.
    std::optional<State> undo(State current) {
        if (undo_.empty()) return std::nullopt;
        State s = std::move(undo_.back());
        undo_.pop_back();
        redo_.push_back(std::move(current));
        return s;
    }
    std::optional<State> redo(State current) {
        if (redo_.empty()) return std::nullopt;
        State s = std::move(redo_.back());
        redo_.pop_back();
        undo_.push_back(std::move(current));
        return s;
    }
    bool can_undo() const { return !undo_.empty(); }
    bool can_redo() const { return !redo_.empty(); }
    std::size_t undo_size() const { return undo_.size(); }
    std::size_t redo_size() const { return redo_.size(); }
    void clear() {
        undo_.clear();
        redo_.clear();
    }

private:
    std::size_t limit_;
    std::deque<State> undo_, redo_;
};

}  // namespace rtview
