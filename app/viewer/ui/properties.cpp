// The selected item's properties: its fields from the schema, a light's colour and
// the material editor (see panels.h).
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
#include "model.h"
#include "paths.h"
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

// A material's texture: the name as the scene text has it (relative to the scene's
// folder), typed (Enter) or chosen with the file browser (`browse`: its button was
// pressed); an empty one takes the texture away.
bool texture_field(const char* id, const rt::schema::Key<rt::Material>& k, rt::Material& m, bool& browse) {
    const std::string label(k.name);
    std::string& name = k.access.text(m, 0);
    std::string typed = name;
    bool changed = false;
    const float gap = ImGui::GetStyle().ItemInnerSpacing.x;
    const float button_w = ImGui::CalcTextSize("...").x + 2 * ImGui::GetStyle().FramePadding.x;
    ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - button_w - gap);
    if (ImGui::InputTextWithHint(("##" + label).c_str(), k.default_text ? k.default_text : "", &typed,
                                 ImGuiInputTextFlags_EnterReturnsTrue) &&
        typed != name) {
        name = typed;
        changed = true;
    }
    // For scripts: "field_material_1_texture", "button_material_1_texture_browse".
    std::string key = std::string(id) + "_" + label;
    std::replace(key.begin(), key.end(), ' ', '_');
    probe_item("field_" + key);
    probe("value_" + key, name);
    ImGui::SameLine(0, gap);
    if (ImGui::Button(("...##browse_" + label).c_str())) browse = true;
    probe_item("button_" + key + "_browse");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Choose the %s file", label.c_str());
    ImGui::SameLine(0, gap);
    ImGui::TextUnformatted(label.c_str());
    return changed;
}

// The keys of a material block, from the schema: weights as 0..1 sliders (values
// above 1 are legal, the renderer normalises them: Ctrl+click to type one), clamped
// keys within their clamp, colours with a picker, the texture's file name
// (texture_field). Labels are the format's key names.
// A message for a typed value just came: once drawn, it is scrolled into sight if the
// panel's edge cuts it off (the field typed into may be the last one showing).
bool g_new_message = false;
void scroll_to_new_message() {
    if (!g_new_message) return;
    g_new_message = false;
    if (ImGui::GetItemRectMax().y > ImGui::GetWindowPos().y + ImGui::GetWindowHeight()) ImGui::SetScrollHereY(1.0f);
}

// The format's weights are 0 or more; the parser takes a negative one as written, so
// the panel says so.
void negative_weights_note(const char* id, const rt::Material& m) {
    std::string negative;
    for (const auto& [name, w] : {std::pair<const char*, double>{"reflection", m.reflection},
                                  {"refraction", m.refraction}, {"scattering", m.scattering}})
        if (w < 0) negative += (negative.empty() ? "" : ", ") + std::string(name);
    if (negative.empty()) return;
    const std::string text = negative + (negative.find(',') == std::string::npos ? " is" : " are") +
                             " negative: weights are 0 or more (the picture is not what the format means)";
    wrapped_coloured(kWarnColour, text);
    probe(std::string("weights_") + id, text);
}

