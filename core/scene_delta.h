// What changed in a scene between two of its versions, as an editor knows it: which
// items changed in place, or that the lists themselves changed (items added, removed
// or reordered, a new file). A compiled world takes it (World::update) and rewrites
// only the entries of what changed.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rt {

struct SceneDelta {
    // The lists changed length or order, or nothing is known: compile in full.
    bool everything = false;
    // Items changed in place (any of their values: a move, a material, a size), by
    // index, ascending and without repeats (normalize()).
    std::vector<std::uint32_t> objects, planes, lights;
    bool camera = false;   // the camera block
    bool picture = false;  // picture_size

    bool empty() const {
        return !everything && objects.empty() && planes.empty() && lights.empty() && !camera && !picture;
    }
    // Sorts the index lists and drops repeats.
    void normalize() {
        for (auto* v : {&objects, &planes, &lights}) {
            std::sort(v->begin(), v->end());
            v->erase(std::unique(v->begin(), v->end()), v->end());
        }
    }
    // This delta followed by `later`: what changed over both.
    void merge(const SceneDelta& later) {
        everything = everything || later.everything;
        camera = camera || later.camera;
        picture = picture || later.picture;
        if (everything) {
            objects.clear(), planes.clear(), lights.clear();
            return;
        }
        objects.insert(objects.end(), later.objects.begin(), later.objects.end());
        planes.insert(planes.end(), later.planes.begin(), later.planes.end());
        lights.insert(lights.end(), later.lights.begin(), later.lights.end());
        normalize();
    }
    static SceneDelta all() {
        SceneDelta d;
        d.everything = true;
        return d;
    }
};

}  // namespace rt
