// Reading model files safely (see model.h): only regular files within the size limit
// are read, in one piece, before a reader looks at them; text formats in UTF-16 or
// UTF-32 are refused as the scene files are; the readers (model_readers.h) check
// every count against the bytes there are before they allocate.
#include "model.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include "diagnostic_text.h"
#include "image_io.h"
#include "model_readers.h"
#include "pages.h"
#include "texture.h"
#include "triangles.h"

namespace rt {

namespace {

// The whole file, if it is a regular file within the size limit: in pages of its own,
// handed back once the reader is done (a 10M-triangle model's text is ~200 MB).
bool read_file(const std::string& path, PageBuffer& out, ModelError& error, const char* what = "a model file",
               const char* kind = "models") {
    // Non-blocking: a FIFO must not stop the open (it is refused below).
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) {
        error.message = std::strerror(errno);
        return false;
    }
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    struct stat st;
    if (::fstat(fd, &st) != 0) {
        error.message = std::strerror(errno);
        return false;
    }
    if (S_ISDIR(st.st_mode)) {
        error.message = std::string("is a folder, not ") + what;
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        error.message = std::string("is not a regular file (a device, pipe or socket); ") +
                        kind + " are read from files";
        return false;
    }
    if (std::uint64_t(st.st_size) > ModelLimits::max_file_size) {
        error.message = "file too large (" + std::to_string(st.st_size) + " bytes, limit " +
                        std::to_string(ModelLimits::max_file_size) + ")";
        return false;
    }
    out = PageBuffer(std::size_t(st.st_size));
    if (out.size() >= (std::size_t(1) << 24)) populate_pages_on_two_threads(out.data(), out.size());
    std::size_t got = 0;
    while (got < out.size()) {
        const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            error.message = std::strerror(errno);
            return false;
        }
        if (n == 0) break;  // shrank while being read: what is there is the file
        got += std::size_t(n);
    }
    out.shrink(got);
    return true;
}

// A path as an OBJ or MTL file writes it, relative to `folder`: backslashes read as
// slashes (files written on Windows), a leading "./" dropped.
std::string file_in(const std::string& folder, std::string name) {
    std::replace(name.begin(), name.end(), '\\', '/');
    while (name.size() > 2 && name[0] == '.' && name[1] == '/') name.erase(0, 2);
    return resolve_model_path(folder, name);
}

// An MTL file's material, with where it came from.
struct FoundMaterial {
    MtlMaterial m;
    std::string lib;       // the MTL file, as the OBJ names it
    std::string tex_path;  // map_Kd resolved ("" if none)
};

// The OBJ's `mtllib` files read into `found` (a missing one is a warning in
// out.warnings); false with `error` set for a file that cannot be read as MTL or whose
// map_Kd names the MTL or OBJ file itself.
bool read_libraries(const std::string& obj_path, MeshData& out, ModelError& error, std::vector<FoundMaterial>& found) {
    const std::string folder = folder_of(obj_path);
    for (const std::string& lib : out.material_libs) {
        const std::string path = file_in(folder, lib);
        if (path == obj_path) {
            error.message = "mtllib " + lib + " names the model file itself";
            return false;
        }
        PageBuffer file;
        ModelError e;
        if (!read_file(path, file, e, "a material file", "material files")) {
            out.warnings.push_back({0, "material file " + lib + ": " + e.message + "; the mesh's own colour is used"});
            continue;
        }
        const std::string_view text(file.data(), file.size());
        if (Status st = check_encoding(text); !st.ok()) {
            error.message = lib + ": " + st.message();
            return false;
        }
        std::vector<MtlMaterial> mats;
        if (!read_mtl(text, mats, e)) {
            error.message = lib + ":" + std::to_string(e.line) + ": " + e.message;
            return false;
        }
        for (MtlMaterial& m : mats) {
            std::string tex;
            if (!m.texture.empty()) {
                tex = file_in(folder_of(path), m.texture);
                if (tex == path || tex == obj_path) {
                    error.message = lib + ":" + std::to_string(m.texture_line) + ": map_Kd " + m.texture + " names the " +
                                    (tex == path ? "material" : "model") + " file itself";
                    return false;
                }
            }
            found.push_back({std::move(m), lib, std::move(tex)});
        }
    }
    return true;
}

// The OBJ's `mtllib` files read and its `usemtl` names found in them: out.materials in
// the order of out.material_names (the first definition of a name counts), with their
// textures, and the triangles renumbered (names no file defines: the mesh's own
// material, with a warning). A missing MTL file is a warning; a file that cannot be
// read as MTL, or a map_Kd that cannot be read, an error.
bool read_materials(const std::string& obj_path, MeshData& out, ModelError& error, TextureStore& textures) {
    std::vector<FoundMaterial> found;
    if (!read_libraries(obj_path, out, error, found)) return false;
    std::vector<std::uint16_t> index(out.material_names.size(), MeshData::kNoMaterial);
    int unknown = 0;
    std::vector<const Texture*> held;  // the textures read, each counted once
    std::vector<std::pair<const Texture*, std::string>> decoding;  // and where each was named
    std::uint64_t texels = 0;
    for (std::size_t i = 0; i < out.material_names.size(); ++i) {
        const std::string& name = out.material_names[i];
        auto it = std::find_if(found.begin(), found.end(), [&](const FoundMaterial& f) { return f.m.name == name; });
        if (it == found.end()) {
            if (!found.empty() && ++unknown <= 5)
                out.warnings.push_back({0, "usemtl " + name + ": no such material in the MTL files; the mesh's own "
                                           "colour is used"});
            continue;
        }
        Material m = it->m.material;
        if (!it->tex_path.empty()) {
            // Decoded on the pool, all of the model's textures at once: waited for below.
            TextureStore::Loaded l = textures.load(it->tex_path, /*later=*/true);
            const std::string at = it->lib + ":" + std::to_string(it->m.texture_line) + ": ";
            if (!l.texture) {
                error.message = at + "map_Kd " + it->m.texture + ": " + l.error;
                return false;
            }
            if (std::find(held.begin(), held.end(), l.texture.get()) == held.end()) {
                held.push_back(l.texture.get());
                texels += std::uint64_t(l.texture->width()) * std::uint64_t(l.texture->height());
                if (texels > TextureLimits::max_scene_texels) {
                    error.message = at + "the model's textures hold more than " +
                                    std::to_string(TextureLimits::max_scene_texels) + " pixels in all";
                    return false;
                }
            }
            m.texture = it->m.texture;
            m.texture_image = std::move(l.texture);
            decoding.push_back({m.texture_image.get(), at + "map_Kd " + it->m.texture + ": "});
        }
        index[i] = std::uint16_t(out.materials.size());
        out.materials.push_back(std::move(m));
    }
    for (const auto& [texture, at] : decoding)
        if (const std::string e = texture->wait(); !e.empty()) {
            error.message = at + e;
            return false;
        }
    for (std::uint16_t& t : out.triangle_material)
        if (t < index.size()) t = index[t];
    return true;
}

}  // namespace

