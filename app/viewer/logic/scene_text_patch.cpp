// Changed items written into the scene text (see scene_text.h): each item's changed
// values in its own block where that can be done (block_patch.h), else the writer's
// block in its place; named materials in their define sections; the camera as one
// block. The text outside the touched blocks stays the user's.
#include "scene_text.h"

#include <algorithm>
#include <memory>
#include <utility>

#include "block_patch.h"
#include "scene_parser.h"
#include "scene_writer.h"

namespace rtview {

namespace {

struct Replacement {
    TextSpan span;
    std::string text;
};

// `m` as `to` holds it when it is a use of a named material of `from` (the definition's
// values there): the values of the definition in `to`.
rt::Material renamed(const rt::Material& m, const rt::Scene& from, const rt::Scene& to) {
    const std::size_t k = std::size_t(m.named);
    if (m.named < 0 || k >= from.materials.size() || k >= to.materials.size() ||
        !m.same_bits(from.materials[k].material))
        return m;
    rt::Material out = to.materials[k].material;
    out.named = m.named;
    return out;
}

rt::Object renamed(rt::Object o, const rt::Scene& from, const rt::Scene& to) {
    o.material = renamed(o.material, from, to);
    if (rt::Csg* g = std::get_if<rt::Csg>(&o.shape)) {
        for (rt::Object& x : g->operands) x = renamed(std::move(x), from, to);
    } else if (rt::Instance* in = std::get_if<rt::Instance>(&o.shape)) {
        for (std::size_t d = 0; d < from.defined.size() && d < to.defined.size(); ++d)
            if (in->defined && from.defined[d].object == in->defined) in->defined = to.defined[d].object;
    }
    return o;
}
rt::Plane renamed(rt::Plane p, const rt::Scene& from, const rt::Scene& to) {
    p.material = renamed(p.material, from, to);
    p.material2 = renamed(p.material2, from, to);
    return p;
}
rt::Light renamed(const rt::Light& l, const rt::Scene&, const rt::Scene&) { return l; }

std::vector<rt::Object>& items_of(rt::Scene& s, const rt::Object&) { return s.objects; }
std::vector<rt::Plane>& items_of(rt::Scene& s, const rt::Plane&) { return s.planes; }
std::vector<rt::Light>& items_of(rt::Scene& s, const rt::Light&) { return s.lights; }
ItemList kind_of(const rt::Object&) { return ItemList::Object; }
ItemList kind_of(const rt::Plane&) { return ItemList::Plane; }
ItemList kind_of(const rt::Light&) { return ItemList::Light; }

// The replacements of one edit, gathered against the layout `l` of `text`.
class Patcher {
public:
    // `names`: the scene whose named materials the items use; `from`: the scene the text
    // holds, if the named materials may have changed.
    Patcher(const std::string& text, const SceneLayout& l, const rt::Scene& names, const rt::Camera& camera,
            const rt::Scene* from = nullptr)
        : text_(text), l_(l), one_(item_scene(names)), names_(names), from_(from) {
        one_.camera = camera;  // a valid camera, so the writer prints a normal scene
    }

    // The item at `at` of its list from `was` to `now`: only its changed values where
    // that can be done (block_patch.h), else the writer's block in its place. An item
    // whose only change is that of a named material it uses stays as it is (its block
    // names the material).
    template <class T>
    bool item(std::size_t at, const T& was, const T& now) {
        if (was == now) return true;
        if (from_ && renamed(was, *from_, names_) == now) return true;
        const ItemList kind = kind_of(now);
        const TextSpan span = (kind == ItemList::Object ? l_.objects : kind == ItemList::Plane ? l_.planes : l_.lights)[at];
        if (std::optional<std::string> t =
                patch_block(std::string_view(text_).substr(span.begin, span.end - span.begin), was, now)) {
            reps_.push_back({span, std::move(*t)});
            return true;
        }
        items_of(one_, now) = {now};
        std::string written = written_item(one_, kind, line_indent(text_, span.begin));
        items_of(one_, now).clear();
        if (written.empty()) return false;
        reps_.push_back({span, std::move(written)});
        return true;
    }

    // Camera keys accumulate over all camera sections, so one complete block in place
    // of the last section gives exactly the new camera.
    bool camera(const rt::Camera& now) {
        one_.camera = now;
        TextSpan span{l_.append_at, l_.append_at};
        if (!l_.cameras.empty()) span = l_.cameras.back();
        std::string block = written_item(one_, ItemList::Camera, l_.cameras.empty() ? "" : line_indent(text_, span.begin));
        if (block.empty()) return false;
        if (l_.cameras.empty()) block += "\n";
        reps_.push_back({span, std::move(block)});
        return true;
    }

