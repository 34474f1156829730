// Tests for the move tool's maths (move_handle.h) and the selection outline's id
// buffer (object_ids.h): projection against viewport.h's rays, the handle's hit
// tests, drags along an axis and in the view plane landing where the pointer points,
// grid snapping, and the outline of a sphere against its analytic size.
#include <doctest/doctest.h>

#include <cmath>

#include "move_handle.h"
#include "object_ids.h"
#include "scene.h"
#include "world.h"

using namespace rtview;

namespace {

rt::Camera camera_at(rt::Vec3 pos, rt::Vec3 centre, rt::Projection proj = rt::Projection::Linear) {
    rt::Camera c;
    c.position = pos;
    c.centre = centre;
    c.up = centre + rt::Vec3{0, 0, 1};
    c.projection = proj;
    c.angle_x = 60;
    c.angle_y = 45;
    return c;
}

const Rect kImage{10, 20, 640, 480};

}  // namespace

TEST_CASE("move handle: a point on a window point's ray projects back to that point") {
    for (rt::Projection proj : {rt::Projection::Linear, rt::Projection::Polar}) {
        ScreenView v(camera_at({-5, -8, 3}, {1, 2, 0}, proj), kImage, 640, 480);
        for (double x : {15.0, 200.5, 330.0, 640.0})
            for (double y : {25.0, 260.0, 497.0}) {
                rt::Ray r = v.ray(x, y);
                for (double t : {0.5, 7.0, 300.0}) {
                    auto p = v.project(r.origin + r.dir * t);
                    REQUIRE(p);
                    CHECK(p->x == doctest::Approx(x).epsilon(1e-9));
                    CHECK(p->y == doctest::Approx(y).epsilon(1e-9));
                }
            }
        // Behind the camera: nowhere.
        CHECK(!v.project(rt::Vec3{-5, -8, 3} - (rt::Vec3{1, 2, 0} - rt::Vec3{-5, -8, 3})));
    }
    // The view's centre is seen at the centre of the film's middle texel.
    ScreenView v(camera_at({0, 0, 0}, {10, 0, 0}), kImage, 640, 480);
    auto c = v.project({10, 0, 0});
    REQUIRE(c);
    CHECK(c->x == doctest::Approx(10 + 320.5));
    CHECK(c->y == doctest::Approx(20 + 240.5));
    // +y is on the picture's left for a camera looking along +x with z up.
    auto l = v.project({10, 1, 0});
    REQUIRE(l);
    CHECK(l->x < c->x);
}

TEST_CASE("move handle: hit tests find the square, then the nearest arrow") {
    HandleShape h;
    h.visible = true;
    h.origin = {100, 100};
    h.square = 6;
    h.tip[0] = {180, 100};
    h.tip[1] = {100, 20};
    h.tip[2] = {43, 157};
    h.axis_shown[0] = h.axis_shown[1] = h.axis_shown[2] = true;
    CHECK(hit_handle(h, 103, 98, 5) == HandlePart::Plane);
    CHECK(hit_handle(h, 150, 103, 5) == HandlePart::X);
    CHECK(hit_handle(h, 97, 40, 5) == HandlePart::Y);
    CHECK(hit_handle(h, 60, 141, 5) == HandlePart::Z);
    CHECK(hit_handle(h, 150, 110, 5) == HandlePart::None);  // 10 from the X arrow
    CHECK(hit_handle(h, 190, 100, 5) == HandlePart::None);  // past its tip
    h.axis_shown[0] = false;
    CHECK(hit_handle(h, 150, 103, 5) == HandlePart::None);
    h.visible = false;
    CHECK(hit_handle(h, 100, 100, 5) == HandlePart::None);
}

