// What the picture shows of the selection and how it is moved there: the selected
// item's outline (from an object-id buffer of the primary hits at the block size of
// the picture on screen, refined while the view rests) and the translate handle
// (three axis arrows and a view-plane square). Dragging the handle edits the item in
// the document every frame, as a slider does (one undo step on release, written into
// the item's block only); Shift snaps to a grid scaled to the scene, Escape cancels.
// Both are drawn over the picture, never into the film.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "document.h"
#include "move_handle.h"
#include "transform_handle.h"
#include "object_ids.h"
#include "render_controller.h"
#include "status_line.h"
#include "scene_edits.h"
#include "selection.h"

struct ImDrawList;

namespace rtview {

class MoveTool {
public:
    // One frame of pointer input, before navigation sees it. `view` is the view the
    // picture is rendered through; `image` where it is drawn. True while the tool owns
    // the pointer (a press on the handle, a drag): navigation must then ignore it.
    // Several things selected: one move handle at their centre moves them all (the
    // turn and size handles are for one thing at a time).
    bool handle_mouse(Document& doc, const Selection& sel, const ScreenView& view, const Rect& image, bool usable,
                      StatusLine& status);
    bool dragging() const { return drag_.has_value(); }
    // What the handle does (G, Y, U); turning and sizing are for whole objects: a
    // plane, a light or a CSG operand keeps the move handle.
    void set_mode(HandleMode m) { mode_ = m; }
    HandleMode mode() const { return mode_; }
    // The mode the handle has for this selection.
    HandleMode mode_for(const Document& doc, const ItemRef& sel) const;

    // The outline's id buffer for this frame's picture: at the preview's block while
    // the view moves, refined toward single pixels (within a time budget per frame)
    // while it rests. Call after RenderController::update().
    void update_outline(const Document& doc, const Selection& sel, const RenderController& render,
                        const rt::Camera& camera, int film_w, int film_h);
    // Outline and handle over the picture in `image` (clipped to `area`), and the
    // markers of the lights that have no glow (`world`: what hides them).
    void draw(const Document& doc, const Selection& sel, const ScreenView& view, const rt::World* world,
              const Rect& image, const Rect& area, int film_w, int film_h);
    // What a click at (x, y) finds of what draw() drew over the picture: the selection's
    // handle (the selection stays), or a light's marker (its index; else -1).
    bool over_handle(const Document& doc, const Selection& sel, const ScreenView& view, double x, double y) const;
    int light_under(double x, double y) const;
    // The lights whose markers lie in the box between (x0, y0) and (x1, y1) (a box
    // select takes them too: a spotlight has no glow to be seen by).
    std::vector<int> lights_in_box(double x0, double y0, double x1, double y1) const;
    // Still refining the outline: frames are needed.
    bool wants_frames() const { return refining_; }
    // Rays the last outline update traced (for --verbose and tests).

private:
    struct Drag {
        Drag(SceneItem i, std::vector<int> p, const MoveDrag& d) : item(i), path(std::move(p)), drag(d) {}
        SceneItem item;
        std::vector<int> path;  // a CSG operand of the object: only it moves
        MoveDrag drag;
        rt::Object object;
        rt::Plane plane;
        rt::Light light;
        double snap = 1;
        rt::Vec3 last{0, 0, 0};
        std::string name;  // the undo step's: "Move sphere 3"
        HandleMode mode = HandleMode::Move;
        rt::Vec3 pivot{0, 0, 0};             // turn and size: the point that stays
        std::optional<TurnDrag> turn;
        std::optional<SizeDrag> size;
        double degrees = 0;                  // turn: as applied
        rt::Vec3 factors{1, 1, 1};           // size: as applied
        bool snapping = false;               // Shift, as the last frame with the button held saw it
        std::optional<GroupMove> group;      // several things: all move (item, path unused)
    };
    void apply(Document& doc, const rt::Vec3& d);
    // Turn and size: the object from how it was at the press.
    // Empty, or why the turn cannot be made (nothing changed then).
    std::string apply_turn(Document& doc, double degrees);
    void apply_size(Document& doc, const rt::Vec3& factors);
    bool drag_turn_or_size(Document& doc, double mx, double my, StatusLine& status);
    void draw_turn(ImDrawList* dl, const TurnShape& h, HandlePart active, float s) const;
    void draw_size(ImDrawList* dl, const SizeShape& h, HandlePart active, float s) const;
    // The press on the handle of several things (handle_mouse's part for them).
    bool press_group(Document& doc, const std::vector<SceneItem>& items, const ScreenView& view, const Rect& image,
                     bool usable, StatusLine& status);
    // Where the handle is drawn now, with the mode it has (nothing: no handle).
    std::optional<rt::Vec3> handle_anchor(const Document& doc, const Selection& sel, HandleMode& mode) const;
    void draw_move_handle(ImDrawList* dl, const HandleShape& h, float s) const;
    // The handles' arrow length and the pointer's tolerance, in unscaled UI units.
    static constexpr double kArrow = 90, kTolerance = 7;
    HandleMode mode_ = HandleMode::Move;
    std::optional<ScreenPoint> before_press_;  // the pointer in the last frame without a button down

    void draw_light_markers(ImDrawList* dl, float scale) const;

    std::optional<Drag> drag_;
    HandlePart hover_ = HandlePart::None;
    std::vector<LightMarker> markers_;  // as last drawn

    IdBuffer ids_;
    std::vector<Segment> edges_;  // the outline of ids_, as drawn (smooth_corners)
    int finest_ = 1;           // the finest block whose outline fits a draw list
    bool has_ids_ = false;
    std::weak_ptr<const rt::World> ids_world_;  // compared with, not kept alive
    rt::Camera ids_camera_;
    int ids_w_ = 0, ids_h_ = 0;
    std::vector<std::uint32_t> ids_codes_;
    Selection ids_sel_;  // the selection ids_ outlines
    bool refining_ = false;
    // A selected CSG operand's world (operand_world()), made again when the document's
    // world or the selection changes; `world` when there is none.
    std::shared_ptr<const rt::World> operand_outline_world(const Document& doc, const ItemRef& sel,
                                                           const std::shared_ptr<const rt::World>& world);
    std::shared_ptr<const rt::World> operand_world_;
    std::weak_ptr<const rt::World> operand_source_;
    ItemRef operand_sel_;
    double per_ray_ = 0;  // measured seconds per id ray
    std::size_t last_rays_ = 0;
};

// The document item a selection edits (a CSG operand: its top-level object).
std::optional<SceneItem> item_of_selection(const ItemRef& s);
// Whether the item was read from an included file (it has no handle: read only).
bool included(const rt::Scene& scene, const SceneItem& item);

}  // namespace rtview