    // The named materials of the scene file's own define sections from `from`'s to
    // `to`'s (the same names in the same places); false if that cannot be done.
    bool definitions(const rt::Scene& from, const rt::Scene& to) {
        if (from.materials == to.materials) return true;
        if (from.materials.size() != to.materials.size()) return false;
        const std::vector<std::pair<std::string, TextSpan>> defs = material_definitions(text_);
        std::size_t own = 0;
        for (std::size_t k = 0; k < to.materials.size(); ++k) {
            const rt::NamedMaterial &a = from.materials[k], &b = to.materials[k];
            if (a.origin != 0 || b.origin != 0) {
                if (!(a == b)) return false;  // an included file's: not in this text
                continue;
            }
            const std::size_t at = own++;
            if (a == b) continue;
            if (a.name != b.name || at >= defs.size() || defs[at].first != a.name) return false;
            // Only the changed values, the user's comments and layout inside kept.
            const TextSpan span = defs[at].second;
            std::optional<std::string> t =
                patch_material(std::string_view(text_).substr(span.begin, span.end - span.begin), a.material, b.material);
            reps_.push_back({span, t ? std::move(*t) : rt::write_material(b.material)});
        }
        return true;
    }

    bool empty() const { return reps_.empty(); }

    // The text with every replacement made (back to front, so each span still holds).
    std::string result() {
        std::sort(reps_.begin(), reps_.end(),
                  [](const Replacement& a, const Replacement& b) { return a.span.begin > b.span.begin; });
        std::string out = text_;
        for (const Replacement& r : reps_) out.replace(r.span.begin, r.span.end - r.span.begin, r.text);
        return out;
    }

private:
    const std::string& text_;
    const SceneLayout& l_;
    rt::Scene one_;
    const rt::Scene& names_;
    const rt::Scene* from_;
    std::vector<Replacement> reps_;
};

// The edit of list `v` from `from` to `to` item by item: own items through `p` at
// their blocks; false if an included one changed (it has no block here).
template <class T>
bool patch_list(Patcher& p, const std::vector<T>& from, const std::vector<T>& to) {
    std::size_t own = 0;
    for (std::size_t k = 0; k < to.size(); ++k) {
        if (from[k].origin != 0 || to[k].origin != 0) {
            if (!(from[k] == to[k]) || from[k].origin != to[k].origin) return false;
            continue;
        }
        if (!p.item(own++, from[k], to[k])) return false;
    }
    return true;
}

}  // namespace

namespace {

// Calls `f` on each material slot of `o` (a CSG's operands too) and tells whether it
// returned true for any.
template <class F>
bool each_material(rt::Object& o, const F& f) {
    bool any = f(o.material);
    if (rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
        for (rt::Object& x : g->operands) any = each_material(x, f) || any;
    return any;
}

// Whether `o` (or an operand of it) has a material `use` says yes to, or is an
// instance of a definition `renewed` says yes to.
template <class U, class R>
bool uses_material(const rt::Object& o, const U& use, const R& renewed) {
    if (use(o.material)) return true;
    if (const rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
        return std::any_of(g->operands.begin(), g->operands.end(),
                           [&](const rt::Object& x) { return uses_material(x, use, renewed); });
    if (const rt::Instance* in = std::get_if<rt::Instance>(&o.shape)) return renewed(in->defined.get());
    return false;
}

}  // namespace

void use_named_material(rt::Scene& s, std::size_t k, const rt::Material& m,
                        const std::function<void(ItemList, std::size_t)>& touch,
                        const std::function<void(std::size_t)>& touch_defined) {
    if (k >= s.materials.size()) return;
    const rt::Material old = s.materials[k].material;
    rt::Material now = m;
    now.named = old.named;  // (the definition's own)
    s.materials[k].material = now;
    rt::Material use = now;
    use.named = int(k);
    // A use: the name, and the definition's values (a use the text spells out differs).
    auto rename = [&](rt::Material& x) {
        if (x.named != int(k) || !x.same_bits(old)) return false;
        x = use;
        return true;
    };
    // Named objects first: the instances of one that changed are given the new one.
    std::vector<std::pair<const rt::Object*, std::shared_ptr<const rt::Object>>> renewed;
    for (std::size_t d = 0; d < s.defined.size(); ++d) {
        rt::NamedObject& def = s.defined[d];
        if (!def.object) continue;
        rt::Object copy = *def.object;
        if (!each_material(copy, rename)) continue;
        if (touch_defined) touch_defined(d);
        auto fresh = std::make_shared<const rt::Object>(std::move(copy));
        renewed.push_back({def.object.get(), fresh});
        def.object = std::move(fresh);
    }
    auto uses = [&](const rt::Object& o) {
        return uses_material(o, [&](const rt::Material& x) { return x.named == int(k) && x.same_bits(old); },
                             [&](const rt::Object* def) {
                                 return std::any_of(renewed.begin(), renewed.end(),
                                                    [def](const auto& r) { return r.first == def; });
                             });
    };
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
        rt::Object& o = s.objects[i];
        if (!uses(o)) continue;
        if (touch) touch(ItemList::Object, i);
        each_material(o, rename);
        if (rt::Instance* in = std::get_if<rt::Instance>(&o.shape))
            for (const auto& r : renewed)
                if (in->defined.get() == r.first) in->defined = r.second;
    }
    for (std::size_t i = 0; i < s.planes.size(); ++i) {
        rt::Plane& p = s.planes[i];
        rt::Material a = p.material, b = p.material2;
        if (!rename(a) && !rename(b)) continue;
        if (touch) touch(ItemList::Plane, i);
        rename(p.material);
        rename(p.material2);
    }
}

std::optional<std::string> patch_scene_text(const std::string& text, const rt::Scene& from, const rt::Scene& to,
                                            const rt::ParseOptions* options) {
    if (from.objects.size() != to.objects.size() || from.planes.size() != to.planes.size() ||
        from.lights.size() != to.lights.size())
        return std::nullopt;
    const SceneLayout l = scan_layout(text);
    if (!layout_matches(l, from)) return std::nullopt;
    // Panels never change the picture size; a change there is left to the writer.
    if (from.width != to.width || from.height != to.height) return std::nullopt;
    Patcher p(text, l, to, to.camera, &from);
    if (!p.definitions(from, to) || !patch_list(p, from.objects, to.objects) || !patch_list(p, from.planes, to.planes) ||
        !patch_list(p, from.lights, to.lights))
        return std::nullopt;
    if (!(from.camera == to.camera) && !p.camera(to.camera)) return std::nullopt;
    if (p.empty()) return text;
    std::string out = p.result();
    rt::ParseResult check = options ? rt::parse_scene(out, *options) : rt::parse_scene(out);
    if (!check.ok() || check.scene != to) return std::nullopt;
    return out;
}

std::optional<std::string> patch_scene_items(const std::string& text, const rt::Scene& from, const ItemIndices& at,
                                             const rt::Scene& values) {
    if (at.objects.size() != values.objects.size() || at.planes.size() != values.planes.size() ||
        at.lights.size() != values.lights.size())
        return std::nullopt;
    const SceneLayout l = scan_layout(text, from.objects.size());
    if (!layout_matches(l, from)) return std::nullopt;
    // What the changed items read back as is all that is checked: the rest of the text
    // is not touched (as a panel edit's commit in the document does).
    rt::Scene changed = values;
    const rt::Scene names = item_scene(from);  // (the text's names)
    changed.materials = names.materials;
    changed.defined = names.defined;
    if (!at.camera) changed.camera = from.camera;
    if (!text_holds(changed)) return std::nullopt;
    Patcher p(text, l, from, changed.camera);
    // An item read from an included file has no block here: such an edit is not made.
    auto each = [&p, &from](ItemList kind, const auto& list, const std::vector<std::size_t>& indices, const auto& now) {
        for (std::size_t k = 0; k < indices.size(); ++k) {
            const std::optional<std::size_t> own = own_index(from, kind, indices[k]);
            if (!own || !p.item(*own, list[indices[k]], now[k])) return false;
        }
        return true;
    };
    if (!each(ItemList::Object, from.objects, at.objects, values.objects) ||
        !each(ItemList::Plane, from.planes, at.planes, values.planes) ||
        !each(ItemList::Light, from.lights, at.lights, values.lights))
        return std::nullopt;
    if (at.camera && !(from.camera == values.camera) && !p.camera(values.camera)) return std::nullopt;
    return p.empty() ? text : p.result();
}

std::string sync_scene_text(const std::string& text, const rt::Scene& from, const rt::Scene& to,
                            const rt::ParseOptions* options) {
    if (auto patched = patch_scene_text(text, from, to, options)) return *patched;
    return rt::write_scene(to);
}

}  // namespace rtview