// `note_key`: the key whose field shows `note` under it (a typed value refused or
// brought into range), in red if `note_error`. `browse`: the texture's browse button
// was pressed.
bool material_editor(const char* id, rt::Material& m, bool& browse, const std::string& note_key = {},
                     const std::string& note = {}, bool note_error = false) {
    auto show_note = [&](const std::string& key) {
        if (note.empty() || key != note_key) return;
        wrapped_coloured(note_error ? kErrorColour : kWarnColour, note);
        scroll_to_new_message();
    };
    namespace sc = rt::schema;
    ImGui::PushID(id);
    bool changed = false;
    for (const sc::Key<rt::Material>& k : sc::material_block().keys) {
        const std::string label(k.name);
        if (k.kind == sc::Kind::File) {
            changed |= texture_field(id, k, m, browse);
            continue;
        }
        if (k.kind == sc::Kind::Vec3) {
            // The three numbers (typed whole, or dragged), and a swatch with a picker.
            rt::Vec3& c = k.access.vec3(m, 0);
            float col[3] = {float(c.x), float(c.y), float(c.z)};
            if (ImGui::ColorEdit3(("##pick" + label).c_str(), col,
                                  ImGuiColorEditFlags_Float | ImGuiColorEditFlags_HDR | ImGuiColorEditFlags_NoInputs)) {
                // The channels as the picker shows them (three decimals); the others
                // as they were, not as a float holds them.
                c = {from_widget(c.x, col[0], 3), from_widget(c.y, col[1], 3), from_widget(c.z, col[2], 3)};
                changed = true;
            }
            ImGui::SameLine(0, ImGui::GetStyle().ItemInnerSpacing.x);
            ImGui::SetNextItemWidth(ImGui::CalcItemWidth() - ImGui::GetFrameHeight() - ImGui::GetStyle().ItemInnerSpacing.x);
            changed |= drag_vec3(label.c_str(), c, 0.005f);
            probe_item(std::string("field_") + id + "_" + label);  // for scripts: "field_material_colour"
            continue;
        }
        if (k.kind != sc::Kind::Number) continue;
        double& v = k.access.number(m, 0);
        if (k.range.rule == sc::Range::Rule::Error) {
            // A range the parser enforces (specular 0..1, shininess 1..10000, texture_scale
            // > 0): a slider over a short one, else a drag; typed values kept inside.
            const double lo = k.range.min, hi = k.range.max;
            const double lo_field = k.range.min_open ? lo + 1e-3 : lo;
            NumberFieldSpec spec;
            spec.slider = hi - lo <= 1;
            spec.min = &lo_field;
            spec.max = hi < 1e300 ? &hi : nullptr;
            spec.speed = spec.slider ? 1 : float(std::max(0.01, 0.005 * std::max(1.0, std::fabs(v))));
            spec.clamp_typed = true;
            changed |= number_field(label.c_str(), &v, spec);
            probe_item(std::string("field_") + id + "_" + label);
            probe(std::string("value_") + id + "_" + label, rt::format_number(v));
            show_note(label);
            continue;
        }
        const bool clamped = k.range.rule == sc::Range::Rule::Clamp;
        const double lo = clamped ? k.range.min : 0;
        const double hi = clamped && k.range.max <= lo + 1 ? k.range.max : lo + (clamped ? 2 : 1);
        NumberFieldSpec spec;
        spec.slider = true;
        spec.min = &lo;
        spec.max = &hi;
        spec.clamp_typed = clamped && k.range.max <= lo + 1;
        // A typed value under the format's least (a refractive index below 1) is
        // raised to it, as the parser would, and the field says so.
        spec.least = clamped ? &k.range.min : nullptr;
        changed |= number_field(label.c_str(), &v, spec);
        probe_item(std::string("field_") + id + "_" + label);
        probe(std::string("value_") + id + "_" + label, rt::format_number(v));
        show_note(label);
        if (label == "scattering") negative_weights_note(id, m);  // under the three weights
    }
    double sum = m.reflection + m.refraction + m.scattering;
    if (sum != 0)
        ImGui::TextWrapped("used as: reflection %.2f, refraction %.2f, scattering %.2f", m.reflection / sum,
                           m.refraction / sum, m.scattering / sum);
    else
        wrapped_coloured(kWarnColour, "all weights 0: the surface renders black");
    ImGui::PopID();
    return changed;
}

// Whether two values of a field are the same (what a message about the field is about).
bool same_value(const FieldValue& a, const FieldValue& b) {
    return a.number == b.number && a.vec == b.vec && a.choice == b.choice && a.material == b.material &&
           a.has_material == b.has_material && a.operand == b.operand && a.text == b.text;
}

}  // namespace

