// Triangle models read from files (OBJ, PLY) for the scene's `mesh` blocks: their
// vertices and triangles, the limits that keep a hostile file from exhausting the
// machine, and a store that reads each file once however many blocks name it and
// again only when it changes on disk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "file_id.h"
#include "math.h"
#include "scene.h"
#include "texture.h"

namespace rt {

struct TriangleAccel;  // triangles.h
struct ModelShading;   // world.h

struct ModelLimits {
    static constexpr std::uint64_t max_file_size = std::uint64_t(1) << 30;  // bytes (a 10M-triangle OBJ is ~0.5 GB)
    // Per model, and over all the models of one scene: 32M triangles take about 2.5 GB
    // at their peak (reading, then the BVH build).
    static constexpr std::size_t max_triangles = std::size_t(1) << 25;
    static constexpr std::size_t max_vertices = std::size_t(1) << 25;
    static constexpr std::size_t max_polygon = 1u << 16;  // vertices of one face
    static constexpr std::size_t max_files = 10000;       // distinct model files in a scene
    static constexpr double max_coordinate = 1e15;         // as the scene's numbers
};

// What went wrong reading a model: the message, and the file's line it concerns (0:
// the file as a whole, or a binary file).
struct ModelError {
    long line = 0;
    std::string message;
};

// A model file's content: vertices (with normals if the file gives them) and
// triangles, polygons already cut into triangles.
struct MeshData {
    std::vector<float> positions;          // x y z per vertex
    std::vector<float> normals;            // x y z per vertex, or empty
    std::vector<std::uint32_t> triangles;  // three vertex indices per triangle
    // New: texture coordinates u v per triangle corner (6 a triangle), or empty.
    std::vector<float> corner_uv;
    // New: linear r g b per vertex (PLY's red green blue, decoded from sRGB), or empty.
    std::vector<float> colours;
    // New: the file's materials (OBJ's MTL files), and per triangle the index of its
    // material, kNoMaterial for the mesh's own (empty: every triangle the mesh's own).
    static constexpr std::uint16_t kNoMaterial = 0xffff;
    static constexpr std::size_t max_materials = 0xfff0;
    std::vector<Material> materials;
    std::vector<std::uint16_t> triangle_material;
    // OBJ: the `mtllib` files named (as written) and the `usemtl` names in the order
    // first met, which triangle_material counts until read_model() has found them in
    // the files (then materials holds them in that order; the names not found are
    // kNoMaterial).
    std::vector<std::string> material_libs;
    std::vector<std::string> material_names;
    // New: what the reading found amiss but could do without (a missing MTL file).
    std::vector<ModelError> warnings;
    std::size_t vertex_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return triangles.size() / 3; }
};

// One model file's triangles, shared by every mesh block (and every world) that names
// the file, with the acceleration structure the renderer builds over them on first use.
class MeshModel {
public:
    MeshModel(std::string path, MeshData data);
    ~MeshModel();
    const std::string& path() const { return path_; }  // as resolved (the scene's folder joined)
    const MeshData& data() const { return data_; }
    const Aabb& bounds() const { return bounds_; }  // of the vertices that triangles use
    // Whether the file is still the one read (same size, modification time and inode);
    // always true for a model made from data rather than read by a ModelStore.
    bool unchanged_on_disk() const;
    // Whether the textures of its materials are (New:; part of unchanged_on_disk()).
    bool textures_unchanged() const;
    // Built once, on the first call from any thread (the others wait for it).
    const TriangleAccel& accel() const;
    // Unit normals per vertex (x y z each): the file's own, else the sum of the
    // vertex's triangles' normals weighted by their areas. Made on the first call.
    const std::vector<float>& vertex_normals() const;
    // New: the file's materials and vertex colours as shading uses them; null when
    // the file has neither (world.cpp). Made on the first call.
    const ModelShading* shading() const;

private:
    friend class ModelStore;
    std::string path_;
    MeshData data_;
    FileId id_;  // of the file as read (unknown: made from data)
    Aabb bounds_;
    mutable std::once_flag built_, normals_made_;
    mutable std::unique_ptr<TriangleAccel> accel_;
    mutable std::vector<float> normals_;
    mutable std::once_flag shading_made_;
    mutable std::shared_ptr<const ModelShading> shading_;
};

// Whether read_model reads a file of this name: .obj or .ply, any case.
bool is_model_file(const std::string& path);
// Reads an .obj or .ply file (chosen by the name's extension, any case). False with
// `error` set if the file cannot be read or is not a model the limits allow.
// An OBJ's MTL files are read too (relative to the OBJ's folder), their map_Kd
// textures through `textures` (null: a store of this call's own).
bool read_model(const std::string& path, MeshData& out, ModelError& error, TextureStore* textures = nullptr);

// The models read so far, by resolved path. A file is read again only when it changed
// on disk (its size, modification time or inode), so that parsing the same scene
// again costs a stat() per file. Models are kept only while some scene holds them.
// Safe to use from several threads.
class ModelStore {
public:
    struct Loaded {
        std::shared_ptr<const MeshModel> model;  // null on error
        ModelError error;
    };
    // The models' MTL textures are read through `textures` (null: textures()).
    Loaded load(const std::string& path, TextureStore* textures = nullptr);
    // New: the store's textures, one decoded copy per file for the models read here and
    // (ParseOptions::models) the materials of the scenes parsed with it.
    TextureStore& textures() { return textures_; }

private:
    FileCache<MeshModel, ModelError> cache_;
    TextureStore textures_;
};

// `file` as named in a scene, relative to `base_dir` unless absolute ("" = the current
// folder).
std::string resolve_model_path(const std::string& base_dir, const std::string& file);
// The folder of a scene file's path, as ParseOptions::base_dir wants it ("" for a bare
// file name: the current folder).
std::string folder_of(const std::string& path);

}  // namespace rt
