// raytracer-mpi: `mpirun -np N raytracer-mpi SCENE OUT [options]`, a final render
// spread over the ranks of an MPI job. Rank 0 reads the scene, broadcasts its text,
// hands out tiles on request and writes OUT; every rank renders tiles on all its cores.
//
// Protocol (all MPI calls on each rank's main thread, so MPI_THREAD_FUNNELED suffices):
//   1. Bcast JobHeader from rank 0: an exit status for everyone (help, usage or scene
//      error: printed once, by rank 0), or the render settings and the text's size.
//   2. Bcast the scene text, then the models its meshes name (each file's triangles as
//      rank 0 read them, so that every rank holds the very same ones); every rank
//      parses the text (without reading model files) and builds its own World and BVH.
//   3. Gather every rank's thread count (or -1: could not build); Bcast go / no-go.
//   4. Rank 0 keeps kDepth tiles out at each worker (one rendering, the others queued,
//      so a worker never idles for a round trip); each finished tile comes back as its
//      float sums (3 per pixel) and ray count, and is answered with the next tile or,
//      once the render is complete, a stop. Rank 0 renders tiles too, in its own pool:
//      a one-rank job then works, and rank 0's machine is not left idle in a cluster;
//      its main thread only moves messages between short sleeps, a few % of one core.
// Rank 0 writes OUT only after every tile of every pass is accounted for. A rank that
// dies makes mpirun end the job (OUT untouched); MPI errors are returned, not fatal
// (MPI_ERRORS_RETURN), so each one is reported with what was being done.
#include <mpi.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstddef>
#include <cstring>
#include <iostream>
#include <list>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "adaptive.h"
#include "cli.h"
#include "image_io.h"
#include "model.h"
#include "scene_parser.h"
#include "schedule.h"
#include "status.h"
#include "tile_pool.h"
#include "texture.h"
#include "world.h"

namespace rtmpi {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kTagAssign = 1;  // rank 0 -> worker: AssignHeader [+ prior sums]
constexpr int kTagResult = 2;  // worker -> rank 0: ResultHeader + sums
// Tiles out at a worker at once: while it renders one, the next ones wait in its
// queue, so neither the round trip to rank 0 nor rank 0's poll period idles it. 3
// covers tiles that take less than a poll period on a many-core worker; more would
// only lengthen the wait for the last tiles.
constexpr int kDepth = 3;
constexpr int kLocalDepth = 2;  // tiles queued in rank 0's own pool
// Sleep between polls of MPI. Open MPI's blocking calls spin a core; sleeping instead
// leaves the cores to the render threads. A thread waiting for its pool wakes as soon
// as a tile is done; the period bounds how late a message from another rank is seen.
constexpr std::chrono::microseconds kPoll{200};

int g_rank = 0, g_size = 1;

// --- MPI errors --------------------------------------------------------------------

[[noreturn]] void fail(int status, const std::string& message) {
    std::cerr << "raytracer-mpi: rank " << g_rank << ": " << message << "; nothing written\n" << std::flush;
    MPI_Abort(MPI_COMM_WORLD, status);  // ends every rank of the job
    std::_Exit(status);                 // MPI_Abort does not return; in case it does
}

void check(int rc, const char* what) {
    if (rc == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    if (MPI_Error_string(rc, text, &len) != MPI_SUCCESS) len = std::snprintf(text, sizeof text, "error %d", rc);
    fail(kExitMpi, std::string("MPI error in ") + what + ": " + std::string(text, std::size_t(len)));
}

// Size in bytes of a received message.
int received_bytes(const MPI_Status& status) {
    int n = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &n), "MPI_Get_count");
    return n;
}

// --- messages ----------------------------------------------------------------------
// Headers travel as bytes in front of the float sums, in one message per tile. The
// ranks are assumed to share byte order and float format (one architecture), as MPI
// jobs built from one binary do.

struct JobHeader {
    std::int32_t status = -1;  // -1: render; else every rank exits with this status
    std::int32_t width = 0, height = 0;
    std::int32_t max_samples = 1, samples_per_pass = 0;
    std::int32_t threads = 0, max_depth = rt::kDefaultMaxDepth, tile = rt::kDefaultTile, mirror = 0;
    std::int32_t pad = 0;  // no uninitialised padding goes on the wire
    double time_limit = 0;
    double aa_threshold = -1;
    std::uint64_t text_size = 0;
};

// A refine assignment (refine >= 0, the round) carries per pixel of the tile its sums,
// its squares and its sample counts from and to (RefineIn); its result, the sums and
// the squares. Otherwise: the sums of the earlier passes, if any, and back the sums.
struct AssignHeader {
    std::int32_t tile = -1;  // -1: stop
    std::int32_t s0 = 0, s1 = 0;
    std::int32_t has_prior = 0;  // the tile's sums of samples [0, s0) follow
    std::int32_t refine = -1;
    std::int32_t pad = 0;
};

struct ResultHeader {
    std::int32_t tile = -1;
    std::int32_t s0 = 0, s1 = 0;
    std::int32_t refine = -1;
    std::uint64_t rays = 0;
};

// Floats a tile of n pixels travels as: an assignment's payload, a result's.
std::size_t assign_floats(const AssignHeader& a, std::size_t n) {
    return a.refine >= 0 ? 6 * n : a.has_prior ? 3 * n : 0;
}
std::size_t result_floats(int refine, std::size_t n) { return refine >= 0 ? 4 * n : 3 * n; }

