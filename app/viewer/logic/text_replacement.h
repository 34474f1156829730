// A text replacement: `length` bytes at `offset` become `text`. The one form every part
// of the viewer uses for it: structural edits (scene_edits.h), the document's undo
// steps and the log of text changes a text widget follows (document.h), a block's
// patch (block_patch.h). (The text editor widget keeps its own undo record, BufferEdit
// in text_buffer.h, in lines and columns with the cursors.)
#pragma once

#include <cstddef>
#include <string>

namespace rtview {

struct TextReplacement {
    std::size_t offset = 0, length = 0;
    std::string text;
    // Makes it in `s` and returns the replacement that takes it back.
    TextReplacement apply(std::string& s) const;
    // The replacement that takes it back, given `before`, the text it is made in.
    TextReplacement inverse(const std::string& before) const;
    bool empty() const { return length == 0 && text.empty(); }
};

// The one replacement that turns `a` into `b` (common prefix and suffix left out).
TextReplacement diff_texts(const std::string& a, const std::string& b);

}  // namespace rtview
