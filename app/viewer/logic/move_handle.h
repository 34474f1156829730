// The move tool's handle, as maths: where a world point lands in the window (GLM
// view and projection matrices of the view camera), the handle's three axis arrows
// and view-plane square on screen, which part a pointer is over, and how far a drag
// moves the item (along an axis or in the view plane, snapped to a grid scaled to the
// scene when asked). No GL, no ImGui: unit-tested.
#pragma once

#include <optional>
#include <vector>

#include "scene.h"
#include "scene_edits.h"
#include "viewport.h"
#include "world.h"

namespace rtview {

struct ScreenPoint {
    double x = 0, y = 0;
};

// The view camera's mapping between the world and window points, for a film of
// film_w x film_h drawn in `image` (the inverse of viewport.h's ray_at).
class ScreenView {
public:
    ScreenView(const rt::Camera& camera, const Rect& image, int film_w, int film_h);
    // The window point where p is seen; nothing when p is behind the camera.
    std::optional<ScreenPoint> project(const rt::Vec3& p) const;
    rt::Ray ray(double x, double y) const;
    const rt::Vec3& eye() const { return eye_; }
    const rt::Vec3& forward() const { return forward_; }

private:
    rt::Camera camera_;
    Rect image_;
    int film_w_, film_h_;
    rt::Vec3 eye_, forward_;
    double view_[16], proj_[16];  // column-major, as GLM keeps them
    bool polar_ = false;
    double half_x_ = 0, half_y_ = 0;
};

enum class HandlePart { None, X, Y, Z, Plane };

// The handle as drawn: arrows from the anchor's window point to each axis end
// (hidden when the axis points nearly at the viewer) and a square around the anchor.
struct HandleShape {
    bool visible = false;
    ScreenPoint origin;
    ScreenPoint tip[3];
    bool axis_shown[3] = {};
    double square = 0;  // half the square's side, in window units
};
// `arrow`: the arrows' length in window units.
HandleShape handle_shape(const ScreenView& view, const rt::Vec3& anchor, double arrow);
// The part under (x, y) within `tolerance` window units: the square first, then the
// nearest arrow.
HandlePart hit_handle(const HandleShape& h, double x, double y, double tolerance);

// A light as the picture marks it: a light that has no glow to be seen by (a
// spotlight, a lamp of size 0) gets a marker where it is, so that it can be found and
// clicked in the picture.
struct LightMarker {
    int light = -1;  // index into Scene::lights
    ScreenPoint at;
};
// The markers of the scene's glowless lights that are in front of the view, inside
// `image` and not hidden behind a surface (`world` may be null: nothing hides them);
// at most `max` of them, the nearest first.
std::vector<LightMarker> light_markers(const rt::Scene& scene, const rt::World* world, const ScreenView& view,
                                       const Rect& image, std::size_t max);
// The light whose marker lies within `radius` of (x, y) (the nearest), or -1.
int light_at(const std::vector<LightMarker>& markers, double x, double y, double radius);

// A grid step for snapping: a round number (1, 2 or 5 times a power of ten) near a
// fiftieth of the scene's size.
double snap_step(double scene_extent);

// One drag of the handle: begun where the pointer went down on `part`, it gives the
// item's move for each later pointer position.
class MoveDrag {
public:
    MoveDrag(HandlePart part, const rt::Vec3& anchor, const ScreenView& view, double x, double y);
    // The move from the anchor. `snap` > 0: the anchor lands on multiples of `snap`
    // in the coordinates the drag moves (one for an arrow, all for the square).
    rt::Vec3 delta(const ScreenView& view, double x, double y, double snap = 0) const;
    HandlePart part() const { return part_; }
    const rt::Vec3& anchor() const { return anchor_; }

private:
    // The point of the drag's line or plane under (x, y), if the pointer's ray meets it.
    std::optional<rt::Vec3> grab(const ScreenView& view, double x, double y) const;

    HandlePart part_;
    rt::Vec3 anchor_, normal_;
    rt::Vec3 start_;  // grab() where the drag began
    bool ok_ = false;
};

// The point a handle sits on for an item (or the CSG operand `path` names below an
// object): a sphere's or torus's centre, a light's position, a plane's first point,
// else the centre of the item's bounds.
std::optional<rt::Vec3> item_anchor(const rt::Scene& scene, const SceneItem& item, const std::vector<int>& path = {});

}  // namespace rtview
