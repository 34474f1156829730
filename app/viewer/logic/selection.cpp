// Several things selected at once and what is done to all of them (see selection.h).
#include "selection.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "move_handle.h"

namespace rtview {

namespace {

ItemList list_of_kind(SceneItem::Kind k) {
    return k == SceneItem::Kind::Object ? ItemList::Object : k == SceneItem::Kind::Plane ? ItemList::Plane : ItemList::Light;
}

std::size_t count_of_kind(const rt::Scene& scene, SceneItem::Kind k) {
    return k == SceneItem::Kind::Object  ? scene.objects.size()
           : k == SceneItem::Kind::Plane ? scene.planes.size()
                                         : scene.lights.size();
}

// Objects, then planes, then lights, each by index.
bool item_less(const SceneItem& a, const SceneItem& b) {
    return a.kind != b.kind ? int(a.kind) < int(b.kind) : a.index < b.index;
}

// Two or more: `one` is the last; one left: it alone.
void settle(Selection& s) {
    if (s.many.size() == 1) {
        s.one = {s.many[0], {}};
        s.many.clear();
    } else if (!s.many.empty()) {
        s.one = {s.many.back(), {}};
    }
}

}  // namespace

std::vector<SceneItem> selected_items(const Selection& s) {
    if (!s.many.empty()) return s.many;
    if (s.one.none()) return {};
    return {s.one.item};
}

bool is_selected(const Selection& s, const SceneItem& item) {
    if (s.many.empty()) return !s.one.none() && s.one.item == item;
    return std::find(s.many.begin(), s.many.end(), item) != s.many.end();
}

void select_one(Selection& s, const ItemRef& r) {
    s.one = r;
    s.many.clear();
}

void toggle(Selection& s, const SceneItem& item) {
    if (item.index < 0) return;
    std::vector<SceneItem> all = selected_items(s);
    auto it = std::find(all.begin(), all.end(), item);
    if (it != all.end()) all.erase(it);
    else all.push_back(item);
    s.many = std::move(all);
    if (s.many.empty()) s.one = {};
    settle(s);
}

void add_all(Selection& s, const std::vector<SceneItem>& items) {
    std::vector<SceneItem> all = selected_items(s);
    bool added = false;
    for (const SceneItem& i : items)
        if (i.index >= 0 && std::find(all.begin(), all.end(), i) == all.end()) {
            all.push_back(i);
            added = true;
        }
    if (!added) return;  // (a CSG operand selected alone stays so)
    s.many = std::move(all);
    settle(s);
}

void keep_existing(Selection& s, const rt::Scene& scene) {
    auto gone = [&](const SceneItem& i) { return i.index < 0 || std::size_t(i.index) >= count_of_kind(scene, i.kind); };
    if (s.many.empty()) {
        if (!s.one.none() && gone(s.one.item)) s.one = {};
        return;
    }
    s.many.erase(std::remove_if(s.many.begin(), s.many.end(), gone), s.many.end());
    if (s.many.empty()) s.one = {};
    settle(s);
}

std::string selection_summary(const Selection& s) {
    const std::vector<SceneItem> all = selected_items(s);
    std::size_t n[3] = {0, 0, 0};
    for (const SceneItem& i : all) ++n[int(i.kind)];
    static const char* const names[3][2] = {{"object", "objects"}, {"plane", "planes"}, {"light", "lights"}};
    std::string parts;
    for (int k = 0; k < 3; ++k) {
        if (!n[k]) continue;
        if (!parts.empty()) parts += ", ";
        parts += std::to_string(n[k]) + " " + names[k][n[k] == 1 ? 0 : 1];
    }
    return std::to_string(all.size()) + (all.size() == 1 ? " thing" : " things") + " selected" +
           (parts.empty() ? "" : ": " + parts);
}

bool item_included(const rt::Scene& scene, const SceneItem& item) {
    return item.index >= 0 && included_file(scene, list_of_kind(item.kind), std::size_t(item.index)) != nullptr;
}

std::optional<rt::Vec3> group_anchor(const rt::Scene& scene, const std::vector<SceneItem>& items) {
    rt::Vec3 lo{HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    bool any = false;
    for (const SceneItem& i : items) {
        const std::optional<rt::Vec3> a = item_anchor(scene, i);
        if (!a || !rt::finite(*a)) continue;
        lo = {std::min(lo.x, a->x), std::min(lo.y, a->y), std::min(lo.z, a->z)};
        hi = {std::max(hi.x, a->x), std::max(hi.y, a->y), std::max(hi.z, a->z)};
        any = true;
    }
    if (!any) return std::nullopt;
    return (lo + hi) * 0.5;
}

GroupMove::GroupMove(const rt::Scene& scene, const std::vector<SceneItem>& items) {
    for (const SceneItem& i : items) {
        if (i.index < 0 || std::size_t(i.index) >= count_of_kind(scene, i.kind)) continue;
        if (item_included(scene, i)) {
            ++left_out_;
            continue;
        }
        const std::size_t k = std::size_t(i.index);
        switch (i.kind) {
            case SceneItem::Kind::Object: objects_.emplace_back(k, scene.objects[k]); break;
            case SceneItem::Kind::Plane: planes_.emplace_back(k, scene.planes[k]); break;
            case SceneItem::Kind::Light: lights_.emplace_back(k, scene.lights[k]); break;
        }
    }
}

void GroupMove::apply(Document& doc, const rt::Vec3& d) const {
    // (The document remembers each item as it was when the held edit first touched it,
    // and writes each one's block on the commit.)
    for (const auto& [k, o] : objects_) {
        rt::Object& e = doc.edit_object(k);
        e = o;
        translate(e, d);
    }
    for (const auto& [k, p] : planes_) {
        rt::Plane& e = doc.edit_plane(k);
        e = p;
        translate(e, d);
    }
    for (const auto& [k, l] : lights_) {
        rt::Light& e = doc.edit_light(k);
        e = l;
        translate(e, d);
    }
}

std::size_t give_material(Document& doc, const std::vector<SceneItem>& items, const rt::Material& m) {
    std::size_t n = 0;
    for (const SceneItem& i : items) {
        if (i.kind != SceneItem::Kind::Object || i.index < 0 || std::size_t(i.index) >= doc.scene().objects.size() ||
            item_included(doc.scene(), i))
            continue;
        const rt::Object& o = doc.scene().objects[std::size_t(i.index)];
        if (o.has_material && o.material.same_bits(m) && o.material.named == m.named) continue;
        rt::Object& e = doc.edit_object(std::size_t(i.index));
        e.material = m;
        e.has_material = true;
        ++n;
    }
    return n;
}

TextReplacement whole_replacement(const std::string& text, const GroupEdit& g) {
    std::optional<TextReplacement> r = merge_replacements(text, g.parts);
    return r ? std::move(*r) : TextReplacement{};
}

std::optional<TextReplacement> merge_replacements(const std::string& text, std::vector<TextReplacement> reps) {
    if (reps.empty()) return std::nullopt;
    std::stable_sort(reps.begin(), reps.end(),
                     [](const TextReplacement& a, const TextReplacement& b) { return a.offset < b.offset; });
    TextReplacement out;
    out.offset = reps.front().offset;
    std::size_t at = out.offset;
    for (const TextReplacement& r : reps) {
        if (r.offset < at || r.offset + r.length > text.size()) return std::nullopt;
        out.text.append(text, at, r.offset - at);
        out.text += r.text;
        at = r.offset + r.length;
    }
    out.length = at - out.offset;
    return out;
}

namespace {

// The items in list order, each once; those outside the scene dropped.
std::vector<SceneItem> sorted_items(const rt::Scene& scene, std::vector<SceneItem> items) {
    std::sort(items.begin(), items.end(), item_less);
    items.erase(std::unique(items.begin(), items.end()), items.end());
    items.erase(std::remove_if(items.begin(), items.end(),
                               [&](const SceneItem& i) {
                                   return i.index < 0 || std::size_t(i.index) >= count_of_kind(scene, i.kind);
                               }),
                items.end());
    return items;
}

// Whether `reps` (some) are in `text` and none overlaps another (merge_replacements()
// would make them one), without copying the text.
bool apart(const std::string& text, std::vector<TextReplacement>& reps) {
    if (reps.empty()) return false;
    std::stable_sort(reps.begin(), reps.end(),
                     [](const TextReplacement& a, const TextReplacement& b) { return a.offset < b.offset; });
    std::size_t at = reps.front().offset;
    for (const TextReplacement& r : reps) {
        if (r.offset < at || r.offset + r.length > text.size()) return false;
        at = r.offset + r.length;
    }
    return true;
}

// The items' edits as Document::splice_texts() takes them (the last in the text first),
// or none when one has no splice or two touch.
std::vector<Document::SpliceEdit> splices_of(std::vector<SceneEdit>& edits) {
    std::vector<Document::SpliceEdit> out;
    for (SceneEdit& e : edits) {
        if (!e.splice) return {};
        out.push_back({std::move(e.replacement), *e.splice});
    }
    std::stable_sort(out.begin(), out.end(), [](const Document::SpliceEdit& a, const Document::SpliceEdit& b) {
        return a.replacement.offset > b.replacement.offset;
    });
    for (std::size_t k = 1; k < out.size(); ++k)
        if (out[k].replacement.offset + out[k].replacement.length > out[k - 1].replacement.offset) return {};
    return out;
}

}  // namespace

std::optional<GroupEdit> delete_items(const std::string& text, const rt::Scene& scene,
                                      const std::vector<SceneItem>& items, const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    if (!layout) layout = &scanned.emplace(scan_layout(text));
    GroupEdit g;
    std::vector<TextReplacement> reps;
    std::vector<SceneEdit> edits;
    for (const SceneItem& i : sorted_items(scene, items)) {
        std::optional<SceneEdit> e = item_included(scene, i) ? std::nullopt : delete_item(text, scene, i, layout);
        if (!e) {
            ++g.skipped;
            continue;
        }
        reps.push_back(e->replacement);
        edits.push_back(std::move(*e));
        ++g.done;
    }
    if (!apart(text, reps)) return std::nullopt;
    g.parts = std::move(reps);
    g.splices = splices_of(edits);
    return g;
}

std::optional<GroupEdit> duplicate_items(const std::string& text, const rt::Scene& scene,
                                         const std::vector<SceneItem>& items, const rt::Vec3& offset,
                                         const SceneLayout* layout) {
    std::optional<SceneLayout> scanned;
    if (!layout) layout = &scanned.emplace(scan_layout(text));
    GroupEdit g;
    std::vector<TextReplacement> reps;
    std::vector<SceneEdit> edits;
    int before[3] = {0, 0, 0};  // copies made so far ahead of this item in its list
    for (const SceneItem& i : sorted_items(scene, items)) {
        std::optional<SceneEdit> e =
            item_included(scene, i) ? std::nullopt : duplicate_item(text, scene, i, offset, layout);
        if (!e) {
            ++g.skipped;
            continue;
        }
        reps.push_back(e->replacement);
        edits.push_back(std::move(*e));
        // Each copy follows its original in the list: the copies before it (and their
        // originals) push it on by one each.
        int& n = before[int(i.kind)];
        g.select.push_back({i.kind, i.index + n + 1});
        ++n;
        ++g.done;
    }
    if (!apart(text, reps)) return std::nullopt;
    g.parts = std::move(reps);
    g.splices = splices_of(edits);
    return g;
}

std::vector<SceneItem> items_in_box(const rt::World& world, const rt::Camera& view_camera, const Rect& image,
                                    int film_w, int film_h, double x0, double y0, double x1, double y1,
                                    std::size_t max_rays, double seconds) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<SceneItem> out;
    if (film_w <= 0 || film_h <= 0 || !(image.w > 0) || !(image.h > 0)) return out;
    if (x1 < x0) std::swap(x0, x1);
    if (y1 < y0) std::swap(y0, y1);
    // Film pixels whose centres lie in the box.
    const double sx = film_w / image.w, sy = film_h / image.h;
    const int i0 = std::max(0, int(std::ceil((x0 - image.x) * sx - 0.5)));
    const int i1 = std::min(film_w - 1, int(std::floor((x1 - image.x) * sx - 0.5)));
    const int j0 = std::max(0, int(std::ceil((y0 - image.y) * sy - 0.5)));
    const int j1 = std::min(film_h - 1, int(std::floor((y1 - image.y) * sy - 0.5)));
    if (i1 < i0 || j1 < j0) return out;
    const double pixels = double(i1 - i0 + 1) * double(j1 - j0 + 1);
    const int step = std::max(1, int(std::ceil(std::sqrt(pixels / double(std::max<std::size_t>(max_rays, 1))))));
    // The grid's rows (the last one too, so that a box's edge counts at any step), in the
    // order that makes any first part of them an even grid: every 8th, then those
    // halfway between, and so on. After the first 8th the rows stop when the time is up
    // (the box is then seen at a coarser grid, never only in part).
    std::vector<int> rows;
    for (int j = j0;; j = std::min(j + step, j1)) {
        rows.push_back(j);
        if (j == j1) break;
    }
    std::vector<int> order;
    order.reserve(rows.size());
    const std::size_t n = rows.size();
    for (std::size_t k = 0; k < n; k += 8) order.push_back(rows[k]);
    if ((n - 1) % 8 != 0) order.push_back(rows[n - 1]);
    const std::size_t first = order.size();
    for (std::size_t k = 4; k < n - 1; k += 8) order.push_back(rows[k]);
    for (std::size_t k = 2; k < n - 1; k += 4) order.push_back(rows[k]);
    for (std::size_t k = 1; k < n - 1; k += 2) order.push_back(rows[k]);
    std::vector<int> found[3];  // objects, planes, lights (as SceneItem::Kind numbers them)
    for (std::size_t r = 0; r < order.size(); ++r) {
        if (r >= first && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > seconds)
            break;
        const int j = order[r];
        for (int i = i0;; i = std::min(i + step, i1)) {
            const double px = image.x + (i + 0.5) / sx, py = image.y + (j + 0.5) / sy;
            const rt::PickResult pr = pick_at(world, view_camera, image, film_w, film_h, px, py);
            const int k = pr.object >= 0 ? 0 : pr.plane >= 0 ? 1 : pr.light >= 0 ? 2 : -1;
            if (k >= 0) found[k].push_back(k == 0 ? pr.object : k == 1 ? pr.plane : pr.light);
            if (i == i1) break;
        }
    }
    for (int k = 0; k < 3; ++k) {
        std::vector<int>& f = found[k];
        std::sort(f.begin(), f.end());
        f.erase(std::unique(f.begin(), f.end()), f.end());
        for (int index : f) out.push_back({SceneItem::Kind(k), index});
    }
    return out;
}

void items_window(const rt::World& world, const rt::Camera& camera, int film_w, int film_h, int block,
                  const std::vector<SceneItem>& items, int& x0, int& y0, int& x1, int& y1) {
    x0 = y0 = x1 = y1 = 0;
    const int b = std::max(1, block);
    if (items.size() > 256) {  // (their bounds cost more than the texels they would save)
        x1 = (film_w + b - 1) / b;
        y1 = (film_h + b - 1) / b;
        return;
    }
    for (const SceneItem& i : items) {
        int a0, b0, a1, b1;
        item_window(world, camera, film_w, film_h, b, i, a0, b0, a1, b1);
        if (a0 >= a1 || b0 >= b1) continue;
        if (x0 >= x1) {
            x0 = a0, y0 = b0, x1 = a1, y1 = b1;
            continue;
        }
        x0 = std::min(x0, a0), y0 = std::min(y0, b0), x1 = std::max(x1, a1), y1 = std::max(y1, b1);
    }
}

std::vector<Edge> outline_edges_of(const IdBuffer& ids, std::vector<std::uint32_t> codes) {
    std::sort(codes.begin(), codes.end());
    auto in = [&](std::uint32_t c) { return c != 0 && std::binary_search(codes.begin(), codes.end(), c); };
    auto border = [&](std::uint32_t a, std::uint32_t b) { return a != b && (in(a) || in(b)); };
    std::vector<Edge> out;
    // Vertical borders: left of texel column x, runs down the rows.
    for (int x = 0; x <= ids.width; ++x) {
        int start = -1;
        for (int y = 0; y <= ids.height; ++y) {
            const bool on = y < ids.height && border(ids.at(x - 1, y), ids.at(x, y));
            if (on && start < 0) start = y;
            if (!on && start >= 0) {
                out.push_back({x, start, x, y});
                start = -1;
            }
        }
    }
    // Horizontal borders: above texel row y, runs along the columns.
    for (int y = 0; y <= ids.height; ++y) {
        int start = -1;
        for (int x = 0; x <= ids.width; ++x) {
            const bool on = x < ids.width && border(ids.at(x, y - 1), ids.at(x, y));
            if (on && start < 0) start = x;
            if (!on && start >= 0) {
                out.push_back({start, y, x, y});
                start = -1;
            }
        }
    }
    return out;
}

void SelectionSteps::made(std::size_t depth_after, const std::string& name, const Selection& before,
                          const Selection& after) {
    // A new step replaces every step at its depth or later (the redo branch it ends).
    while (!steps_.empty() && steps_.back().depth >= depth_after) steps_.pop_back();
    steps_.push_back({depth_after, name, before, after});
    while (steps_.size() > 64) steps_.pop_front();
}

std::optional<Selection> SelectionSteps::undone(std::size_t depth, const std::string& name) const {
    for (const Step& s : steps_)
        if (s.depth == depth + 1 && s.name == name) return s.before;
    return std::nullopt;
}

std::optional<Selection> SelectionSteps::redone(std::size_t depth, const std::string& name) const {
    for (const Step& s : steps_)
        if (s.depth == depth && s.name == name) return s.after;
    return std::nullopt;
}

}  // namespace rtview
