// The Objects tab's outline: every object (CSG operands nested), plane and light,
// one row each (see panels.h).
#include "panels.h"

#include <imgui.h>
#include <imgui_stdlib.h>

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

bool Panels::outline_selected(const ItemRef& me) const {
    if (sel_.many.empty()) return sel_.one == me;
    return me.path.empty() && is_selected(sel_, me.item);
}

void Panels::outline_click(const ItemRef& me) {
    // Shift, or Ctrl as ImGui's own lists have it: one more, or one fewer (an operand's
    // whole object: several things are moved, deleted and copied whole).
    const ImGuiIO& io = ImGui::GetIO();
    if (io.KeyShift || io.KeyCtrl) toggle(sel_, me.item);
    else select_one(sel_, me);
}

void Panels::draw_objects_tab() {
    if (!selection_valid(editor_.doc().scene(), sel_.one)) sel_.one = {};
    keep_existing(sel_, editor_.doc().scene());
    // At least seven rows of the outline, whatever the UI scale.
    float h = std::max(ImGui::GetTextLineHeightWithSpacing() * 7, ImGui::GetContentRegionAvail().y * 0.45f);
    ImVec2 top = ImGui::GetCursorScreenPos();
    float width = ImGui::GetContentRegionAvail().x;
    // A filter over the objects: a number or words of their rows (its row taken from
    // the outline's height, so that the properties below stay where they were).
    ImGui::SetNextItemWidth(-1);
    ImGui::InputTextWithHint("##outline_filter", "filter objects: a number or a name", &outline_filter_text_);
    probe_item("field_outline_filter");
    h = std::max(ImGui::GetTextLineHeightWithSpacing() * 6, h - ImGui::GetFrameHeightWithSpacing());
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
    if (outline_selected(me)) f |= ImGuiTreeNodeFlags_Selected;
    if (csg) f |= ImGuiTreeNodeFlags_DefaultOpen;
    else f |= ImGuiTreeNodeFlags_Leaf | ImGuiTreeNodeFlags_NoTreePushOnOpen;
    bool open = ImGui::TreeNodeEx("node", f, "%s", label.c_str());
    if (ImGui::IsItemVisible()) probe_item("outline_" + selection_name(me));
    if (ImGui::IsItemClicked() && !ImGui::IsItemToggledOpen()) outline_click(me);
    if (sel_.one == me && scroll_to_selection_) {
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

// The objects' rows: all of them, or those the filter finds (up to 2,000 rows: a long
// list says how many more there are).
void Panels::draw_outline_objects(const rt::Scene& s) {
    auto label_of = [&](std::size_t k) {
        const rt::Object& o = s.objects[k];
        std::string label = std::to_string(k + 1) + "  " + shape_name(o.shape) + "  " + shape_summary(o.shape);
        // Read from an included file: shown, edited there (the properties say so).
        if (const rt::Include* inc = included_file(s, ItemList::Object, k)) label += "  [" + inc->file + "]";
        return label;
    };
    outline_filter_.set(outline_filter_text_, editor_.doc().scene_version(), s.objects.size());
    const bool filtered = outline_filter_.active();
    std::string heading = "Objects (" + std::to_string(s.objects.size()) + ")";
    if (filtered) {
        // A few milliseconds of the frame: a million labels are read over a few seconds.
        outline_filter_.scan(0.004, label_of);
        heading += ", " + std::to_string(outline_filter_.matches().size()) + " matching";
        if (!outline_filter_.done()) heading += " (searching, " + std::to_string(int(outline_filter_.fraction() * 100)) + " %)";
        probe("outline_filter", std::to_string(outline_filter_.matches().size()) + (outline_filter_.done() ? " done" : " searching"));
    } else {
        probe("outline_filter", "off");
    }
    ImGui::SetNextItemOpen(true, ImGuiCond_Once);
    if (!ImGui::TreeNode("objects", "%s", heading.c_str())) return;
    const std::size_t n = filtered ? outline_filter_.matches().size() : s.objects.size();
    auto row = [&](std::size_t r) {
        const std::size_t k = filtered ? outline_filter_.matches()[r] : r;
        std::vector<int> path;
        ImGui::PushID(int(k));
        draw_object_node(s.objects[k], int(k), path, label_of(k));
        ImGui::PopID();
    };
    auto more = [&](std::size_t count) {
        if (count > 0)
            ImGui::TextDisabled(filtered ? "... %d more matching" : "... %d more (select them in the image, or filter)",
                                int(count));
    };
    // The selected object's row among them (n if none): shown past the first rows too,
    // without the rows between (a hundred thousand rows would hold up the frame).
    std::size_t selected = n;
    if (sel_.one.is(SceneItem::Kind::Object)) {
        const std::size_t k = std::size_t(sel_.one.item.index);
        if (!filtered) selected = k < n ? k : n;
        else if (auto it = std::lower_bound(outline_filter_.matches().begin(), outline_filter_.matches().end(), k);
                 it != outline_filter_.matches().end() && *it == k)
            selected = std::size_t(it - outline_filter_.matches().begin());
    }
    for (std::size_t r = 0; r < n; ++r) {
        row(r);
        if (r > 2000 && r + 1 < n) {
            if (selected > r && selected < n) {
                more(selected - r - 1);
                row(selected);
                more(n - selected - 1);
            } else {
                more(n - r - 1);
            }
            break;
        }
    }
    ImGui::TreePop();
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
        if (outline_selected(me)) f |= ImGuiTreeNodeFlags_Selected;
        ImGui::TreeNodeEx("node", f, "%s", label.c_str());
        if (ImGui::IsItemVisible()) probe_item("outline_" + selection_name(me));
        if (ImGui::IsItemClicked()) outline_click(me);
        if (sel_.one == me && scroll_to_selection_) {
            ImGui::SetScrollHereY();
            scroll_to_selection_ = false;
        }
    };
    draw_outline_objects(s);
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