TEST_CASE("move handle: the arrows point where the axes go on screen; an axis toward the viewer is hidden") {
    // Looking along +x with z up: +y goes left, +z goes up, x points away.
    ScreenView v(camera_at({0, 0, 0}, {10, 0, 0}), kImage, 640, 480);
    HandleShape h = handle_shape(v, {10, 0, 0}, 80);
    REQUIRE(h.visible);
    CHECK(!h.axis_shown[0]);
    REQUIRE(h.axis_shown[1]);
    REQUIRE(h.axis_shown[2]);
    CHECK(h.tip[1].x == doctest::Approx(h.origin.x - 80));
    CHECK(h.tip[1].y == doctest::Approx(h.origin.y));
    CHECK(h.tip[2].y == doctest::Approx(h.origin.y - 80));
}

TEST_CASE("move handle: a drag moves the anchor to the pointer, along the axis or in the view plane") {
    ScreenView v(camera_at({-6, -9, 5}, {0, 0, 0}), kImage, 640, 480);
    rt::Vec3 anchor{0.5, -0.25, 0.75};
    auto at = [&](rt::Vec3 p) {
        auto s = v.project(p);
        REQUIRE(s);
        return *s;
    };
    ScreenPoint p0 = at(anchor);
    for (int k = 0; k < 3; ++k) {
        rt::Vec3 axis{};
        axis[k] = 1;
        // Grabbed a little off the anchor (on the arrow): the grab point does not jump.
        ScreenPoint g = at(anchor + axis * 0.3);
        MoveDrag d(HandlePart(int(HandlePart::X) + k), anchor, v, g.x, g.y);
        ScreenPoint to = at(anchor + axis * 2.3);
        rt::Vec3 m = d.delta(v, to.x, to.y);
        CHECK(m[k] == doctest::Approx(2.0).epsilon(1e-6));
        CHECK(m[(k + 1) % 3] == 0);
        CHECK(m[(k + 2) % 3] == 0);
        // The pointer off the arrow's line moves it by the nearest point only.
        rt::Vec3 m2 = d.delta(v, to.x + 3, to.y + 2);
        CHECK(rt::length(m2 - m) < 0.2);
    }
    // In the view plane: a move across the view lands under the pointer.
    MoveDrag d(HandlePart::Plane, anchor, v, p0.x, p0.y);
    rt::Vec3 across = rt::normalize(rt::cross(v.forward(), rt::Vec3{0, 0, 1})) * 1.5 + rt::Vec3{0, 0, 0.4};
    across = across - v.forward() * rt::dot(across, v.forward());
    ScreenPoint to = at(anchor + across);
    rt::Vec3 m = d.delta(v, to.x, to.y);
    CHECK(rt::length(m - across) < 1e-9);
    CHECK(d.delta(v, p0.x, p0.y) == rt::Vec3{0, 0, 0});
}

TEST_CASE("move handle: snapping lands the anchor on the grid in the coordinates the drag moves") {
    CHECK(snap_step(50) == 1);
    CHECK(snap_step(100) == 2);
    CHECK(snap_step(260) == 5);
    CHECK(snap_step(0.3) == 0.005);
    CHECK(snap_step(0) == 1);
    ScreenView v(camera_at({-6, -9, 5}, {0, 0, 0}), kImage, 640, 480);
    rt::Vec3 anchor{0.3, 0.12, -0.07};
    auto at = [&](rt::Vec3 p) { return *v.project(p); };
    ScreenPoint p0 = at(anchor);
    MoveDrag dx(HandlePart::X, anchor, v, p0.x, p0.y);
    ScreenPoint to = at(anchor + rt::Vec3{1.13, 0, 0});
    rt::Vec3 m = dx.delta(v, to.x, to.y, 0.5);
    CHECK(anchor.x + m.x == doctest::Approx(1.5));
    CHECK(m.y == 0);
    CHECK(m.z == 0);
    MoveDrag dp(HandlePart::Plane, anchor, v, p0.x, p0.y);
    rt::Vec3 mp = dp.delta(v, p0.x + 40, p0.y - 25, 0.25);
    for (int k = 0; k < 3; ++k) {
        double c = anchor[k] + mp[k];
        CHECK(std::fabs(c / 0.25 - std::round(c / 0.25)) < 1e-9);
    }
}

