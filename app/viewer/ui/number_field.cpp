// Number fields (see number_field.h). One field at a time is typed into: its ImGui id,
// its text and whether it has had the keyboard yet are kept here, on the UI thread.
#include "number_field.h"

#include <imgui.h>
#include <imgui_internal.h>  // PushMultiItemsWidths, ClearActiveID: 1.86 has no public way

#include <algorithm>

#include "bounded_input.h"
#include "item_fields.h"
#include "probe.h"
#include "scene_writer.h"

namespace rtview {

namespace {

constexpr std::size_t kMaxTypedBytes = 1024;

struct Typing {
    ImGuiID id = 0;        // the field typed into; 0: none
    std::string text;
    int frames = 0;        // frames since typing began (the text field takes a frame to activate)
    bool had_focus = false;
    std::string refusal;   // the last refused text's message, until taken
    bool refusal_error = true;  // else a note
    std::string refusal_label;  // the field's label
} g_typing;

// The message when a typed value is brought into the field's range.
std::string range_note(const char* label, double typed, double now, double old, const std::string& range) {
    const char* end = ImGui::FindRenderedTextEnd(label);
    std::string text = std::string(label, end) + (end == label ? "" : " ");
    text += rt::format_number(typed) + " is " + range + ": ";
    return text + (now == old ? "it stays " : "set to ") + rt::format_number(now);
}

bool starts_typing() {
    const ImGuiIO& io = ImGui::GetIO();
    return ImGui::IsItemHovered() && ((ImGui::IsMouseClicked(0) && io.KeyCtrl) || ImGui::IsMouseDoubleClicked(0));
}

// The typed text, committed on Enter or when the field loses the keyboard; Escape
// drops it. True when *v took a new value.
bool typed_field(const char* label, double* v, const NumberFieldSpec& spec) {
    Typing& t = g_typing;
    if (t.frames++ == 0) ImGui::SetKeyboardFocusHere();
    // (Past the parser's longest token a number is refused anyway: a paste is cut.)
    const bool enter = bounded_input(label, nullptr, t.text, kMaxTypedBytes,
                                     ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    const bool active = ImGui::IsItemActive();
    probe("typing", std::string(label) + (active ? " active" : ""));
    t.had_focus |= active;
    const bool escape = active && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape));
    // Focus never came (another widget took it) or went: the text is let go or taken.
    const bool left = (t.had_focus && !active) || (!t.had_focus && t.frames > 3);
    if (!enter && !left && !escape) return false;
    const std::string text = t.text;
    t = Typing{0, {}, 0, false, t.refusal, t.refusal_error, t.refusal_label};
    if (escape) return false;
    double x = 0;
    if (const rt::Status st = parse_typed_number(text, x); !st) {
        t.refusal = st.message();
        t.refusal_error = true;
        t.refusal_label = label;
        return false;
    }
    auto note = [&](double now, const std::string& range) {
        t.refusal = range_note(label, x, now, *v, range);
        t.refusal_error = false;
        t.refusal_label = label;
        x = now;
    };
    if (spec.clamp_typed && spec.min && spec.max && (x < *spec.min || x > *spec.max))
        note(std::clamp(x, *spec.min, *spec.max),
             "outside " + rt::format_number(*spec.min) + ".." + rt::format_number(*spec.max));
    if (spec.least && x < *spec.least) note(*spec.least, "below the least value, " + rt::format_number(*spec.least));
    if (x == *v) return false;
    *v = x;
    return true;
}

}  // namespace

bool number_field(const char* label, double* v, const NumberFieldSpec& spec) {
    const ImGuiID id = ImGui::GetID(label);
    if (g_typing.id == id) {
        ImGui::PushID("typing");
        const bool changed = typed_field(label, v, spec);
        ImGui::PopID();
        return changed;
    }
    const ImGuiSliderFlags flags = ImGuiSliderFlags_NoInput | (spec.clamp_typed ? ImGuiSliderFlags_AlwaysClamp : 0);
    // A slider takes the value under the pointer in the frame it is clicked (1.86's
    // SliderBehavior, even with NoInput): a Ctrl+click that opens the text field must
    // not have moved it, so the value as it was is kept for that case.
    const double before = *v;
    bool changed = spec.slider && spec.min && spec.max
                             ? ImGui::SliderScalar(label, ImGuiDataType_Double, v, spec.min, spec.max, spec.format, flags)
                             : ImGui::DragScalar(label, ImGuiDataType_Double, v, spec.speed, spec.min, spec.max,
                                                 spec.format, flags);
    if (starts_typing()) {
        ImGui::ClearActiveID();  // the click is the typing's, not the start of a drag
        *v = before;
        changed = false;
        g_typing = Typing{id, rt::format_number(*v), 0, false, g_typing.refusal, g_typing.refusal_error,
                          g_typing.refusal_label};
    } else if (ImGui::IsItemHovered() && !ImGui::IsItemActive()) {
        ImGui::SetTooltip(spec.slider ? "Drag, or Ctrl+click to type a value" : "Drag, or Ctrl+click (double-click) to type a value");
    }
    return changed;
}

bool number_fields(const char* label, double* v, int n, const NumberFieldSpec& spec) {
    const ImGuiStyle& style = ImGui::GetStyle();
    bool changed = false;
    ImGui::BeginGroup();
    ImGui::PushID(label);
    ImGui::PushMultiItemsWidths(n, ImGui::CalcItemWidth());
    for (int i = 0; i < n; ++i) {
        ImGui::PushID(i);
        if (i > 0) ImGui::SameLine(0, style.ItemInnerSpacing.x);
        changed |= number_field("", v + i, spec);
        ImGui::PopID();
        ImGui::PopItemWidth();
    }
    ImGui::PopID();
    const char* end = ImGui::FindRenderedTextEnd(label);
    if (end != label) {
        ImGui::SameLine(0, style.ItemInnerSpacing.x);
        ImGui::TextEx(label, end);
    }
    ImGui::EndGroup();
    return changed;
}

bool number_typing() { return g_typing.id != 0; }

bool take_number_refusal(std::string& message, bool* error, std::string* label) {
    if (g_typing.refusal.empty()) return false;
    message = std::move(g_typing.refusal);
    g_typing.refusal.clear();
    if (error) *error = g_typing.refusal_error;
    if (label) *label = std::string(g_typing.refusal_label.c_str(), ImGui::FindRenderedTextEnd(g_typing.refusal_label.c_str()));
    return true;
}

}  // namespace rtview
