// Structural edits as text replacements (see scene_edits.h). Block extents come from
// scene_text's scan_layout (the parser's lexical rules); new blocks come from the
// scene writer, re-indented to sit where they go. Moving an item's points:
// item_moves.cpp.
#include "scene_edits.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <utility>
#include <vector>

#include "model.h"
#include "placement.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "triangles.h"

namespace rtview {

const char* new_item_name(NewItem k) {
    switch (k) {
    case NewItem::Sphere: return "sphere";
    case NewItem::Cylinder: return "cylinder";
    case NewItem::Tetrahedron: return "tetrahedron";
    case NewItem::Torus: return "torus";
    case NewItem::Box: return "box";
    case NewItem::Cone: return "cone";
    case NewItem::Plane: return "plane";
    case NewItem::ChessPlane: return "chess_plane";
    case NewItem::Lamp: return "lamp";
    case NewItem::Spotlight: return "spotlight";
    }
    return "";
}

std::optional<NewItem> new_item_kind(std::string_view name) {
    for (NewItem k : kNewItems)
        if (name == new_item_name(k)) return k;
    return std::nullopt;
}

namespace {

using rt::Vec3;

// ---- numbers a person would write --------------------------------------------------

// A coordinate rounded to a thousandth of the scene's extent, so a click at
// 2.3418765 becomes 2.342 in the text.
double round_to(double v, double extent) {
    if (!std::isfinite(v)) return 0;
    double e = std::floor(std::log10(extent > 0 && std::isfinite(extent) ? extent : 1.0)) - 3;
    // (+ 0.0: a value rounded to zero is written 0, not -0.)
    if (e < 0) {
        double k = std::pow(10.0, -e);
        return std::round(v * k) / k + 0.0;
    }
    double q = std::pow(10.0, e);
    return std::round(v / q) * q + 0.0;
}
Vec3 round_to(Vec3 v, double extent) { return {round_to(v.x, extent), round_to(v.y, extent), round_to(v.z, extent)}; }

// ---- text helpers -----------------------------------------------------------------

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

ItemList list_of(SceneItem::Kind kind) {
    return kind == SceneItem::Kind::Object ? ItemList::Object : kind == SceneItem::Kind::Plane ? ItemList::Plane : ItemList::Light;
}

// The writer's text of the only item of `one`, indented for a line starting with `indent`.
std::string written_block(const rt::Scene& one, SceneItem::Kind kind, const std::string& indent) {
    return written_item(one, list_of(kind), indent);
}

const std::vector<TextSpan>& spans_of(const SceneLayout& l, SceneItem::Kind k) {
    return k == SceneItem::Kind::Object ? l.objects : k == SceneItem::Kind::Plane ? l.planes : l.lights;
}
std::size_t count_of(const rt::Scene& s, SceneItem::Kind k) {
    return k == SceneItem::Kind::Object ? s.objects.size() : k == SceneItem::Kind::Plane ? s.planes.size() : s.lights.size();
}

// The layout, if it matches the scene's own items (those of the file itself, not of
// its includes) one for one.
// The layout to plan on: `given` (the document keeps it up to date) or one scanned
// into `own`; null when it does not match the scene's items one for one.
const SceneLayout* layout_of(const std::string& text, const rt::Scene& scene, const SceneLayout* given,
                             std::optional<SceneLayout>& own) {
    if (!given) {
        own = scan_layout(text);
        given = &*own;
    }
    return layout_matches(*given, scene) ? given : nullptr;
}

// The block of a scene item in the text, and its place among the own items; nothing
// for an item read from an included file (it has no block here) or out of range.
std::optional<std::pair<TextSpan, std::size_t>> block_of(const SceneLayout& l, const rt::Scene& scene,
                                                          SceneItem::Kind kind, int index) {
    if (index < 0) return std::nullopt;
    const std::optional<std::size_t> own = own_index(scene, list_of(kind), std::size_t(index));
    const std::vector<TextSpan>& spans = spans_of(l, kind);
    if (!own || *own >= spans.size()) return std::nullopt;
    return std::make_pair(spans[*own], *own);
}

// Where a block inserted after the last own block of `kind` lands in the scene's list:
// after the last own item, or at the end (a new section goes before `end`, after
// every include).
int appended_index(const rt::Scene& scene, SceneItem::Kind kind) {
    const std::size_t n = count_of(scene, kind);
    if (scene.includes.empty()) return int(n);
    for (std::size_t k = n; k-- > 0;)
        if (own_index(scene, list_of(kind), k)) return int(k + 1);
    return int(n);
}

// Text for a new block of `kind`: after the last block of that kind (on its own line,
// with that block's indentation), or in a new section before `end`.
TextReplacement insert_block(const std::string& text, const SceneLayout& l, SceneItem::Kind kind,
                             const rt::Scene& one, std::size_t after_index = std::size_t(-1), bool* new_section = nullptr) {
    const std::vector<TextSpan>& spans = spans_of(l, kind);
    if (new_section) *new_section = spans.empty();
    if (!spans.empty()) {
        TextSpan s = spans[std::min(after_index, spans.size() - 1)];
        std::string indent = line_indent(text, s.begin);
        return {s.end, 0, "\n" + indent + written_block(one, kind, indent)};
    }
    const char* section = kind == SceneItem::Kind::Object  ? "thing"
                          : kind == SceneItem::Kind::Plane ? "special_thing"
                                                           : "light";
    std::string block = std::string(section) + " {\n  " + written_block(one, kind, "  ") + "\n}\n";
    std::size_t at = l.append_at;
    if (at > 0 && text[at - 1] != '\n') block = "\n" + block;
    return {at, 0, block};
}

// The span of a block to delete: its whole line(s) when nothing else is on them (a
// trailing // comment goes with it), else the block and the blanks after it.
TextSpan deletion_span(const std::string& text, TextSpan s) {
    std::size_t b = s.begin, e = s.end;
    while (b > 0 && blank(text[b - 1]) && text[b - 1] != '\r') --b;
    bool line_start = b == 0 || text[b - 1] == '\n';
    std::size_t t = e;
    while (t < text.size() && blank(text[t])) ++t;
    bool comment = t + 1 < text.size() && text[t] == '/' && text[t + 1] == '/';
    if (comment)
        while (t < text.size() && text[t] != '\n') ++t;
    bool line_end = t == text.size() || text[t] == '\n';
    if (line_start && line_end) {
        if (t < text.size()) return {b, t + 1};  // the line and its newline
        // Last line without a newline: take the newline before it instead.
        if (b > 0) --b;
        return {b, t};
    }
    std::size_t after = e;
    while (after < text.size() && blank(text[after])) ++after;
    if (after < text.size() && text[after] != '\n') return {s.begin, after};
    std::size_t before = s.begin;
    while (before > 0 && blank(text[before - 1])) --before;
    return {before, e};
}

// One replacement covering several (sorted, disjoint) ones, with the text between
// them unchanged.
TextReplacement merge(const std::string& text, std::vector<TextReplacement> reps) {
    std::sort(reps.begin(), reps.end(), [](const TextReplacement& a, const TextReplacement& b) { return a.offset < b.offset; });
    TextReplacement out{reps.front().offset, 0, {}};
    std::size_t pos = out.offset;
    for (const TextReplacement& r : reps) {
        out.text += text.substr(pos, r.offset - pos);
        out.text += r.text;
        pos = r.offset + r.length;
    }
    out.length = pos - out.offset;
    return out;
}

// The normal of an upright plane (one that contains `up`) facing `toward`: toward's
// part across `up`, or `fallback` (across `up` too) when toward runs along it.
Vec3 upright_facing(const Vec3& up, const Vec3& toward, const Vec3& fallback) {
    Vec3 n = toward - up * rt::dot(toward, up);
    if (!rt::finite(n) || !(rt::length2(n) > 1e-12 * rt::length2(toward))) return fallback;
    return rt::normalize(n);
}

// A new light's colour at `position`, lighting the point `at`: as bright there as the
// last light is (light falls off as 1/r^2, so a lamp put near a surface gets less than
// one far above the scene: a copy of its colour would burn the surface white), to three
// digits.
rt::Colour new_light_colour(const rt::Scene& scene, double extent, const Vec3& at, const Vec3& position) {
    if (!scene.lights.empty()) {
        const rt::Light& last = scene.lights.back();
        const double far = rt::length2(last.position - at), near = rt::length2(position - at);
        if (!(far > 0) || !(near > 0) || !std::isfinite(far) || !std::isfinite(near)) return last.colour;
        auto three_digits = [](double v) {
            if (!(v > 0) || !std::isfinite(v)) return v;
            const double p = std::pow(10.0, std::floor(std::log10(v)) - 2);
            return std::round(v / p) * p;
        };
        const double k = near / far;
        return {three_digits(last.colour.x * k), three_digits(last.colour.y * k), three_digits(last.colour.z * k)};
    }
    // Light falls off as 1/r^2: about 1 at half the scene's size.
    double c = nice_size(std::max(1.0, 0.25 * extent * extent));
    return {c, c, c};
}

constexpr const char* kSizeMark = "// lamp size ";

// The number after the last `// lamp size ` in `block`, if any.
std::optional<double> kept_size(const std::string& block) {
    std::size_t p = block.rfind(kSizeMark);
    if (p == std::string::npos) return std::nullopt;
    p += std::string(kSizeMark).size();
    std::size_t e = p;
    while (e < block.size() && !blank(block[e]) && block[e] != '\n' && block[e] != '}') ++e;
    double v = 0;
    auto r = std::from_chars(block.data() + p, block.data() + e, v);
    if (r.ec != std::errc() || r.ptr != block.data() + e || !std::isfinite(v)) return std::nullopt;
    return v;
}

// The new item's block (in `one`) at `at`, with coordinates rounded to a thousandth of
// `scale`; `where` says which list it is in.
// `extent` and `r`: scene_extent(scene) and nice_size(typical_object_size(scene)),
// passes over every object, found once by the caller.
void new_item(const rt::Scene& scene, NewItem kind, const Placement& at, double scale, double extent, double r,
              rt::Scene& one, SceneItem::Kind& where) {
    const Vec3 up = up_of(scene, at);
    const rt::Frame f = rt::Frame::from_axis(up);
    const Vec3 p = at.point;
    auto rp = [&](Vec3 v) { return round_to(v, scale); };

    one.camera = scene.camera;
    where = SceneItem::Kind::Object;
    rt::Object o;
    switch (kind) {
    case NewItem::Sphere: o.shape = rt::Sphere{rp(p + up * r), r}; break;
    case NewItem::Cylinder: o.shape = rt::Cylinder{rp(p), rp(p + up * (2 * r)), r}; break;
    case NewItem::Tetrahedron: {
        // Three corners on the surface around the point, the fourth above it.
        rt::Tetrahedron t;
        for (int k = 0; k < 3; ++k) {
            double a = 2.0943951023931957 * k;  // 120 degrees apart
            t.v[k] = rp(p + (f.u * std::cos(a) + f.v * std::sin(a)) * r);
        }
        t.v[3] = rp(p + up * (1.5 * r));
        o.shape = t;
        break;
    }
    case NewItem::Torus: {
        double minor = nice_size(r / 3);
        // A direction is a unit vector whatever the scene's size: rounded to hundredths
        // at most (coarser, a big scene's rounding would make it 0 0 0).
        o.shape = rt::Torus{rp(p + up * minor), round_to(up, std::min(scale, 10.0)), r, minor};
        break;
    }
    case NewItem::Box: {
        // A cube of side 2r resting on the surface at the point (its sides along the
        // axes: turned with the handle's `rotation`).
        const Vec3 c = p + up * r;
        o.shape = rt::Box{rp(c - Vec3{r, r, r}), rp(c + Vec3{r, r, r})};
        break;
    }
    case NewItem::Cone: o.shape = rt::Cone{rp(p), rp(p + up * (2 * r)), r, 0}; break;
    case NewItem::Plane:
    case NewItem::ChessPlane: {
        // Through the point, upright on the surface and facing the viewer (lit on the
        // viewer's side); a chess plane's cells are 2r wide.
        rt::Plane pl;
        pl.chess = kind == NewItem::ChessPlane;
        const double cell = 2 * r;
        const Vec3 n = upright_facing(up, rt::length2(at.toward) > 0 ? at.toward : scene.camera.position - p, f.u);
        pl.point[0] = rp(p);
        pl.point[1] = rp(p + rt::normalize(rt::cross(up, n)) * cell);
        pl.point[2] = rp(p + up * cell);
        pl.point[3] = rp(p + n * cell);
        if (pl.chess) {
            pl.has_material = pl.has_material2 = true;
            pl.material = rt::Material{};
            pl.material.colour = {0.9, 0.9, 0.9};
            pl.material2 = rt::Material{};
            pl.material2.colour = {0.1, 0.1, 0.1};
        }
        one.planes.push_back(pl);
        where = SceneItem::Kind::Plane;
        break;
    }
    case NewItem::Lamp:
    case NewItem::Spotlight: {
        rt::Light li;
        li.lamp = kind == NewItem::Lamp;
        // Off the surface, so it lights it rather than sitting inside it.
        li.position = rp(p + up * (4 * r));
        li.colour = new_light_colour(scene, extent, p, li.position);
        li.size = li.lamp ? nice_size(r / 2) : 1;
        one.lights.push_back(li);
        where = SceneItem::Kind::Light;
        break;
    }
    }
    if (where == SceneItem::Kind::Object) one.objects.push_back(o);
}

}  // namespace

std::optional<SceneEdit> add_item(const std::string& text, const rt::Scene& scene, NewItem kind, const Placement& at,
                                  const SceneLayout* layout, const rt::World* world) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, layout, scanned);
    if (!l || !rt::finite(at.point)) return std::nullopt;
    // Coordinates rounded to a thousandth of the scene's size keep the text short. In a
    // scene much bigger than its objects (a light far away) that would move the item
    // far from the point, or merge its corners: then a tenth of the item's own size,
    // and if that still merges corners (far out, where doubles are coarse), a
    // thousandth of it.
    const double extent = scene_extent(scene, world), r = nice_size(typical_object_size(scene));
    for (double scale : {std::min(extent, 100 * r), std::min(extent, r)}) {
        rt::Scene one;
        SceneItem::Kind where;
        new_item(scene, kind, at, scale, extent, r, one, where);
        if (!text_holds(one)) continue;
        SceneEdit e;
        bool section = false;
        e.replacement = insert_block(text, *l, where, one, std::size_t(-1), &section);
        e.select = {where, appended_index(scene, where)};
        if (scene.includes.empty())
            e.splice = ItemSplice{ItemSplice::Op::Insert, list_of(where), std::size_t(e.select.index), section};
        return e;
    }
    return std::nullopt;  // no block the format takes fits there (numbers past 1e15)
}

