// embree_ref: the reference point for our traversal. Traces the rays our renderer
// traces for a scene's camera, shadow and mirror rays (no refraction, no shading: a
// hit only decides where the next rays go) with Embree 3: with its single-ray API and
// with 8- and 16-wide packets of pixel tiles (4x2 and 4x4), and prints the best time of
// each (wall and processor time). Every call carries Embree's coherent flag
// (RTC_INTERSECT_CONTEXT_FLAG_COHERENT): camera rays of a tile, their shadow rays toward
// one light and their mirror rays off one flat mirror are coherent, and without the
// flag Embree takes them as incoherent.
//
//   embree_ref SCENE.txt [--threads N] [--repeats N] [--width W --height H]
//
// Spheres are Embree's own (float) sphere primitives and meshes its own triangles
// (each mesh's triangles placed in world space, one triangle geometry per mesh: no
// instancing, Embree's fastest case); every other object is a user primitive whose
// intersection is ours (core/shapes), and planes are tested one by one as our
// renderer does. Rays: one per pixel through the pixel's corner (sample 0),
// from each hit a shadow ray toward every light the surface faces, and a mirror ray
// where the material reflects, up to depth 20.
#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

#include <sys/resource.h>

#include "bench_scene.h"
#include "camera.h"
#include "image_io.h"
#include "model.h"
#include "scene_parser.h"
#include "shapes.h"
#include "world.h"

