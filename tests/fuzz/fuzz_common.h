// Invariants every parse result must satisfy, shared by the fuzz targets and the
// regression tests (tests/test_fuzz_regressions.cpp). A broken invariant throws
// rtfuzz::Broken; the fuzz targets turn that into abort(), which libFuzzer reports as a
// crash (saving the input), and the tests into a failed check.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "camera.h"
#include "model.h"
#include "model_readers.h"
#include "scene.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "texture.h"
#include "triangles.h"

namespace rtfuzz {

struct Broken {
    std::string what;
};

[[noreturn]] inline void fail(const char* what, const std::string& detail = {}) {
    throw Broken{std::string(what) + (detail.empty() ? "" : ": ") + detail};
}

// For the fuzz targets: run `f`, abort with the message if an invariant broke.
template <class F>
void or_abort(F f) {
    try {
        f();
    } catch (const Broken& b) {
        std::fprintf(stderr, "fuzz invariant broken: %s\n", b.what.c_str());
        std::fflush(stderr);
        std::abort();
    }
}

inline void check_number(double v, const char* what) {
    // The parser accepts magnitudes up to 1e15 only, so products in the tracer stay finite.
    if (!std::isfinite(v) || std::fabs(v) > 1e15) fail("number out of range in a parsed scene", what);
}
inline void check_vec(const rt::Vec3& v, const char* what) {
    check_number(v.x, what);
    check_number(v.y, what);
    check_number(v.z, what);
}
inline void check_material(const rt::Material& m) {
    check_number(m.reflection, "reflection");
    check_number(m.refraction, "refraction");
    check_number(m.scattering, "scattering");
    check_number(m.translusans, "translusans");
    check_number(m.refractive_index, "refractive_index");
    check_vec(m.colour, "colour");
    if (m.translusans < 0 || m.translusans > 1) fail("translusans not clamped to [0,1]");
    if (m.refractive_index < 1) fail("refractive_index below 1");
}

// Returns the number of objects in `o` (operands included); checks depth and shapes.
inline std::size_t check_object(const rt::Object& o, int csg_depth) {
    check_material(o.material);
    std::size_t count = 1;
    if (o.transform.set()) {
        const rt::Transform& t = o.transform.get();
        check_vec(t.rotation, "rotation");
        check_vec(t.scale, "scale");
        check_vec(t.translate, "translate");
        for (double f : {t.scale.x, t.scale.y, t.scale.z})
            if (!(f >= 1e-9 && f <= 1e9)) fail("a scale outside 1e-9 .. 1e9 accepted");
        if (std::holds_alternative<rt::Mesh>(o.shape) && (t.rotation != rt::Vec3{0, 0, 0} || t.scale != rt::Vec3{1, 1, 1}))
            fail("a mesh with a transform's rotation or scale (its own keys hold them)");
    }
    if (const auto* s = std::get_if<rt::Sphere>(&o.shape)) {
        check_vec(s->position, "sphere position");
        check_number(s->radius, "sphere radius");
        if (!(s->radius > 0)) fail("sphere with radius <= 0 accepted");
    } else if (const auto* t = std::get_if<rt::Tetrahedron>(&o.shape)) {
        for (const auto& v : t->v) check_vec(v, "tetrahedron corner");
    } else if (const auto* c = std::get_if<rt::Cylinder>(&o.shape)) {
        check_vec(c->end1, "cylinder end_1");
        check_vec(c->end2, "cylinder end_2");
        check_number(c->radius, "cylinder radius");
        if (!(c->radius > 0)) fail("cylinder with radius <= 0 accepted");
        if (c->end1 == c->end2) fail("cylinder with end_1 == end_2 accepted");
    } else if (const auto* tor = std::get_if<rt::Torus>(&o.shape)) {
        check_vec(tor->position, "torus position");
        check_vec(tor->direction, "torus direction");
        check_number(tor->major, "torus major");
        check_number(tor->minor, "torus minor");
        if (!(tor->minor > 0) || tor->major < 0) fail("torus with bad radii accepted");
        if (tor->direction == rt::Vec3{0, 0, 0}) fail("torus with direction 0 0 0 accepted");
    } else if (const auto* b = std::get_if<rt::Box>(&o.shape)) {
        check_vec(b->corner1, "box corner_1");
        check_vec(b->corner2, "box corner_2");
        if (b->corner1.x == b->corner2.x || b->corner1.y == b->corner2.y || b->corner1.z == b->corner2.z)
            fail("flat box accepted");
    } else if (const auto* cn = std::get_if<rt::Cone>(&o.shape)) {
        check_vec(cn->end1, "cone end_1");
        check_vec(cn->end2, "cone end_2");
        check_number(cn->radius1, "cone radius_1");
        check_number(cn->radius2, "cone radius_2");
        if (cn->radius1 < 0 || cn->radius2 < 0 || (cn->radius1 == 0 && cn->radius2 == 0))
            fail("cone with bad radii accepted");
        if (cn->end1 == cn->end2) fail("cone with end_1 == end_2 accepted");
    } else if (const auto* g = std::get_if<rt::Csg>(&o.shape)) {
        if (csg_depth >= rt::Limits::max_csg_depth) fail("CSG nested deeper than the limit accepted");
        if (g->operands.size() != 2) fail("CSG without exactly two operands accepted");
        if (g->type != rt::CsgType::Union && g->type != rt::CsgType::Intersection &&
            g->type != rt::CsgType::Difference)
            fail("CSG with a bad type accepted");
        for (const auto& op : g->operands) {
            if (std::holds_alternative<rt::Mesh>(op.shape)) fail("a mesh accepted as a CSG operand");
            count += check_object(op, csg_depth + 1);
        }
    } else if (const auto* m = std::get_if<rt::Mesh>(&o.shape)) {
        check_vec(m->position, "mesh position");
        check_vec(m->scale, "mesh scale");
        check_vec(m->rotation, "mesh rotation");
        if (m->scale.x == 0 || m->scale.y == 0 || m->scale.z == 0) fail("mesh with a scale of 0 accepted");
        if (m->smooth != 0 && m->smooth != 1) fail("mesh smooth other than 0 or 1 accepted");
        if (m->file.empty() || m->file.find_first_of("\"\n\r") != std::string::npos)
            fail("mesh file name empty or holding a quote or line end accepted");
    }
    return count;
}

inline void check_scene(const rt::Scene& s) {
    if (s.width < 1 || s.width > rt::Limits::max_picture_side || s.height < 1 ||
        s.height > rt::Limits::max_picture_side)
        fail("picture size outside 1..16384 accepted",
             std::to_string(s.width) + "x" + std::to_string(s.height));
    std::size_t objects = s.planes.size();
    for (const auto& o : s.objects) objects += check_object(o, 0);
    if (objects > rt::Limits::max_objects) fail("more objects than the limit accepted");
    for (const auto& p : s.planes) {
        for (const auto& v : p.point) check_vec(v, "plane point");
        check_material(p.material);
        check_material(p.material2);
    }
    for (const auto& l : s.lights) {
        check_vec(l.position, "light position");
        check_vec(l.colour, "light colour");
        check_number(l.size, "lamp size");
    }
    const rt::Camera& c = s.camera;
    check_vec(c.position, "camera position");
    check_vec(c.centre, "camera centre");
    check_vec(c.up, "camera up");
    check_number(c.angle_x, "angle_x");
    check_number(c.angle_y, "angle_y");
    if (!(c.angle_x > 0 && c.angle_x < 180 && c.angle_y > 0 && c.angle_y < 180))
        fail("camera angle outside (0, 180) accepted");
    if (const char* why = rt::camera_problem(c)) fail("invalid camera accepted", why);
}

// Every diagnostic points inside the text (or just past its end) and says something.
inline void check_diagnostics(std::string_view text, const rt::ParseResult& r) {
    // Byte length of each line, computed lazily only when there are diagnostics.
    if (r.diagnostics.empty()) return;
    // Lines end at LF, at CR LF (the CR counts in the line) and at a CR alone.
    std::vector<std::size_t> line_len(1, 0);
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] == '\n' || (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n')))
            line_len.push_back(0);
        else
            ++line_len.back();
    }
    int prev_line = 0, prev_col = 0;
    for (const auto& d : r.diagnostics) {
        const std::string where = std::to_string(d.line) + ":" + std::to_string(d.col) + " " + d.message;
        if (d.line < 1 || d.col < 1) fail("diagnostic without a 1-based position", where);
        if (std::size_t(d.line) > line_len.size()) fail("diagnostic line past the end of the text", where);
        if (std::size_t(d.col) > line_len[std::size_t(d.line) - 1] + 1)
            fail("diagnostic column past the end of its line", where);
        if (d.message.empty()) fail("diagnostic without a message", where);
        if (d.line < prev_line || (d.line == prev_line && d.col < prev_col))
            fail("diagnostics not in file order", where);
        prev_line = d.line;
        prev_col = d.col;
    }
}

