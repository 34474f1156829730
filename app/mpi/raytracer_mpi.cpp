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
#include <cstddef>
#include <cstring>

#include "coordinator.h"
#include "messages.h"
#include "texture.h"
#include "worker.h"

namespace rtmpi {
namespace {

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
    rt::set_process_threads(opt.render.threads > 0 ? opt.render.threads : rt::hardware_threads());
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

// A rank's means to render: the World and the tile pool that renders it.
struct Built {
    std::shared_ptr<const rt::World> world;
    std::unique_ptr<TilePool> pool;
};

// Step 2's second half, on every rank: success, or why this rank could not build.
rt::Status build_rank(const std::string& text, const Models& models, const Textures& textures, const JobHeader& job,
                      Built& b) {
    try {
        rt::Expected<std::shared_ptr<const rt::World>> world = build_world(text, models, textures, job);
        if (!world) return world.status();
        b.world = std::move(*world);
        b.pool = std::make_unique<TilePool>(b.world, b.world->camera, job.width, job.height, job.mirror != 0,
                                            job.max_samples, rt::process_pool());
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
    rt::set_process_threads(job.threads > 0 ? job.threads : rt::hardware_threads());
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