void Panels::draw_properties() {
    if (!editor_.doc().has_scene()) return;
    if (!sel_.many.empty()) return draw_group_properties();
    const rt::Scene& s = editor_.doc().scene();
    if (!(field_message_.selection == sel_.one)) field_message_ = {};
    if (sel_.one.none()) {
        wrapped_hint("Click an object in the image or in the list above.");
        return;
    }
    const ItemRef ref = sel_.one;
    const char* block = item_block_name(s, ref);
    if (!block) return;
    // "Object 5: constructive_solid_geometry", "Object 5, left, right: sphere".
    std::string title;
    switch (sel_.one.item.kind) {
        case SceneItem::Kind::Object: title = "Object " + std::to_string(sel_.one.item.index + 1); break;
        case SceneItem::Kind::Plane: title = "Plane " + std::to_string(sel_.one.item.index + 1); break;
        case SceneItem::Kind::Light: title = "Light " + std::to_string(sel_.one.item.index + 1); break;
    }
    for (int k : sel_.one.path) title += k == 0 ? ", left" : ", right";
    title += std::string(": ") + block;
    ImGui::TextWrapped("%s", title.c_str());
    rt::SourceLoc loc;
    if (sel_.one.is(SceneItem::Kind::Object)) {
        if (const rt::Object* o = resolve(s, sel_.one)) loc = o->loc;
    } else if (sel_.one.is(SceneItem::Kind::Plane)) {
        loc = s.planes[std::size_t(sel_.one.item.index)].loc;
    } else {
        loc = s.lights[std::size_t(sel_.one.item.index)].loc;
    }
    // An item an include brought has no block in this file's text: shown, not edited
    // here (Save could not keep the edit).
    const ItemList list = sel_.one.item.kind == SceneItem::Kind::Object  ? ItemList::Object
                          : sel_.one.item.kind == SceneItem::Kind::Plane ? ItemList::Plane
                                                                           : ItemList::Light;
    const rt::Include* included = included_file(s, list, std::size_t(sel_.one.item.index));
    if (included) {
        wrapped_coloured(kWarnColour, "From the included file \"" + included->file +
                                          "\" (read only here: open that file to edit it).");
        probe("included_from", included->file);
        if (included->loc.line > 0 && ImGui::SmallButton("show the include"))
            editor_.focus(int(offset_of(std::as_const(editor_.doc()).editor_text(), included->loc.line, included->loc.col)));
        loc = {};  // (a place in the other file)
    }
    if (loc.line > 0 && ImGui::SmallButton("show in text"))
        editor_.focus(int(offset_of(std::as_const(editor_.doc()).editor_text(), loc.line, loc.col)));
    if (!sel_.one.path.empty()) {
        if (loc.line > 0) same_line_if_fits("select the parent");
        const bool parent = ImGui::SmallButton("select the parent");
        probe_item("button_select_the_parent");
        if (parent) {
            sel_.one.path.pop_back();
            return;
        }
        wrapped_hint("A CSG operand: its shape counts; its colour and finish are the whole CSG's material (select "
                     "the parent to edit it).");
    }
    if (sel_.one.is(SceneItem::Kind::Light)) {
        // The block's kind: switching keeps the lamp's size for switching back.
        const bool lamp = s.lights[std::size_t(sel_.one.item.index)].lamp;
        if (ImGui::SmallButton(lamp ? "make it a spotlight" : "make it a lamp")) commands_.run(Command::SwitchLight);
        const char* what = lamp ? "(point light and glow)" : "(point light)";
        same_line_if_fits(what);
        ImGui::TextDisabled("%s", what);
    }
    ImGui::Separator();
    // Nothing here may change the scene while the text holds changes it could not be
    // written into: Save writes that text.
    const std::string blocked = editor_.doc().edit_blocker();
    if (!blocked.empty()) {
        wrapped_coloured(kWarnColour, blocked);
        probe("edits", "blocked");
    }
    ImGui::BeginDisabled(!blocked.empty() || included);
    draw_fields(ref);
    ImGui::EndDisabled();
}

