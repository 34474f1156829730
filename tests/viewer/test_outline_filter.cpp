// The outline's filter (outline_filter.h): numbers name objects, words find labels,
// and a long scene is read a slice at a time.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "outline_filter.h"

using rtview::OutlineFilter;

namespace {
std::string label(std::size_t k) { return std::to_string(k + 1) + "  " + (k % 3 == 0 ? "Sphere" : "box") + "  at 1 2 3"; }
}  // namespace

TEST_CASE("outline filter: a number is that object, words are found in the labels case aside") {
    OutlineFilter f;
    f.set("", 1, 5000);
    CHECK_FALSE(f.active());
    f.set(" 2900 ", 1, 5000);
    CHECK(f.active());
    CHECK(f.done());  // (no labels to read)
    REQUIRE(f.matches().size() == 1);
    CHECK(f.matches()[0] == 2899);
    f.set("5001", 1, 5000);
    CHECK(f.matches().empty());
    f.set("0", 1, 5000);
    CHECK(f.matches().empty());
    f.set("99999999999999999999999", 1, 5000);
    CHECK(f.matches().empty());

    f.set("SPHERE", 1, 5000);
    while (!f.scan(1.0, label)) {
    }
    CHECK(f.matches().size() == 1667);  // every third of 5000, from the first
    CHECK(f.matches().front() == 0);
    CHECK(f.matches().back() == 4998);
    f.set("nothing like it", 1, 5000);
    f.scan(1.0, label);
    CHECK(f.done());
    CHECK(f.matches().empty());
}

TEST_CASE("outline filter: a scan stops at its time and goes on where it stopped; a new scene starts over") {
    OutlineFilter f;
    f.set("box", 1, 200000);
    std::size_t read = 0;
    auto slow = [&](std::size_t k) {
        ++read;
        return label(k);
    };
    const bool done = f.scan(0.0, slow);  // no time at all: one slice of 256
    CHECK_FALSE(done);
    CHECK(read == 256);
    CHECK(f.fraction() > 0);
    CHECK(f.fraction() < 0.01);
    while (!f.scan(0.01, slow)) {
    }
    CHECK(read == 200000);  // every label read once
    CHECK(f.matches().size() == 200000 - 66667);
    // The same text and scene: nothing to do again; another version: read again.
    f.set("box", 1, 200000);
    CHECK(f.done());
    f.set("box", 2, 200000);
    CHECK_FALSE(f.done());
    CHECK(f.matches().empty());
}
