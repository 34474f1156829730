// The status bar's message: what the viewer last said, and whether it is an error.
#pragma once

#include <string>

namespace rtview {

class StatusLine {
public:
    void set(const std::string& text, bool error = false) {
        text_ = text;
        error_ = error;
    }
    const std::string& text() const { return text_; }
    bool error() const { return error_; }

private:
    std::string text_;
    bool error_ = false;
};

}  // namespace rtview
