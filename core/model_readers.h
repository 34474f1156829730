// The model file formats, each read from the whole file's bytes into MeshData (see
// model.h for the limits they keep). Internal to the model reading; the fuzz targets
// call them directly.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "model.h"

namespace rt {

// Wavefront OBJ, through tinyobjloader: vertices, normals (used when every face corner
// has one), faces of any number of vertices, negative (relative) indices.
bool read_obj(std::string_view text, MeshData& out, ModelError& error);
// Stanford PLY, ASCII or binary of either byte order: the vertex element's x, y, z
// (and nx, ny, nz) and the face element's vertex_indices list; other elements and
// properties are skipped.
bool read_ply(std::string_view bytes, MeshData& out, ModelError& error);

// One material of a Wavefront MTL file, mapped to the scene's Material
// (docs/scene-format.md, "Models with their materials"); `texture` is map_Kd as written
// (backslashes made slashes), `texture_line` its line.
struct MtlMaterial {
    std::string name;
    Material material;
    std::string texture;
    long texture_line = 0;
};
// Wavefront MTL: newmtl, Kd, Ks, Ns, d, Tr, Ni and map_Kd (other statements are
// passed over). False with `error` set (and its line) at a malformed value.
bool read_mtl(std::string_view text, std::vector<MtlMaterial>& out, ModelError& error);

// Cuts the polygon of `n` vertex indices into n - 2 triangles appended to `out`: by
// ear clipping in the plane the polygon faces (so concave polygons come out right),
// falling back to a fan where no ear is found (a self-crossing or degenerate polygon).
void triangulate(const std::vector<float>& positions, const std::uint32_t* poly, std::size_t n,
                 std::vector<std::uint32_t>& out);

// Checks the finished data: at least one triangle, no more than the limits, every
// vertex a finite number within range. False with `error` set otherwise.
bool check_mesh(const MeshData& m, ModelError& error);

}  // namespace rt
