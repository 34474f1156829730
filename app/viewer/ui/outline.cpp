// The Objects tab's outline: every object (CSG operands nested), plane and light,
// one row each (see panels.h).
#include "panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "camera_control.h"
#include "item_fields.h"
#include "imgui_common.h"
#include "number_field.h"
#include "layout.h"
#include "panel_widgets.h"
#include "probe.h"
#include "scene_schema.h"
#include "readout.h"
#include "render_request.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "shown_numbers.h"

namespace rtview {

namespace {

std::string fmt_vec(const rt::Vec3& v) {
    return rt::format_number(v.x) + " " + rt::format_number(v.y) + " " + rt::format_number(v.z);
}

// A short "where is it" for outline labels.
std::string shape_summary(const rt::Shape& s) {
    if (auto* sp = std::get_if<rt::Sphere>(&s)) return "at " + fmt_vec(sp->position);
    if (auto* t = std::get_if<rt::Torus>(&s)) return "at " + fmt_vec(t->position);
    if (auto* c = std::get_if<rt::Cylinder>(&s)) return fmt_vec(c->end1) + " .. " + fmt_vec(c->end2);
    if (auto* t = std::get_if<rt::Tetrahedron>(&s)) return "vect1 " + fmt_vec(t->v[0]);
    if (auto* m = std::get_if<rt::Mesh>(&s)) return m->file.substr(m->file.find_last_of('/') + 1) + " at " + fmt_vec(m->position);
    if (auto* b = std::get_if<rt::Box>(&s)) return fmt_vec(b->corner1) + " .. " + fmt_vec(b->corner2);
    if (auto* c = std::get_if<rt::Cone>(&s)) return fmt_vec(c->end1) + " .. " + fmt_vec(c->end2);
    if (auto* in = std::get_if<rt::Instance>(&s)) return "of " + in->object;
    return {};
}

bool selection_valid(const rt::Scene& s, const ItemRef& sel) {
    if (sel.none()) return true;
    switch (sel.item.kind) {
        case SceneItem::Kind::Object: return resolve(s, sel) != nullptr;
        case SceneItem::Kind::Plane: return sel.item.index < int(s.planes.size());
        case SceneItem::Kind::Light: return sel.item.index < int(s.lights.size());
    }
    return false;
}

}  // namespace

void Panels::draw_objects_tab() {
    if (!selection_valid(editor_.doc().scene(), selection_)) selection_ = {};
    // At least seven rows of the outline, whatever the UI scale.
    float h = std::max(ImGui::GetTextLineHeightWithSpacing() * 7, ImGui::GetContentRegionAvail().y * 0.45f);
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    // Long labels scroll sideways instead of being cut at the edge.
    if (ImGui::BeginChild("outline", ImVec2(0, h), true, ImGuiWindowFlags_HorizontalScrollbar)) draw_outline();
    ImGui::EndChild();
    layout_.outline = item_block(top, width);
    if (ImGui::BeginChild("properties", ImVec2(0, 0), false)) draw_properties();
    ImGui::EndChild();
}

void Panels::draw_object_node(const rt::Object& obj, int top, std::vector<int>& path, const std::string& label) {
    ItemRef me{{SceneItem::Kind::Object, top}, path};
    auto* csg = std::get_if<rt::Csg>(&obj.shape);
    ImGuiTreeNodeFlags f = ImGuiTreeNodeFlags_OpenOnArrow | ImGuiTreeNodeFlags_SpanAvailWidth;
    if (selection_ == me) f |= ImGuiTreeNodeFlags_Selected;
    if (csg) f |= ImGuiTreeNodeFlags_DefaultOpen;
    else f |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
    bool open = ImGui::TreeNodeEx("node", f, "%s", label.c_str());
    if (ImGui::IsItemVisible()) probe_item("outline_" + selection_name(me));
    if (ImGui::IsItemClicked() && !ImGui::IsItemToggledOpen()) selection_ = me;
    if (selection_ == me && scroll_to_selection_) {
        ImGui::SetScrollHereY();
        scroll_to_selection_ = false;
    }
    if (csg && open) {
        for (std::size_t i = 0; i < csg->operands.size(); ++i) {
            const rt::Object& o = csg->operands[i];
            path.push_back(int(i));
            ImGui::PushID(int(i));
            draw_object_node(o, top, path, std::string(i == 0 ? "left: " : "right: ") + shape_name(o.shape));
            ImGui::PopID();
            path.pop_back();
        }
        ImGui::TreePop();
    }
}

void Panels::draw_outline() {
    if (!editor_.doc().has_scene()) {
        ImGui::TextDisabled(editor_.doc().has_errors() ? "No scene yet: fix the errors in the Text tab."
                                                       : "No scene yet.");
        return;
    }
    const rt::Scene& s = editor_.doc().scene();
    auto leaf = [&](const ItemRef& me, const std::string& label) {
        ImGuiTreeNodeFlags f = ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen |
                               ImGuiTreeNodeFlags_SpanAvailWidth;
        if (selection_ == me) f |= ImGuiTreeNodeFlags_Selected;
        ImGui::TreeNodeEx("node", f, "%s", label.c_str());
        if (ImGui::IsItemVisible()) probe_item("outline_" + selection_name(me));
        if (ImGui::IsItemClicked()) selection_ = me;
        if (selection_ == me && scroll_to_selection_) {
            ImGui::SetScrollHereY();
            scroll_to_selection_ = false;
        }
    };
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("objects", "Objects (%d)", int(s.objects.size()))) {
        // Clip long lists: only visible rows cost anything (scenes may hold many objects).
        for (int k = 0; k < int(s.objects.size()); ++k) {
            const rt::Object& o = s.objects[std::size_t(k)];
            std::vector<int> path;
            ImGui::PushID(k);
            std::string label = std::to_string(k + 1) + "  " + shape_name(o.shape) + "  " + shape_summary(o.shape);
            // Read from an included file: shown, edited there (the properties say so).
            if (const rt::Include* inc = included_file(s, ItemList::Object, std::size_t(k))) label += "  [" + inc->file + "]";
            draw_object_node(o, k, path, label);
            ImGui::PopID();
            if (k > 2000 && !scroll_to_selection_) {
                ImGui::TextDisabled("... %d more (select them in the image)", int(s.objects.size()) - k - 1);
                break;
            }
        }
        ImGui::TreePop();
    }
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("planes", "Planes (%d)", int(s.planes.size()))) {
        for (int k = 0; k < int(s.planes.size()); ++k) {
            ImGui::PushID(k);
            leaf({{SceneItem::Kind::Plane, k}, {}}, std::to_string(k + 1) + "  " + (s.planes[std::size_t(k)].chess ? "chess_plane" : "plane"));
            ImGui::PopID();
        }
        ImGui::TreePop();
    }
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (ImGui::TreeNode("lights", "Lights (%d)", int(s.lights.size()))) {
        for (int k = 0; k < int(s.lights.size()); ++k) {
            const rt::Light& l = s.lights[std::size_t(k)];
            ImGui::PushID(k);
            leaf({{SceneItem::Kind::Light, k}, {}}, std::to_string(k + 1) + "  " + (l.lamp ? "lamp" : "spotlight") + "  at " + fmt_vec(l.position));
            ImGui::PopID();
        }
        ImGui::TreePop();
    }
    if (s.lights.empty()) {
        // Whatever is added stays black until a light is: say so where lights are listed.
        const char* hint = "No lights: everything renders black. Right-click the picture > Add here > lamp.";
        wrapped_coloured(kWarnColour, hint);
        probe("outline_hint", hint);
    }
    scroll_to_selection_ = false;
}

}  // namespace rtview