// One widget per key of the selected item's block, from the schema (item_fields.h):
// what the panel offers is what the format has. A change goes through set_field, so the
// parser's ranges apply; a refused value leaves the item as it was and says why.
void Panels::draw_fields(const ItemRef& ref) {
    Document& doc = editor_.doc();
    const std::vector<Field> fields = item_fields(doc.scene(), ref);
    // Room for the longest label, whatever the UI scale.
    const float label_w = field_label_width();
    const float size = float(rtview::scene_extent(editor_.doc().scene(), render_.world()));
    // Dragging rounds to the digits shown: enough of them for a small scene.
    char vec_format[16];
    std::snprintf(vec_format, sizeof vec_format, "%%.%df", std::clamp(4 - int(std::floor(std::log10(size))), 3, 9));
    int operand = 0;
    std::string shown;  // the fields drawn, for scripts (probe.h)
    for (const Field& f : fields) {
        std::optional<FieldValue> cur = field_value(doc.scene(), ref, f);
        if (!cur) continue;
        shown += (shown.empty() ? "" : ",") + f.label;
        FieldValue v = *cur;
        if (field_message_.field == f.label) {
            // (A message set with an edit is about the value the edit left: the next frame's.)
            if (!field_message_.value) field_message_.value = *cur;
            else if (!same_value(*field_message_.value, *cur)) field_message_ = {};
        }
        ImGui::PushID(f.label.c_str());
        ImGui::PushItemWidth(-(label_w + ImGui::GetStyle().ItemInnerSpacing.x + 2));
        const bool changed = draw_field(ref, f, v, size, vec_format, operand);
        ImGui::PopItemWidth();
        {
            // Where the field is, for scripts that click on it, and its value as the
            // text will hold it (a drag's value before it reaches the text).
            std::string key = "field_" + f.label;
            std::replace(key.begin(), key.end(), ' ', '_');
            probe_item(key);
            if (f.kind == rt::schema::Kind::Number) probe("value_" + f.label, rt::format_number(cur->number));
            else if (f.kind == rt::schema::Kind::Vec3)
                probe("value_" + f.label, rt::format_number(cur->vec.x) + " " + rt::format_number(cur->vec.y) + " " +
                                              rt::format_number(cur->vec.z));
        }
        bool error = true, noted = false;
        if (std::string refused, label; take_number_refusal(refused, &error, &label)) {
            // (A material's own keys are typed into inside the "material" field.)
            const bool inner = !label.empty() && label != f.label;
            if (inner && refused.compare(0, label.size() + 1, label + " ") != 0) refused = label + ": " + refused;
            field_message_ = {sel_.one, f.label, refused, error, inner ? label : std::string(), *cur};
            noted = !error;
            g_new_message = true;
        }
        if (changed) {
            const FieldResult r = set_field(doc, ref, f, v);
            if (!r.status) field_message_ = {sel_.one, f.label, r.status.message(), true, {}, *cur};
            // (A material's own warning is shown by its editor already.)
            else if (!r.warning.empty() && f.kind != rt::schema::Kind::Material) field_message_ = {sel_.one, f.label, r.warning, false, {}, {}};
            else if (field_message_.field == f.label && (field_message_.error || !noted)) field_message_ = {};
            else if (field_message_.field == f.label) field_message_.value.reset();  // about the value set
        }
        if (field_message_.field == f.label && !field_message_.text.empty()) {
            if (field_message_.sub.empty()) {
                wrapped_coloured(field_message_.error ? kErrorColour : kWarnColour, field_message_.text);
                scroll_to_new_message();
            }
            probe("field_message", f.label + ": " + field_message_.text);
        }
        ImGui::PopID();
    }
    probe("fields", shown);
}

// A material field: whose it is (a named material's users, Make local), then its
// editor; true if it changed.
bool Panels::draw_material_field(const ItemRef& ref, const Field& f, FieldValue& v) {
    ImGui::Separator();
    const rt::Scene& scene = editor_.doc().scene();
    if (const int k = named_material_of(scene, ref, f); k >= 0) {
        // A named material: an edit here changes it for every thing that uses it.
        const std::string& name = scene.materials[std::size_t(k)].name;
        const std::size_t users = material_users(scene, std::size_t(k));
        const std::string said = f.label + " `" + name + "`, used by " + std::to_string(users) +
                                 (users == 1 ? " thing" : " things") + ": an edit changes it for all";
        ImGui::TextWrapped("%s", said.c_str());
        probe("material_shared", said);
        if (ImGui::Button("Make local")) {
            const FieldResult r = make_material_local(editor_.doc(), ref, f);
            if (!r.status) field_message_ = {sel_.one, f.label, r.status.message(), true, {}, {}};
        }
        probe_item("make_local");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Give this thing its own copy of %s to edit", name.c_str());
    } else {
        ImGui::TextWrapped("%s%s", f.label.c_str(), v.has_material ? "" : " (none in the file: the default)");
        probe("material_shared", "");
    }
    bool browse = false;
    // A message about one of its keys shows under that key's field.
    const bool note = field_message_.field == f.label && !field_message_.sub.empty();
    const bool changed = material_editor(f.label.c_str(), v.material, browse, note ? field_message_.sub : std::string(),
                                         note ? field_message_.text : std::string(), field_message_.error);
    if (browse) {
        // The browser starts at the texture's file, else in the scene's folder;
        // its answer comes back as set_texture().
        texture_target_ = {ref, f.label};
        const rt::Material& now = v.material;
        commands_.run(Command::TextureDialog, now.texture_image && !now.texture_image->path().empty()
                                                  ? now.texture_image->path()
                                                  : rt::folder_of(editor_.doc().path()));
    }
    return changed;
}

