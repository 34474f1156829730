// The status bar's message: what the viewer last said, and whether it is an error.
#pragma once

#include <cstdint>
#include <string>

namespace rtview {

class StatusLine {
public:
    // What a message is about, when it can go stale: the scene text's errors (the
    // message goes once the text has none); the undo step just made, undone or redone
    // ("... (Ctrl+Z undoes)": the message goes when the history moves on, since Ctrl+Z
    // would then take back something else).
    enum class Cause { None, TextErrors, UndoStep };

    void set(const std::string& text, bool error = false, Cause cause = Cause::None) {
        text_ = text;
        error_ = error;
        cause_ = cause;
    }
    // A message about the step the history has just made, undone or redone; `history`:
    // Document::history_changes() after it.
    void set_about_step(const std::string& text, std::uint64_t history) {
        set(text, false, Cause::UndoStep);
        history_ = history;
    }
    // The history moved on from the step a message is about: the message goes.
    void clear_if_history_moved(std::uint64_t history) {
        if (cause_ == Cause::UndoStep && history != history_) set({});
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
    std::uint64_t history_ = 0;  // Cause::UndoStep: the history it is about
};

}  // namespace rtview
