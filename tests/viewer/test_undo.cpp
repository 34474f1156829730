// The undo history.
#include <doctest/doctest.h>

#include <string>

#include "undo.h"

using rtview::UndoHistory;

TEST_CASE("undo walks back through pushed states and redo walks forward again") {
    UndoHistory<int> h;
    int state = 0;
    for (int v = 1; v <= 3; ++v) {
        h.push(state);
        state = v;
    }
    state = *h.undo(state);
    CHECK(state == 2);
    state = *h.undo(state);
    CHECK(state == 1);
    state = *h.redo(state);
    CHECK(state == 2);
    state = *h.redo(state);
    CHECK(state == 3);
    CHECK_FALSE(h.redo(state).has_value());
}

TEST_CASE("a new edit after undo forgets the redo branch") {
    UndoHistory<int> h;
    h.push(0);          // 0 -> 1
    int s = *h.undo(1);  // back to 0
    CHECK(s == 0);
    CHECK(h.can_redo());
    h.push(0);  // 0 -> 5
    CHECK_FALSE(h.can_redo());
    CHECK(*h.undo(5) == 0);
}

TEST_CASE("the history keeps at most its limit, dropping the oldest") {
    UndoHistory<int> h(3);
    for (int v = 0; v < 10; ++v) h.push(v);
    CHECK(h.undo_size() == 3);
    int s = 10;
    s = *h.undo(s);
    s = *h.undo(s);
    s = *h.undo(s);
    CHECK(s == 7);
    CHECK_FALSE(h.can_undo());
}

TEST_CASE("undo on an empty history does nothing") {
    UndoHistory<std::string> h;
    CHECK_FALSE(h.undo("x").has_value());
    CHECK_FALSE(h.can_redo());
}
