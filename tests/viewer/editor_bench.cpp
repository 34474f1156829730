// Typing latency of the scene text editor on a large file, in a window-less ImGui
// context: each keystroke is one whole UI frame (NewFrame, the editor's input and
// drawing, Render to draw lists, and the document's copy of the text following the
// edit), which is what a key costs in the viewer apart from the GL upload of the draw
// lists and the rest of the viewer's panels. For comparison it times ImGui's
// InputTextMultiline (the widget the editor replaces) on the same text.
//
// It also times a panel edit's write-back as the widget follows it (against set_text,
// which the widget took for each such change before).
//
//   rtview-editor-bench [MEGABYTES=10] [KEYS=300] [--no-baseline]
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "imgui_harness.h"
#include "text_editor.h"

using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// A scene like the writer prints one, with comments: about `bytes` long.
std::string big_scene(std::size_t bytes) {
    std::string s = "// benchmark scene\nthing {\n";
    for (int i = 0; s.size() < bytes; ++i) {
        s += "  sphere {  // number " + std::to_string(i) + "\n";
        s += "    material { reflection 0.1 refraction 0 scattering 0.9 translusans 1 refractive_index 1 colour 0.8 0.5 0.25 }\n";
        s += "    position " + std::to_string(i % 100) + " " + std::to_string(i / 100) + " 0.5\n";
        s += "    radius 0.4\n  }\n";
    }
    s += "}\ncamera { position -10 -10 5 centre 50 50 0 up 50 50 1 angle_x 60 angle_y 45 }\n";
    s += "picture_size { x_max 640 y_max 480 }\nend\n";
    return s;
}

struct Summary {
    double median = 0, p95 = 0, max = 0;
};
Summary summarise(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    Summary s;
    if (v.empty()) return s;
    s.median = v[v.size() / 2];
    s.p95 = v[std::min(v.size() - 1, v.size() * 95 / 100)];
    s.max = v.back();
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    double mb = 10;
    int keys = 300;
    bool baseline = true;
    int pos = 0;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--no-baseline") == 0) baseline = false;
        else if (pos++ == 0) mb = std::atof(argv[i]);
        else keys = std::atoi(argv[i]);
    }
    const std::string text = big_scene(std::size_t(mb * 1024 * 1024));

    rtview_test::ImGuiHarness h(1280, 800);
    rtview::TextEditor ed;
    // As raytracer-view does: the document's std::string follows the widget through
    // its edit log, so each key also pays one replace() in a 10 MB string.
    // The viewer's loader reads with 1/32 spare capacity, so the first key does not
    // move the string: the same here.
    std::string mirror;
    mirror.reserve(text.size() + text.size() / 32);
    mirror = text;
    auto body = [&] {
        if (ed.draw("editor", ImVec2(0, 0)))
            for (const rtview::BufferEdit& e : ed.buffer().take_edits()) mirror.replace(e.offset, e.removed.size(), e.inserted);
    };

    auto t0 = Clock::now();
    ed.set_text(text);
    ed.buffer().set_logging(true);
    double load_ms = ms_since(t0);
    std::printf("text: %.1f MB, %d lines; set_text %.1f ms\n", double(text.size()) / (1024 * 1024),
                ed.buffer().line_count(), load_ms);
    h.frame(body);
    h.click(ImVec2(300, 40), body);
    if (!ed.focused()) {
        std::fprintf(stderr, "the editor did not take focus\n");
        return 1;
    }
    // In the middle of the file, on a key line: the worst place for line inserts.
    const int mid = ed.buffer().line_count() / 2;
    ed.show({mid, 4});
    h.frame(body);
    h.frame(body);

    // Keystrokes: letters (merged into undo steps), Enter (inserts a line: the line
    // vector's tail moves), Backspace at a line start (joins two lines).
    std::vector<double> t_char, t_enter, t_join, t_move;
    for (int k = 0; k < keys; ++k) {
        auto t = Clock::now();
        ed.push_char('a' + unsigned(k % 26));
        h.frame(body);
        t_char.push_back(ms_since(t));
        if (k % 10 == 9) {
            t = Clock::now();
            ed.push_key(rtview::TextEditor::Key::Enter, false, false);
            h.frame(body);
            t_enter.push_back(ms_since(t));
            t = Clock::now();
            ed.push_key(rtview::TextEditor::Key::Home, false, false);
            ed.push_key(rtview::TextEditor::Key::Home, false, false);
            h.frame(body);
            t_move.push_back(ms_since(t));
            t = Clock::now();
            ed.push_key(rtview::TextEditor::Key::Backspace, false, false);
            h.frame(body);
            t_join.push_back(ms_since(t));
            ed.push_key(rtview::TextEditor::Key::End, false, false);
            h.frame(body);
        }
    }
    // An idle frame (nothing typed) for reference.
    std::vector<double> t_idle;
    for (int k = 0; k < 50; ++k) {
        auto t = Clock::now();
        h.frame(body);
        t_idle.push_back(ms_since(t));
    }
    // A panel edit written back into the text (or its undo): the document replaces one
    // item's block and the widget follows the replacement, here one number's line at
    // places spread over the text, each followed by a frame.
    std::vector<double> t_follow;
    for (int k = 0; k < 40; ++k) {
        const std::size_t at = mirror.find("radius 0.4", mirror.size() / 41 * std::size_t(k + 1));
        if (at == std::string::npos) break;
        auto t = Clock::now();
        ed.buffer().follow_replacement(at, 10, "radius 0.5");
        h.frame(body);
        t_follow.push_back(ms_since(t));
        mirror.replace(at, 10, "radius 0.5");
    }
    auto report = [](const char* what, const std::vector<double>& v) {
        Summary s = summarise(v);
        std::printf("%-28s n=%4zu  median %7.3f ms  p95 %7.3f ms  max %7.3f ms\n", what, v.size(), s.median, s.p95, s.max);
    };
    std::printf("draw lists of one editor frame: %d vertices (lines %d-%d drawn)\n", ImGui::GetDrawData()->TotalVtxCount,
                ed.stats().first_line + 1, ed.stats().last_line + 1);
    report("editor: character", t_char);
    report("editor: Enter (new line)", t_enter);
    report("editor: Backspace (join)", t_join);
    report("editor: Home (cursor move)", t_move);
    report("editor: idle frame", t_idle);
    report("panel edit followed + frame", t_follow);
    t0 = Clock::now();
    std::string back = ed.text();
    std::printf("text() for the parser: %.1f ms (%zu bytes)\n", ms_since(t0), back.size());
    if (back != mirror) {
        std::fprintf(stderr, "the mirrored text differs from the editor's\n");
        return 1;
    }

    if (baseline) {
        // ImGui's InputTextMultiline on a std::string, as the viewer used it.
        rtview_test::ImGuiHarness h2(1280, 800);
        std::string s = text;
        auto body2 = [&] {
            ImGui::InputTextMultiline("##t", &s, ImVec2(-1, -1), ImGuiInputTextFlags_AllowTabInput);
        };
        h2.frame(body2);
        h2.click(ImVec2(300, 40), body2);
        std::vector<double> t_base;
        for (int k = 0; k < std::min(keys, 10); ++k) {
            auto t = Clock::now();
            h2.type("a");
            h2.frame(body2);
            t_base.push_back(ms_since(t));
        }
        if (s.size() != text.size() + t_base.size()) std::printf("(baseline: the field did not take the keys)\n");
        report("InputTextMultiline: char", t_base);
    }
    return 0;
}