std::optional<SceneEdit> add_model(const std::string& text, const rt::Scene& scene, const std::string& file,
                                   const rt::MeshModel& model, const Placement& at, const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, layout, scanned);
    const rt::Aabb mb = model.bounds();
    if (!l || !rt::finite(at.point) || mb.empty()) return std::nullopt;
    const double extent = scene_extent(scene);
    const Vec3 up = up_of(scene, at);
    rt::Mesh m;
    m.file = file;
    const double own = rt::length(mb.hi - mb.lo) / (2 * std::sqrt(3.0));  // as typical_object_size measures
    const double s = nice_size(typical_object_size(scene) / (own > 0 ? own : 1.0));
    m.scale = {s, s, s};
    const Vec3 scene_up = up_of(scene, Placement{});
    if (std::fabs(scene_up.z) > std::fabs(scene_up.y) && scene_up.z > 0) m.rotation = {90, 0, 0};
    // The box as placed at the origin, moved so that it rests on the surface.
    const rt::Aabb wb = rt::MeshInstance::make({0, 0, 0}, m.scale, m.rotation).world_bounds(mb);
    const Vec3 half = (wb.hi - wb.lo) * 0.5;
    const double lift = rt::length2(at.normal) > 0
                            ? std::fabs(up.x) * half.x + std::fabs(up.y) * half.y + std::fabs(up.z) * half.z
                            : 0.0;
    m.position = round_to(at.point + up * lift - (wb.lo + wb.hi) * 0.5, extent);
    rt::Scene one = item_scene(scene);
    rt::Object o;
    o.shape = m;
    one.objects.push_back(o);
    SceneEdit e;
    bool section = false;
    e.replacement = insert_block(text, *l, SceneItem::Kind::Object, one, std::size_t(-1), &section);
    e.select = {SceneItem::Kind::Object, appended_index(scene, SceneItem::Kind::Object)};
    if (scene.includes.empty())
        e.splice = ItemSplice{ItemSplice::Op::Insert, ItemList::Object, std::size_t(e.select.index), section};
    return e;
}

