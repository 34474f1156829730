// Camera motions: orbit, pan, dolly, fly, frame, aspect fit and projection.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "camera_control.h"

using namespace rtview;
using rt::Vec3;

namespace {

std::mt19937 rng(12345);
double uni(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
Vec3 rvec(double s) { return {uni(-s, s), uni(-s, s), uni(-s, s)}; }

rt::Camera random_camera() {
    for (;;) {
        rt::Camera c;
        c.position = rvec(10);
        c.centre = rvec(10);
        c.up = c.centre + Vec3{uni(-0.3, 0.3), uni(-0.3, 0.3), 1};
        c.angle_x = uni(20, 100);
        c.angle_y = uni(20, 90);
        if (!rt::camera_problem(c) && rt::length(c.centre - c.position) > 1) return c;
    }
}

double angle_deg(const Vec3& a, const Vec3& b) {
    return std::acos(std::clamp(rt::dot(rt::normalize(a), rt::normalize(b)), -1.0, 1.0)) * 180 / 3.14159265358979;
}

}  // namespace

TEST_CASE("orbiting keeps the eye's distance to the pivot and moves the rig rigidly") {
    for (int n = 0; n < 500; ++n) {
        rt::Camera c = random_camera();
        Vec3 pivot = rvec(10);
        Vec3 up = world_up_of(c);
        rt::Camera o = orbit(c, pivot, up, uni(-4, 4), uni(-1, 1));
        CHECK(rt::length(o.position - pivot) == doctest::Approx(rt::length(c.position - pivot)).epsilon(1e-9));
        CHECK(rt::length(o.centre - pivot) == doctest::Approx(rt::length(c.centre - pivot)).epsilon(1e-9));
        CHECK(rt::length(o.centre - o.position) == doctest::Approx(rt::length(c.centre - c.position)).epsilon(1e-9));
        CHECK(rt::length(o.up - o.centre) == doctest::Approx(rt::length(c.up - c.centre)).epsilon(1e-9));
        CHECK(rt::camera_problem(o) == nullptr);
    }
}

TEST_CASE("a pure yaw keeps the eye's height along world up") {
    rt::Camera c = random_camera();
    Vec3 up = world_up_of(c), pivot = rvec(3);
    rt::Camera o = orbit(c, pivot, up, 1.234, 0);
    CHECK(rt::dot(o.position - pivot, up) == doctest::Approx(rt::dot(c.position - pivot, up)));
}

TEST_CASE("orbit elevation stops short of the pole instead of flipping over") {
    rt::Camera c;
    c.position = {-5, 0, 0};
    c.centre = {0, 0, 0};
    c.up = {0, 0, 1};
    Vec3 up{0, 0, 1};
    rt::Camera o = orbit(c, c.centre, up, 0, 10.0);  // far more than 90 degrees
    double a = angle_deg(o.centre - o.position, up);
    CHECK(a <= 179.0 + 1e-6);
    CHECK(a >= 178.9);
    CHECK(o.position.z > 4.9);  // it did rise to (nearly) straight above
    rt::Camera d = orbit(c, c.centre, up, 0, -10.0);
    CHECK(angle_deg(d.centre - d.position, up) >= 1.0 - 1e-6);
}

TEST_CASE("dragging right moves the eye to the camera's left (the scene turns with the hand)") {
    rt::Camera c;
    c.position = {-5, 0, 1};
    c.centre = {0, 0, 1};
    c.up = {0, 0, 2};
    rt::CameraBasis b = rt::CameraBasis::make(c, 100, 100, false);
    // Screen right is where column index grows: direction(i = width) side.
    Vec3 screen_right = rt::normalize(b.direction(100, 50) - b.direction(0, 50));
    rt::Camera o = orbit(c, c.centre, {0, 0, 1}, -0.2, 0);  // what a rightward drag asks for
    CHECK(rt::dot(o.position - c.position, screen_right) < 0);
}

TEST_CASE("pan keeps the grabbed point under the cursor") {
    for (int n = 0; n < 200; ++n) {
        rt::Camera c = random_camera();
        int w = 640, h = 400;
        rt::Camera v = fit_camera_to_aspect(c, w, h);
        rt::CameraBasis b = rt::CameraBasis::make(v, w, h, false);
        double i0 = uni(0, w), j0 = uni(0, h), i1 = uni(0, w), j1 = uni(0, h);
        Vec3 anchor = b.origin + rt::normalize(b.direction(i0, j0)) * uni(1, 30);
        rt::Camera p = translate(v, pan_offset(b, anchor, i0, j0, i1, j1));
        double i, j;
        REQUIRE(project(rt::CameraBasis::make(p, w, h, false), anchor, i, j));
        CHECK(i == doctest::Approx(i1).epsilon(1e-6));
        CHECK(j == doctest::Approx(j1).epsilon(1e-6));
        CHECK(p.angle_x == v.angle_x);
    }
}

TEST_CASE("dolly moves toward the point under the cursor and keeps it there") {
    for (int n = 0; n < 200; ++n) {
        rt::Camera c = random_camera();
        int w = 500, h = 300;
        rt::CameraBasis b = rt::CameraBasis::make(c, w, h, false);
        double i0 = uni(0, w), j0 = uni(0, h);
        double dist = uni(1, 50);
        Vec3 target = b.origin + rt::normalize(b.direction(i0, j0)) * dist;
        double notches = uni(-3, 3);
        rt::Camera d = translate(c, dolly_offset(c.position, target, notches));
        double expect = notches > 0 ? std::max(std::pow(0.8, notches), 0.1) : std::pow(0.8, notches);
        CHECK(rt::length(target - d.position) == doctest::Approx(dist * expect).epsilon(1e-9));
        double i, j;
        REQUIRE(project(rt::CameraBasis::make(d, w, h, false), target, i, j));
        CHECK(i == doctest::Approx(i0).epsilon(1e-6));
        CHECK(j == doctest::Approx(j0).epsilon(1e-6));
    }
}

TEST_CASE("dolly brings the look-at point along: the distance to it scales with the step, the view stays") {
    for (int n = 0; n < 200; ++n) {
        rt::Camera c = random_camera();
        const int w = 500, h = 300;
        const rt::CameraBasis b = rt::CameraBasis::make(c, w, h, false);
        const double i0 = uni(0, w), j0 = uni(0, h);
        const Vec3 target = b.origin + rt::normalize(b.direction(i0, j0)) * uni(1, 50);
        const double notches = uni(-3, 3);
        const rt::Camera d = dolly(c, target, notches);
        const double f = rt::length(target - d.position) / rt::length(target - c.position);
        CHECK(rt::length(d.centre - d.position) == doctest::Approx(f * rt::length(c.centre - c.position)));
        CHECK(angle_deg(d.centre - d.position, c.centre - c.position) < 1e-4);
        CHECK(rt::length((d.up - d.centre) - (c.up - c.centre)) < 1e-9);
        CHECK(rt::length(d.position - translate(c, dolly_offset(c.position, target, notches)).position) < 1e-9);
        double i, j;
        REQUIRE(project(rt::CameraBasis::make(d, w, h, false), target, i, j));
        CHECK(i == doctest::Approx(i0).epsilon(1e-6));
        CHECK(j == doctest::Approx(j0).epsilon(1e-6));
    }
}

TEST_CASE("dolly never reaches or passes its target") {
    Vec3 eye{0, 0, 0}, target{10, 0, 0};
    for (double n : {1.0, 5.0, 50.0, 1000.0}) {
        Vec3 e = eye + dolly_offset(eye, target, n);
        CHECK(e.x < 10);
        CHECK(e.x >= 0);
    }
}

TEST_CASE("an orbit pivot beyond the scene's reach comes to that reach along its ray") {
    rt::Camera c = random_camera();
    rt::Aabb box;
    box.grow({1, 2, 3});
    box.grow({4, -5, 6});
    const double reach = scene_reach(c, box);
    CHECK(reach >= rt::length(c.centre - c.position));
    for (int k = 0; k < 8; ++k) {
        const Vec3 corner{k & 1 ? 4.0 : 1.0, k & 2 ? -5.0 : 2.0, k & 4 ? 6.0 : 3.0};
        CHECK(rt::length(corner - c.position) <= reach + 1e-12);
    }
    // Empty bounds: the distance to the centre.
    CHECK(scene_reach(c, rt::Aabb{}) == rt::length(c.centre - c.position));
    for (int n = 0; n < 100; ++n) {
        const Vec3 dir = rt::normalize(rvec(1));
        const double t = uni(0.1, 3) * reach;
        const Vec3 p = clamp_pivot(c.position, c.position + dir * t, reach);
        CHECK(rt::length(p - c.position) == doctest::Approx(std::min(t, reach)));
        CHECK(angle_deg(p - c.position, dir) < 1e-4);
    }
}

TEST_CASE("fly steps along the view, the horizontal right and world up") {
    rt::Camera c;
    c.position = {0, 0, 0};
    c.centre = {1, 0, 0};
    c.up = {1, 0, 1};
    Vec3 up{0, 0, 1};
    Vec3 f = fly_offset(c, up, {0, 0, 1}, 2);
    CHECK(f.x == doctest::Approx(2));
    Vec3 r = fly_offset(c, up, {1, 0, 0}, 1);
    CHECK(rt::length(r) == doctest::Approx(1));
    CHECK(rt::dot(r, up) == doctest::Approx(0));
    Vec3 u = fly_offset(c, up, {0, 1, 0}, 3);
    CHECK(u.z == doctest::Approx(3));
}

TEST_CASE("the aspect fit keeps angle_y and makes pixels square") {
    rt::Camera c = random_camera();
    for (auto [w, h] : {std::pair{1280, 720}, std::pair{300, 900}, std::pair{640, 480}}) {
        rt::Camera f = fit_camera_to_aspect(c, w, h);
        CHECK(f.angle_y == c.angle_y);
        double k = rt::kDegree / 2;
        CHECK(std::tan(f.angle_x * k) / std::tan(f.angle_y * k) == doctest::Approx(double(w) / h));
        // Square pixels: one pixel step subtends the same at the centre both ways.
        rt::CameraBasis b = rt::CameraBasis::make(f, w, h, false);
        Vec3 d0 = rt::normalize(b.direction(w / 2.0, h / 2.0));
        double dx = angle_deg(d0, b.direction(w / 2.0 + 1, h / 2.0));
        double dy = angle_deg(d0, b.direction(w / 2.0, h / 2.0 + 1));
        CHECK(dx == doctest::Approx(dy).epsilon(1e-6));
    }
}

TEST_CASE("framing puts every corner of the scene bounds in view, keeping the direction") {
    for (int n = 0; n < 100; ++n) {
        rt::Camera c = random_camera();
        rt::Aabb box;
        box.grow(rvec(20));
        box.grow(rvec(20));
        rt::Camera f = frame_bounds(c, box);
        CHECK(angle_deg(f.centre - f.position, c.centre - c.position) < 1e-5);
        rt::CameraBasis b = rt::CameraBasis::make(f, 400, 300, false);
        for (int k = 0; k < 8; ++k) {
            Vec3 p{k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z};
            double i, j;
            REQUIRE(project(b, p, i, j));
            CHECK(i >= 0);
            CHECK(i <= 400);
            CHECK(j >= 0);
            CHECK(j <= 300);
        }
    }
    rt::Camera c = random_camera();
    CHECK(frame_bounds(c, rt::Aabb{}) == c);
}

TEST_CASE("view angles read back what set_view_angles wrote") {
    rt::Camera c = random_camera();
    Vec3 up = world_up_of(c);
    ViewAngles want{37, -21, 7.5};
    rt::Camera s = set_view_angles(c, up, want);
    ViewAngles got = view_angles(s, up);
    CHECK(got.azimuth == doctest::Approx(want.azimuth));
    CHECK(got.elevation == doctest::Approx(want.elevation));
    CHECK(got.distance == doctest::Approx(want.distance));
    CHECK(s.centre == c.centre);
}

TEST_CASE("project inverts CameraBasis::direction for both projections") {
    for (rt::Projection pr : {rt::Projection::Linear, rt::Projection::Polar}) {
        for (bool mirror : {false, true}) {
            rt::Camera c = random_camera();
            c.projection = pr;
            rt::CameraBasis b = rt::CameraBasis::make(c, 321, 200, mirror);
            for (int n = 0; n < 50; ++n) {
                double i0 = uni(0, 320), j0 = uni(0, 199);
                Vec3 p = b.origin + rt::normalize(b.direction(i0, j0)) * uni(0.5, 20);
                double i, j;
                REQUIRE(project(b, p, i, j));
                CHECK(i == doctest::Approx(i0).epsilon(1e-7));
                CHECK(j == doctest::Approx(j0).epsilon(1e-7));
            }
        }
    }
}

TEST_CASE("a tidied camera is the same view to under 1e-7 radians, at any scale") {
    for (double scale : {1e-4, 1.0, 3e6}) {
        for (int k = 0; k < 200; ++k) {
            rt::Camera c = orbit(random_camera(), Vec3{0, 0, 0}, Vec3{0, 0, 1}, uni(-3, 3), uni(-1, 1));
            c.position = c.position * scale, c.centre = c.centre * scale, c.up = c.up * scale;
            const rt::Camera t = tidy_camera(c);
            CAPTURE(scale);
            const double d = rt::length(c.centre - c.position);
            // Each point moves by at most half the grid's step (<= 1e-7 d), so the
            // view direction and the up direction turn by well under 1e-6 degrees.
            CHECK(rt::length(t.position - c.position) <= 1e-7 * d);
            CHECK(rt::length(t.centre - c.centre) <= 1e-7 * d);
            CHECK(angle_deg(t.centre - t.position, c.centre - c.position) < 1e-5);
            CHECK(angle_deg(t.up - t.position, c.up - c.position) < 1e-5);
            CHECK(t.angle_x == c.angle_x);
            CHECK(tidy_camera(t) == t);  // already on the grid: unchanged
        }
    }
}
