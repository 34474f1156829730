// Wavefront OBJ through tinyobjloader's streaming interface: it splits the lines and
// reads the numbers; the callbacks here check each value as it comes (with the line it
// is on, found from how far the reader has got in the bytes), resolve relative
// indices, and keep polygons of more than three corners to be cut once all vertices
// are known (a face may name vertices defined after it).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <istream>
#include <streambuf>
#include <string>
#include <unordered_map>

#include "model_readers.h"

namespace rt {

namespace {

// The file's bytes as a stream, without a copy, telling how far the reader has got.
class ByteStream : public std::streambuf {
public:
    explicit ByteStream(std::string_view s) {
        char* p = const_cast<char*>(s.data());  // read only: the stream never writes
        setg(p, p, p + s.size());
    }
    std::size_t pos() const { return std::size_t(gptr() - eback()); }
};

bool line_end(char c) { return c == '\n' || c == '\r'; }

// A number as OBJ writes it: [+-] digits [. digits] [e [+-] digits], or starting with '.'.
bool number_word(std::string_view w) {
    std::size_t i = 0;
    if (i < w.size() && (w[i] == '+' || w[i] == '-')) ++i;
    std::size_t digits = 0;
    while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i]))) ++i, ++digits;
    if (i < w.size() && w[i] == '.') {
        ++i;
        while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i]))) ++i, ++digits;
    }
    if (digits == 0) return false;
    if (i < w.size() && (w[i] == 'e' || w[i] == 'E')) {
        ++i;
        if (i < w.size() && (w[i] == '+' || w[i] == '-')) ++i;
        std::size_t e = 0;
        while (i < w.size() && std::isdigit(static_cast<unsigned char>(w[i]))) ++i, ++e;
        if (e == 0) return false;
    }
    return i == w.size();
}

struct ObjReader {
    ObjReader(std::string_view t, ByteStream* s, MeshData& o, ModelError& e) : text(t), stream(s), out(o), error(e) {}
    std::string_view text;
    ByteStream* stream;
    MeshData& out;
    ModelError& error;
    bool failed = false;
    std::vector<float> normals;                 // the file's vn, in order
    std::vector<std::int32_t> corner_normal;    // per triangle corner: its vn index, or -1
    std::vector<std::uint32_t> polygons;        // n, then n vertex indices, per polygon of n > 3
    std::vector<std::int32_t> polygon_normals;  // the same corners' vn indices
    std::vector<float> uvs;                     // the file's vt (u v), in order
    std::vector<std::int32_t> corner_uv;        // per triangle corner: its vt index, or -1
    std::vector<std::int32_t> polygon_uvs;      // per polygon corner: its vt index, or -1
    std::vector<std::uint16_t> polygon_material;  // per polygon of n > 3: its usemtl's index
    std::uint16_t material = MeshData::kNoMaterial;  // the last usemtl's index in out.material_names
    bool any_uv = false;
    std::size_t triangles = 0;                  // what the faces so far will be cut into
    std::int64_t max_index = -1;                // the largest positive vertex index (0-based)