std::string model_scene(const std::string& file, const rt::MeshModel& model) {
    const rt::Aabb b = model.bounds().empty() ? rt::Aabb{{-1, -1, -1}, {1, 1, 1}} : model.bounds();
    const Vec3 c = (b.lo + b.hi) * 0.5;
    const double r = std::max(rt::length(b.hi - b.lo) * 0.5, 1e-9);  // the box's half diagonal
    rt::Scene s;
    s.width = 640;
    s.height = 480;
    rt::Mesh m;
    m.file = file;
    m.smooth = model.data().normals.empty() ? 0 : 1;  // the file's own normals say it is curved
    rt::Object o;
    o.shape = m;
    // A model with materials of its own (an MTL file's, a PLY's vertex colours) shows
    // them: a material block would take their place.
    if (model.data().materials.empty() && model.data().colours.empty()) {
        o.material.colour = {0.8, 0.72, 0.6};
        o.has_material = true;
    }
    s.objects.push_back(o);
    // Cells about a fifth of the model wide, the floor at its lowest point.
    rt::Plane floor;
    floor.chess = floor.has_material = floor.has_material2 = true;
    floor.material.colour = {0.7, 0.7, 0.7};
    floor.material2.colour = {0.25, 0.25, 0.3};
    const double cell = nice_size(r / 2.5);
    const Vec3 p0{c.x, b.lo.y, c.z};
    floor.point[0] = p0;
    floor.point[1] = p0 + Vec3{0, 0, cell};
    floor.point[2] = p0 + Vec3{cell, 0, 0};
    floor.point[3] = p0 + Vec3{0, cell, 0};
    // Seen from the front, a little above and to the right; the whole bounding sphere
    // fits in the narrower field of view.
    s.camera.angle_x = 55;
    s.camera.angle_y = 41.25;
    const double dist = 1.1 * r / std::sin(s.camera.angle_y * 0.5 * 3.14159265358979 / 180);
    s.camera.centre = c;
    s.camera.position = c + rt::normalize(Vec3{0.45, 0.35, 1.0}) * dist;
    s.camera.up = c + Vec3{0, 1, 0};
    // A lamp over the camera's left shoulder, bright enough at its distance (light
    // falls off as 1/r^2).
    rt::Light lamp;
    lamp.lamp = true;
    lamp.position = c + Vec3{-0.8, 1.6, 1.0} * dist;
    const double d2 = rt::length2(lamp.position - c);
    lamp.colour = {0.9 * d2, 0.88 * d2, 0.82 * d2};
    lamp.size = nice_size(r / 10);
    auto rp = [&](Vec3 v) { return round_to(v, 2 * r) + Vec3{0, 0, 0}; };  // (+0: no "-0" in the text)
    s.camera.position = rp(s.camera.position);
    s.camera.centre = rp(s.camera.centre);
    s.camera.up = rp(s.camera.up);
    lamp.position = rp(lamp.position);
    lamp.colour = round_to(lamp.colour, lamp.colour.x);
    for (Vec3& v : floor.point) v = rp(v);
    s.lights.push_back(lamp);
    s.planes.push_back(floor);
    return "// A model opened on its own: a floor under it, a lamp and a camera around it.\n" + rt::write_scene(s);
}

