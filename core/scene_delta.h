// What changed in a scene between two of its versions, as an editor knows it: which
// items changed in place, which objects were inserted or removed, or that the lists
// changed beyond that (a new file). A compiled world takes it (World::update) and
// rewrites only the entries of what changed.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

namespace rt {

struct SceneDelta {
    // The lists changed in ways not said below, or nothing is known: compile in full.
    bool everything = false;
    // Objects inserted into or removed from the scene's list, in the order they were:
    // each at index `at` of the list as the splices before it left it (an insertion's
    // object is then object `at`). They come before `objects` below, whose indices
    // are those of the list after them; an inserted object is new whatever they say.
    struct Splice {
        std::uint32_t at = 0;
        bool insert = false;
        bool operator==(const Splice& o) const { return at == o.at && insert == o.insert; }
    };
    std::vector<Splice> object_splices;
    // Items changed in place (any of their values: a move, a material, a size), by
    // index, ascending and without repeats (normalize()).
    std::vector<std::uint32_t> objects, planes, lights;
    // The planes' or lights' list changed length or order: all of it is made again.
    bool all_planes = false, all_lights = false;
    bool camera = false;   // the camera block
    bool picture = false;  // picture_size

    bool empty() const {
        return !everything && object_splices.empty() && objects.empty() && planes.empty() && lights.empty() &&
               !all_planes && !all_lights && !camera && !picture;
    }
    // Whether only items changed in place (no list changed length or order).
    bool in_place() const { return !everything && object_splices.empty() && !all_planes && !all_lights; }
    // Sorts the index lists and drops repeats.
    void normalize() {
        for (auto* v : {&objects, &planes, &lights}) {
            std::sort(v->begin(), v->end());
            v->erase(std::unique(v->begin(), v->end()), v->end());
        }
        if (all_planes) planes.clear();
        if (all_lights) lights.clear();
    }
    // This delta followed by `later`: what changed over both.
    void merge(const SceneDelta& later) {
        everything = everything || later.everything;
        camera = camera || later.camera;
        picture = picture || later.picture;
        all_planes = all_planes || later.all_planes;
        all_lights = all_lights || later.all_lights;
        if (everything) {
            objects.clear(), planes.clear(), lights.clear(), object_splices.clear();
            return;
        }
        // The objects changed here, numbered as the later splices leave the list (one
        // removed is gone: nothing of it is left to change).
        for (const Splice& s : later.object_splices) {
            std::size_t k = 0;
            for (std::uint32_t i : objects) {
                if (s.insert) objects[k++] = i >= s.at ? i + 1 : i;
                else if (i != s.at) objects[k++] = i > s.at ? i - 1 : i;
            }
            objects.resize(k);
        }
        object_splices.insert(object_splices.end(), later.object_splices.begin(), later.object_splices.end());
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