// The parser's promises for any input: positioned diagnostics; a scene without
// errors within the limits; the same verdict with a lower error cap.
inline bool same_loc(const rt::SourceLoc& a, const rt::SourceLoc& b) { return a.line == b.line && a.col == b.col; }
inline bool same_locs(const rt::Object& a, const rt::Object& b) {
    if (!same_loc(a.loc, b.loc)) return false;
    if (const auto* ca = std::get_if<rt::Csg>(&a.shape)) {
        const auto* cb = std::get_if<rt::Csg>(&b.shape);
        if (!cb || ca->operands.size() != cb->operands.size()) return false;
        for (std::size_t i = 0; i < ca->operands.size(); ++i)
            if (!same_locs(ca->operands[i], cb->operands[i])) return false;
    }
    return true;
}

// Reading in pieces on threads (forced even on a small text) gives what reading in
// one go gave: the same scene, item locations and diagnostics.
inline void check_pieces(std::string_view text, const rt::ParseResult& one, rt::ParseOptions o, int threads) {
    o.threads = threads;
    o.min_piece_bytes = 1;
    const rt::ParseResult many = rt::parse_scene(text, o);
    if (many.diagnostics.size() != one.diagnostics.size()) fail("pieces: another number of diagnostics");
    for (std::size_t i = 0; i < one.diagnostics.size(); ++i) {
        const rt::Diagnostic &a = one.diagnostics[i], &b = many.diagnostics[i];
        if (a.message != b.message || a.line != b.line || a.col != b.col || a.severity != b.severity)
            fail("pieces: another diagnostic", rt::format_diagnostic("one go", a) + " / " +
                                                  rt::format_diagnostic("pieces", b));
    }
    if (!(many.scene == one.scene) || many.ok() != one.ok()) fail("pieces: another scene");
    for (std::size_t i = 0; i < one.scene.objects.size(); ++i)
        if (!same_locs(one.scene.objects[i], many.scene.objects[i])) fail("pieces: another object location");
    for (std::size_t i = 0; i < one.scene.planes.size(); ++i)
        if (!same_loc(one.scene.planes[i].loc, many.scene.planes[i].loc)) fail("pieces: another plane location");
    for (std::size_t i = 0; i < one.scene.lights.size(); ++i)
        if (!same_loc(one.scene.lights[i].loc, many.scene.lights[i].loc)) fail("pieces: another light location");
    if (!same_loc(one.scene.camera_loc, many.scene.camera_loc)) fail("pieces: another camera location");
}

