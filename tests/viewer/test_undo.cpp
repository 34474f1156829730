// The undo history: steps in a byte budget, oldest dropped first.
#include <doctest/doctest.h>

#include <string>

#include "undo.h"

using rtview::UndoHistory;

TEST_CASE("undo walks back through pushed steps and redo walks forward again") {
    UndoHistory<int> h;
    for (int v = 1; v <= 3; ++v) h.push(v, 4);
    REQUIRE(h.undo());
    CHECK(*h.redo() == 3);
    CHECK(*h.undo() == 3);
    CHECK(*h.undo() == 2);
    CHECK(*h.undo() == 1);
    CHECK(h.undo() == nullptr);
    CHECK(*h.redo() == 1);
    CHECK(*h.redo() == 2);
    CHECK(*h.redo() == 3);
    CHECK(h.redo() == nullptr);
}

TEST_CASE("a new edit after undo forgets the redo branch") {
    UndoHistory<int> h;
    h.push(1, 4);
    CHECK(*h.undo() == 1);
    CHECK(h.can_redo());
    h.push(5, 4);
    CHECK_FALSE(h.can_redo());
    CHECK(h.bytes() == 4);
    CHECK(*h.undo() == 5);
    CHECK(h.undo() == nullptr);
}

TEST_CASE("the history keeps at most its byte budget, dropping the oldest") {
    UndoHistory<int> h(100);
    for (int v = 0; v < 10; ++v) h.push(v, 30);  // 3 fit in 100 bytes
    CHECK(h.undo_size() == 3);
    CHECK(h.bytes() == 90);
    CHECK(*h.undo() == 9);
    CHECK(*h.undo() == 8);
    CHECK(*h.undo() == 7);
    CHECK(h.undo() == nullptr);
    // Redo steps count too; a new step drops them first (a new edit forgets them).
    h.push(42, 60);
    CHECK(h.bytes() == 60);
    // A step bigger than the whole budget is not kept.
    h.push(43, 101);
    CHECK(h.undo_size() == 0);
    CHECK(h.bytes() == 0);
}

TEST_CASE("undo on an empty history does nothing") {
    UndoHistory<std::string> h;
    CHECK(h.undo() == nullptr);
    CHECK_FALSE(h.can_redo());
}