TEST_CASE("move handle: lights without a glow are marked where they are seen, unless something hides them") {
    rt::Scene s;
    s.camera = camera_at({0, 0, 0}, {10, 0, 0});
    rt::Object o;
    o.shape = rt::Sphere{{10, -3, 0}, 1};
    s.objects.push_back(o);
    auto light = [](bool lamp, rt::Vec3 p, double size) {
        rt::Light l;
        l.lamp = lamp;
        l.position = p;
        l.size = size;
        return l;
    };
    s.lights = {light(false, {10, 2, 1}, 1),    // a spotlight in view
                light(true, {10, 0, 2}, 0.2),   // a lamp: its glow shows it
                light(false, {14, -3, 0}, 1),   // behind the sphere
                light(false, {-5, 0, 0}, 1),    // behind the camera
                light(true, {12, 1, -1}, 0),    // a lamp without a glow, in view
                light(false, {10, 30, 0}, 1)};  // outside the picture
    auto world = rt::compile_world(s);
    ScreenView v(s.camera, kImage, 640, 480);
    std::vector<LightMarker> m = light_markers(s, world.get(), v, kImage, 100);
    REQUIRE(m.size() == 2);
    CHECK(m[0].light == 0);  // the nearer first
    CHECK(m[1].light == 4);
    auto at = v.project(s.lights[0].position);
    REQUIRE(at);
    CHECK(m[0].at.x == doctest::Approx(at->x));
    CHECK(m[0].at.y == doctest::Approx(at->y));
    // Without a world nothing hides the one behind the sphere; `max` keeps the nearest.
    CHECK(light_markers(s, nullptr, v, kImage, 100).size() == 3);
    CHECK(light_markers(s, world.get(), v, kImage, 1).size() == 1);
    // A click finds the marker within the radius, the nearest of two.
    CHECK(light_at(m, at->x + 3, at->y - 2, 5) == 0);
    CHECK(light_at(m, at->x + 6, at->y, 5) == -1);
    CHECK(light_at({{0, {100, 100}}, {4, {104, 100}}}, 103, 100, 5) == 4);
}

TEST_CASE("object ids: a sphere's texels match its analytic size, and the outline encloses them") {
    rt::Scene s;
    rt::Object o;
    o.shape = rt::Sphere{{10, 0, 0}, 2};
    s.objects.push_back(o);
    o.shape = rt::Sphere{{30, 8, 0}, 1};
    s.objects.push_back(o);
    rt::Camera cam = camera_at({0, 0, 0}, {10, 0, 0});
    s.camera = cam;
    auto world = rt::compile_world(s);
    const int W = 400, H = 300;
    SceneItem item{SceneItem::Kind::Object, 0};
    int x0, y0, x1, y1;
    item_window(*world, cam, W, H, 1, item, x0, y0, x1, y1);
    CHECK(x0 > 0);
    CHECK(x1 < W);
    IdBuffer part, whole;
    trace_ids(*world, cam, W, H, 1, x0, y0, x1, y1, part);
    trace_ids(*world, cam, W, H, 1, 0, 0, W, H, whole);
    const std::uint32_t code = id_code(item);
    CHECK(code == id_code(rt::PickResult{true, 0, -1, -1, 1, {}}));
    std::size_t n_part = 0, n_whole = 0;
    for (std::uint32_t v : part.ids) n_part += v == code;
    for (std::uint32_t v : whole.ids) n_whole += v == code;
    CHECK(n_part == n_whole);  // the window loses none of its texels
    // The disc seen from distance 10, radius 2: angular radius asin(0.2), on a film
    // whose half width spans tan(30 deg) and half height tan(22.5 deg).
    double Rx = std::tan(std::asin(0.2)) / std::tan(30 * rt::kDegree) * (W / 2.0);
    double Ry = std::tan(std::asin(0.2)) / std::tan(22.5 * rt::kDegree) * (H / 2.0);
    double R = std::max(Rx, Ry);
    double area = M_PI * Rx * Ry;
    CHECK(std::fabs(double(n_whole) - area) < 2 * M_PI * R);
    // The outline's length is about the circle's perimeter (staircase: up to 4/pi of it).
    double len = 0;
    for (const Edge& e : outline_edges(part, code)) len += std::abs(e.x1 - e.x0) + std::abs(e.y1 - e.y0);
    CHECK(len > 2 * M_PI * R * 0.95);
    CHECK(len < 2 * M_PI * R * 4 / M_PI * 1.05);
    // A coarser block: about block^2 fewer texels.
    IdBuffer coarse;
    item_window(*world, cam, W, H, 4, item, x0, y0, x1, y1);
    trace_ids(*world, cam, W, H, 4, x0, y0, x1, y1, coarse);
    std::size_t n4 = 0;
    for (std::uint32_t v : coarse.ids) n4 += v == code;
    CHECK(std::fabs(double(n4) * 16 - area) < 2 * M_PI * R * 4);
}

