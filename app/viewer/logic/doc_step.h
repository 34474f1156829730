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
#include "scene_text.h"
#include "text_replacement.h"

namespace rtview {

// A structural edit made without parsing the whole text (Document::replace_text with
// an ItemSplice): one item of one list inserted, removed or replaced, with its value as
// it was and as it is (the only item of its list in `before`, `after`), where its block
// is in the text, and the place of the text's replacement as the parser counts lines
// and columns (the same before and after it: the text before it does not change).
struct SplicedItem {
    ItemSplice::Op op = ItemSplice::Op::Insert;
    ItemList list = ItemList::Object;
    std::size_t index = 0;
    rt::Scene before, after;
    TextSpan block_before, block_after;
    rt::SourceLoc at;
};

// What a spliced item changes in the scene, made (`forward`) or undone: an object
// inserted or removed, the planes' or lights' list made again, or one item in place.
inline rt::SceneDelta splice_delta(const SplicedItem& s, bool forward = true) {
    rt::SceneDelta d;
    if (s.op != ItemSplice::Op::Replace) {
        if (s.list == ItemList::Object)
            d.object_splices.push_back({std::uint32_t(s.index), (s.op == ItemSplice::Op::Insert) == forward});
        else if (s.list == ItemList::Plane)
            d.all_planes = true;
        else
            d.all_lights = true;
        return d;
    }
    (s.list == ItemList::Object ? d.objects : s.list == ItemList::Plane ? d.planes : d.lights)
        .push_back(std::uint32_t(s.index));
    return d;
}

// One undo step: what an edit changed, both ways.
struct DocStep {
    std::string name;  // what the edit did, for the user: "Move sphere 3"
    // The editor text's replacements, applied in order going forward; and each one's
    // inverse, applied in reverse order going back.
    std::vector<TextReplacement> editor, editor_back;
    // The line and column of each replacement's offset, as the text has it both ways
    // (the positions after it move with it), when known.
    std::vector<rt::SourceLoc> editor_at;
    // `r`, made in `before` (the editor text before it), is part of the step.
    void made(TextReplacement r, const std::string& before) {
        if (r.empty()) return;
        editor_back.push_back(r.inverse(before));
        editor.push_back(std::move(r));
    }
    // The applied text when it differed from the editor text (a draft), before and after.
    std::optional<std::string> applied_before, applied_after;
    // The scene: the items that changed (index, value), or, for wide changes, nothing:
    // the scene is parsed again from the applied text.
    bool reparse = false;
    std::vector<std::pair<std::size_t, rt::Object>> objects_before, objects_after;
    std::vector<std::pair<std::size_t, rt::Plane>> planes_before, planes_after;
    std::vector<std::pair<std::size_t, rt::Light>> lights_before, lights_after;
    std::optional<rt::Camera> camera_before, camera_after;
    // A named material's edit: its definition, and those of the named objects that use
    // it (the items that use it are among the objects and planes above).
    std::vector<std::pair<std::size_t, rt::NamedMaterial>> materials_before, materials_after;
    std::vector<std::pair<std::size_t, rt::NamedObject>> defined_before, defined_after;
    bool has_scene_before = false, has_scene_after = false;
    bool behind_before = false, behind_after = false;
    bool keep_applied = false;  // typing: the applied text is not part of the step
    // A structural edit of one item, spliced into the scene rather than parsed again
    // (with `editor` its one replacement).
    std::optional<SplicedItem> spliced;
    // Several such edits as one step (a group Delete or Duplicate): the i-th is made by
    // the i-th of `editor`, in order going forward, and undone in reverse order.
    std::vector<SplicedItem> spliced_many;
    std::size_t bytes() const;
};

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
