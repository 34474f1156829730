// Results of operations that can fail in a way the caller must handle: Status (success,
// or a message and the exit code it maps to) and Expected<T> (a value, or a Status).
// Both are [[nodiscard]], so a dropped error is a compiler warning.
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace rt {

// The programs' exit codes: 1 for a bad scene, 2 for usage and I/O errors.
constexpr int kExitOk = 0;
constexpr int kExitScene = 1;
constexpr int kExitUsage = 2;
// A result used wrongly by the program itself (a bug), not by its input.
constexpr int kExitInternal = 70;

class [[nodiscard]] Status {
public:
    Status() = default;  // success
    // A failure; an exit code of 0 would read as success, so it becomes kExitInternal.
    static Status error(std::string message, int exit_code = kExitScene) {
        Status s;
        s.message_ = std::move(message);
        s.exit_code_ = exit_code != kExitOk ? exit_code : kExitInternal;
        return s;
    }

    bool ok() const { return exit_code_ == kExitOk; }
    explicit operator bool() const { return ok(); }
    // Empty on success.
    const std::string& message() const { return message_; }
    int exit_code() const { return exit_code_; }

    // The same failure with `context` in front ("file.txt: " + message); success stays
    // success.
    Status with_context(const std::string& context) const {
        return ok() ? *this : error(context + message_, exit_code_);
    }

    bool operator==(const Status& o) const { return exit_code_ == o.exit_code_ && message_ == o.message_; }
    bool operator!=(const Status& o) const { return !(*this == o); }

private:
    std::string message_;
    int exit_code_ = kExitOk;
};

template <class T>
class [[nodiscard]] Expected {
public:
    Expected(T value) : value_(std::move(value)) {}  // NOLINT: implicit, as a return value
    // A failure. Passing a success Status is a bug: it becomes an internal error
    // rather than an Expected with neither a value nor an error.
    Expected(Status error)  // NOLINT: implicit, as a return value
        : status_(error.ok() ? Status::error("internal error: a result with no value", kExitInternal)
                             : std::move(error)) {}

    bool ok() const { return value_.has_value(); }
    explicit operator bool() const { return ok(); }
    // Success, or why not.
    const Status& status() const { return status_; }

    // The value; only when ok().
    T& value() & { return *value_; }
    const T& value() const& { return *value_; }
    T&& value() && { return std::move(*value_); }
    T& operator*() & { return *value_; }
    const T& operator*() const& { return *value_; }
    T* operator->() { return &*value_; }
    const T* operator->() const { return &*value_; }
    // The value, or `fallback` on failure.
    T value_or(T fallback) const& { return ok() ? *value_ : std::move(fallback); }

private:
    std::optional<T> value_;
    Status status_;
};

}  // namespace rt