inline void check_parse(std::string_view text, int low_max_errors) {
    rt::ParseOptions one_go;
    one_go.threads = 1;
    one_go.read_models = false;  // the text alone (the model readers have targets of their own)
    one_go.read_textures = false;
    const rt::ParseResult r = rt::parse_scene(text, one_go);
    check_diagnostics(text, r);
    if (r.ok()) check_scene(r.scene);
    check_pieces(text, r, one_go, 3);
    rt::ParseOptions low = one_go;
    low.max_errors = low_max_errors;
    const rt::ParseResult r1 = rt::parse_scene(text, low);
    check_diagnostics(text, r1);
    if (r1.ok() != r.ok()) fail("max_errors changed whether the scene is ok");
    check_pieces(text, r1, low, 2);
}

// parse -> write -> parse gives an equal scene, and writing it again the same text.
inline void check_roundtrip(std::string_view text) {
    rt::ParseOptions o;
    o.read_models = false;
    o.read_textures = false;
    const rt::ParseResult r = rt::parse_scene(text, o);
    if (!r.ok()) return;
    const std::string text2 = rt::write_scene(r.scene);
    const rt::ParseResult r2 = rt::parse_scene(text2, o);
    if (!r2.ok()) {
        std::string why;
        for (const auto& d : r2.diagnostics) why += "\n  " + rt::format_diagnostic("written", d);
        fail("the written scene does not parse", why + "\n--- written text ---\n" + text2);
    }
    if (!(r2.scene == r.scene)) fail("parse(write(scene)) != scene", "\n--- written text ---\n" + text2);
    const std::string text3 = rt::write_scene(r2.scene);
    if (text3 != text2)
        fail("write(parse(text2)) != text2", "\n--- text2 ---\n" + text2 + "--- text3 ---\n" + text3);
}