std::optional<SceneEdit> duplicate_item(const std::string& text, const rt::Scene& scene, SceneItem item, Vec3 offset,
                                        const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, layout, scanned);
    const auto block = l ? block_of(*l, scene, item.kind, item.index) : std::nullopt;
    if (!block) return std::nullopt;
    const TextSpan s = block->first;
    SceneEdit e;
    e.select = {item.kind, item.index + 1};
    if (scene.includes.empty()) e.splice = ItemSplice{ItemSplice::Op::Insert, list_of(item.kind), std::size_t(item.index) + 1};
    if (offset == Vec3{0, 0, 0}) {
        std::string indent = line_indent(text, s.begin);
        e.replacement = {s.end, 0, "\n" + indent + text.substr(s.begin, s.end - s.begin)};
        return e;
    }
    rt::Scene one = item_scene(scene);
    if (item.kind == SceneItem::Kind::Object) {
        one.objects.push_back(scene.objects[std::size_t(item.index)]);
        translate(one.objects[0], offset);
    } else if (item.kind == SceneItem::Kind::Plane) {
        one.planes.push_back(scene.planes[std::size_t(item.index)]);
        translate(one.planes[0], offset);
    } else {
        one.lights.push_back(scene.lights[std::size_t(item.index)]);
        translate(one.lights[0], offset);
    }
    // (Rounding the moved copy's numbers can merge a tiny shape's corners far out.)
    if (!text_holds(one)) return std::nullopt;
    e.replacement = insert_block(text, *l, item.kind, one, block->second);
    return e;
}

