// The ImGui panels: menu bar, sidebar (camera, outline and properties, scene text,
// render settings) and status bar, plus the dimmed surround of the image. Panels
// read the parts they show and change things only through the document's edit calls,
// the navigator (the view) and Commands.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "outline_filter.h"
#include "editor.h"
#include "image_tools.h"
#include "item_fields.h"
#include "navigator.h"
#include "render_controller.h"
#include "selection.h"
#include "commands.h"
#include "layout.h"
#include "status_line.h"

namespace rtview {

// What is loading in the background, for the status bar.
struct LoadStatus {
    bool active = false;
    std::string text;   // "reading 40 of 114 MB", "building the BVH", ...
    double fraction = 0;
};

class Panels {
public:
    enum Tab { Objects = 0, Text = 1, Render = 2 };

    Panels(Commands& commands, DocumentEditor& editor, Navigator& nav, RenderController& render, Layout& layout,
           StatusLine& status, ImageTools& tools)
        : commands_(commands), editor_(editor), nav_(nav), render_(render), layout_(layout), status_(status),
          tools_(tools) {}

    void draw_menu_bar();
    void draw_file_menu(bool can);  // can: structural edits allowed
    void draw_sidebar();
    void draw_status_bar(const LoadStatus& load);
    void draw_surround();  // the area around a letterboxed image, dimmed

    void show_tab(Tab t) { want_tab_ = t; }
    bool wants_frames() const { return want_tab_ >= 0; }
    Tab current_tab() const { return Tab(current_tab_); }
    // A plain click: this alone.
    void select(const ItemRef& s);
    // What the panels edit: the one selected item, or of several the last one added.
    const ItemRef& selection() const { return sel_.one; }
    // Everything selected (selection.h): several things with Shift+click or a box.
    const Selection& selected() const { return sel_; }
    void set_selected(const Selection& s);
    void clear_selection() { sel_ = {}; }
    // --select "object N" etc.
    void select_from_option(const std::string& spec);
    // The status bar's height in a window `width` wide: one row (its text is cut to fit).
    float status_height(float width);
    float min_sidebar_width();
    static std::string selection_name(const ItemRef& s);
    // The file browser's answer for a material's texture (Command::SetTexture): the
    // material whose browse button asked gets `path`, named from the scene's folder (one
    // undo step); a file that does not read leaves it as it was, the reason under it.
    bool set_texture(const std::string& path);

private:
    void draw_sidebar_edge();
    void draw_render_status();  // the status bar's part while no scene loads
    void draw_undo_items();
    void draw_camera_panel();
    bool draw_lens_fields(rt::Camera& cam, float speed);
    void draw_scene_camera_fields(float speed);
    void draw_objects_tab();
    void draw_outline();
    void draw_object_node(const rt::Object& obj, int top, std::vector<int>& path, const std::string& label);
    void draw_properties();
    // The properties of several things: how many, and what is done to all of them.
    void draw_group_properties();
    // A click in the outline on `me`: it alone, or with Shift or Ctrl added or taken out.
    void outline_click(const ItemRef& me);
    bool outline_selected(const ItemRef& me) const;
    void draw_fields(const ItemRef& ref);
    bool draw_field(const ItemRef& ref, const Field& f, FieldValue& v, float size, const char* vec_format, int& operand);
    bool draw_material_field(const ItemRef& ref, const Field& f, FieldValue& v);
    bool light_colour_editor(rt::Vec3& colour);
    static std::string choice_label(std::string_view key, std::string_view word);
    float field_label_width();
    void draw_render_tab();
    // `message_share`: the part of a row too narrow for both that the message keeps.
    void status_text(const std::string& text, bool show_message, float message_share = 0.4f);

    Commands& commands_;
    DocumentEditor& editor_;
    Navigator& nav_;
    RenderController& render_;
    Layout& layout_;
    StatusLine& status_;
    ImageTools& tools_;

    Selection sel_;
    // The last refusal or warning of a property field, shown under it until that field
    // is set again or another item is selected.
    struct FieldMessage {
        ItemRef selection;
        std::string field, text;
        bool error = false;
        std::string sub;  // a key inside the field (a material's) that the message is about
        // The field's value the message is about: once the value changes otherwise (the
        // text, an undo), the message has gone stale and goes.
        std::optional<FieldValue> value;
    } field_message_;
    // The material field whose texture the file browser is choosing.
    struct TextureTarget {
        ItemRef ref;
        std::string field;
    } texture_target_;
    float label_w_ = 0, label_w_font_ = 0;  // field_label_width() at that font size
    float edge_grab_ = 0;  // where on the sidebar's edge the drag began
    bool scroll_to_selection_ = false;
    // The outline's filter: the text typed, and the objects it finds.
    std::string outline_filter_text_;
    OutlineFilter outline_filter_;
    void draw_outline_objects(const rt::Scene& s);
    int want_tab_ = -1;  // select this tab on the next frame
    int current_tab_ = 0;
};

}  // namespace rtview