    // The line the reader has just read, without its end.
    std::string_view current_line() const {
        std::size_t end = stream->pos();
        if (end > 0 && text[end - 1] == '\n') --end;
        if (end > 0 && text[end - 1] == '\r') --end;
        std::size_t begin = end;
        while (begin > 0 && !line_end(text[begin - 1])) --begin;
        return text.substr(begin, end - begin);
    }
    long line_number(std::size_t offset) const {
        long line = 1;
        for (std::size_t i = 0; i < offset && i < text.size(); ++i)
            line += text[i] == '\n' || (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n'));
        return line;
    }
    void fail(std::string message) {
        if (failed) return;
        failed = true;
        const std::string_view line = current_line();
        error.line = line_number(std::size_t(line.data() - text.data()));
        error.message = std::move(message);
    }

    void vertex(float x, float y, float z) {
        if (failed) return;
        if (out.positions.size() / 3 >= ModelLimits::max_vertices)
            return fail("too many vertices (limit " + std::to_string(ModelLimits::max_vertices) + ")");
        const float c[3] = {x, y, z};
        // tinyobjloader reads a word that is no number (nan, inf, a missing one) as 0.
        if (x == 0 || y == 0 || z == 0) check_vertex_words();
        for (float v : c)
            if (!(std::fabs(v) <= ModelLimits::max_coordinate))
                return fail("vertex coordinate out of range (magnitude at most 1e15)");
        out.positions.insert(out.positions.end(), c, c + 3);
    }
    void check_vertex_words() {
        std::string_view line = current_line();
        std::size_t i = line.find('v') + 1, count = 0;
        while (count < 3) {
            while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
            if (i >= line.size()) break;
            std::size_t j = i;
            while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
            const std::string_view w = line.substr(i, j - i);
            if (!number_word(w)) return fail("vertex coordinate '" + std::string(w.substr(0, 40)) + "' is not a number");
            ++count;
            i = j;
        }
        if (count < 3) fail("a vertex needs 3 coordinates, this one has " + std::to_string(count));
    }

    void normal(float x, float y, float z) {
        if (failed) return;
        if (normals.size() / 3 >= ModelLimits::max_vertices)
            return fail("too many normals (limit " + std::to_string(ModelLimits::max_vertices) + ")");
        normals.push_back(x), normals.push_back(y), normals.push_back(z);
    }

    void texcoord(float u, float v) {
        if (failed) return;
        if (uvs.size() / 2 >= ModelLimits::max_vertices)
            return fail("too many texture coordinates (limit " + std::to_string(ModelLimits::max_vertices) + ")");
        uvs.push_back(std::isfinite(u) ? u : 0.0f), uvs.push_back(std::isfinite(v) ? v : 0.0f);
    }

    // `usemtl NAME`: the faces after it are of that material (names are numbered as
    // first met; read_model finds them in the MTL files).
    void use_material(const char* name) {
        if (failed) return;
        const std::string n = trimmed(name);
        std::vector<std::string>& names = out.material_names;
        auto it = std::find(names.begin(), names.end(), n);
        if (it == names.end()) {
            if (names.size() >= MeshData::max_materials)
                return fail("too many materials (limit " + std::to_string(MeshData::max_materials) + ")");
            it = names.insert(names.end(), n);
        }
        material = std::uint16_t(it - names.begin());
    }
    static std::string trimmed(std::string_view s) {
        while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r' || s.back() == '\n'))
            s.remove_suffix(1);
        while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
        return std::string(s.substr(0, 4096));
    }

    // A face's vertex index (1-based, or negative: back from the last vertex) made 0-based.
    bool resolve(int index, std::size_t count, const char* what, std::int64_t& out_index) {
        if (index == 0) {
            fail(std::string(what) + " index 0 (OBJ counts from 1) or not a number");
            return false;
        }
        const std::int64_t i = index > 0 ? std::int64_t(index) - 1 : std::int64_t(count) + index;
        if (i < 0) {
            fail(std::string(what) + " index " + std::to_string(index) + " out of range (" + std::to_string(count) +
                 " " + what + (count == 1 ? "" : "s") + " before it)");
            return false;
        }
        out_index = i;
        return true;
    }

    void face(const tinyobj::index_t* idx, int n) {
        if (failed) return;
        if (n < 3) return fail("a face needs at least 3 vertices, this one has " + std::to_string(n));
        if (std::size_t(n) > ModelLimits::max_polygon)
            return fail("a face of " + std::to_string(n) + " vertices (limit " + std::to_string(ModelLimits::max_polygon) + ")");
        triangles += std::size_t(n) - 2;
        if (triangles > ModelLimits::max_triangles)
            return fail("too many triangles (limit " + std::to_string(ModelLimits::max_triangles) + ")");
        // tinyobjloader reads indices with atoi, which wraps numbers of 10 digits or more.
        int digits = 0;
        for (char c : current_line())
            if ((digits = c >= '0' && c <= '9' ? digits + 1 : 0) > 9) return fail("a face index is out of range");
        std::uint32_t v[3];
        std::int32_t vn[3], vt[3];
        const bool polygon = n > 3;
        if (polygon) polygons.push_back(std::uint32_t(n)), polygon_material.push_back(material);
        for (int k = 0; k < n; ++k) {
            std::int64_t vi, ni = -1, ti = -1;
            if (!resolve(idx[k].vertex_index, out.positions.size() / 3, "vertex", vi)) return;
            if (idx[k].normal_index != 0 && !resolve(idx[k].normal_index, normals.size() / 3, "normal", ni)) return;
            if (idx[k].texcoord_index != 0) {
                if (!resolve(idx[k].texcoord_index, uvs.size() / 2, "texture coordinate", ti)) return;
                if (ti >= std::int64_t(uvs.size() / 2))
                    return fail("texture coordinate index " + std::to_string(idx[k].texcoord_index) + " out of range (" +
                                std::to_string(uvs.size() / 2) + " before it)");
                any_uv = true;
            }
            max_index = std::max(max_index, vi);
            if (vi >= std::int64_t(ModelLimits::max_vertices))
                return fail("vertex index " + std::to_string(idx[k].vertex_index) + " out of range");
            if (polygon) {
                polygons.push_back(std::uint32_t(vi));
                polygon_normals.push_back(std::int32_t(ni));
                polygon_uvs.push_back(std::int32_t(ti));
            } else {
                v[k] = std::uint32_t(vi), vn[k] = std::int32_t(ni), vt[k] = std::int32_t(ti);
            }
        }
        if (!polygon) {
            out.triangles.insert(out.triangles.end(), v, v + 3);
            corner_normal.insert(corner_normal.end(), vn, vn + 3);
            corner_uv.insert(corner_uv.end(), vt, vt + 3);
            out.triangle_material.push_back(material);
        }
    }

    bool finish();
    void cut_polygons();
    void split_by_normals();
    bool report_index_range();
};

// The first face naming a vertex beyond the last one, found again in the text (the
// reader only kept the largest index).
bool ObjReader::report_index_range() {
    const std::size_t count = out.positions.size() / 3;
    std::size_t line_start = 0;
    long line = 1;
    for (std::size_t i = 0; i <= text.size(); ++i) {
        if (i < text.size() && !line_end(text[i])) continue;
        std::string_view l = text.substr(line_start, i - line_start);
        l.remove_prefix(std::min(l.find_first_not_of(" \t"), l.size()));
        if (l.size() > 1 && l[0] == 'f' && (l[1] == ' ' || l[1] == '\t')) {
            for (std::size_t p = 1; p < l.size();) {
                while (p < l.size() && (l[p] == ' ' || l[p] == '\t')) ++p;
                const long index = std::atol(std::string(l.substr(p, 20)).c_str());
                if (index > 0 && std::size_t(index) > count) {
                    error.line = line;
                    error.message = "face index " + std::to_string(index) + " out of range (" + std::to_string(count) +
                                    (count == 1 ? " vertex)" : " vertices)");
                    return false;
                }
                while (p < l.size() && l[p] != ' ' && l[p] != '\t') ++p;
            }
        }
        if (i < text.size() && text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
        line += 1;
        line_start = i + 1;
    }
    error.message = "a face index is out of range (" + std::to_string(count) + " vertices)";
    return false;
}

void ObjReader::cut_polygons() {
    std::vector<std::uint32_t> cut;
    std::size_t corner = 0, polygon = 0;
    for (std::size_t p = 0; p < polygons.size();) {
        const std::size_t n = polygons[p++];
        cut.clear();
        triangulate(out.positions, &polygons[p], n, cut);
        out.triangles.insert(out.triangles.end(), cut.begin(), cut.end());
        // Each triangle's corners take the normal and texture indices of the polygon
        // corners they are, and the polygon's material.
        for (std::uint32_t v : cut) {
            std::size_t k = 0;
            while (k < n && polygons[p + k] != v) ++k;
            corner_normal.push_back(k < n ? polygon_normals[corner + k] : -1);
            corner_uv.push_back(k < n ? polygon_uvs[corner + k] : -1);
        }
        out.triangle_material.insert(out.triangle_material.end(), cut.size() / 3, polygon_material[polygon]);
        p += n;
        corner += n;
        ++polygon;
    }
}

// A vertex met with different normals is split, so that every vertex has one normal.
void ObjReader::split_by_normals() {
    std::unordered_map<std::uint64_t, std::uint32_t> made;
    made.reserve(out.triangles.size() / 2);
    std::vector<float> positions;
    for (std::size_t c = 0; c < out.triangles.size(); ++c) {
        const std::uint64_t key = std::uint64_t(out.triangles[c]) << 32 | std::uint32_t(corner_normal[c]);
        auto [it, fresh] = made.emplace(key, std::uint32_t(positions.size() / 3));
        if (fresh) {
            const float* p = &out.positions[3 * std::size_t(out.triangles[c])];
            const float* n = &normals[3 * std::size_t(corner_normal[c])];
            positions.insert(positions.end(), p, p + 3);
            out.normals.insert(out.normals.end(), n, n + 3);
        }
        out.triangles[c] = it->second;
    }
    out.positions.swap(positions);
}

bool ObjReader::finish() {
    if (failed) return false;
    if (max_index >= std::int64_t(out.positions.size() / 3)) return report_index_range();
    cut_polygons();
    if (out.triangles.size() / 3 > ModelLimits::max_triangles) {
        error.message = "too many triangles (limit " + std::to_string(ModelLimits::max_triangles) + ")";
        return false;
    }
    // The file's normals count only if every corner has one, and all are finite.
    bool all = !corner_normal.empty();
    for (std::int32_t n : corner_normal) all = all && n >= 0 && std::size_t(n) < normals.size() / 3;
    for (float x : normals) all = all && std::isfinite(x);
    if (all) split_by_normals();
    if (any_uv) {
        out.corner_uv.assign(2 * corner_uv.size(), 0.0f);
        for (std::size_t c = 0; c < corner_uv.size(); ++c)
            if (corner_uv[c] >= 0) {
                out.corner_uv[2 * c] = uvs[2 * std::size_t(corner_uv[c])];
                out.corner_uv[2 * c + 1] = uvs[2 * std::size_t(corner_uv[c]) + 1];
            }
    }
    if (out.material_names.empty()) out.triangle_material.clear();
    return check_mesh(out, error);
}

}  // namespace

bool read_obj(std::string_view text, MeshData& out, ModelError& error) {
    ByteStream bytes(text);
    std::istream in(&bytes);
    ObjReader r(text, &bytes, out, error);
    tinyobj::callback_t cb;
    cb.vertex_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z, tinyobj::real_t) {
        static_cast<ObjReader*>(u)->vertex(x, y, z);
    };
    cb.normal_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t z) {
        static_cast<ObjReader*>(u)->normal(x, y, z);
    };
    cb.index_cb = [](void* u, tinyobj::index_t* idx, int n) { static_cast<ObjReader*>(u)->face(idx, n); };
    cb.texcoord_cb = [](void* u, tinyobj::real_t x, tinyobj::real_t y, tinyobj::real_t) {
        static_cast<ObjReader*>(u)->texcoord(x, y);
    };
    cb.usemtl_cb = [](void* u, const char* name, int) { static_cast<ObjReader*>(u)->use_material(name); };
    // The `mtllib` names only: read_model reads the files (the bytes here may come from
    // no file at all).
    struct Libraries : tinyobj::MaterialReader {
        std::vector<std::string>* names;
        explicit Libraries(std::vector<std::string>* n) : names(n) {}
        bool operator()(const std::string& name, std::vector<tinyobj::material_t>*, std::map<std::string, int>*,
                        std::string*, std::string*) override {
            if (names->size() < 64 && std::find(names->begin(), names->end(), name) == names->end())
                names->push_back(name.substr(0, 4096));
            return false;
        }
    } libraries(&out.material_libs);
    std::string warn, err;
    tinyobj::LoadObjWithCallback(in, cb, &r, &libraries, &warn, &err);
    return r.finish();
}

}  // namespace rt