std::optional<SceneEdit> delete_item(const std::string& text, const rt::Scene& scene, SceneItem item,
                                     const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, layout, scanned);
    const auto block = l ? block_of(*l, scene, item.kind, item.index) : std::nullopt;
    if (!block) return std::nullopt;
    TextSpan d = deletion_span(text, block->first);
    SceneEdit e;
    e.replacement = {d.begin, d.end - d.begin, {}};
    // Select the neighbour that takes its place, if any.
    int n = int(count_of(scene, item.kind)) - 1;
    e.select = {item.kind, n == 0 ? -1 : std::min(item.index, n - 1)};
    if (scene.includes.empty()) e.splice = ItemSplice{ItemSplice::Op::Remove, list_of(item.kind), std::size_t(item.index)};
    return e;
}

std::optional<SceneEdit> delete_operand(const std::string& text, const rt::Scene& scene, int index,
                                        const std::vector<int>& path, const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, layout, scanned);
    const auto block = l ? block_of(*l, scene, SceneItem::Kind::Object, index) : std::nullopt;
    if (!block || path.empty()) return std::nullopt;
    const int side = path.back();
    if (side != 0 && side != 1) return std::nullopt;
    rt::Object top = scene.objects[std::size_t(index)];
    rt::Object* parent = operand_of(top, std::vector<int>(path.begin(), path.end() - 1));
    rt::Csg* csg = parent ? std::get_if<rt::Csg>(&parent->shape) : nullptr;
    if (!csg || csg->operands.size() != 2) return std::nullopt;
    rt::Object keep = csg->operands[std::size_t(1 - side)];
    if (path.size() == 1) {
        keep.material = top.material;
        keep.has_material = top.has_material;
    }
    *parent = std::move(keep);
    rt::Scene one = item_scene(scene);
    one.objects.push_back(std::move(top));
    const TextSpan s = block->first;
    SceneEdit e;
    e.replacement = {s.begin, s.end - s.begin, written_block(one, SceneItem::Kind::Object, line_indent(text, s.begin))};
    e.select = {SceneItem::Kind::Object, index};
    if (scene.includes.empty()) e.splice = ItemSplice{ItemSplice::Op::Replace, ItemList::Object, std::size_t(index)};
    return e;
}

