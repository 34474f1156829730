// The move tool with several things selected (see move_tool.h): one move handle at
// their centre moves them all, as one undo step; where the handle is for any selection;
// the light markers a box select takes.
#include "move_tool.h"

#include <imgui.h>

#include <algorithm>

namespace rtview {

std::optional<rt::Vec3> MoveTool::handle_anchor(const Document& doc, const Selection& sel, HandleMode& mode) const {
    mode = HandleMode::Move;
    if (!doc.has_scene()) return std::nullopt;
    if (!sel.many.empty()) return group_anchor(doc.scene(), sel.many);  // (turn and size: one thing at a time)
    const std::optional<SceneItem> item = item_of_selection(sel.one);
    if (!item || included(doc.scene(), *item)) return std::nullopt;
    mode = mode_for(doc, sel.one);
    return item_anchor(doc.scene(), *item, sel.one.path);
}

bool MoveTool::press_group(Document& doc, const std::vector<SceneItem>& items, const ScreenView& view,
                           const Rect& image, bool usable, StatusLine& status) {
    ImGuiIO& io = ImGui::GetIO();
    double mx = io.MousePos.x, my = io.MousePos.y;
    const double s = ImGui::GetFontSize() / 13.0;
    if (!usable || !doc.has_scene() || doc.edit_held()) return false;
    const std::optional<rt::Vec3> anchor = group_anchor(doc.scene(), items);
    if (!anchor) return false;
    // (As for one item: a press is taken where the pointer was before it.)
    if (ImGui::IsMouseClicked(0) && before_press_) mx = before_press_->x, my = before_press_->y;
    before_press_.reset();
    if (!ImGui::IsMouseDown(0)) before_press_ = ScreenPoint{mx, my};
    const bool over = !io.WantCaptureMouse && image.contains(mx, my);
    hover_ = over ? hit_handle(handle_shape(view, *anchor, kArrow * s), mx, my, kTolerance * s) : HandlePart::None;
    if (hover_ == HandlePart::None || !ImGui::IsMouseClicked(0)) return hover_ != HandlePart::None && ImGui::IsMouseDown(0);
    if (const std::string blocked = doc.edit_blocker(); !blocked.empty()) {
        status.set(blocked, true);
        return true;
    }
    const rt::Scene& scene = doc.scene();
    GroupMove group(scene, items);
    if (group.size() == 0) {
        status.set("These things come from included files: edit them there", true);
        return true;
    }
    if (group.left_out() > 0)
        status.set(std::to_string(group.left_out()) + " of them come from included files and stay where they are");
    drag_.emplace(SceneItem{}, std::vector<int>{}, MoveDrag(hover_, *anchor, view, mx, my));
    drag_->snap = snap_step(scene_extent(scene));
    drag_->mode = HandleMode::Move;
    drag_->pivot = *anchor;
    drag_->group = std::move(group);
    return true;
}

std::vector<int> MoveTool::lights_in_box(double x0, double y0, double x1, double y1) const {
    if (x1 < x0) std::swap(x0, x1);
    if (y1 < y0) std::swap(y0, y1);
    std::vector<int> out;
    for (const LightMarker& m : markers_)
        if (m.at.x >= x0 && m.at.x <= x1 && m.at.y >= y0 && m.at.y <= y1) out.push_back(m.light);
    return out;
}

}  // namespace rtview