TEST_CASE("object ids: a selected CSG operand is outlined as its own silhouette, hidden parts too") {
    // A sphere of radius 2 with a dimple carved by a sphere of radius 1 nearer the eye:
    // the carving sphere shows as the dimple only, and its outline is its whole disc.
    rt::Scene s;
    rt::Object big, small, csg;
    big.shape = rt::Sphere{{10, 0, 0}, 2};
    small.shape = rt::Sphere{{8.5, 0, 0}, 1};
    csg.shape = rt::Csg{rt::CsgType::Difference, {big, small}};
    s.objects.push_back(csg);
    rt::Camera cam = camera_at({0, 0, 0}, {10, 0, 0});
    s.camera = cam;
    const int W = 400, H = 300;
    auto disc_texels = [&](double dist, double r) {
        double a = std::tan(std::asin(r / dist));
        return M_PI * a / std::tan(30 * rt::kDegree) * (W / 2.0) * a / std::tan(22.5 * rt::kDegree) * (H / 2.0);
    };
    auto count = [&](const rt::World& w, std::uint32_t code) {
        IdBuffer ids;
        trace_ids(w, cam, W, H, 1, 0, 0, W, H, ids);
        std::size_t n = 0;
        for (std::uint32_t v : ids.ids) n += v == code;
        return double(n);
    };
    ItemRef sel;
    sel.item = {SceneItem::Kind::Object, 0};
    CHECK_FALSE(bool(operand_world(s, sel)));  // the CSG itself: the scene's world serves
    sel.path = {1};
    auto carver = operand_world(s, sel);
    REQUIRE(bool(carver));
    const std::uint32_t code = id_code(SceneItem{SceneItem::Kind::Object, 0});
    const double small_disc = disc_texels(8.5, 1), big_disc = disc_texels(10, 2);
    CHECK(std::fabs(count(*carver, code) - small_disc) < 0.05 * small_disc);
    sel.path = {0};
    auto outer = operand_world(s, sel);
    REQUIRE(bool(outer));
    CHECK(std::fabs(count(*outer, code) - big_disc) < 0.05 * big_disc);
    // The whole CSG, for contrast, is the big disc (the dimple is still its surface).
    CHECK(std::fabs(count(*rt::compile_world(s), code) - big_disc) < 0.05 * big_disc);
    sel.path = {1, 0};  // below a sphere: no operand
    CHECK_FALSE(bool(operand_world(s, sel)));
    sel.path = {1};
    sel.item.index = 3;  // no such object
    CHECK_FALSE(bool(operand_world(s, sel)));
}