// The widget of one field of the kind the schema gives it, editing `v`; true if it
// changed. `size`: the scene's extent (drag speeds); `operand` counts a CSG's operands.
bool Panels::draw_field(const ItemRef& ref, const Field& f, FieldValue& v, float size, const char* vec_format,
                        int& operand) {
    namespace sc = rt::schema;
    bool changed = false;
    switch (f.kind) {
        case sc::Kind::Number: {
            NumberFieldSpec spec;
            spec.speed = std::max(float(std::fabs(v.number)) * 0.005f, size * 0.0005f);
            spec.format = "%.6g";
            changed = number_field(f.label.c_str(), &v.number, spec);
            break;
        }
        case sc::Kind::Vec3: {
            if (ref.item.kind == SceneItem::Kind::Light && f.key == "colour") {
                changed = light_colour_editor(v.vec);
                break;
            }
            changed = drag_vec3(f.label.c_str(), v.vec, size * 0.002f, vec_format);
            break;
        }
        case sc::Kind::Integer: {
            NumberFieldSpec spec;
            spec.format = "%.0f";
            changed = number_field(f.label.c_str(), &v.number, spec);
            break;
        }
        case sc::Kind::Choice: {
            const std::string now(f.choice->word_for(v.choice));
            if (ImGui::BeginCombo(f.label.c_str(), choice_label(f.key, now).c_str())) {
                std::vector<int> seen;
                for (const sc::Choice::Word& w : f.choice->words) {
                    if (std::find(seen.begin(), seen.end(), w.value) != seen.end()) continue;
                    seen.push_back(w.value);
                    if (ImGui::Selectable(choice_label(f.key, w.word).c_str(), w.value == v.choice) && w.value != v.choice) {
                        v.choice = w.value;
                        changed = true;
                    }
                }
                ImGui::EndCombo();
            }
            break;
        }
        case sc::Kind::Material: changed = draw_material_field(ref, f, v); break;
        case sc::Kind::File:
            // The model is read with the scene: a new name is typed in the scene text.
            ImGui::TextWrapped("%s: %s", f.label.c_str(), v.text.c_str());
            break;
        case sc::Kind::Operand: {
            // A CSG's operands: select one to edit its keys (also in the outline).
            const int side = operand++;
            std::string b = f.label + ": " + (v.operand ? sc::object_block(*v.operand).name.data() : "-");
            if (v.operand && ImGui::Button((b + " (edit)").c_str())) {
                sel_.one.path.push_back(side);
                scroll_to_selection_ = true;
            }
            break;
        }
    }
    return changed;
}

bool Panels::set_texture(const std::string& path) {
    Document& doc = editor_.doc();
    const ItemRef ref = texture_target_.ref;
    if (!doc.has_scene() || texture_target_.field.empty()) return false;
    if (const std::string blocked = doc.edit_blocker(); !blocked.empty()) {
        status_.set(blocked, true);
        return false;
    }
    for (const Field& f : item_fields(doc.scene(), ref)) {
        if (f.label != texture_target_.field || f.kind != rt::schema::Kind::Material) continue;
        std::optional<FieldValue> v = field_value(doc.scene(), ref, f);
        if (!v) break;
        v->material.texture = scene_file_name(path, doc.path());
        const FieldResult r = set_field(doc, ref, f, *v);
        doc.commit();  // one undo step
        if (!r.status) {
            field_message_ = {ref, f.label, r.status.message(), true, {}, {}};
            return false;
        }
        if (field_message_.field == f.label) field_message_ = {};
        status_.set_about_step("Texture " + path + " set (Ctrl+Z undoes)", doc.history_changes());
        return true;
    }
    status_.set("The item whose texture was to be set is gone", true);
    return false;
}

