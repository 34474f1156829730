// ImGui text fields with a bound on what they hold. A std::string field takes whatever
// is pasted into it, and ImGui then converts and draws all of it every frame: a paste of
// 10 MB makes every frame slow and reserves a gigabyte of vertices. These fields keep
// at most `max_bytes` (a path's PATH_MAX, a number's few hundred): a longer paste is cut.
#pragma once

#include <imgui.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <string_view>

namespace rtview {

// `s` as ImGui 1.86 reads it back byte for byte: sequences of one to three bytes kept,
// anything else (a stray byte, a four-byte character, which ImGui holds as U+FFFD) as
// U+FFFD. ImGui counts a field's bytes when it is activated and then per character
// edited; on bytes it reads otherwise the counts disagree, and deleting went below zero
// (an assertion: a file name that is not UTF-8 in the file field, then Backspace).
inline std::string imgui_utf8(std::string_view s) {
    std::string out;
    out.reserve(s.size());
    auto cont = [&](std::size_t i) { return i < s.size() && (static_cast<unsigned char>(s[i]) & 0xC0) == 0x80; };
    for (std::size_t i = 0; i < s.size();) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        std::size_t n = 0;
        if (c < 0x80) n = 1;
        else if (c >= 0xC2 && c < 0xE0 && cont(i + 1)) n = 2;
        else if (c >= 0xE0 && c < 0xF0 && cont(i + 1) && cont(i + 2) && (c != 0xE0 || static_cast<unsigned char>(s[i + 1]) >= 0xA0))
            n = 3;
        if (n == 0) {
            out += "\xEF\xBF\xBD";
            ++i;
            while (cont(i)) ++i;  // the rest of a four-byte character, or stray continuations
        } else {
            out.append(s.substr(i, n));
            i += n;
        }
    }
    return out;
}

// An InputTextWithHint on `text`, holding at most `max_bytes` of it. Bytes ImGui would
// not read back are shown as U+FFFD; the text keeps them until the field is edited.
inline bool bounded_input(const char* label, const char* hint, std::string& text, std::size_t max_bytes,
                          ImGuiInputTextFlags flags = 0, ImGuiInputTextCallback callback = nullptr,
                          void* user_data = nullptr) {
    if (text.size() > max_bytes) text.resize(max_bytes);
    const std::string shown = imgui_utf8(text);
    std::string buf = shown;
    buf.resize(std::max(shown.size(), max_bytes) + 1, '\0');
    const bool r = ImGui::InputTextWithHint(label, hint, buf.data(), buf.size(), flags, callback, user_data);
    if (std::strcmp(buf.c_str(), shown.c_str()) != 0) {
        text.assign(buf.c_str());
        if (text.size() > max_bytes) text.resize(max_bytes);
    }
    return r;
}

}  // namespace rtview
