// move_bench: what editing one object costs in a big scene, as the viewer does it
// (World::update): the BVH refit alone, the whole world update for a move (the object
// compiled again, its chunks copied, refit) and for a material change, and for
// comparison a full compile of the edited scene (BVH built again).
//
//   move_bench SCENE.txt [--moves N]
//   bench/make-grid.sh 100 /tmp/g100.txt && move_bench /tmp/g100.txt    (10,000 spheres)
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_args.h"
#include "bvh_update.h"
#include "scene_parser.h"
#include "shapes.h"
#include "world.h"

namespace {

using bench::now;

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return bench::usage("move_bench SCENE.txt [--moves N]");
    const int moves = bench::count_option(argc, argv, "--moves", 50);
    std::ifstream in(argv[1], std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    rt::ParseResult parsed = rt::parse_scene(ss.str());
    if (!parsed.ok() || parsed.scene.objects.empty()) {
        std::fprintf(stderr, "move_bench: %s does not parse or has no objects\n", argv[1]);
        return 1;
    }
    rt::Scene scene = std::move(parsed.scene);
    const std::size_t n = scene.objects.size();
    double t0 = now();
    std::shared_ptr<const rt::World> world = rt::compile_world(scene);
    double build = now() - t0;

    // The links are made once per drag.
    t0 = now();
    auto links = std::make_shared<const rt::BvhLinks>(world->geometry->bvh, n);
    double link_time = now() - t0;

    // Refit alone: one object moved by up to a few units per step, on one private
    // copy of the tree (what a drag does to the tree each frame).
    rt::Geometry g = *world->geometry;
    std::vector<double> refit, update;
    for (int k = 0; k < moves; ++k) {
        std::uint32_t obj = std::uint32_t((std::size_t(k) * 7919u) % n);
        rt::Aabb& b = g.object_bounds.write(obj);
        rt::Vec3 d{0.37 * (k % 5), -0.21 * (k % 3), 0.5};
        b.lo = b.lo + d;
        b.hi = b.hi + d;
        t0 = now();
        if (!links->refit(g.bvh, g.object_bounds, {obj})) return 1;
        refit.push_back(now() - t0);
    }
    // The whole world update, as each frame of a drag makes it (World::update with the
    // moved object as the delta).
    for (int k = 0; k < moves; ++k) {
        std::uint32_t obj = std::uint32_t((std::size_t(k) * 7919u) % n);
        rt::Object& o = scene.objects[obj];
        if (auto* s = std::get_if<rt::Sphere>(&o.shape)) s->position.z += 0.25;
        rt::SceneDelta delta;
        delta.objects = {obj};
        t0 = now();
        std::shared_ptr<const rt::World> next = world->update(scene, delta);
        update.push_back(now() - t0);
        if (!next) return 1;
        world = next;
    }
    // A material slider: one object's colour, every step.
    std::vector<double> material;
    for (int k = 0; k < moves; ++k) {
        std::uint32_t obj = std::uint32_t((std::size_t(k) * 104729u) % n);
        scene.objects[obj].material.colour.x = 0.01 * (k % 100);
        rt::SceneDelta delta;
        delta.objects = {obj};
        t0 = now();
        std::shared_ptr<const rt::World> next = world->update(scene, delta);
        material.push_back(now() - t0);
        if (!next) return 1;
        world = next;
    }
    t0 = now();
    std::shared_ptr<const rt::World> full = rt::compile_world(scene);
    double rebuild = now() - t0;
    std::printf("%zu objects: BVH refit for a one-object move %.4f ms (median of %d); world update for a move %.2f ms, "
                "for a material %.2f ms; links (once per tree) %.2f ms; full compile with BVH build %.1f ms (first "
                "load %.1f ms)\n",
                n, median(refit) * 1e3, moves, median(update) * 1e3, median(material) * 1e3, link_time * 1e3,
                rebuild * 1e3, build * 1e3);
    return 0;
}
