// Object-id buffer and selection outline (see object_ids.h).
#include "object_ids.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "parallel.h"
#include "renderer.h"
#include "shapes.h"

namespace rtview {

std::uint32_t id_code(const rt::PickResult& r) { return rt::pick_id(r); }

std::uint32_t id_code(const SceneItem& item) {
    if (item.index < 0) return 0;
    std::uint32_t k = item.kind == SceneItem::Kind::Object ? 1 : item.kind == SceneItem::Kind::Plane ? 2 : 3;
    return std::uint32_t(item.index + 1) * 4 + k;
}

std::shared_ptr<const rt::World> operand_world(const rt::Scene& scene, const ItemRef& sel) {
    if (sel.path.empty() || !sel.is(SceneItem::Kind::Object)) return nullptr;
    const std::size_t i = std::size_t(sel.item.index);
    if (i >= scene.objects.size()) return nullptr;
    const rt::Object* op = operand_of(scene.objects[i], sel.path);
    if (!op) return nullptr;
    rt::Scene alone;
    alone.camera = scene.camera;
    alone.width = scene.width;
    alone.height = scene.height;
    alone.objects.push_back(*op);
    return rt::compile_world(alone);
}

void item_window(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block,
                 const SceneItem& item, int& x0, int& y0, int& x1, int& y1) {
    int b = std::max(1, block);
    int tw = (film_w + b - 1) / b, th = (film_h + b - 1) / b;
    x0 = y0 = x1 = y1 = 0;
    rt::Aabb box;
    std::size_t i = std::size_t(item.index);
    if (item.index < 0) return;
    if (item.kind == SceneItem::Kind::Object) {
        if (i >= world.object_count()) return;
        box = world.geometry->object_bounds[world.slot_of(i)];
    } else if (item.kind == SceneItem::Kind::Light) {
        if (i >= world.lights.size()) return;
        const rt::ShadeLight& l = world.lights[i];
        if (!(l.size > 0)) return;  // only a lamp's glow disc is seen
        rt::Vec3 e{l.size, l.size, l.size};
        box = {l.position - e, l.position + e};
    } else {
        if (i >= world.planes.size()) return;
        x1 = tw, y1 = th;  // a plane may be anywhere on screen
        return;
    }
    if (box.empty()) return;
    // Film coordinates of the box's corners. A corner at or behind the eye's plane
    // gives no bound: the whole film then.
    rt::CameraBasis cb = rt::CameraBasis::make(camera, film_w, film_h, false);
    if (cb.projection != rt::Projection::Linear) {
        x1 = tw, y1 = th;
        return;
    }
    double lo_i = HUGE_VAL, hi_i = -HUGE_VAL, lo_j = HUGE_VAL, hi_j = -HUGE_VAL;
    for (int c = 0; c < 8; ++c) {
        rt::Vec3 p{c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y, c & 4 ? box.hi.z : box.lo.z};
        rt::Vec3 d = p - cb.origin;
        double z = rt::dot(d, cb.forward);
        if (!(z > 1e-9 * rt::length(d))) {
            x1 = tw, y1 = th;
            return;
        }
        // Inverse of CameraBasis::direction (not mirrored): sx = -tan_x (hw - i) / hw.
        double sx = rt::dot(d, cb.side) / z, sy = rt::dot(d, cb.up) / z;
        double fi = film_w / 2.0 * (1 + sx / cb.tan_x), fj = film_h / 2.0 * (1 - sy / cb.tan_y);
        lo_i = std::min(lo_i, fi), hi_i = std::max(hi_i, fi);
        lo_j = std::min(lo_j, fj), hi_j = std::max(hi_j, fj);
    }
    // Texel k samples film coordinate k b; one texel of margin each side.
    auto clampi = [](double v, int hi) { return int(std::clamp(v, 0.0, double(hi))); };
    x0 = clampi(std::floor(lo_i / b) - 1, tw);
    x1 = clampi(std::ceil(hi_i / b) + 2, tw);
    y0 = clampi(std::floor(lo_j / b) - 1, th);
    y1 = clampi(std::ceil(hi_j / b) + 2, th);
    if (x0 >= x1 || y0 >= y1) x0 = x1 = y0 = y1 = 0;
}

std::size_t trace_ids(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block, int x0,
                      int y0, int x1, int y1, IdBuffer& out) {
    int b = std::max(1, block);
    out.block = b;
    out.width = (film_w + b - 1) / b;
    out.height = (film_h + b - 1) / b;
    out.x0 = std::clamp(x0, 0, out.width), out.x1 = std::clamp(x1, out.x0, out.width);
    out.y0 = std::clamp(y0, 0, out.height), out.y1 = std::clamp(y1, out.y0, out.height);
    out.ids.assign(std::size_t(out.width) * std::size_t(out.height), 0);
    if (out.x0 == out.x1 || out.y0 == out.y1) return 0;
    // An id pass of the window, on the one pool's workers; the world is the caller's
    // for as long as this waits (a pointer that owns nothing).
    rt::Renderer renderer(rt::process_pool());
    rt::RenderSettings st;
    st.width = film_w;
    st.height = film_h;
    st.camera = camera;
    st.pass = rt::RenderPass::Ids;
    st.step = b;
    st.crop = {out.x0, out.y0, out.x1, out.y1};
    renderer.start(std::shared_ptr<const rt::World>(std::shared_ptr<const rt::World>(), &world), st);
    renderer.wait();
    int w = 0, h = 0;
    renderer.ids(out.ids, w, h);
    return std::size_t(out.x1 - out.x0) * std::size_t(out.y1 - out.y0);
}

std::vector<Edge> outline_edges(const IdBuffer& ids, std::uint32_t code) {
    std::vector<Edge> out;
    if (code == 0) return out;
    auto in = [&](int x, int y) { return ids.at(x, y) == code; };
    // Horizontal borders: along the top of row y, between rows y - 1 and y.
    for (int y = ids.y0; y <= ids.y1; ++y) {
        int run = -1;
        for (int x = ids.x0; x <= ids.x1; ++x) {
            bool edge = x < ids.x1 && in(x, y) != in(x, y - 1);
            if (edge && run < 0) run = x;
            if (!edge && run >= 0) {
                out.push_back({run, y, x, y});
                run = -1;
            }
        }
    }
    // Vertical borders: along the left of column x.
    for (int x = ids.x0; x <= ids.x1; ++x) {
        int run = -1;
        for (int y = ids.y0; y <= ids.y1; ++y) {
            bool edge = y < ids.y1 && in(x, y) != in(x - 1, y);
            if (edge && run < 0) run = y;
            if (!edge && run >= 0) {
                out.push_back({x, run, x, y});
                run = -1;
            }
        }
    }
    return out;
}

namespace {

// An edge's end as a key: the texel corner's two coordinates.
std::uint64_t corner_key(int x, int y) { return (std::uint64_t(std::uint32_t(x)) << 32) | std::uint32_t(y); }

}  // namespace

std::vector<Segment> smooth_corners(const std::vector<Edge>& edges) {
    // The edge ends meeting at each corner (edge index * 2 + which end).
    std::unordered_map<std::uint64_t, std::vector<std::size_t>> at;
    at.reserve(edges.size() * 2);
    for (std::size_t i = 0; i < edges.size(); ++i) {
        at[corner_key(edges[i].x0, edges[i].y0)].push_back(2 * i);
        at[corner_key(edges[i].x1, edges[i].y1)].push_back(2 * i + 1);
    }
    auto length = [&](std::size_t i) { return float(std::abs(edges[i].x1 - edges[i].x0) + std::abs(edges[i].y1 - edges[i].y0)); };
    auto horizontal = [&](std::size_t i) { return edges[i].y0 == edges[i].y1; };
    // How far each end is cut back, and the point it is cut back to.
    std::vector<float> cut(edges.size() * 2, 0.f);
    auto cut_point = [&](std::size_t end, float c) {
        const Edge& e = edges[end / 2];
        const bool first = end % 2 == 0;
        const float x = float(first ? e.x0 : e.x1), y = float(first ? e.y0 : e.y1);
        const float dx = float(first ? e.x1 - e.x0 : e.x0 - e.x1), dy = float(first ? e.y1 - e.y0 : e.y0 - e.y1);
        const float len = std::abs(dx) + std::abs(dy);
        return std::pair<float, float>{x + dx / len * c, y + dy / len * c};
    };
    std::vector<Segment> out;
    out.reserve(edges.size() * 2);
    for (const auto& [key, ends] : at) {
        if (ends.size() != 2) continue;
        const std::size_t a = ends[0], b = ends[1];
        if (horizontal(a / 2) == horizontal(b / 2)) continue;
        const float c = std::min({0.5f, length(a / 2) / 2, length(b / 2) / 2});
        cut[a] = cut[b] = c;
        const auto [ax, ay] = cut_point(a, c);
        const auto [bx, by] = cut_point(b, c);
        out.push_back({ax, ay, bx, by});
    }
    for (std::size_t i = 0; i < edges.size(); ++i) {
        if (length(i) - cut[2 * i] - cut[2 * i + 1] <= 0) continue;
        const auto [x0, y0] = cut_point(2 * i, cut[2 * i]);
        const auto [x1, y1] = cut_point(2 * i + 1, cut[2 * i + 1]);
        out.push_back({x0, y0, x1, y1});
    }
    return out;
}

}  // namespace rtview
