// The turn and size handles beside the move handle, as maths: rings about the world
// axes and the view axis, boxes on the object's own axes and one in the middle for all
// three, which part a pointer is over, the angle or factors a drag gives (Shift: 15
// degrees, factors in tenths), and what they write: a thing's `rotation`, `scale` and
// `translate` (a mesh's own `rotation`, `scale` and `position`), never the shape's own
// keys, so a user's numbers stay theirs. The object turns and sizes about its handle's
// point, which stays where it is. No GL, no ImGui: unit-tested.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "move_handle.h"
#include "scene.h"

namespace rtview {

// What the handle does: G, Y and U switch (R and S are taken by the view).
enum class HandleMode { Move, Turn, Size };
const char* handle_mode_name(HandleMode m);  // "move", "turn", "size"

// A rotation as written (degrees about x, then y, then z) as its matrix, and back (the
// angles each in (-180, 180], rounded to a millionth of a degree, -0 as 0).
struct Mat3 {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    rt::Vec3 operator*(const rt::Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    Mat3 operator*(const Mat3& b) const;
    Mat3 transposed() const;
    rt::Vec3 column(int k) const { return {m[0][k], m[1][k], m[2][k]}; }
};
Mat3 rotation_matrix(const rt::Vec3& degrees);
rt::Vec3 rotation_degrees(const Mat3& r);
// A turn by `degrees` about the unit vector `axis` (right-handed); exact for the world
// axes at multiples of 90 degrees.
Mat3 axis_rotation(const rt::Vec3& axis, double degrees);

// How an object is placed: x_world = R S x + t + after. A thing's transform (after:
// 0), or a mesh's own keys (t: its position; after: its `translate`).
struct Placing {
    rt::Vec3 rotation{0, 0, 0}, scale{1, 1, 1}, t{0, 0, 0}, after{0, 0, 0};
};
Placing placing_of(const rt::Object& o);
// Writes `p` back into the keys placing_of() read (numbers tidied for the text).
void set_placing(rt::Object& o, const Placing& p);

// `o` turned by `degrees` about the world `axis` (unit) through `anchor`.
void turn_object(rt::Object& o, const rt::Vec3& axis, double degrees, const rt::Vec3& anchor);
// `o` sized by `factors` along its own axes (the directions its rotation gives x, y
// and z), `anchor` staying where it is. Factors are kept to scales of 1e-6 .. 1e9.
void size_object(rt::Object& o, const rt::Vec3& factors, const rt::Vec3& anchor);

// The turn handle on screen: a ring about each world axis through the anchor (as
// polylines; pieces behind the eye left out) and a bigger circle about the view axis.
struct TurnShape {
    bool visible = false;
    ScreenPoint origin;
    std::vector<ScreenPoint> ring[3];  // closed: the last point joins the first
    double view_radius = 0;
};
// `radius`: the rings' radius on screen near the anchor, window units.
TurnShape turn_shape(const ScreenView& view, const rt::Vec3& anchor, double radius);
// X, Y, Z: a ring; Plane: the view circle; the nearest within `tolerance`.
HandlePart hit_turn(const TurnShape& h, double x, double y, double tolerance);

// The size handle: a line to a box on each of the object's own axes, a box in the
// middle (all three axes).
struct SizeShape {
    bool visible = false;
    ScreenPoint origin;
    ScreenPoint tip[3];
    bool axis_shown[3] = {};
    double box = 0;  // half a box's side, window units
};
SizeShape size_shape(const ScreenView& view, const rt::Vec3& anchor, const Mat3& axes, double length);
HandlePart hit_size(const SizeShape& h, double x, double y, double tolerance);

// One drag of the turn handle: the angle, in degrees, for each later pointer position,
// measured about the anchor's point on screen; `snap`: to multiples of 15, else to
// tenths of a degree.
class TurnDrag {
public:
    TurnDrag(HandlePart part, const rt::Vec3& anchor, const ScreenView& view, double x, double y);
    double degrees(double x, double y, bool snap) const;
    // The world axis turned about (unit): a world axis, or the view's, towards the eye.
    const rt::Vec3& axis() const { return axis_; }
    HandlePart part() const { return part_; }

private:
    HandlePart part_;
    rt::Vec3 axis_;
    ScreenPoint origin_;
    double start_ = 0;  // the pointer's angle about origin_ at the press
    double sign_ = 1;   // +1 when the axis points at the eye: counter-clockwise turns it positive
    // The last angle seen and the whole turns counted, so that a drag round more than
    // half a turn keeps counting (degrees() is called once per pointer move, in order).
    mutable double last_ = 0;
    mutable double turns_ = 0;
};

// One drag of the size handle: the factors along the object's own axes for each later
// pointer position. An axis box: the pointer's distance from the middle along the
// axis's direction on screen over that at the press; the middle box: 1 plus the
// pointer's move right and up over `length`. `snap`: factors in tenths, else in
// hundredths; never below 0.01.
class SizeDrag {
public:
    SizeDrag(HandlePart part, const SizeShape& shape, double length, double x, double y);
    rt::Vec3 factors(double x, double y, bool snap) const;
    HandlePart part() const { return part_; }

private:
    HandlePart part_;
    ScreenPoint origin_, press_;
    double dir_x_ = 0, dir_y_ = 0;  // the axis's unit direction on screen
    double start_ = 1;              // the press's distance along it
    double length_ = 1;
};

// The object's own axes in the world (the columns of its rotation), for the size handle.
Mat3 object_axes(const rt::Object& o);

// The same for the CSG operand `path` names below `top` (top itself for an empty path):
// its own transform is what changes, the CSGs above it stay. The axis and anchor are
// the world's: the operand's points turn about them exactly. Where a CSG above it
// scales unequally along its axes, the turned operand is in general sheared in the
// frame it is written in, which its `rotation` and `scale` cannot hold: then nothing
// changes, false, and `why` (if given) says so. False too if there is no such operand.
bool turn_operand(rt::Object& top, const std::vector<int>& path, const rt::Vec3& axis, double degrees,
                  const rt::Vec3& anchor, std::string* why = nullptr);
bool size_operand(rt::Object& top, const std::vector<int>& path, const rt::Vec3& factors, const rt::Vec3& anchor);
// The world directions of the operand's own axes (object_axes of top for an empty path).
Mat3 operand_axes(const rt::Object& top, const std::vector<int>& path);

}  // namespace rtview
