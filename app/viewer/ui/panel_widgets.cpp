// Small ImGui pieces the panels share (see panel_widgets.h).
#include "panel_widgets.h"

#include "number_field.h"

namespace rtview {

void wrapped_coloured(const ImVec4& colour, const std::string& text) {
    ImGui::PushStyleColor(ImGuiCol_Text, colour);
    ImGui::TextWrapped("%s", text.c_str());
    ImGui::PopStyleColor();
}
void wrapped_hint(const std::string& text) {
    wrapped_coloured(ImGui::GetStyle().Colors[ImGuiCol_TextDisabled], text);
}

void same_line_if_fits(const char* next, float extra) {
    const ImGuiStyle& st = ImGui::GetStyle();
    const float w = ImGui::CalcTextSize(next, nullptr, true).x + 2 * st.FramePadding.x + extra;
    const float right = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
    if (ImGui::GetItemRectMax().x + st.ItemSpacing.x + w <= right) ImGui::SameLine();
}

const rt::Object* resolve(const rt::Scene& s, const ItemRef& sel) {
    if (!sel.is(SceneItem::Kind::Object) || sel.item.index >= int(s.objects.size())) return nullptr;
    const rt::Object* o = &s.objects[std::size_t(sel.item.index)];
    for (int k : sel.path) {
        auto* g = std::get_if<rt::Csg>(&o->shape);
        if (!g || k < 0 || k >= int(g->operands.size())) return nullptr;
        o = &g->operands[std::size_t(k)];
    }
    return o;
}

bool drag_vec3(const char* label, rt::Vec3& v, float speed, const char* format) {
    double a[3] = {v.x, v.y, v.z};
    NumberFieldSpec spec;
    spec.speed = speed;
    spec.format = format;
    if (!number_fields(label, a, 3, spec)) return false;
    v = {a[0], a[1], a[2]};
    return true;
}

Rect item_block(const ImVec2& top_left, float width) {
    ImVec2 end = ImGui::GetCursorScreenPos();
    return {top_left.x, top_left.y, width, end.y - top_left.y};
}

}  // namespace rtview