std::optional<SceneEdit> make_csg(const std::string& text, const rt::Scene& scene, int a, int b, rt::CsgType type) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, nullptr, scanned);
    const auto block_a = l ? block_of(*l, scene, SceneItem::Kind::Object, a) : std::nullopt;
    const auto block_b = l ? block_of(*l, scene, SceneItem::Kind::Object, b) : std::nullopt;
    if (!block_a || !block_b || a == b) return std::nullopt;
    // The format's operands are solids: no mesh, no instance (a whole CSG is defined and
    // placed instead).
    for (int k : {a, b}) {
        const rt::Shape& sh = scene.objects[std::size_t(k)].shape;
        if (std::holds_alternative<rt::Mesh>(sh) || std::holds_alternative<rt::Instance>(sh)) return std::nullopt;
    }
    rt::Csg csg;
    csg.type = type;
    csg.operands = {scene.objects[std::size_t(a)], scene.objects[std::size_t(b)]};
    rt::Object o;
    o.material = scene.objects[std::size_t(a)].material;
    o.has_material = scene.objects[std::size_t(a)].has_material;
    o.shape = std::move(csg);
    rt::Scene one = item_scene(scene);
    one.objects.push_back(std::move(o));

    const TextSpan sa = block_a->first, sb = block_b->first;
    std::string indent = line_indent(text, sa.begin);
    TextSpan db = deletion_span(text, sb);
    // The CSG replaces a's block; b's block goes. Both at once: one replacement.
    SceneEdit e;
    e.replacement = merge(text, {{sa.begin, sa.end - sa.begin, written_block(one, SceneItem::Kind::Object, indent)},
                                 {db.begin, db.end - db.begin, {}}});
    e.select = {SceneItem::Kind::Object, b < a ? a - 1 : a};
    return e;
}

