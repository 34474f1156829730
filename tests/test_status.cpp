// Tests for core/status.h: Status and Expected<T> carry a message and an exit code,
// and a success never hides an error. (That dropping one is a warning is checked by
// compiling tests/status_discard.cpp: see tests/CMakeLists.txt.)
#include <doctest/doctest.h>

#include <memory>
#include <string>
#include <vector>

#include "status.h"

using namespace rt;

namespace {

Expected<int> parse_digit(char c) {
    if (c < '0' || c > '9') return Status::error(std::string("not a digit: '") + c + "'", kExitUsage);
    return c - '0';
}

}  // namespace

TEST_CASE("status: success has no message and exit code 0") {
    Status s;
    CHECK(s.ok());
    CHECK(bool(s));
    CHECK(s.message().empty());
    CHECK(s.exit_code() == 0);
    CHECK(s == Status());
}

TEST_CASE("status: an error keeps its message and exit code; 0 is not a failure code") {
    Status scene = Status::error("scene.txt:3:7: error: radius must be positive");
    CHECK_FALSE(scene.ok());
    CHECK_FALSE(bool(scene));
    CHECK(scene.exit_code() == 1);
    CHECK(scene.message() == "scene.txt:3:7: error: radius must be positive");

    Status io = Status::error("cannot write out.png: Permission denied", kExitUsage);
    CHECK(io.exit_code() == 2);
    CHECK(io != scene);

    Status zero = Status::error("failed, but said 0", 0);
    CHECK_FALSE(zero.ok());
    CHECK(zero.exit_code() == kExitInternal);
}

TEST_CASE("status: context goes in front of an error, and success stays success") {
    Status e = Status::error("no such file", kExitUsage).with_context("scene.txt: ");
    CHECK(e.message() == "scene.txt: no such file");
    CHECK(e.exit_code() == 2);
    CHECK(Status().with_context("scene.txt: ").ok());
    CHECK(Status().with_context("scene.txt: ").message().empty());
}

TEST_CASE("expected: a value or a status, never both") {
    Expected<int> seven = parse_digit('7');
    REQUIRE(seven.ok());
    CHECK(*seven == 7);
    CHECK(seven.value() == 7);
    CHECK(seven.status().ok());
    CHECK(seven.value_or(-1) == 7);

    Expected<int> bad = parse_digit('x');
    CHECK_FALSE(bad.ok());
    CHECK_FALSE(bool(bad));
    CHECK(bad.status().message() == "not a digit: 'x'");
    CHECK(bad.status().exit_code() == 2);
    CHECK(bad.value_or(-1) == -1);
}

TEST_CASE("expected: a success status given as an error becomes an internal error") {
    Expected<std::string> r{Status()};
    CHECK_FALSE(r.ok());
    CHECK(r.status().exit_code() == kExitInternal);
    CHECK_FALSE(r.status().message().empty());
}

TEST_CASE("expected: move-only values and access through ->") {
    Expected<std::unique_ptr<std::vector<int>>> r{std::make_unique<std::vector<int>>(3, 5)};
    REQUIRE(r.ok());
    CHECK((*r)->size() == 3);
    std::unique_ptr<std::vector<int>> owned = std::move(r).value();
    CHECK(owned->at(2) == 5);

    Expected<std::string> s{std::string("abc")};
    CHECK(s->size() == 3);
}