// Floats taken by a header at the front of a float buffer (keeps the sums aligned).
template <class H>
constexpr std::size_t head_floats() {
    return (sizeof(H) + sizeof(float) - 1) / sizeof(float);
}

template <class H>
void put_header(std::vector<float>& buf, const H& h) {
    std::memcpy(static_cast<void*>(buf.data()), static_cast<const void*>(&h), sizeof h);
}

template <class H>
H get_header(const std::vector<float>& buf) {
    H h;
    std::memcpy(static_cast<void*>(&h), static_cast<const void*>(buf.data()), sizeof h);
    return h;
}

int bytes_of(std::size_t floats) { return int(floats * sizeof(float)); }

// Waits for a request by polling, so a waiting rank does not spin a core.
void wait_polling(MPI_Request& req, MPI_Status* status, const char* what) {
    for (;;) {
        int done = 0;
        check(MPI_Test(&req, &done, status ? status : MPI_STATUS_IGNORE), what);
        if (done) return;
        std::this_thread::sleep_for(kPoll);
    }
}

// --- signals (rank 0) ----------------------------------------------------------------
// Ctrl+C reaches mpirun, which signals the ranks; rank 0's handler (app/cli) ends it at
// once in every phase but the write of OUT, which removes its temporary file first
// and then comes here.
// Exits without MPI_Abort: the exit status (not 0, no MPI_Finalize) is enough for
// mpirun to end the rest of the job, and mpirun has usually started doing so already.
[[noreturn]] void interrupted() {
    const int sig = caught_signal();
    if (sig == SIGTERM)
        std::cerr << "raytracer-mpi: terminated (SIGTERM, as mpirun ends a job when a rank fails or the job is "
                     "cancelled); nothing written\n";
    else
        std::cerr << "raytracer-mpi: interrupted (" << (sig == SIGINT ? "SIGINT" : "signal") << "); nothing written\n";
    std::cerr << std::flush;
    std::_Exit(128 + sig);
}

// --- setup -------------------------------------------------------------------------

// What rank 0 knows after the command line and the scene; rank 0 only.
struct Front {
    bool render = false;  // the command line asks for a render, and the scene is good
    Options opt;
    std::string scene_path, out_path, text;
    double t_parse = 0;
    Clock::time_point t_start;
};

// Rank 0: the command line and the scene, as raytracer does it. Sets f.render if the
// render is to follow; else the outcome is what every rank ends with (printed by rank
// 0 only, once).
rt::Status front_end(int argc, char** argv, Front& f, rt::Scene& scene) {
    Options& opt = f.opt;
    if (rt::Status st = parse_args(argc, argv, opt); !st) return st;
    if (print_help_or_version(opt)) return {};
    if (opt.check) return check_scene(opt);
    if (opt.positional.size() > 2) return usage_error("too many arguments");
    if (opt.print_scene && opt.positional.size() != 1)
        return usage_error("--print-scene takes exactly one scene file and no output");
    if (opt.positional.empty() || opt.positional[0].empty()) return usage_error("no scene file given");
    f.scene_path = opt.positional[0];
    if (!opt.print_scene) {
        if (opt.positional.size() < 2 || opt.positional[1].empty()) return usage_error("no output file given");
        f.out_path = opt.positional[1];
        // Handlers first: the output check creates (and removes) a temporary file.
        install_signal_handlers();
        if (rt::Status st = check_output(f.out_path, f.scene_path); !st) return st;
        if (caught_signal()) interrupted();  // came during the check
    }
    install_signal_handlers();
    // The pool the reading, the build and the render share (its threads started after
    // the handlers, so that they block the signals too).
    rt::set_process_threads(opt.render.threads > 0 ? opt.render.threads : default_threads());
    f.t_start = Clock::now();
    if (rt::Status st = load_scene(f.scene_path, f.text, scene); !st) return st;
    if (opt.width) scene.width = *opt.width;
    if (opt.height) scene.height = *opt.height;
    f.t_parse = seconds_since(f.t_start);
    if (opt.print_scene) return print_scene(std::move(scene));  // nothing needs it after
    f.render = true;
    return {};
}

// The models of the scene's meshes by the file name the scene gives them.
using Models = std::map<std::string, std::shared_ptr<const rt::MeshModel>>;

// A buffer of any size from rank 0 to every rank, in pieces an int can count.
void bcast_bytes(void* data, std::uint64_t size, const char* what) {
    constexpr std::uint64_t kPiece = std::uint64_t(1) << 30;
    for (std::uint64_t at = 0; at < size; at += kPiece)
        check(MPI_Bcast(static_cast<char*>(data) + at, int(std::min(kPiece, size - at)), MPI_BYTE, 0, MPI_COMM_WORLD),
              what);
}

template <class T>
void bcast_vector(std::vector<T>& v, const char* what) {
    std::uint64_t n = v.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), what);
    v.resize(std::size_t(n));
    bcast_bytes(v.data(), n * sizeof(T), what);
}

// The textures of a scene and its models (New:), by the name the materials give.
using Textures = std::map<std::string, std::shared_ptr<const rt::Texture>>;