std::optional<SceneEdit> switch_light_kind(const std::string& text, const rt::Scene& scene, int light,
                                           const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    const SceneLayout* l = layout_of(text, scene, layout, scanned);
    const auto at = l ? block_of(*l, scene, SceneItem::Kind::Light, light) : std::nullopt;
    if (!at) return std::nullopt;
    const TextSpan s = at->first;
    const std::string old_block = text.substr(s.begin, s.end - s.begin);
    rt::Light li = scene.lights[std::size_t(light)];
    rt::Scene one = item_scene(scene);
    std::string indent = line_indent(text, s.begin);
    std::string block;
    if (li.lamp) {
        li.lamp = false;
        one.lights.push_back(li);
        block = written_block(one, SceneItem::Kind::Light, indent);
        // Before the closing brace, on its own line (a comment runs to the line's end).
        std::size_t close = block.rfind('}');
        block.insert(close, "  " + std::string(kSizeMark) + rt::format_number(scene.lights[std::size_t(light)].size) + "\n" + indent);
    } else {
        li.lamp = true;
        if (auto kept = kept_size(old_block)) li.size = *kept;
        else li.size = nice_size(0.025 * scene_extent(scene));
        one.lights.push_back(li);
        block = written_block(one, SceneItem::Kind::Light, indent);
    }
    SceneEdit e;
    e.replacement = {s.begin, s.end - s.begin, block};
    e.select = {SceneItem::Kind::Light, light};
    if (scene.includes.empty()) e.splice = ItemSplice{ItemSplice::Op::Replace, ItemList::Light, std::size_t(light)};
    return e;
}

}  // namespace rtview
