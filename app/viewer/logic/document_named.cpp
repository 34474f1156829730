// A named material edited once for every use of it (see document.h, set_named_material).
#include "document.h"

#include <algorithm>
#include <utility>

namespace rtview {

namespace {

template <class T>
void save_once(std::vector<std::pair<std::size_t, T>>& saved, std::size_t i, const T& value) {
    if (std::none_of(saved.begin(), saved.end(), [i](const auto& p) { return p.first == i; })) saved.push_back({i, value});
}

}  // namespace

bool Document::set_named_material(std::size_t k, const rt::Material& m) {
    if (!has_scene_ || k >= scene_.materials.size() || scene_.materials[k].origin != 0) return false;
    rt::Material now = m;
    now.named = scene_.materials[k].material.named;  // (the definition's own)
    if (now == scene_.materials[k].material) return true;
    hold_edit();
    const bool keep = !saved_.whole;  // edit() keeps the whole scene already
    if (keep) save_once(saved_.materials, k, scene_.materials[k]);
    rt::SceneDelta d;
    use_named_material(
        scene_, k, now,
        [&](ItemList list, std::size_t i) {
            if (list == ItemList::Object) {
                if (keep) save_once(saved_.objects, i, scene_.objects[i]);
                d.objects.push_back(std::uint32_t(i));
            } else {
                if (keep) save_once(saved_.planes, i, scene_.planes[i]);
                d.planes.push_back(std::uint32_t(i));
            }
        },
        [&](std::size_t i) {
            if (keep) save_once(saved_.defined, i, scene_.defined[i]);
        });
    changed(std::move(d));
    return true;
}

}  // namespace rtview