// A model reader's promises for any bytes: an error with a message, or triangles within
// the limits whose indices name vertices there are, at finite coordinates; and the
// triangles' BVH builds and answers rays without going outside its arrays.
inline void check_model(std::string_view bytes, bool (*read)(std::string_view, rt::MeshData&, rt::ModelError&)) {
    rt::MeshData m;
    rt::ModelError e;
    if (!read(bytes, m, e)) {
        if (e.message.empty()) fail("a model refused without a message");
        if (e.line < 0) fail("a model error at a negative line");
        return;
    }
    if (m.triangles.empty() || m.triangles.size() % 3 != 0 || m.positions.size() % 3 != 0)
        fail("a model without whole triangles or vertices accepted");
    if (!m.normals.empty() && m.normals.size() != m.positions.size()) fail("normals not one per vertex");
    if (!m.colours.empty() && m.colours.size() != m.positions.size()) fail("colours not one per vertex");
    if (!m.corner_uv.empty() && m.corner_uv.size() != 2 * m.triangles.size()) fail("texture coordinates not one per corner");
    for (float x : m.corner_uv)
        if (!std::isfinite(x)) fail("a texture coordinate not finite");
    for (float x : m.colours)
        if (!(x >= 0 && x <= 1)) fail("a vertex colour outside 0..1");
    if (!m.triangle_material.empty() && m.triangle_material.size() != m.triangle_count())
        fail("materials not one per triangle");
    if (m.triangle_count() > rt::ModelLimits::max_triangles || m.vertex_count() > rt::ModelLimits::max_vertices)
        fail("a model over the limits accepted");
    for (std::uint32_t v : m.triangles)
        if (v >= m.vertex_count()) fail("a triangle naming a vertex beyond the last", std::to_string(v));
    for (float x : m.positions)
        if (!(std::fabs(x) <= rt::ModelLimits::max_coordinate)) fail("a coordinate out of range accepted");
    const rt::TriangleAccel acc = rt::TriangleAccel::build(m, 1);
    const rt::Aabb b = rt::MeshModel("fuzz", m).bounds();
    const rt::Vec3 c = (b.lo + b.hi) * 0.5;
    for (int k = 0; k < 8; ++k) {
        const rt::Vec3 d{k & 1 ? 1.0 : -1.0, k & 2 ? 0.5 : -0.7, k & 4 ? 0.3 : -1.1};
        rt::TriHit h;
        double t;
        if (acc.nearest(rt::TriRay::make(c - d * 1e3, d), 0, HUGE_VAL, h) && h.slot >= acc.ids.size())
            fail("a hit outside the triangles");
        (void)acc.any(rt::TriRay::make(c, d), 0, HUGE_VAL, t);
    }
}

