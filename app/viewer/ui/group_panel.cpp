// The properties panel with several things selected (see panels.h): how many, which,
// and what is done to all of them.
#include "panels.h"

#include <imgui.h>

#include <string>
#include <vector>

#include "item_fields.h"
#include "panel_widgets.h"
#include "probe.h"

namespace rtview {

void Panels::draw_group_properties() {
    Document& doc = editor_.doc();
    const rt::Scene& s = doc.scene();
    const std::string summary = selection_summary(sel_);
    ImGui::TextUnformatted(summary.c_str());
    probe("group", summary);
    // Which (the first few; the outline marks them all).
    constexpr std::size_t kListed = 8;
    std::string names;
    for (std::size_t k = 0; k < sel_.many.size() && k < kListed; ++k)
        names += (k ? ", " : "") + item_label(s, ItemRef{sel_.many[k], {}});
    if (sel_.many.size() > kListed) names += " and " + std::to_string(sel_.many.size() - kListed) + " more";
    wrapped_hint(names);
    ImGui::Separator();
    if (ImGui::Button("Duplicate all")) commands_.run(Command::Duplicate);
    probe_item("button_duplicate_all");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Ctrl+D: a copy of each beside it (one undo step)");
    ImGui::SameLine();
    if (ImGui::Button("Delete all")) commands_.run(Command::Delete);
    probe_item("button_delete_all");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Delete: all of them (one undo step)");
    // The material of the one added last, for every object among them.
    const ItemRef& last = sel_.one;
    if (last.is(SceneItem::Kind::Object) && std::size_t(last.item.index) < s.objects.size()) {
        const std::string label = "Give all objects the material of " + item_label(s, last);
        if (ImGui::Button(label.c_str()) && doc.edit_blocker().empty() && !doc.edit_held()) {
            const rt::Material m = s.objects[std::size_t(last.item.index)].material;
            const std::size_t n = give_material(doc, sel_.many, m);
            if (n > 0) {
                const std::string objects = std::to_string(n) + (n == 1 ? " object" : " objects");
                doc.name_edit("Material of " + item_label(s, last) + " for " + objects);
                doc.commit();
                status_.set_about_step("Gave " + objects + " the material of " + item_label(s, last) + " (Ctrl+Z undoes)",
                                       doc.history_changes());
            } else {
                status_.set("They have that material already");
            }
        }
        probe_item("button_give_material");
    }
    ImGui::Spacing();
    wrapped_hint("Drag the move handle in the picture: all of them move, as one undo step. Turning and sizing "
                 "(Y, U) and the fields work on one thing at a time: click one alone.");
    wrapped_hint("Shift+click in the picture or the list adds or takes out one; Ctrl+Shift+drag in the picture "
                 "adds what a box sees; Esc selects nothing.");
}

}  // namespace rtview