namespace {

using rt::Vec3;
constexpr int kMaxDepth = 20;

struct Ref {
    const rt::World* world = nullptr;
    const rt::Geometry* g = nullptr;
    RTCScene scene = nullptr;
    unsigned sphere_geom = RTC_INVALID_GEOMETRY_ID, user_geom = RTC_INVALID_GEOMETRY_ID;
    std::vector<std::uint32_t> sphere_obj, user_obj;  // primitive -> object
    std::vector<std::uint32_t> mesh_obj;              // mesh -> object
    std::vector<unsigned> mesh_geom;                  // mesh -> its triangle geometry
    rt::CameraBasis cam;
};

// The intersect context carries, per ray of a call (by its id), the surface a user
// primitive was hit on, so that its normal can be found afterwards.
struct Context {
    RTCIntersectContext ctx;
    rt::SpanEnd ends[16];
    rt::SpanScratch* scratch;
};

void user_bounds(const RTCBoundsFunctionArguments* a) {
    const Ref& r = *static_cast<const Ref*>(a->geometryUserPtr);
    const rt::Aabb& b = r.g->object_bounds[r.user_obj[a->primID]];
    a->bounds_o->lower_x = std::nextafter(float(b.lo.x), -INFINITY);
    a->bounds_o->lower_y = std::nextafter(float(b.lo.y), -INFINITY);
    a->bounds_o->lower_z = std::nextafter(float(b.lo.z), -INFINITY);
    a->bounds_o->upper_x = std::nextafter(float(b.hi.x), INFINITY);
    a->bounds_o->upper_y = std::nextafter(float(b.hi.y), INFINITY);
    a->bounds_o->upper_z = std::nextafter(float(b.hi.z), INFINITY);
}

void user_intersect(const RTCIntersectFunctionNArguments* a) {
    const Ref& r = *static_cast<const Ref*>(a->geometryUserPtr);
    Context& c = *reinterpret_cast<Context*>(a->context);
    RTCRayN* ray = RTCRayHitN_RayN(a->rayhit, a->N);
    RTCHitN* hit = RTCRayHitN_HitN(a->rayhit, a->N);
    std::uint32_t obj = r.user_obj[a->primID];
    for (unsigned i = 0; i < a->N; ++i) {
        if (!a->valid[i]) continue;
        Vec3 o{RTCRayN_org_x(ray, a->N, i), RTCRayN_org_y(ray, a->N, i), RTCRayN_org_z(ray, a->N, i)};
        Vec3 d{RTCRayN_dir_x(ray, a->N, i), RTCRayN_dir_y(ray, a->N, i), RTCRayN_dir_z(ray, a->N, i)};
        rt::SpanEnd e;
        if (!r.g->hit(obj, o, d, RTCRayN_tnear(ray, a->N, i), e, *c.scratch)) continue;
        if (!(e.t < RTCRayN_tfar(ray, a->N, i))) continue;
        RTCRayN_tfar(ray, a->N, i) = float(e.t);
        RTCHitN_geomID(hit, a->N, i) = a->geomID;
        RTCHitN_primID(hit, a->N, i) = a->primID;
        RTCHitN_instID(hit, a->N, i, 0) = RTC_INVALID_GEOMETRY_ID;
        c.ends[RTCRayN_id(ray, a->N, i) & 15] = e;
    }
}

void user_occluded(const RTCOccludedFunctionNArguments* a) {
    const Ref& r = *static_cast<const Ref*>(a->geometryUserPtr);
    Context& c = *reinterpret_cast<Context*>(a->context);
    std::uint32_t obj = r.user_obj[a->primID];
    for (unsigned i = 0; i < a->N; ++i) {
        if (!a->valid[i]) continue;
        Vec3 o{RTCRayN_org_x(a->ray, a->N, i), RTCRayN_org_y(a->ray, a->N, i), RTCRayN_org_z(a->ray, a->N, i)};
        Vec3 d{RTCRayN_dir_x(a->ray, a->N, i), RTCRayN_dir_y(a->ray, a->N, i), RTCRayN_dir_z(a->ray, a->N, i)};
        rt::SpanEnd e;
        if (r.g->hit(obj, o, d, 0.0, e, *c.scratch) && e.t < RTCRayN_tfar(a->ray, a->N, i))
            RTCRayN_tfar(a->ray, a->N, i) = -INFINITY;
    }
}

// Where a ray found its nearest surface: the point's normal (facing the ray) and
// whether the material there reflects.
struct Surface {
    bool hit = false;
    Vec3 p, n;
    bool mirror = false;
};

// Planes first, as our renderer does: their distance limits the search.
double nearest_plane(const rt::World& w, const Vec3& o, const Vec3& d, int& which) {
    double best = HUGE_VAL;
    which = -1;
    for (std::size_t i = 0; i < w.planes.size(); ++i) {
        double dn = dot(w.planes[i].n, d);
        if (dn == 0) continue;
        double t = -(dot(w.planes[i].n, o) + w.planes[i].D) / dn;
        if (t > rt::kDelta && t < best) best = t, which = int(i);
    }
    return best;
}

bool plane_blocks(const rt::World& w, const Vec3& o, const Vec3& d, double limit) {
    for (std::size_t i = 0; i < w.planes.size(); ++i) {
        const rt::PlaneShape& pl = w.planes[i];
        double dn = dot(pl.n, d);
        if (dn == 0) continue;
        double t = -(dot(pl.n, o) + pl.D) / dn;
        if (t > 0 && t < limit && w.plane_mats[2 * i + pl.cell(o + d * t)].refraction == 0) return true;
    }
    return false;
}

// The object a hit belongs to.
std::uint32_t object_of(const Ref& r, unsigned geom, unsigned prim) {
    if (geom == r.sphere_geom) return r.sphere_obj[prim];
    if (geom == r.user_geom) return r.user_obj[prim];
    for (std::size_t m = 0; m < r.mesh_geom.size(); ++m)
        if (r.mesh_geom[m] == geom) return r.mesh_obj[m];
    return 0;
}

Surface resolve(const Ref& r, const Vec3& o, const Vec3& d, float t, unsigned geom, unsigned prim, int plane,
                double plane_t, const rt::SpanEnd& end, const Vec3& ng) {
    Surface s;
    const rt::World& w = *r.world;
    if (geom != RTC_INVALID_GEOMETRY_ID) {
        std::uint32_t obj = object_of(r, geom, prim);
        s.p = o + d * double(t);
        if (geom != r.sphere_geom && geom != r.user_geom) {
            s.n = normalize(ng);  // a triangle's geometric normal, from Embree
        } else if (geom == r.sphere_geom) {
            s.n = normalize(s.p - r.g->spheres[r.g->nodes[r.g->object_node[obj]].index].c);
        } else {
            s.n = r.g->normal(end.node, end.face, s.p);
            if (end.flip) s.n = -s.n;
        }
        s.mirror = w.materials[obj].reflection > 0;
    } else if (plane >= 0) {
        s.p = o + d * plane_t;
        s.n = w.planes[std::size_t(plane)].n;
        s.mirror = w.plane_mats[2 * std::size_t(plane) + w.planes[std::size_t(plane)].cell(s.p)].reflection > 0;
    } else {
        return s;
    }
    if (dot(s.n, d) > 0) s.n = -s.n;
    s.hit = true;
    return s;
}

RTCRay make_ray(const Vec3& o, const Vec3& d, double tnear, double tfar, unsigned id) {
    RTCRay ray;
    ray.org_x = float(o.x), ray.org_y = float(o.y), ray.org_z = float(o.z);
    ray.dir_x = float(d.x), ray.dir_y = float(d.y), ray.dir_z = float(d.z);
    ray.tnear = float(tnear);
    ray.tfar = tfar == HUGE_VAL ? INFINITY : float(tfar);
    ray.time = 0;
    ray.mask = ~0u;
    ray.id = id;
    ray.flags = 0;
    return ray;
}

// One ray at a time: a pixel's path of mirror bounces, with its shadow rays.
std::uint64_t trace_single(const Ref& r, Context& c, const Vec3& origin, Vec3 d) {
    const rt::World& w = *r.world;
    std::uint64_t rays = 0;
    Vec3 o = origin;
    for (int depth = 0; depth < kMaxDepth; depth += 2) {
        int plane;
        double pt = nearest_plane(w, o, d, plane);
        RTCRayHit rh;
        rh.ray = make_ray(o, d, rt::kDelta, pt, 0);
        rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(r.scene, &c.ctx, &rh);
        ++rays;
        Surface s = resolve(r, o, d, rh.ray.tfar, rh.hit.geomID, rh.hit.primID, plane, pt, c.ends[0],
                            Vec3{rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z});
        if (!s.hit) break;
        for (const rt::ShadeLight& l : w.lights) {
            Vec3 v = l.position - s.p;
            if (!(dot(v, s.n) > 0)) continue;
            double len = length(v);
            Vec3 vh = v / len, so = s.p + vh * rt::kDelta;
            double limit = len - 10 * rt::kDelta;
            RTCRay sr = make_ray(so, vh, 0, limit, 0);
            rtcOccluded1(r.scene, &c.ctx, &sr);
            ++rays;
            if (sr.tfar >= 0) plane_blocks(w, so, vh, limit);
        }
        if (!s.mirror) break;
        o = s.p;
        d = d - s.n * (2 * dot(d, s.n));
    }
    return rays;
}

// Packet types and calls by width.
template <int N>
struct Packet;
template <>
struct Packet<8> {
    using RayHit = RTCRayHit8;
    using Ray = RTCRay8;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect8(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded8(v, s, c, r); }
};
template <>
struct Packet<16> {
    using RayHit = RTCRayHit16;
    using Ray = RTCRay16;
    static void intersect(const int* v, RTCScene s, RTCIntersectContext* c, RayHit* r) { rtcIntersect16(v, s, c, r); }
    static void occluded(const int* v, RTCScene s, RTCIntersectContext* c, Ray* r) { rtcOccluded16(v, s, c, r); }
};

// N pixels of a tile at a time (dirs[i], i < n); each bounce and each light is one
// packet call for the lanes still going.
template <int N>
std::uint64_t trace_packet(const Ref& r, Context& c, const Vec3& origin, const Vec3* dirs, int n) {
    using P = Packet<N>;
    const rt::World& w = *r.world;
    std::uint64_t rays = 0;
    Vec3 o[N], d[N];
    bool live[N];
    for (int i = 0; i < N; ++i) {
        live[i] = i < n;
        o[i] = origin;
        d[i] = i < n ? dirs[i] : Vec3{0, 0, 1};
    }
    for (int depth = 0; depth < kMaxDepth; depth += 2) {
        alignas(64) int valid[N];
        alignas(64) typename P::RayHit rh;
        int plane[N];
        double pt[N];
        int count = 0;
        for (int i = 0; i < N; ++i) {
            valid[i] = live[i] ? -1 : 0;
            count += live[i];
            pt[i] = live[i] ? nearest_plane(w, o[i], d[i], plane[i]) : HUGE_VAL;
            rh.ray.org_x[i] = float(o[i].x), rh.ray.org_y[i] = float(o[i].y), rh.ray.org_z[i] = float(o[i].z);
            rh.ray.dir_x[i] = float(d[i].x), rh.ray.dir_y[i] = float(d[i].y), rh.ray.dir_z[i] = float(d[i].z);
            rh.ray.tnear[i] = float(rt::kDelta);
            rh.ray.tfar[i] = pt[i] == HUGE_VAL ? INFINITY : float(pt[i]);
            rh.ray.time[i] = 0;
            rh.ray.mask[i] = ~0u;
            rh.ray.id[i] = unsigned(i);
            rh.ray.flags[i] = 0;
            rh.hit.geomID[i] = rh.hit.instID[0][i] = RTC_INVALID_GEOMETRY_ID;
        }
        if (count == 0) break;
        P::intersect(valid, r.scene, &c.ctx, &rh);
        rays += unsigned(count);
        Surface s[N];
        for (int i = 0; i < N; ++i)
            if (live[i])
                s[i] = resolve(r, o[i], d[i], rh.ray.tfar[i], rh.hit.geomID[i], rh.hit.primID[i], plane[i], pt[i],
                               c.ends[i], Vec3{rh.hit.Ng_x[i], rh.hit.Ng_y[i], rh.hit.Ng_z[i]});
        for (const rt::ShadeLight& l : w.lights) {
            alignas(64) int sv[N];
            alignas(64) typename P::Ray sr;
            Vec3 so[N], vh[N];
            double limit[N];
            int sc = 0;
            for (int i = 0; i < N; ++i) {
                Vec3 v = l.position - s[i].p;
                bool go = live[i] && s[i].hit && dot(v, s[i].n) > 0;
                sv[i] = go ? -1 : 0;
                double len = go ? length(v) : 1;
                vh[i] = go ? v / len : Vec3{0, 0, 1};
                so[i] = s[i].p + vh[i] * rt::kDelta;
                limit[i] = len - 10 * rt::kDelta;
                sc += go;
                sr.org_x[i] = float(so[i].x), sr.org_y[i] = float(so[i].y), sr.org_z[i] = float(so[i].z);
                sr.dir_x[i] = float(vh[i].x), sr.dir_y[i] = float(vh[i].y), sr.dir_z[i] = float(vh[i].z);
                sr.tnear[i] = 0;
                sr.tfar[i] = float(limit[i]);
                sr.time[i] = 0;
                sr.mask[i] = ~0u;
                sr.id[i] = unsigned(i);
                sr.flags[i] = 0;
            }
            if (sc == 0) continue;
            P::occluded(sv, r.scene, &c.ctx, &sr);
            rays += unsigned(sc);
            for (int i = 0; i < N; ++i)
                if (sv[i] && sr.tfar[i] >= 0) plane_blocks(w, so[i], vh[i], limit[i]);
        }
        for (int i = 0; i < N; ++i) {
            live[i] = live[i] && s[i].hit && s[i].mirror;
            if (!live[i]) continue;
            o[i] = s[i].p;
            d[i] = d[i] - s[i].n * (2 * dot(d[i], s[i].n));
        }
    }
    return rays;
}

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

// The processor time of the process so far (user + system, all threads): on a machine
// other jobs share, wall time stretches with their load, this much less.
double cpu_now() {
    rusage u;
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Rows handed out to the threads one at a time; returns the rays traced.
template <class Row>
std::uint64_t run_rows(int height, int threads, Row&& row) {
    std::atomic<int> next{0};
    std::atomic<std::uint64_t> total{0};
    auto work = [&] {
        std::uint64_t rays = 0;
        for (int y; (y = next++) < height;) rays += row(y);
        total += rays;
    };
    std::vector<std::thread> pool;
    for (int i = 1; i < threads; ++i) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    return total;
}

int usage() {
    std::fprintf(stderr, "usage: embree_ref SCENE.txt [--threads N] [--repeats N] [--width W --height H]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    std::string path;
    int threads = int(std::max(1u, std::thread::hardware_concurrency())), repeats = 3, width = 0, height = 0;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto value = [&](int& out) {
            if (i + 1 >= argc || (out = std::atoi(argv[++i])) <= 0) std::exit(usage());
        };
        if (a == "--threads") value(threads);
        else if (a == "--repeats") value(repeats);
        else if (a == "--width") value(width);
        else if (a == "--height") value(height);
        else if (!a.empty() && a[0] != '-' && path.empty()) path = a;
        else return usage();
    }
    if (path.empty()) return usage();
    int exit_code = 0;
    const std::optional<rt::Scene> scene = bench::read_scene("embree_ref", path, exit_code);
    if (!scene) return exit_code;
    auto world = rt::compile_world(*scene);
    if (width > 0) world = [&] { auto w = std::make_shared<rt::World>(*world); w->width = width; return w; }();
    if (height > 0) world = [&] { auto w = std::make_shared<rt::World>(*world); w->height = height; return w; }();
    const int W = world->width, H = world->height;

    std::string config = "threads=" + std::to_string(threads);
    RTCDevice device = rtcNewDevice(config.c_str());
    if (!device) {
        std::fprintf(stderr, "embree_ref: rtcNewDevice failed (%d)\n", int(rtcGetDeviceError(nullptr)));
        return 2;
    }
    Ref ref;
    ref.world = world.get();
    ref.g = world->geometry.get();
    ref.cam = rt::CameraBasis::make(world->camera, W, H, false);
    const rt::Geometry& g = *ref.g;
    for (std::uint32_t obj = 0; obj < g.object_node.size(); ++obj) {
        if (g.object_bounds[obj].empty()) continue;
        const rt::NodeKind kind = g.nodes[g.object_node[obj]].kind;
        (kind == rt::NodeKind::Sphere ? ref.sphere_obj : kind == rt::NodeKind::Mesh ? ref.mesh_obj : ref.user_obj)
            .push_back(obj);
    }
    double t0 = now();
    ref.scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(ref.scene, RTC_BUILD_QUALITY_HIGH);
    if (!ref.sphere_obj.empty()) {
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), ref.sphere_obj.size()));
        for (std::size_t i = 0; i < ref.sphere_obj.size(); ++i) {
            const rt::SphereG& s = g.spheres[g.nodes[g.object_node[ref.sphere_obj[i]]].index];
            v[4 * i] = float(s.c.x), v[4 * i + 1] = float(s.c.y), v[4 * i + 2] = float(s.c.z), v[4 * i + 3] = float(s.r);
        }
        rtcCommitGeometry(geom);
        ref.sphere_geom = rtcAttachGeometry(ref.scene, geom);
        rtcReleaseGeometry(geom);
    }
    std::size_t triangles = 0;
    for (std::uint32_t obj : ref.mesh_obj) {
        const rt::MeshG& m = g.meshes[g.nodes[g.object_node[obj]].index];
        const rt::MeshData& data = m.model->data();
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), data.vertex_count()));
        for (std::size_t i = 0; i < data.vertex_count(); ++i) {
            const Vec3 p = m.instance.point_to_world({data.positions[3 * i], data.positions[3 * i + 1], data.positions[3 * i + 2]});
            v[3 * i] = float(p.x), v[3 * i + 1] = float(p.y), v[3 * i + 2] = float(p.z);
        }
        auto* tri = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), data.triangle_count()));
        std::copy(data.triangles.begin(), data.triangles.end(), tri);
        triangles += data.triangle_count();
        rtcCommitGeometry(geom);
        ref.mesh_geom.push_back(rtcAttachGeometry(ref.scene, geom));
        rtcReleaseGeometry(geom);
    }
    if (!ref.user_obj.empty()) {
        RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
        rtcSetGeometryUserPrimitiveCount(geom, unsigned(ref.user_obj.size()));
        rtcSetGeometryUserData(geom, &ref);
        rtcSetGeometryBoundsFunction(geom, user_bounds, nullptr);
        rtcSetGeometryIntersectFunction(geom, user_intersect);
        rtcSetGeometryOccludedFunction(geom, user_occluded);
        rtcCommitGeometry(geom);
        ref.user_geom = rtcAttachGeometry(ref.scene, geom);
        rtcReleaseGeometry(geom);
    }
    rtcCommitScene(ref.scene);
    double build = now() - t0;

    // The camera rays of each row, made once: both APIs trace exactly these.
    std::vector<Vec3> dirs(std::size_t(W) * H);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) dirs[std::size_t(y) * W + x] = normalize(ref.cam.direction(x, y));

    // Bands of four rows handed out to the threads: single rays go through a band row
    // by row, packets of 8 as 4x2 tiles and packets of 16 as 4x4 tiles (the lanes of a
    // tile past the picture's right or bottom edge are off).
    constexpr int kBand = 4;
    auto pass = [&](int width) {
        return run_rows((H + kBand - 1) / kBand, threads, [&](int band) {
            thread_local rt::SpanScratch scratch;
            Context c;
            rtcInitIntersectContext(&c.ctx);
            c.ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
            c.scratch = &scratch;
            const int y0 = band * kBand, y1 = std::min(H, y0 + kBand);
            std::uint64_t rays = 0;
            if (width == 1) {
                for (int y = y0; y < y1; ++y)
                    for (int x = 0; x < W; ++x) rays += trace_single(ref, c, ref.cam.origin, dirs[std::size_t(y) * W + x]);
                return rays;
            }
            const int th = width == 8 ? 2 : 4;
            for (int ty = y0; ty < y1; ty += th)
                for (int x = 0; x < W; x += 4) {
                    Vec3 tile[16];
                    int n = 0;
                    for (int y = ty; y < std::min(y1, ty + th); ++y)
                        for (int dx = x; dx < std::min(W, x + 4); ++dx) tile[n++] = dirs[std::size_t(y) * W + dx];
                    rays += width == 8 ? trace_packet<8>(ref, c, ref.cam.origin, tile, n)
                                       : trace_packet<16>(ref, c, ref.cam.origin, tile, n);
                }
            return rays;
        });
    };
    const int widths[3] = {1, 8, 16};
    double best[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, cpu[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    std::uint64_t rays[3] = {0, 0, 0};
    for (int r = 0; r < repeats; ++r)
        for (int k = 0; k < 3; ++k) {
            const double t = now(), c = cpu_now();
            rays[k] = pass(widths[k]);
            best[k] = std::min(best[k], now() - t);
            cpu[k] = std::min(cpu[k], cpu_now() - c);
        }
    std::printf("embree_ref: %s at %dx%d, %d threads, Embree %s, coherent flag, best of %d\n", path.c_str(), W, H,
                threads, RTC_VERSION_STRING, repeats);
    std::printf("  scene build: %.3f s (%zu spheres, %zu triangles, %zu user primitives)\n", build,
                ref.sphere_obj.size(), triangles, ref.user_obj.size());
    const char* names[3] = {"single rays:      ", "packets of 8 (4x2):", "packets of 16 (4x4):"};
    for (int k = 0; k < 3; ++k)
        std::printf("  %s %.3f s, %llu rays (%.1f M rays/s), processor time %.3f s\n", names[k], best[k],
                    (unsigned long long)rays[k], rays[k] / best[k] / 1e6, cpu[k]);
    std::printf("best %.4f\n", std::min({best[0], best[1], best[2]}));
    std::printf("best_cpu %.4f\n", std::min({cpu[0], cpu[1], cpu[2]}));
    rtcReleaseScene(ref.scene);
    rtcReleaseDevice(device);
    return 0;
}
