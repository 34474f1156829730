// An undo step of the document (DocStep): what one edit changed, both ways, and the
// helpers that build one (document_edit.cpp, document_history.cpp, document.cpp).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "scene.h"
#include "scene_delta.h"

namespace rtview {

// A replacement made in a text, with what it replaced, so that an undo step can take it
// back: [pos, pos + before.size()) held `before` and now holds `after`.
struct UndoableReplacement {
    std::size_t pos = 0;
    std::string before, after;
};

// A change of the editor text made by the document (a panel edit written back, undo,
// redo, revert): [pos, pos + removed) now holds `inserted`.
struct TextChange {
    std::size_t pos = 0, removed = 0;
    std::string inserted;
};

// One undo step: what an edit changed, both ways.
struct DocStep {
    std::string name;  // what the edit did, for the user: "Move sphere 3"
    std::vector<UndoableReplacement> editor;  // applied in order going forward, in reverse going back
    // The applied text when it differed from the editor text (a draft), before and after.
    std::optional<std::string> applied_before, applied_after;
    // The scene: the items that changed (index, value), or, for wide changes, nothing:
    // the scene is parsed again from the applied text.
    bool reparse = false;
    std::vector<std::pair<std::size_t, rt::Object>> objects_before, objects_after;
    std::vector<std::pair<std::size_t, rt::Plane>> planes_before, planes_after;
    std::vector<std::pair<std::size_t, rt::Light>> lights_before, lights_after;
    std::optional<rt::Camera> camera_before, camera_after;
    bool has_scene_before = false, has_scene_after = false;
    bool behind_before = false, behind_after = false;
    bool keep_applied = false;  // typing: the applied text is not part of the step
    std::size_t bytes() const;
};

// The one replacement that turns `a` into `b` (common prefix and suffix left out).
UndoableReplacement diff_texts(const std::string& a, const std::string& b);

// Changed items of two equally long lists, as (index, value) pairs both ways.
template <class T>
bool diff_items(const std::vector<T>& a, const std::vector<T>& b, std::vector<std::pair<std::size_t, T>>& before,
                std::vector<std::pair<std::size_t, T>>& after, std::size_t limit) {
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i] == b[i]) continue;
        if (before.size() >= limit) return false;
        before.push_back({i, a[i]});
        after.push_back({i, b[i]});
    }
    return true;
}

// The items of (index, value) lists, as a delta.
template <class O, class P, class L>
rt::SceneDelta items_of(const O& objects, const P& planes, const L& lights) {
    rt::SceneDelta d;
    for (const auto& p : objects) d.objects.push_back(std::uint32_t(p.first));
    for (const auto& p : planes) d.planes.push_back(std::uint32_t(p.first));
    for (const auto& p : lights) d.lights.push_back(std::uint32_t(p.first));
    d.normalize();
    return d;
}

// Beyond this many changed items an undo step parses the text again instead.
constexpr std::size_t kMaxStepItems = 4096;

constexpr const char* kTypingName = "Typing in the scene text";

}  // namespace rtview