// The texture decoder's promises for any bytes: an error with a message, or an image
// within the limits whose texels are linear values in 0..1 and whose samples are too.
inline void check_texture(std::string_view bytes) {
    // A few bytes can claim an image of a quarter million pixels or more (a zlib stream of
    // zeros): decoding it takes longer than the fuzzer's time limit, so such headers
    // are only checked for being refused over the limits (the unit tests decode big
    // images whole).
    long long w = 0, h = 0;
    if (rt::image_size(bytes, w, h) && std::uint64_t(w) * std::uint64_t(h) > (1u << 18)) {
        if (w > rt::TextureLimits::max_side || h > rt::TextureLimits::max_side ||
            std::uint64_t(w) * std::uint64_t(h) > rt::TextureLimits::max_texels) {
            std::string error;
            if (rt::decode_texture(bytes, error)) fail("an image over the limits accepted");
        }
        return;
    }
    std::string error;
    const std::shared_ptr<rt::Texture> t = rt::decode_texture(bytes, error);
    if (!t) {
        if (error.empty()) fail("an image refused without a message");
        return;
    }
    if (t->width() < 1 || t->height() < 1 || t->width() > rt::TextureLimits::max_side ||
        t->height() > rt::TextureLimits::max_side ||
        std::uint64_t(t->width()) * std::uint64_t(t->height()) > rt::TextureLimits::max_texels)
        fail("an image over the limits accepted");
    auto in_range = [](const rt::Colour& c) {
        return c.x >= 0 && c.x <= 1 && c.y >= 0 && c.y <= 1 && c.z >= 0 && c.z <= 1;
    };
    for (long k = 0; k < 64; ++k)
        if (!in_range(t->texel(k * 7919, k * 104729))) fail("a texel outside 0..1");
    for (double u : {-1e300, -2.5, 0.0, 0.3, 1.0, 1e15, double(NAN)})
        if (!in_range(t->sample(u, 1 - u))) fail("a sample outside 0..1");
}

// The MTL reader's promises: an error with a message at a line, or materials within
// the ranges the scene format keeps (as a material block's clamps would leave them).
inline void check_mtl(std::string_view bytes) {
    std::vector<rt::MtlMaterial> out;
    rt::ModelError e;
    if (!rt::read_mtl(bytes, out, e)) {
        if (e.message.empty()) fail("an MTL refused without a message");
        if (e.line < 1) fail("an MTL error without its line");
        return;
    }
    if (out.size() > rt::MeshData::max_materials) fail("too many MTL materials accepted");
    for (const rt::MtlMaterial& m : out) {
        check_material(m.material);
        if (!(m.material.specular >= 0 && m.material.specular <= 1)) fail("specular outside 0..1");
        if (!(m.material.shininess >= 1 && m.material.shininess <= 10000)) fail("shininess outside 1..10000");
        if (!(m.material.refraction >= 0 && m.material.refraction <= 1)) fail("refraction outside 0..1");
        if (!(m.material.refractive_index >= 1)) fail("refractive_index below 1");
        if (m.texture.size() > 4096) fail("a texture name too long");
        for (char c : m.texture)
            if (static_cast<unsigned char>(c) < 0x20 || c == '\\') fail("a control character or backslash in a texture name");
    }
}

}  // namespace rtfuzz
