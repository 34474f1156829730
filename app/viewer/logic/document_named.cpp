// A named material edited once for every use of it (see document.h, set_named_material).
#include "document.h"

#include <algorithm>
#include <memory>
#include <utility>

namespace rtview {

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

template <class T>
void save_once(std::vector<std::pair<std::size_t, T>>& saved, std::size_t i, const T& value) {
    if (std::none_of(saved.begin(), saved.end(), [i](const auto& p) { return p.first == i; })) saved.push_back({i, value});
}

}  // namespace

bool Document::set_named_material(std::size_t k, const rt::Material& m) {
    if (!has_scene_ || k >= scene_.materials.size() || scene_.materials[k].origin != 0) return false;
    const rt::Material old = scene_.materials[k].material;
    rt::Material now = m;
    now.named = old.named;  // (the definition's own)
    if (now == old) return true;
    hold_edit();
    const bool keep = !saved_.whole;  // edit() keeps the whole scene already
    if (keep) save_once(saved_.materials, k, scene_.materials[k]);
    scene_.materials[k].material = now;
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
    for (std::size_t d = 0; d < scene_.defined.size(); ++d) {
        rt::NamedObject& def = scene_.defined[d];
        if (!def.object) continue;
        rt::Object copy = *def.object;
        if (!each_material(copy, rename)) continue;
        if (keep) save_once(saved_.defined, d, def);
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
    rt::SceneDelta d;
    for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
        rt::Object& o = scene_.objects[i];
        if (!uses(o)) continue;
        if (keep) save_once(saved_.objects, i, o);
        each_material(o, rename);
        if (rt::Instance* in = std::get_if<rt::Instance>(&o.shape))
            for (const auto& r : renewed)
                if (in->defined.get() == r.first) in->defined = r.second;
        d.objects.push_back(std::uint32_t(i));
    }
    for (std::size_t i = 0; i < scene_.planes.size(); ++i) {
        rt::Plane& p = scene_.planes[i];
        rt::Material a = p.material, b = p.material2;
        if (!rename(a) && !rename(b)) continue;
        if (keep) save_once(saved_.planes, i, p);
        rename(p.material);
        rename(p.material2);
        d.planes.push_back(std::uint32_t(i));
    }
    changed(std::move(d));
    return true;
}

}  // namespace rtview