namespace {
// A 6 x 5 id buffer whose texels x 2..4, y 1..2 (a block of 3 x 2) hold code 9.
IdBuffer block_of_texels() {
    IdBuffer b;
    b.width = 6, b.height = 5;
    b.x0 = 0, b.y0 = 0, b.x1 = 6, b.y1 = 5;
    b.ids.assign(30, 0);
    for (int y = 1; y < 3; ++y)
        for (int x = 2; x < 5; ++x) b.ids[std::size_t(y * 6 + x)] = 9;
    return b;
}
}  // namespace

TEST_CASE("object ids: the outline of a block of texels is its four sides") {
    IdBuffer b = block_of_texels();
    b.ids[0] = 5;  // another item
    std::vector<Edge> e = outline_edges(b, 9);
    REQUIRE(e.size() == 4);
    int total = 0;
    for (const Edge& x : e) total += std::abs(x.x1 - x.x0) + std::abs(x.y1 - x.y0);
    CHECK(total == 10);
    CHECK(outline_edges(b, 0).empty());
    CHECK(outline_edges(b, 13).empty());
}

namespace {
double seg_length(const Segment& g) { return std::hypot(double(g.x1 - g.x0), double(g.y1 - g.y0)); }
}  // namespace

TEST_CASE("object ids: the outline as drawn cuts each corner; a staircase of texels becomes a diagonal") {
    // A block of 3 x 2 texels: its four sides, each corner cut by a half-texel diagonal.
    IdBuffer b = block_of_texels();
    std::vector<Segment> box = smooth_corners(outline_edges(b, 9));
    REQUIRE(box.size() == 8);
    int diagonals = 0;
    double total = 0;
    for (const Segment& g : box) {
        total += seg_length(g);
        if (g.x0 != g.x1 && g.y0 != g.y1) {
            ++diagonals;
            CHECK(std::abs(g.x1 - g.x0) == doctest::Approx(0.5));
            CHECK(std::abs(g.y1 - g.y0) == doctest::Approx(0.5));
        }
    }
    CHECK(diagonals == 4);
    CHECK(total == doctest::Approx(10 - 8 * 0.5 + 4 * std::sqrt(0.5)));

    // A staircase of single texels (x = y, a diagonal band): its stepped side becomes
    // diagonals on one straight line.
    IdBuffer st;
    st.width = st.height = 8;
    st.x0 = st.y0 = 0, st.x1 = st.y1 = 8;
    st.ids.assign(64, 0);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x <= y; ++x) st.ids[std::size_t(y * 8 + x)] = 4;  // below the diagonal
    const std::vector<Edge> steps = outline_edges(st, 4);
    const std::vector<Segment> smooth = smooth_corners(steps);
    // The steps: row y's top from (y, y) to (y + 1, y), then down to (y + 1, y + 1); the
    // diagonals join their midpoints, on the line y = x - 0.5 (the staircase's middle).
    int on_line = 0, cuts = 0;
    for (const Segment& g : smooth)
        if (g.x0 != g.x1 && g.y0 != g.y1) {
            ++cuts;
            on_line += std::abs(g.y0 - g.x0 + 0.5f) < 1e-6f && std::abs(g.y1 - g.x1 + 0.5f) < 1e-6f;
        }
    CHECK(on_line == 15);    // the 16 unit steps meet at 15 corners
    CHECK(cuts == 18);  // and the triangle's three other corners
    // Nothing of the steps is left between them: each unit run is cut to nothing.
    for (const Segment& g : smooth)
        if (g.x0 == g.x1 || g.y0 == g.y1) CHECK(seg_length(g) >= 0.5);

    // Where three edges meet (two selected things side by side), nothing is cut.
    const std::vector<Edge> tee = {{0, 0, 2, 0}, {2, 0, 4, 0}, {2, 0, 2, 3}};
    const std::vector<Segment> kept = smooth_corners(tee);
    REQUIRE(kept.size() == 3);
    double sum = 0;
    for (const Segment& g : kept) sum += seg_length(g);
    CHECK(sum == doctest::Approx(7));
}
