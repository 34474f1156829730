// Where a new item goes and how big it is: the scene's size, the size of a new object,
// the up it stands along, and the first candidate place where one stands clear of
// the others. No GL: unit-tested in tests/viewer.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "scene.h"
#include "viewport.h"
#include "world.h"

namespace rtview {

// Where a new item goes: a point on a surface with its normal, or a point in space
// (normal zero; the camera's up then orients it). `toward`: the direction from the
// point to the viewer (zero: to the scene camera), which a new plane faces.
struct Placement {
    rt::Vec3 point;
    rt::Vec3 normal{0, 0, 0};
    rt::Vec3 toward{0, 0, 0};
};

// The size of the scene: the diagonal of its objects' and lights' bounds (given the
// scene's compiled `world`, its bounds, which need no pass over the objects), or the
// camera's distance to its centre when there is nothing to bound. New items are
// scaled from it, the view's fly speed and the panels' drag speeds too.
double scene_extent(const rt::Scene& scene, const rt::World* world = nullptr);
// The size new objects get: the median size of the scene's objects (a sphere's
// radius), or a twentieth of scene_extent when there are none.
double typical_object_size(const rt::Scene& scene);

// One or two significant digits: sizes of new items (0.37 -> 0.4, 12.3 -> 10).
double nice_size(double v);
// The direction a new item at `at` stands along: the surface's normal, else the
// scene camera's up.
rt::Vec3 up_of(const rt::Scene& scene, const Placement& at);

// The menu's Add (no place pointed at) puts a new object where it is seen and stands
// free: of `candidates` (best first), the index of the first where an object of
// typical_object_size, standing as add_item() stands it, keeps clear of every object's
// box (the ball around it, 1.5 times its size, meets none) and, given `seen`, that
// says `seen(middle, reach)` of that ball; if `seen` says it of none, the first clear
// one. nullopt: none is clear. (In a scene of more than
// 133,000 objects only the first 20M / objects candidates are tried.)
std::optional<std::size_t> first_clear(const rt::Scene& scene, const std::vector<Placement>& candidates,
                                       const std::function<bool(const rt::Vec3&, double)>& seen = {});

// The picture the viewer shows: a film of film_w x film_h drawn in `image` (window
// units), seen by `camera` (the view camera), of `world` (null: none compiled yet).
struct PictureView {
    const rt::World* world = nullptr;
    rt::Camera camera;
    Rect image;
    int film_w = 1, film_h = 1;
};

// What lies under the window point (px, py): the surface with its normal (from two
// neighbouring picks; none where they hit something else), or a point in the air at
// the distance the camera looks at. `toward` points back to the camera.
Placement placement_at(const PictureView& view, double px, double py);

// Where an added item goes: at the window point `pointed` (right-click > Add here),
// else near the picture's centre; an object from the menu (`object`, nothing pointed)
// goes where it stands clear of the others and is seen whole (first_clear), on a
// surface nearest the centre before a point in the air.
Placement new_item_placement(const PictureView& view, const rt::Scene* scene, bool object,
                             std::optional<std::pair<double, double>> pointed);

}  // namespace rtview
