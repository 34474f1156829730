// Selection outline and translate handle (see move_tool.h).
#include "move_tool.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "item_fields.h"
#include "pacing.h"
#include "probe.h"
#include "scene_edits.h"
#include "scene_text.h"

namespace rtview {

namespace {

// What the outline may take of a resting frame: refined a level a frame within it.
constexpr double kOutlineBudget = 0.012;
// Outline segments drawn at most (two lines each: well within the 65,536 vertices of
// an ImGui draw list with 16-bit indices, which the picture shares).
constexpr std::size_t kMaxEdges = 5000;
// A light marker's radius, in unscaled UI units.
constexpr double kMarker = 7;
// Light markers drawn at most (each costs a pick ray a frame).
constexpr std::size_t kMaxMarkers = 256;

ImU32 axis_colour(int k, bool hot) {
    static const ImU32 normal[3] = {IM_COL32(235, 64, 52, 255), IM_COL32(70, 200, 60, 255), IM_COL32(60, 120, 245, 255)};
    return hot ? IM_COL32(255, 230, 60, 255) : normal[k];
}

}  // namespace

bool included(const rt::Scene& scene, const SceneItem& item) {
    const ItemList list = item.kind == SceneItem::Kind::Object  ? ItemList::Object
                          : item.kind == SceneItem::Kind::Plane ? ItemList::Plane
                                                                : ItemList::Light;
    return item.index >= 0 && included_file(scene, list, std::size_t(item.index)) != nullptr;
}

std::optional<SceneItem> item_of_selection(const ItemRef& s) {
    if (s.none()) return std::nullopt;
    return s.item;
}

void MoveTool::apply(Document& doc, const rt::Vec3& d) {
    Drag& g = *drag_;
    if (g.group) {
        g.group->apply(doc, d);
        if (g.name.empty()) g.name = "Move " + std::to_string(g.group->size()) + " things";
        doc.name_edit(g.name);
        g.last = d;
        return;
    }
    std::size_t i = std::size_t(g.item.index);
    // (The document notes which item changed: the world takes only that.)
    switch (g.item.kind) {
        case SceneItem::Kind::Object: {
            rt::Object& o = doc.edit_object(i);
            o = g.object;
            translate_operand(o, g.path, d);
            break;
        }
        case SceneItem::Kind::Plane: {
            rt::Plane& p = doc.edit_plane(i);
            p = g.plane;
            translate(p, d);
            break;
        }
        case SceneItem::Kind::Light: {
            rt::Light& l = doc.edit_light(i);
            l = g.light;
            translate(l, d);
            break;
        }
    }
    if (g.name.empty()) g.name = "Move " + item_label(doc.scene(), ItemRef{g.item, g.path});
    doc.name_edit(g.name);
    g.last = d;
}

HandleMode MoveTool::mode_for(const Document& doc, const ItemRef& sel) const {
    if (mode_ == HandleMode::Move || !sel.is(SceneItem::Kind::Object) || !doc.has_scene())
        return HandleMode::Move;
    return mode_;
}

std::string MoveTool::apply_turn(Document& doc, double degrees) {
    Drag& g = *drag_;
    rt::Object o = g.object;
    std::string why;  // (a CSG operand: its own transform, which may not hold the turn)
    if (!turn_operand(o, g.path, g.turn->axis(), degrees, g.pivot, &why)) return why;
    doc.edit_object(std::size_t(g.item.index)) = std::move(o);
    if (g.name.empty()) g.name = "Turn " + item_label(doc.scene(), ItemRef{g.item, g.path});
    doc.name_edit(g.name);
    g.degrees = degrees;
    return {};
}

void MoveTool::apply_size(Document& doc, const rt::Vec3& factors) {
    Drag& g = *drag_;
    rt::Object o = g.object;
    size_operand(o, g.path, factors, g.pivot);
    doc.edit_object(std::size_t(g.item.index)) = std::move(o);
    if (g.name.empty()) g.name = "Size " + item_label(doc.scene(), ItemRef{g.item, g.path});
    doc.name_edit(g.name);
    g.factors = factors;
}

// A turn or size drag after its press: the object from how it was then, every frame
// (Shift snaps); released, one undo step.
bool MoveTool::drag_turn_or_size(Document& doc, double mx, double my, StatusLine& status) {
    Drag& g = *drag_;
    // Shift as it was while the button was held: a release seen in the same frame as
    // Shift's (a busy frame) keeps the snapping the drag had.
    const bool held = ImGui::IsMouseDown(0);
    if (held) g.snapping = ImGui::GetIO().KeyShift;
    const bool snap = g.snapping;
    const bool turn = g.mode == HandleMode::Turn;
    // (Also on the frame of the release: a pointer moved and let go between two
    // frames ends where it was let go.)
    if (turn) {
        const double d = g.turn->degrees(mx, my, snap);
        if (d != g.degrees && std::isfinite(d))
            if (const std::string why = apply_turn(doc, d); !why.empty()) status.set(why, true);
    } else {
        const rt::Vec3 f = g.size->factors(mx, my, snap);
        if (!(f == g.factors) && rt::finite(f)) apply_size(doc, f);
    }
    if (held) return true;
    const bool changed = turn ? g.degrees != 0 : !(g.factors == rt::Vec3{1, 1, 1});
    if (changed) doc.commit();
    else doc.cancel_edit();
    if (changed) {
        char buf[160];
        const char* axis = g.turn && g.turn->part() != HandlePart::Plane
                               ? (g.turn->part() == HandlePart::X ? "x" : g.turn->part() == HandlePart::Y ? "y" : "z")
                               : "the view axis";
        if (turn) std::snprintf(buf, sizeof buf, "Turned by %.6g degrees about %s (Ctrl+Z undoes)", g.degrees, axis);
        else std::snprintf(buf, sizeof buf, "Sized by %.6g %.6g %.6g (Ctrl+Z undoes)", g.factors.x, g.factors.y, g.factors.z);
        status.set_about_step(buf, doc.history_changes());
    }
    drag_.reset();
    return true;
}

bool MoveTool::handle_mouse(Document& doc, const Selection& selection, const ScreenView& view, const Rect& image,
                            bool usable, StatusLine& status) {
    const ItemRef& sel = selection.one;
    ImGuiIO& io = ImGui::GetIO();
    double mx = io.MousePos.x, my = io.MousePos.y;
    double s = ImGui::GetFontSize() / 13.0;  // the UI scale
    if (drag_) {
        if (!usable || !doc.has_scene() || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) {
            doc.cancel_edit();
            const HandleMode m = drag_->mode;
            drag_.reset();
            status.set(m == HandleMode::Move ? "Move cancelled" : m == HandleMode::Turn ? "Turn cancelled" : "Size cancelled");
            return true;
        }
        if (drag_->mode != HandleMode::Move) return drag_turn_or_size(doc, mx, my, status);
        if (ImGui::IsMouseDown(0)) {
            // Shift: the grid. Else a hundredth of its step, far below a pixel at
            // the scene's scale, so the text gets short numbers (-0.2636, not
            // -0.26361007019).
            rt::Vec3 d = drag_->drag.delta(view, mx, my, io.KeyShift ? drag_->snap : drag_->snap / 100);
            if (!(d == drag_->last) && rt::finite(d)) apply(doc, d);
            return true;
        }
        // Released: one undo step, or nothing if it did not move.
        rt::Vec3 d = drag_->last;
        if (d == rt::Vec3{0, 0, 0}) doc.cancel_edit();
        else doc.commit();
        drag_.reset();
        if (!(d == rt::Vec3{0, 0, 0})) {
            char buf[160];
            std::snprintf(buf, sizeof buf, "Moved by %.6g %.6g %.6g (Ctrl+Z undoes)", d.x, d.y, d.z);
            status.set(buf);
        }
        return true;
    }
    hover_ = HandlePart::None;
    if (!selection.many.empty()) return press_group(doc, selection.many, view, image, usable, status);
    std::optional<SceneItem> item = item_of_selection(sel);
    if (!usable || !item || !doc.has_scene() || doc.edit_held() || included(doc.scene(), *item)) return false;
    std::optional<rt::Vec3> anchor = item_anchor(doc.scene(), *item, sel.path);
    if (!anchor) return false;
    const HandleMode mode = mode_for(doc, sel);
    const std::size_t i = std::size_t(item->index);
    // A press is taken where the pointer was before it: on a busy frame the pointer may
    // have moved on by the time the frame sees the press (a turn would start from the
    // wrong angle, a size from the wrong length).
    if (ImGui::IsMouseClicked(0) && before_press_) mx = before_press_->x, my = before_press_->y;
    before_press_.reset();
    if (!ImGui::IsMouseDown(0)) before_press_ = ScreenPoint{mx, my};
    bool over = !io.WantCaptureMouse && image.contains(mx, my);
    if (!over) hover_ = HandlePart::None;
    else if (mode == HandleMode::Turn) hover_ = hit_turn(turn_shape(view, *anchor, kArrow * s), mx, my, kTolerance * s);
    else if (mode == HandleMode::Size)
        hover_ = hit_size(size_shape(view, *anchor, operand_axes(doc.scene().objects[i], sel.path), kArrow * s), mx, my, kTolerance * s);
    else hover_ = hit_handle(handle_shape(view, *anchor, kArrow * s), mx, my, kTolerance * s);
    if (hover_ == HandlePart::None || !ImGui::IsMouseClicked(0)) return hover_ != HandlePart::None && ImGui::IsMouseDown(0);
    if (const std::string blocked = doc.edit_blocker(); !blocked.empty()) {
        status.set(blocked, true);
        return true;
    }
    const rt::Scene& scene = doc.scene();
    drag_.emplace(*item, sel.path, MoveDrag(mode == HandleMode::Move ? hover_ : HandlePart::None, *anchor, view, mx, my));
    drag_->snap = snap_step(scene_extent(scene));
    drag_->mode = mode;
    drag_->pivot = *anchor;
    if (mode == HandleMode::Turn) drag_->turn.emplace(hover_, *anchor, view, mx, my);
    if (mode == HandleMode::Size)
        drag_->size.emplace(hover_, size_shape(view, *anchor, operand_axes(scene.objects[i], sel.path), kArrow * s), kArrow * s, mx, my);
    if (item->kind == SceneItem::Kind::Object) drag_->object = scene.objects[i];
    else if (item->kind == SceneItem::Kind::Plane) drag_->plane = scene.planes[i];
    else drag_->light = scene.lights[i];
    return true;
}

std::shared_ptr<const rt::World> MoveTool::operand_outline_world(const Document& doc, const ItemRef& sel,
                                                                 const std::shared_ptr<const rt::World>& world) {
    if (!operand_world_ || !same_world(operand_source_, world) || !(operand_sel_ == sel)) {
        operand_world_ = operand_world(doc.scene(), sel);
        operand_source_ = world;
        operand_sel_ = sel;
    }
    return operand_world_ ? operand_world_ : world;
}

void MoveTool::update_outline(const Document& doc, const Selection& selection, const RenderController& render,
                              const rt::Camera& camera, int film_w, int film_h) {
    refining_ = false;
    last_rays_ = 0;
    const ItemRef& sel = selection.one;
    std::vector<SceneItem> items = selected_items(selection);
    std::shared_ptr<const rt::World> world = render.world_ptr();
    if (items.empty() || !world || !doc.has_scene()) {
        has_ids_ = false;
        return;
    }
    if (selection.many.empty() && !sel.path.empty() && (world = operand_outline_world(doc, sel, world)) == operand_world_)
        items = {SceneItem{SceneItem::Kind::Object, 0}};  // an operand: its own silhouette
    std::vector<std::uint32_t> codes;
    for (const SceneItem& i : items) codes.push_back(id_code(i));
    bool same_view = has_ids_ && same_world(ids_world_, world) && ids_camera_ == camera && ids_w_ == film_w && ids_h_ == film_h &&
                     ids_codes_ == codes;
    const bool preview = render.showing_preview();
    int block = 8;
    int x0, y0, x1, y1;
    auto cost = [&] { return double(x1 - x0) * double(y1 - y0) * per_ray_; };
    if (preview) {
        // The picture on screen is the UI thread's preview: the outline at its blocks.
        block = std::max(1, render.last_preview_block());
        if (same_view && ids_.block == block) return;
        items_window(*world, camera, film_w, film_h, block, items, x0, y0, x1, y1);
    } else if (same_view) {
        // Resting: one level finer a frame, while a level fits a few frames' budget.
        if (ids_.block <= finest_) return;
        block = ids_.block / 2;
        items_window(*world, camera, film_w, film_h, block, items, x0, y0, x1, y1);
        if (per_ray_ > 0 && cost() > 4 * kOutlineBudget) return;
    } else {
        // A new view at rest: the finest level within the budget.
        for (block = 1;; block *= 2) {
            items_window(*world, camera, film_w, film_h, block, items, x0, y0, x1, y1);
            if (block >= 64 || (per_ray_ > 0 && cost() <= kOutlineBudget)) break;
            if (per_ray_ <= 0 && block >= 8) break;
        }
    }
    if (!same_view) finest_ = 1;
    IdBuffer ids;
    std::vector<Edge> edges;
    for (;;) {
        auto t0 = std::chrono::steady_clock::now();
        last_rays_ += trace_ids(*world, camera, film_w, film_h, block, x0, y0, x1, y1, ids);
        double took = seconds_since(t0);
        if (last_rays_ > 64) {
            double sample = took / double(last_rays_);
            per_ray_ = per_ray_ > 0 ? std::min(sample, 0.5 * per_ray_ + 0.5 * sample) : sample;
        }
        edges = codes.size() == 1 ? outline_edges(ids, codes[0]) : outline_edges_of(ids, codes);
        // An outline of more segments than one draw list holds (a plane seen between
        // thousands of spheres) stays at the coarser level.
        if (edges.size() <= kMaxEdges || block >= 64) break;
        if (same_view && !preview) {
            finest_ = ids_.block;
            return;
        }
        block *= 2;
        items_window(*world, camera, film_w, film_h, block, items, x0, y0, x1, y1);
    }
    ids_ = std::move(ids);
    edges_ = smooth_corners(edges);
    has_ids_ = true;
    ids_world_ = world;
    ids_camera_ = camera;
    ids_w_ = film_w;
    ids_h_ = film_h;
    ids_codes_ = std::move(codes);
    ids_sel_ = selection;
    refining_ = !preview && ids_.block > finest_;
}

bool MoveTool::over_handle(const Document& doc, const Selection& sel, const ScreenView& view, double x,
                           double y) const {
    HandleMode mode = HandleMode::Move;
    const std::optional<rt::Vec3> anchor = handle_anchor(doc, sel, mode);
    if (!anchor) return false;
    const double s = ImGui::GetFontSize() / 13.0;
    switch (mode) {
        case HandleMode::Turn: return hit_turn(turn_shape(view, *anchor, kArrow * s), x, y, kTolerance * s) != HandlePart::None;
        case HandleMode::Size: {
            const Mat3 axes = operand_axes(doc.scene().objects[std::size_t(sel.one.item.index)], sel.one.path);
            return hit_size(size_shape(view, *anchor, axes, kArrow * s), x, y, kTolerance * s) != HandlePart::None;
        }
        case HandleMode::Move: break;
    }
    return hit_handle(handle_shape(view, *anchor, kArrow * s), x, y, kTolerance * s) != HandlePart::None;
}

int MoveTool::light_under(double x, double y) const {
    return light_at(markers_, x, y, kMarker * ImGui::GetFontSize() / 13.0 + kTolerance * 0.5);
}

void MoveTool::draw_light_markers(ImDrawList* dl, float s) const {
    // A small sun: a ring with four rays, dark-edged to show on any picture.
    const float r = float(kMarker) * s;
    for (const LightMarker& m : markers_) {
        const ImVec2 c(float(m.at.x), float(m.at.y));
        for (int pass = 0; pass < 2; ++pass) {
            const ImU32 col = pass == 0 ? IM_COL32(0, 0, 0, 170) : IM_COL32(255, 220, 90, 255);
            const float w = (pass == 0 ? 3.2f : 1.5f) * s;
            dl->AddCircle(c, r * 0.55f, col, 16, w);
            for (int k = 0; k < 4; ++k) {
                const float dx = k == 0 ? 1.f : k == 1 ? -1.f : 0.f, dy = k == 2 ? 1.f : k == 3 ? -1.f : 0.f;
                dl->AddLine(ImVec2(c.x + dx * r * 0.8f, c.y + dy * r * 0.8f), ImVec2(c.x + dx * r * 1.3f, c.y + dy * r * 1.3f),
                            col, w);
            }
        }
    }
}

void MoveTool::draw(const Document& doc, const Selection& sel, const ScreenView& view, const rt::World* world,
                    const Rect& image, const Rect& area, int film_w, int film_h) {
    markers_.clear();
    if (!doc.has_scene()) return;
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    dl->PushClipRect(ImVec2(float(area.x), float(area.y)), ImVec2(float(area.x + area.w), float(area.y + area.h)), true);
    float s = ImGui::GetFontSize() / 13.f;
    markers_ = light_markers(doc.scene(), world, view, image, kMaxMarkers);
    draw_light_markers(dl, s);
    if (has_ids_ && ids_sel_ == sel && ids_w_ == film_w &&
        ids_h_ == film_h) {
        // Texel borders to window units: texel k starts at film pixel k * block.
        auto wx = [&](float tx) { return float(image.x + std::min(double(tx) * ids_.block, double(film_w)) * image.w / film_w); };
        auto wy = [&](float ty) { return float(image.y + std::min(double(ty) * ids_.block, double(film_h)) * image.h / film_h); };
        for (int pass = 0; pass < 2; ++pass) {
            // A dark border under a bright line: visible on light and dark pictures.
            ImU32 c = pass == 0 ? IM_COL32(0, 0, 0, 170) : IM_COL32(255, 170, 30, 255);
            float w = pass == 0 ? 3.5f * s : 1.6f * s;
            for (const Segment& e : edges_) dl->AddLine(ImVec2(wx(e.x0), wy(e.y0)), ImVec2(wx(e.x1), wy(e.y1)), c, w);
        }
    }
    HandleMode mode = HandleMode::Move;
    std::optional<rt::Vec3> anchor;
    if (drag_) {
        mode = drag_->mode;
        anchor = mode == HandleMode::Move ? drag_->drag.anchor() + drag_->last : drag_->pivot;
    } else {
        anchor = handle_anchor(doc, sel, mode);
    }
    probe("handle_mode", handle_mode_name(mode));
    const std::optional<SceneItem> item = item_of_selection(sel.one);
    if (anchor && mode != HandleMode::Move && item && std::size_t(item->index) < doc.scene().objects.size()) {
        const HandlePart active = drag_ ? (drag_->turn ? drag_->turn->part() : drag_->size->part()) : hover_;
        if (mode == HandleMode::Turn) draw_turn(dl, turn_shape(view, *anchor, kArrow * s), active, s);
        else draw_size(dl, size_shape(view, *anchor, operand_axes(doc.scene().objects[std::size_t(item->index)], sel.one.path),
                                      kArrow * s), active, s);
        anchor.reset();
    }
    if (anchor) draw_move_handle(dl, handle_shape(view, *anchor, kArrow * s), s);
    dl->PopClipRect();
}

// Three arrows in the axes' colours and the view-plane square; the active part bright.
void MoveTool::draw_move_handle(ImDrawList* dl, const HandleShape& h, float s) const {
    if (!h.visible) return;
    HandlePart active = drag_ ? drag_->drag.part() : hover_;
    ImVec2 o(float(h.origin.x), float(h.origin.y));
    for (int k = 0; k < 3; ++k) {
        if (!h.axis_shown[k]) continue;
        bool hot = active == HandlePart(int(HandlePart::X) + k);
        ImVec2 t(float(h.tip[k].x), float(h.tip[k].y));
        float dx = t.x - o.x, dy = t.y - o.y, l = std::sqrt(dx * dx + dy * dy);
        if (l < 1) continue;
        float ux = dx / l, uy = dy / l, head = 12 * s;
        ImVec2 base(t.x - ux * head, t.y - uy * head);
        dl->AddLine(o, base, IM_COL32(0, 0, 0, 150), 5 * s);
        dl->AddLine(o, base, axis_colour(k, hot), 3 * s);
        ImVec2 a(base.x - uy * head * 0.45f, base.y + ux * head * 0.45f);
        ImVec2 b(base.x + uy * head * 0.45f, base.y - ux * head * 0.45f);
        dl->AddTriangleFilled(t, a, b, axis_colour(k, hot));
        dl->AddTriangle(t, a, b, IM_COL32(0, 0, 0, 150), 1.f);
    }
    float q = float(h.square);
    bool hot = active == HandlePart::Plane;
    dl->AddRectFilled(ImVec2(o.x - q, o.y - q), ImVec2(o.x + q, o.y + q),
                      hot ? IM_COL32(255, 230, 60, 200) : IM_COL32(240, 240, 240, 120));
    dl->AddRect(ImVec2(o.x - q, o.y - q), ImVec2(o.x + q, o.y + q), IM_COL32(0, 0, 0, 200), 0, 0, 1.5f * s);
}

// Three rings in the axes' colours and a wider circle about the view axis; the
// active one bright. Points for scripts: where each ring is grabbed (probe.h).
void MoveTool::draw_turn(ImDrawList* dl, const TurnShape& h, HandlePart active, float s) const {
    if (!h.visible) return;
    const ImVec2 o(float(h.origin.x), float(h.origin.y));
    const bool view_hot = active == HandlePart::Plane;
    dl->AddCircle(o, float(h.view_radius), IM_COL32(0, 0, 0, 150), 64, 4.5f * s);
    dl->AddCircle(o, float(h.view_radius), view_hot ? IM_COL32(255, 230, 60, 255) : IM_COL32(235, 235, 235, 230), 64,
                  2.2f * s);
    for (int k = 0; k < 3; ++k) {
        const std::vector<ScreenPoint>& ring = h.ring[k];
        if (ring.size() < 3) continue;
        std::vector<ImVec2> pts;
        pts.reserve(ring.size());
        for (const ScreenPoint& p : ring) pts.emplace_back(float(p.x), float(p.y));
        const bool hot = active == HandlePart(int(HandlePart::X) + k);
        dl->AddPolyline(pts.data(), int(pts.size()), IM_COL32(0, 0, 0, 150), ImDrawFlags_Closed, 4.5f * s);
        dl->AddPolyline(pts.data(), int(pts.size()), axis_colour(k, hot), ImDrawFlags_Closed, 2.5f * s);
        // (An eighth of the way round: clear of the other rings seen from most sides.)
        const ScreenPoint& at = ring[ring.size() / 8];
        probe(std::string("turn_ring_") + "xyz"[k], std::to_string(std::lround(at.x)) + " " + std::to_string(std::lround(at.y)));
    }
    probe("turn_view_ring", std::to_string(std::lround(h.origin.x + h.view_radius)) + " " + std::to_string(std::lround(h.origin.y)));
}

// A line to a box on each of the object's axes, and a box in the middle for all three.
void MoveTool::draw_size(ImDrawList* dl, const SizeShape& h, HandlePart active, float s) const {
    if (!h.visible) return;
    const ImVec2 o(float(h.origin.x), float(h.origin.y));
    const float q = float(h.box);
    for (int k = 0; k < 3; ++k) {
        if (!h.axis_shown[k]) continue;
        const bool hot = active == HandlePart(int(HandlePart::X) + k);
        const ImVec2 t(float(h.tip[k].x), float(h.tip[k].y));
        dl->AddLine(o, t, IM_COL32(0, 0, 0, 150), 5 * s);
        dl->AddLine(o, t, axis_colour(k, hot), 3 * s);
        dl->AddRectFilled(ImVec2(t.x - q, t.y - q), ImVec2(t.x + q, t.y + q), axis_colour(k, hot));
        dl->AddRect(ImVec2(t.x - q, t.y - q), ImVec2(t.x + q, t.y + q), IM_COL32(0, 0, 0, 200), 0, 0, 1.5f * s);
        probe(std::string("size_box_") + "xyz"[k], std::to_string(std::lround(t.x)) + " " + std::to_string(std::lround(t.y)));
    }
    const bool hot = active == HandlePart::Plane;
    dl->AddRectFilled(ImVec2(o.x - q, o.y - q), ImVec2(o.x + q, o.y + q),
                      hot ? IM_COL32(255, 230, 60, 220) : IM_COL32(240, 240, 240, 200));
    dl->AddRect(ImVec2(o.x - q, o.y - q), ImVec2(o.x + q, o.y + q), IM_COL32(0, 0, 0, 200), 0, 0, 1.5f * s);
}

}  // namespace rtview