bool is_model_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".obj" || ext == ".ply";
}

bool read_model(const std::string& path, MeshData& out, ModelError& error, TextureStore* textures) {
    out = MeshData();
    error = ModelError();
    const std::string ext = lower_extension(path);
    if (!is_model_file(path)) {
        error.message = "unknown model format '" + ext + "' (expected a .obj or .ply file)";
        return false;
    }
    PageBuffer file;
    if (!read_file(path, file, error)) return false;
    const std::string_view text(file.data(), file.size());
    if (ext == ".obj") {
        if (Status s = check_encoding(text); !s.ok()) {
            error.message = s.message();
            return false;
        }
        if (!read_obj(text, out, error)) return false;
        if (out.material_libs.empty() && out.material_names.empty()) return true;
        TextureStore own;
        if (!read_materials(path, out, error, textures ? *textures : own)) return false;
        if (out.materials.empty()) {
            out.triangle_material.clear();
            out.triangle_material.shrink_to_fit();
        }
        return true;
    }
    return read_ply(text, out, error);
}

MeshModel::MeshModel(std::string path, MeshData data) : path_(std::move(path)), data_(std::move(data)) {
    const std::vector<float>& p = data_.positions;
    for (std::uint32_t v : data_.triangles) bounds_.grow(Vec3{p[3 * v], p[3 * v + 1], p[3 * v + 2]});
}

MeshModel::~MeshModel() = default;

const TriangleAccel& MeshModel::accel() const {
    std::call_once(built_, [this] { accel_ = std::make_unique<TriangleAccel>(TriangleAccel::build(data_)); });
    return *accel_;
}

const std::vector<float>& MeshModel::vertex_normals() const {
    std::call_once(normals_made_, [this] {
        const MeshData& m = data_;
        const std::size_t nv = m.vertex_count();
        std::vector<double> sum(3 * nv, 0.0);
        if (m.normals.size() == 3 * nv) {
            sum.assign(m.normals.begin(), m.normals.end());
        } else {
            auto at = [&](std::uint32_t v) { return Vec3{m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]}; };
            for (std::size_t t = 0; t < m.triangles.size(); t += 3) {
                const std::uint32_t* v = &m.triangles[t];
                const Vec3 a = at(v[0]);
                const Vec3 n = cross(at(v[1]) - a, at(v[2]) - a);  // twice the area, along the normal
                for (int k = 0; k < 3; ++k)
                    for (int c = 0; c < 3; ++c) sum[3 * std::size_t(v[k]) + std::size_t(c)] += n[c];
            }
        }
        normals_.assign(3 * nv, 0.0f);
        for (std::size_t i = 0; i < nv; ++i) {
            const Vec3 n = normalize(Vec3{sum[3 * i], sum[3 * i + 1], sum[3 * i + 2]});
            if (!finite(n)) continue;  // left 0: shading takes the triangle's own normal there
            for (int c = 0; c < 3; ++c) normals_[3 * i + std::size_t(c)] = float(n[c]);
        }
    });
    return normals_;
}

bool MeshModel::textures_unchanged() const {
    for (const Material& m : data_.materials)
        if (m.texture_image && !m.texture_image->unchanged_on_disk()) return false;
    return true;
}

bool MeshModel::unchanged_on_disk() const { return textures_unchanged() && FileId::unchanged(path_, id_); }

ModelStore::Loaded ModelStore::load(const std::string& path, TextureStore* textures) {
    Loaded result;
    const FileId id = FileId::of(path);
    // (A model's textures changed on disk: the model is read again with them.)
    if (cache_.find(path, id, result.model, result.error) && (!result.model || result.model->textures_unchanged()))
        return result;
    result.model = nullptr;
    // Read outside the cache's lock: another thread may read another file meanwhile.
    MeshData data;
    if (read_model(path, data, result.error, textures ? textures : &textures_)) {
        auto model = std::make_shared<MeshModel>(path, std::move(data));
        model->id_ = id;
        result.model = std::move(model);
    }
    cache_.store(path, id, result.model, result.error, id.known());
    return result;
}

std::string folder_of(const std::string& path) {
    const std::size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) return {};
    return slash == 0 ? "/" : path.substr(0, slash);
}

std::string resolve_model_path(const std::string& base_dir, const std::string& file) {
    if (file.empty() || file[0] == '/' || base_dir.empty()) return file;
    return base_dir.back() == '/' ? base_dir + file : base_dir + "/" + file;
}

}  // namespace rt
