// The status bar's message: what the viewer last said, and whether it is an error.
#pragma once

#include <string>

namespace rtview {

class StatusLine {
public:
    // What a message is about, when it can go stale: the scene text's errors (the
    // message goes once the text has none).
    enum class Cause { None, TextErrors };

    void set(const std::string& text, bool error = false, Cause cause = Cause::None) {
        text_ = text;
        error_ = error;
        cause_ = cause;
    }
    // The message, if it is about `cause`, has gone stale: it goes.
    void clear_if(Cause cause) {
        if (cause_ == cause && cause != Cause::None) set({});
    }
    const std::string& text() const { return text_; }
    bool error() const { return error_; }
    Cause cause() const { return cause_; }

private:
    std::string text_;
    bool error_ = false;
    Cause cause_ = Cause::None;
};

}  // namespace rtview