// A light's colour is an intensity (often >> 1 because of the 1/r^2 fall-off): its three
// numbers, and the same as a tint and a strength.
bool Panels::light_colour_editor(rt::Vec3& colour) {
    char shown[128];  // what the field shows, for scripts (probe.h)
    std::snprintf(shown, sizeof shown, "%.3f %.3f %.3f", colour.x, colour.y, colour.z);
    probe("light_colour", shown);
    bool changed = drag_vec3("colour", colour, float(std::max({colour.x, colour.y, colour.z, 1.0}) * 0.005));
    double intensity = std::max({colour.x, colour.y, colour.z, 0.0});
    rt::Vec3 tint = intensity > 0 ? colour / intensity : rt::Vec3{1, 1, 1};
    float col[3] = {float(tint.x), float(tint.y), float(tint.z)};
    bool tinted = false;
    if (ImGui::ColorEdit3("tint", col, ImGuiColorEditFlags_Float | ImGuiColorEditFlags_NoInputs)) {
        tint = {col[0], col[1], col[2]};
        if (intensity == 0) intensity = 1;
        tinted = true;
    }
    ImGui::SameLine();
    const double zero = 0;
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 6);
    NumberFieldSpec spec;
    spec.speed = float(std::max(intensity * 0.005, 0.01));
    spec.min = &zero;
    spec.format = "%.2f";
    if (number_field("intensity", &intensity, spec)) tinted = true;
    probe_item("field_intensity");
    if (tinted) {
        // As the colour field shows it: tint * intensity has noise in its last digits.
        const rt::Vec3 c = tint * intensity;
        colour = {as_shown(c.x, 3), as_shown(c.y, 3), as_shown(c.z, 3)};
        changed = true;
    }
    return changed;
}

// "U (union)" for the CSG types; other words as they are.
std::string Panels::choice_label(std::string_view key, std::string_view word) {
    if (key == "type") {
        if (word == "U") return "U (union)";
        if (word == "I") return "I (intersection)";
        if (word == "C") return "C (difference: left minus right)";
    }
    return std::string(word);
}

// The narrowest sidebar in which the property fields keep their labels whole and
// three numbers of a point stay readable.
float Panels::min_sidebar_width() {
    const ImGuiStyle& st = ImGui::GetStyle();
    const float number = ImGui::CalcTextSize("-00.000").x + 2 * st.FramePadding.x;
    const float fields = field_label_width() + st.ItemInnerSpacing.x + 2 + 3 * number + 2 * st.ItemInnerSpacing.x;
    // The sidebar's padding, and its and the properties' scroll bars.
    return std::ceil(fields + 2 * st.WindowPadding.x + 2 * st.ScrollbarSize);
}

// The widest label the property fields use, at the current font: every key of every
// block (and of the material block), so the layout does not jump between selections.
float Panels::field_label_width() {
    namespace sc = rt::schema;
    const float font = ImGui::GetFontSize();
    if (label_w_font_ == font) return label_w_;
    float w = 0;
    auto measure = [&w](std::string_view name, int count) {
        std::string l(name);
        if (count > 0) l += " " + std::to_string(count);
        w = std::max(w, ImGui::CalcTextSize(l.c_str()).x);
    };
    for (const auto& b : sc::object_blocks())
        for (const auto& k : b.keys) measure(k.name, k.count);
    for (const auto& b : sc::plane_blocks())
        for (const auto& k : b.keys) measure(k.name, k.count);
    for (const auto& b : sc::light_blocks())
        for (const auto& k : b.keys) measure(k.name, k.count);
    for (const auto& k : sc::material_block().keys) measure(k.name, k.count);
    measure("intensity", 0);
    label_w_ = w;
    label_w_font_ = font;
    return w;
}

}  // namespace rtview