void add_texture(Textures& t, const rt::Material& m) {
    if (m.texture_image) t.emplace(m.texture, m.texture_image);
}
void add_textures(Textures& t, const rt::Object& o) {
    add_texture(t, o.material);
    if (const rt::Csg* c = std::get_if<rt::Csg>(&o.shape))
        for (const rt::Object& k : c->operands) add_textures(t, k);
}

void bcast_string(std::string& s, const char* what) {
    std::vector<char> v(s.begin(), s.end());
    bcast_vector(v, what);
    s.assign(v.begin(), v.end());
}

// Step 2's textures: rank 0 sends the images of `scene`'s materials and of its models'
// materials (which it read); the others make textures from the same texels.
Textures share_textures(const rt::Scene& scene) {
    Textures textures;
    if (g_rank == 0) {
        for (const rt::Object& o : scene.objects) {
            add_textures(textures, o);
            if (const rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape); m && m->model)
                for (const rt::Material& mm : m->model->data().materials) add_texture(textures, mm);
        }
        for (const rt::Plane& p : scene.planes) add_texture(textures, p.material), add_texture(textures, p.material2);
    }
    std::uint64_t count = textures.size();
    check(MPI_Bcast(&count, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast (textures)");
    auto it = textures.begin();
    for (std::uint64_t k = 0; k < count; ++k) {
        std::string name;
        std::int32_t size[2] = {0, 0};
        std::vector<float> rgb;
        if (g_rank == 0) {
            name = it->first;
            size[0] = it->second->width(), size[1] = it->second->height();
            rgb = it->second->texels();
            ++it;
        }
        bcast_string(name, "MPI_Bcast (texture name)");
        check(MPI_Bcast(size, 2, MPI_INT32_T, 0, MPI_COMM_WORLD), "MPI_Bcast (texture size)");
        bcast_vector(rgb, "MPI_Bcast (texels)");
        if (g_rank != 0) textures.emplace(name, std::make_shared<const rt::Texture>(size[0], size[1], std::move(rgb)));
    }
    return textures;
}

// A material's image from the shared textures (false: it names one that was not sent).
bool take_texture(rt::Material& m, const Textures& textures) {
    if (m.texture.empty()) return true;
    auto it = textures.find(m.texture);
    if (it == textures.end()) return false;
    m.texture_image = it->second;
    return true;
}
bool take_textures(rt::Object& o, const Textures& textures) {
    bool ok = take_texture(o.material, textures);
    if (rt::Csg* c = std::get_if<rt::Csg>(&o.shape))
        for (rt::Object& k : c->operands) ok = take_textures(k, textures) && ok;
    return ok;
}

// A model's materials through MPI: the numbers (the 11 doubles that come first) and
// each texture's name.
void bcast_materials(std::vector<rt::Material>& materials, const Textures& textures) {
    std::uint64_t n = materials.size();
    check(MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast (model materials)");
    materials.resize(std::size_t(n));
    for (rt::Material& m : materials) {
        double numbers[11];
        static_assert(offsetof(rt::Material, texture) == sizeof numbers, "the numbers come first");
        std::memcpy(numbers, &m, sizeof numbers);
        check(MPI_Bcast(numbers, 11, MPI_DOUBLE, 0, MPI_COMM_WORLD), "MPI_Bcast (model material)");
        std::memcpy(static_cast<void*>(&m), numbers, sizeof numbers);
        bcast_string(m.texture, "MPI_Bcast (model texture name)");
        if (g_rank != 0) take_texture(m, textures);
    }
}

// Step 2's models: rank 0 sends those of `scene` (which it read); the others receive
// them and make models of their own from the same triangles, corners' texture
// coordinates, vertex colours and materials.
Models share_models(const rt::Scene& scene, const Textures& textures) {
    Models models;
    if (g_rank == 0)
        for (const rt::Object& o : scene.objects)
            if (const rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape)) models.emplace(m->file, m->model);
    std::uint64_t count = models.size();
    check(MPI_Bcast(&count, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Bcast (models)");
    auto it = models.begin();
    for (std::uint64_t k = 0; k < count; ++k) {
        std::vector<char> name;
        rt::MeshData data;
        if (g_rank == 0) {
            name.assign(it->first.begin(), it->first.end());
            data = it->second->data();
        }
        bcast_vector(name, "MPI_Bcast (model name)");
        bcast_vector(data.positions, "MPI_Bcast (model vertices)");
        bcast_vector(data.normals, "MPI_Bcast (model normals)");
        bcast_vector(data.triangles, "MPI_Bcast (model triangles)");
        bcast_vector(data.corner_uv, "MPI_Bcast (model texture coordinates)");
        bcast_vector(data.colours, "MPI_Bcast (model vertex colours)");
        bcast_vector(data.triangle_material, "MPI_Bcast (model triangle materials)");
        bcast_materials(data.materials, textures);
        if (g_rank == 0) {
            ++it;
        } else {
            const std::string file(name.begin(), name.end());
            models.emplace(file, std::make_shared<const rt::MeshModel>(file, std::move(data)));
        }
    }
    return models;
}

// Every rank: the World from the broadcast text, models and settings. Rank 0 parsed
// the same text already, so an error here means a broken broadcast, not a bad scene.
rt::Expected<std::shared_ptr<const rt::World>> build_world(const std::string& text, const Models& models,
                                                           const Textures& textures, const JobHeader& job) {
    rt::ParseOptions options;
    options.read_models = false;  // they came with the text
    options.read_textures = false;
    rt::ParseResult parsed = rt::parse_scene(text, options);
    if (!parsed.ok()) return rt::Status::error("the broadcast scene text does not parse", kExitMpi);
    rt::Scene& scene = parsed.scene;
    bool all_textures = true;
    for (rt::Plane& p : scene.planes)
        all_textures = take_texture(p.material, textures) && take_texture(p.material2, textures) && all_textures;
    for (rt::Object& o : scene.objects) all_textures = take_textures(o, textures) && all_textures;
    if (!all_textures) return rt::Status::error("a material's texture was not broadcast", kExitMpi);
    for (rt::Object& o : scene.objects)
        if (rt::Mesh* m = std::get_if<rt::Mesh>(&o.shape)) {
            auto it = models.find(m->file);
            if (it == models.end()) return rt::Status::error("a mesh's model was not broadcast", kExitMpi);
            m->model = it->second;
        }
    scene.width = job.width;
    scene.height = job.height;
    return rtcli::build_world(scene, job.max_depth);
}

// --- workers -----------------------------------------------------------------------

// A worker's tiles in flight: rendering, then being sent back (std::map: the
// buffers stay put while MPI and the pool use them).
struct WorkerState {
    struct Held {
        AssignHeader a;
        std::vector<float> buf;  // ResultHeader + sums (+ squares)
        std::vector<std::uint32_t> counts;  // a refine assignment's n0, then n1
        MPI_Request req = MPI_REQUEST_NULL;
        bool sending = false;
    };
    std::map<int, Held> held;
    int next_id = 0;
    bool stop = false;
    std::vector<float> in;  // the posted receive of the next assignment
    MPI_Request rreq = MPI_REQUEST_NULL;

    void post_receive() {
        check(MPI_Irecv(in.data(), bytes_of(in.size()), MPI_BYTE, 0, kTagAssign, MPI_COMM_WORLD, &rreq),
              "MPI_Irecv (assignment)");
    }
};

// Takes an assignment if one has arrived: into the pool's queue, or the stop. True
// if one did.
bool take_assignment(const std::vector<Tile>& tiles, TilePool& pool, WorkerState& w) {
    const std::size_t ah = head_floats<AssignHeader>(), rh = head_floats<ResultHeader>();
    int arrived = 0;
    MPI_Status st;
    check(MPI_Test(&w.rreq, &arrived, &st), "waiting for a tile from rank 0");
    if (!arrived) return false;
    const int got = received_bytes(st);
    if (got < int(sizeof(AssignHeader))) fail(kExitMpi, "short message from rank 0");
    const auto a = get_header<AssignHeader>(w.in);
    if (a.tile == -1) {
        w.stop = true;  // rank 0 sends it only once this rank holds nothing
        return true;
    }
    if (a.tile < 0 || std::size_t(a.tile) >= tiles.size() || (a.refine < 0 && (a.s0 < 0 || a.s1 <= a.s0)))
        fail(kExitMpi, "rank 0 sent an invalid tile");
    const Tile& t = tiles[std::size_t(a.tile)];
    const std::size_t px = std::size_t(t.pixels()), n = result_floats(a.refine, px);
    if (got != bytes_of(ah + assign_floats(a, px))) fail(kExitMpi, "rank 0 sent a tile of the wrong size");
    WorkerState::Held& h = w.held[w.next_id];
    h.a = a;
    h.buf.assign(rh + n, 0.f);
    if (a.has_prior || a.refine >= 0) std::copy_n(w.in.data() + ah, n, h.buf.data() + rh);
    if (a.refine >= 0) {
        h.counts.resize(2 * px);
        std::memcpy(h.counts.data(), w.in.data() + ah + n, 2 * px * sizeof(std::uint32_t));
        pool.submit_refine(w.next_id++, t, h.counts.data(), h.counts.data() + px, h.buf.data() + rh,
                           h.buf.data() + rh + 3 * px);
    } else {
        pool.submit(w.next_id++, t, a.s0, a.s1, h.buf.data() + rh);
    }
    w.post_receive();  // `in` is free again
    return true;
}

// Sends every tile the pool has finished back to rank 0. True if any.
bool send_finished(TilePool& pool, WorkerState& w, bool crash_me) {
    bool any = false;
    for (const TilePool::Finished& f : pool.take_finished()) {
        any = true;
        WorkerState::Held& h = w.held.at(f.id);
        ResultHeader r;
        r.tile = h.a.tile;
        r.s0 = h.a.s0;
        r.s1 = h.a.s1;
        r.refine = h.a.refine;
        r.rays = f.rays;
        put_header(h.buf, r);
        check(MPI_Isend(h.buf.data(), bytes_of(h.buf.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD, &h.req),
              "sending a tile to rank 0");
        h.sending = true;
        if (crash_me) {
            wait_polling(h.req, nullptr, "sending a tile to rank 0");
            std::cerr << "raytracer-mpi: rank " << g_rank << ": aborting on purpose (RAYTRACER_MPI_TEST_CRASH_RANK)\n"
                      << std::flush;
            std::abort();
        }
    }
    return any;
}

// Ranks 1..N-1: render what rank 0 assigns until told to stop. Every assignment goes
// into the pool's queue the moment it arrives, so the render threads always find the
// next tile waiting; this thread only moves messages.
void run_worker(const std::vector<Tile>& tiles, int side, TilePool& pool) {
    // Test hook: RAYTRACER_MPI_TEST_CRASH_RANK=R makes rank R abort after sending its
    // first tile, to check that a dying rank fails the job and leaves OUT untouched.
    const char* crash = std::getenv("RAYTRACER_MPI_TEST_CRASH_RANK");
    const bool crash_me = crash && std::atoi(crash) == g_rank;

    WorkerState w;
    w.in.resize(head_floats<AssignHeader>() + 6 * std::size_t(side) * std::size_t(side));
    w.post_receive();
    for (;;) {
        bool busy = false;
        if (!w.stop) busy = take_assignment(tiles, pool, w);
        busy |= send_finished(pool, w, crash_me);
        // Also keeps MPI moving: a result too big to send eagerly only completes while
        // this rank calls into MPI.
        for (auto it = w.held.begin(); it != w.held.end();) {
            int sent = 0;
            if (it->second.sending) check(MPI_Test(&it->second.req, &sent, MPI_STATUS_IGNORE), "sending a tile to rank 0");
            it = sent ? w.held.erase(it) : std::next(it);
        }
        if (w.stop && w.held.empty()) return;
        if (!busy) pool.wait_finished(kPoll);
    }
}

// --- rank 0 ------------------------------------------------------------------------

// Rank 0's main thread: owns the schedule, serves the workers and feeds its own pool.
// Single-threaded apart from the pool, so the schedule needs no lock.
class Coordinator {
public:
    Coordinator(const ScheduleSettings& settings, TilePool& pool) : sched_(settings), pool_(pool) {
        peers_.resize(std::size_t(g_size));
        reqs_.assign(std::size_t(g_size), MPI_REQUEST_NULL);
        tiles_by_rank_.assign(std::size_t(g_size), 0);
    }

    // Renders the whole picture; returns with the schedule complete (or fails the job).
    void run(bool show_progress) {
        t0_ = Clock::now();
        ProgressBar bar(show_progress);
        auto next_draw = Clock::now();
        for (;;) {
            if (caught_signal()) interrupted();
            bool busy = collect_local();
            busy |= receive_results();
            busy |= feed_local();
            busy |= hand_out();
            reap_sends();
            if (sched_.done() && local_.empty() &&
                std::all_of(peers_.begin() + 1, peers_.end(), [](const Peer& p) { return p.stopped; }))
                break;
            if (show_progress && Clock::now() >= next_draw) {
                next_draw = Clock::now() + std::chrono::milliseconds(100);
                const double elapsed = seconds_since(t0_);
                const std::string pass =
                    sched_.pass_count() > 1 ? "pass " + std::to_string(sched_.pass_index() + 1) + ", " : "";
                char detail[160];
                std::snprintf(detail, sizeof detail, "%stiles %d/%zu, %s, %.2f M rays/s", pass.c_str(),
                              sched_.pass_tiles_done(), sched_.tiles().size(), count(std::size_t(g_size), "rank").c_str(),
                              elapsed > 0 ? double(sched_.rays()) / elapsed / 1e6 : 0.0);
                bar.update(sched_.fraction(), elapsed, detail);
            }
            // Sleeps until rank 0's own pool finishes a tile, or for one poll period.
            if (!busy) pool_.wait_finished(kPoll);
        }
        bar.clear();
        // Every stop has been sent; wait until MPI is done with the buffers.
        while (!sends_.empty()) reap_sends(), std::this_thread::sleep_for(kPoll);
        render_time_ = seconds_since(t0_);
        if (!sched_.complete()) fail(kExitMpi, "internal error: the render ended with pixels missing");
    }

    rt::Image image() const { return sched_.image(); }
    const Schedule& schedule() const { return sched_; }
    double render_time() const { return render_time_; }
    const std::vector<int>& tiles_by_rank() const { return tiles_by_rank_; }
    std::uint64_t bytes_received() const { return bytes_received_; }
    std::uint64_t messages_received() const { return messages_received_; }

private:
    struct Peer {
        std::vector<Assignment> out;  // handed out and not back yet
        std::vector<float> buf;      // receives the result of out.front()
        bool stopped = false;
    };
    struct Send {
        std::vector<float> buf;
        MPI_Request req = MPI_REQUEST_NULL;
    };
    struct Local {
        Assignment a;
        std::vector<float> sums;  // (+ squares, for a refine assignment)
        std::vector<std::uint32_t> counts;
    };

    // Rank 0's own share: kLocalDepth tiles queued in its pool.
    bool feed_local() {
        bool fed = false;
        Assignment a;
        while (local_.size() < std::size_t(kLocalDepth) && sched_.take(a, seconds_since(t0_))) {
            Local& l = local_[next_local_];
            const Tile& t = sched_.tiles()[std::size_t(a.tile)];
            const std::size_t px = std::size_t(t.pixels());
            l.a = a;
            l.sums.assign(result_floats(a.refine, px), 0.f);
            if (a.refine >= 0) {
                l.counts.resize(2 * px);
                sched_.refine_input(a, l.sums.data(), l.sums.data() + 3 * px, l.counts.data(), l.counts.data() + px);
                pool_.submit_refine(next_local_++, t, l.counts.data(), l.counts.data() + px, l.sums.data(),
                                    l.sums.data() + 3 * px);
            } else {
                if (a.s0 > 0) sched_.prior_sums(a, l.sums.data());
                pool_.submit(next_local_++, t, a.s0, a.s1, l.sums.data());
            }
            fed = true;
        }
        return fed;
    }

    bool collect_local() {
        const std::vector<TilePool::Finished> done = pool_.take_finished();
        for (const TilePool::Finished& f : done) {
            auto it = local_.find(f.id);
            if (const rt::Status st = sched_.commit(it->second.a, it->second.sums.data(), f.rays, seconds_since(t0_)); !st)
                fail(kExitMpi, "internal error: " + st.message());
            ++tiles_by_rank_[0];
            local_.erase(it);
        }
        return !done.empty();
    }

    void post_receive(int w) {
        Peer& p = peers_[std::size_t(w)];
        p.buf.resize(head_floats<ResultHeader>() + 4 * std::size_t(sched_.tile_side()) * std::size_t(sched_.tile_side()));
        check(MPI_Irecv(p.buf.data(), bytes_of(p.buf.size()), MPI_BYTE, w, kTagResult, MPI_COMM_WORLD,
                        &reqs_[std::size_t(w)]),
              "MPI_Irecv (tile)");
    }

    // Commits every result that has arrived. True if any did.
    bool receive_results() {
        if (g_size < 2) return false;
        int n = 0;
        idx_.resize(std::size_t(g_size));
        st_.resize(std::size_t(g_size));
        const int rc = MPI_Testsome(g_size, reqs_.data(), &n, idx_.data(), st_.data());
        if (rc == MPI_ERR_IN_STATUS)
            for (int i = 0; i < n; ++i) check(st_[std::size_t(i)].MPI_ERROR, "receiving a tile");
        check(rc, "receiving a tile");
        if (n == MPI_UNDEFINED || n == 0) return false;
        for (int i = 0; i < n; ++i) {
            const int w = idx_[std::size_t(i)];
            Peer& p = peers_[std::size_t(w)];
            const int got = received_bytes(st_[std::size_t(i)]);
            // The pool finishes tiles in any order (a cheap one can overtake a costly one).
            const auto r = got >= int(sizeof(ResultHeader)) ? get_header<ResultHeader>(p.buf) : ResultHeader{};
            auto it = std::find_if(p.out.begin(), p.out.end(), [&](const Assignment& x) {
                return x.tile == r.tile && x.s0 == r.s0 && x.s1 == r.s1 && x.refine == r.refine;
            });
            if (it == p.out.end())
                fail(kExitMpi, "rank " + std::to_string(w) + " sent back tile " + std::to_string(r.tile) +
                                   ", which it does not hold");
            const Assignment a = *it;
            p.out.erase(it);
            const std::size_t sums = result_floats(a.refine, std::size_t(sched_.tiles()[std::size_t(a.tile)].pixels()));
            if (got != bytes_of(head_floats<ResultHeader>() + sums))
                fail(kExitMpi, "rank " + std::to_string(w) + " sent tile " + std::to_string(a.tile) +
                                   " with the wrong size");
            bytes_received_ += std::uint64_t(got);
            ++messages_received_;
            if (const rt::Status st =
                    sched_.commit(a, p.buf.data() + head_floats<ResultHeader>(), r.rays, seconds_since(t0_));
                !st)
                fail(kExitMpi, "rank " + std::to_string(w) + ": " + st.message());
            ++tiles_by_rank_[std::size_t(w)];
            if (!p.out.empty()) post_receive(w);
        }
        return true;
    }

    // Tops every worker up to kDepth tiles, or stops it once the render is complete.
    // True if anything was sent.
    bool hand_out() {
        bool sent = false;
        for (int w = 1; w < g_size; ++w) {
            Peer& p = peers_[std::size_t(w)];
            if (p.stopped) continue;
            Assignment a;
            while (p.out.size() < std::size_t(kDepth) && sched_.take(a, seconds_since(t0_))) {
                send(w, assignment(a));
                p.out.push_back(a);
                if (p.out.size() == 1) post_receive(w);
                sent = true;
            }
            // Stop a worker only when the render is complete and it holds nothing.
            if (sched_.done() && p.out.empty()) {
                Send s;
                s.buf.resize(head_floats<AssignHeader>());
                put_header(s.buf, AssignHeader{});
                send(w, std::move(s));
                p.stopped = true;
                sent = true;
            }
        }
        return sent;
    }

    // The message that hands out `a`: its header, then what the worker continues.
    Send assignment(const Assignment& a) const {
        const std::size_t px = std::size_t(sched_.tiles()[std::size_t(a.tile)].pixels());
        const AssignHeader h{a.tile, a.s0, a.s1, a.refine < 0 && a.s0 > 0, a.refine, 0};
        Send s;
        s.buf.resize(head_floats<AssignHeader>() + assign_floats(h, px));
        put_header(s.buf, h);
        float* data = s.buf.data() + head_floats<AssignHeader>();
        if (h.has_prior) sched_.prior_sums(a, data);
        if (a.refine >= 0) {
            std::vector<std::uint32_t> counts(2 * px);
            sched_.refine_input(a, data, data + 3 * px, counts.data(), counts.data() + px);
            std::memcpy(data + 4 * px, counts.data(), 2 * px * sizeof(std::uint32_t));
        }
        return s;
    }

    void send(int w, Send&& s) {
        sends_.push_back(std::move(s));
        Send& b = sends_.back();
        check(MPI_Isend(b.buf.data(), bytes_of(b.buf.size()), MPI_BYTE, w, kTagAssign, MPI_COMM_WORLD, &b.req),
              "sending a tile");
    }

    // Frees the buffers of completed sends (std::list: the others must not move).
    void reap_sends() {
        for (auto it = sends_.begin(); it != sends_.end();) {
            int done = 0;
            check(MPI_Test(&it->req, &done, MPI_STATUS_IGNORE), "sending a tile");
            it = done ? sends_.erase(it) : std::next(it);
        }
    }

    Schedule sched_;
    TilePool& pool_;
    std::map<int, Local> local_;  // tiles in rank 0's own pool, by submit id
    int next_local_ = 0;
    Clock::time_point t0_;
    std::vector<Peer> peers_;        // by rank; [0] unused
    std::vector<MPI_Request> reqs_;  // by rank: the posted receive of each worker's next tile
    std::vector<int> idx_;
    std::vector<MPI_Status> st_;
    std::list<Send> sends_;
    std::vector<int> tiles_by_rank_;
    std::uint64_t bytes_received_ = 0, messages_received_ = 0;
    double render_time_ = 0;
};

// --- main --------------------------------------------------------------------------

// Step 1 on rank 0: the outcome of the command line and the scene, as the header
// every rank receives.
JobHeader settle_job(int argc, char** argv, Front& f, rt::Scene& scene) {
    JobHeader job;
    const rt::Status outcome = front_end(argc, argv, f, scene);
    if (!f.render) {
        job.status = report(outcome);
        return job;
    }
    job.width = scene.width;
    job.height = scene.height;
    // What raytracer renders with: the same passes make the same picture.
    const rt::RenderRequest& r = f.opt.render;
    const rt::RenderSettings s = rt::final_settings(r, scene.width, scene.height);
    job.max_samples = s.max_samples;
    job.samples_per_pass = s.samples_per_pass;
    job.aa_threshold = s.aa_threshold;
    job.threads = r.threads;
    job.max_depth = r.max_depth;
    job.tile = r.tile;
    job.mirror = r.mirror;
    job.time_limit = s.time_limit;
    job.text_size = f.text.size();
    return job;
}

// A rank's means to render: the World, the camera and the tile pool using both.
struct Built {
    std::shared_ptr<const rt::World> world;
    rt::CameraBasis camera;
    std::unique_ptr<TilePool> pool;  // declared after world and camera: it uses both
};

// Step 2's second half, on every rank: success, or why this rank could not build.
rt::Status build_rank(const std::string& text, const Models& models, const Textures& textures, const JobHeader& job,
                      Built& b) {
    try {
        rt::Expected<std::shared_ptr<const rt::World>> world = build_world(text, models, textures, job);
        if (!world) return world.status();
        b.world = std::move(*world);
        b.camera = rt::CameraBasis::make(b.world->camera, job.width, job.height, job.mirror != 0);
        b.pool = std::make_unique<TilePool>(*b.world, b.camera, rt::process_pool());
    } catch (const std::bad_alloc&) {
        return rt::Status::error("out of memory building the scene", kExitMpi);
    } catch (const std::exception& e) {
        return rt::Status::error(e.what(), kExitMpi);
    }
    return {};
}

// Step 3: whether every rank is ready (threads -1: this one is not). Rank 0 learns
// every rank's thread count on the way, into all_threads.
bool all_ready(int threads, std::vector<int>& all_threads) {
    all_threads.assign(std::size_t(g_rank == 0 ? g_size : 0), 0);
    check(MPI_Gather(&threads, 1, MPI_INT, all_threads.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    int go = 1;
    if (g_rank == 0)
        for (int r = 0; r < g_size; ++r)
            if (all_threads[std::size_t(r)] < 0) {
                std::cerr << "raytracer-mpi: rank " << r << " could not build the scene; nothing written\n";
                go = 0;
                break;
            }
    check(MPI_Bcast(&go, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast (go)");
    return go != 0;
}

// Seconds of the phases before the render, for --stats.
struct Times {
    double bcast = 0, compile = 0;
};

void print_stats(const Front& f, const JobHeader& job, const Coordinator& coord, const std::vector<int>& all_threads,
                 const Times& t, double t_write) {
    const Schedule& s = coord.schedule();
    const double total = seconds_since(f.t_start), t_render = coord.render_time();
    int total_threads = 0;
    for (int n : all_threads) total_threads += n;
    char line[320];
    std::cerr << f.scene_path << ": " << job.width << "x" << job.height << ", ";
    if (s.adaptive()) {
        std::snprintf(line, sizeof line, "%.3f samples per pixel on average (adaptive, %lld not settled)",
                      double(s.film_samples()) / (double(job.width) * job.height), static_cast<long long>(s.refining()));
        std::cerr << line;
    } else {
        std::cerr << s.samples_done() << (s.samples_done() == 1 ? " sample" : " samples") << " per pixel";
    }
    std::cerr << ", " << count(std::size_t(g_size), "rank") << ", " << count(std::size_t(total_threads), "thread")
              << "\n";
    std::snprintf(line, sizeof line,
                  "time: parse %.3f s, broadcast %.3f s, compile %.3f s, render %.3f s, write %.3f s, total %.3f s\n",
                  f.t_parse, t.bcast, t.compile, t_render, t_write, total);
    std::cerr << line << "rays: " << with_commas(s.rays());
    std::snprintf(line, sizeof line, " (%.2f M rays/s)\n", t_render > 0 ? double(s.rays()) / t_render / 1e6 : 0.0);
    std::cerr << line << "tiles: " << s.tiles().size() << " of " << job.tile << "x" << job.tile << " per pass (";
    for (int r = 0; r < g_size; ++r)
        std::cerr << (r ? ", " : "") << "rank " << r << ": " << coord.tiles_by_rank()[std::size_t(r)];
    std::snprintf(line, sizeof line, "); received %.2f MiB in %llu messages\n",
                  double(coord.bytes_received()) / (1024.0 * 1024.0),
                  static_cast<unsigned long long>(coord.messages_received()));
    std::cerr << line;
}

// Step 4 on rank 0: coordinates the render, writes OUT and the statistics. Returns
// the exit status.
int render_and_write(const Front& f, const JobHeader& job, TilePool& pool, const std::vector<int>& all_threads,
                     const Times& times) {
    ScheduleSettings ss;
    ss.width = job.width;
    ss.height = job.height;
    ss.tile_side = job.tile;
    ss.max_samples = job.max_samples;
    ss.samples_per_pass = job.samples_per_pass;
    ss.time_limit = job.time_limit;
    ss.aa_threshold = job.aa_threshold;
    Coordinator coord(ss, pool);
    coord.run(!f.opt.quiet && stderr_watched());
    if (caught_signal()) interrupted();

    const auto t_write0 = Clock::now();
    if (const rt::Status st = rt::write_image(f.out_path, coord.image()); !st) {
        if (caught_signal()) interrupted();  // the temporary file is gone
        std::cerr << "raytracer-mpi: cannot write '" << f.out_path << "': " << st.message() << "\n";
        return kExitUsage;
    }
    const double t_write = seconds_since(t_write0);
    if (f.opt.stats) print_stats(f, job, coord, all_threads, times, t_write);
    return kExitOk;
}

int run(int argc, char** argv) {
    // Step 1: rank 0 settles the command line and the scene; everyone learns the outcome.
    Front f;
    rt::Scene scene;
    JobHeader job;
    if (g_rank == 0) job = settle_job(argc, argv, f, scene);
    Times times;
    const auto t_bcast0 = Clock::now();
    check(MPI_Bcast(&job, int(sizeof job), MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast (settings)");
    if (job.status >= 0) return job.status;

    // Step 2: the text, and every rank's own World.
    std::string text = std::move(f.text);
    text.resize(std::size_t(job.text_size));
    check(MPI_Bcast(text.data(), int(job.text_size), MPI_BYTE, 0, MPI_COMM_WORLD), "MPI_Bcast (scene)");
    const Textures textures = share_textures(scene);
    const Models models = share_models(scene, textures);
    times.bcast = seconds_since(t_bcast0);
    const auto t_compile0 = Clock::now();
    // (Rank 0 set it from the same count before reading the scene.)
    rt::set_process_threads(job.threads > 0 ? job.threads : default_threads());
    Built built;
    const rt::Status built_ok = build_rank(text, models, textures, job, built);
    times.compile = seconds_since(t_compile0);

    // Step 3: everyone ready?
    const int threads = built_ok ? built.pool->threads() : -1;
    if (!built_ok) std::cerr << "raytracer-mpi: rank " << g_rank << ": " << built_ok.message() << "\n" << std::flush;
    std::vector<int> all_threads;
    if (!all_ready(threads, all_threads)) return kExitMpi;

    // Step 4: render.
    if (g_rank > 0) {
        run_worker(make_tiles(job.width, job.height, job.tile), job.tile, *built.pool);
        return kExitOk;
    }
    return render_and_write(f, job, *built.pool, all_threads, times);
}

}  // namespace
}  // namespace rtmpi

int main(int argc, char** argv) {
    using namespace rtmpi;
    int provided = 0;
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
        std::cerr << "raytracer-mpi: MPI_Init_thread failed\n";
        return kExitMpi;
    }
    // Errors come back as return codes, each reported with what was being done.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    check(MPI_Comm_rank(MPI_COMM_WORLD, &g_rank), "MPI_Comm_rank");
    check(MPI_Comm_size(MPI_COMM_WORLD, &g_size), "MPI_Comm_size");
    if (provided < MPI_THREAD_FUNNELED)
        fail(kExitMpi, "the MPI library does not support threads (MPI_THREAD_FUNNELED)");
    int status = kExitUsage;
    try {
        status = run(argc, argv);
    } catch (const std::bad_alloc&) {
        fail(kExitUsage, "out of memory");
    } catch (const std::exception& e) {
        fail(kExitUsage, e.what());
    }
    // By now OUT is written (or the outcome is settled): a failing shutdown is
    // reported but does not turn a complete, checked picture into a failure.
    if (MPI_Finalize() != MPI_SUCCESS) std::cerr << "raytracer-mpi: rank " << g_rank << ": MPI_Finalize failed\n";
    return status;
}
