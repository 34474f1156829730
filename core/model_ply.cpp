// Stanford PLY, the project's own reader: a header of elements and their properties,
// then the elements' records in ASCII or binary (either byte order). Every count in
// the header is checked against the bytes that follow before anything is allocated
// (a record takes at least one byte each property in binary, two in ASCII), so a
// header claiming 10^12 faces is refused at once.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "model_readers.h"
#include "texture.h"

namespace rt {

namespace {

enum class Type : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
enum class Format { Ascii, Little, Big };

struct Property {
    std::string name;
    Type type = Type::Float32;
    bool list = false;
    Type count_type = Type::UInt8;
};

struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Property> props;
};

struct Header {
    Format format = Format::Ascii;
    std::vector<Element> elements;
    std::size_t body = 0;  // offset of the first record
    long body_line = 1;    // its line (ASCII)
};

constexpr std::size_t kMaxHeader = 1 << 20;

int size_of(Type t) {
    static constexpr int sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[int(t)];
}

bool type_named(std::string_view s, Type& t) {
    static constexpr std::pair<std::string_view, Type> names[] = {
        {"char", Type::Int8},     {"int8", Type::Int8},     {"uchar", Type::UInt8},  {"uint8", Type::UInt8},
        {"short", Type::Int16},   {"int16", Type::Int16},   {"ushort", Type::UInt16}, {"uint16", Type::UInt16},
        {"int", Type::Int32},     {"int32", Type::Int32},   {"uint", Type::UInt32},  {"uint32", Type::UInt32},
        {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64}};
    for (const auto& [name, type] : names)
        if (name == s) return t = type, true;
    return false;
}

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
        if (j > i) out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

std::string shown(std::string_view s) {
    std::string out(s.substr(0, 40));
    return "'" + out + (s.size() > 40 ? "...'" : "'");
}

// One header line's meaning. False with error.message set.
// A face's count or index as the file gives it, for a message: a value past the
// 64-bit integers (converting it would be undefined behaviour) in floating-point
// notation.
std::string index_text(double v) {
    if (std::isnan(v)) return "nan";
    if (std::fabs(v) < 9e18) return std::to_string(std::int64_t(v));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

bool header_line(const std::vector<std::string_view>& w, Header& h, bool& format_seen, ModelError& error) {
    if (w.empty() || w[0] == "comment" || w[0] == "obj_info") return true;
    if (w[0] == "format") {
        if (w.size() < 2 || (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian")) {
            error.message = "unknown PLY format (expected ascii, binary_little_endian or binary_big_endian)";
            return false;
        }
        h.format = w[1] == "ascii" ? Format::Ascii : w[1] == "binary_little_endian" ? Format::Little : Format::Big;
        format_seen = true;
        return true;
    }
    if (w[0] == "element") {
        Element e;
        const char* end = w.size() == 3 ? w[2].data() + w[2].size() : nullptr;
        if (!end || std::from_chars(w[2].data(), end, e.count).ptr != end) {
            error.message = "expected 'element NAME COUNT'";
            return false;
        }
        e.name = std::string(w[1]);
        h.elements.push_back(std::move(e));
        return true;
    }
    if (w[0] == "property") {
        if (h.elements.empty()) {
            error.message = "a property before any element";
            return false;
        }
        Property p;
        const bool list = w.size() == 5 && w[1] == "list";
        const bool ok = list ? type_named(w[2], p.count_type) && type_named(w[3], p.type) && p.count_type != Type::Float32 &&
                                   p.count_type != Type::Float64
                             : w.size() == 3 && type_named(w[1], p.type);
        if (!ok) {
            error.message = "expected 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME' with known types";
            return false;
        }
        p.list = list;
        p.name = std::string(w.back());
        h.elements.back().props.push_back(std::move(p));
        return true;
    }
    // Other lines (some writers add free text such as "Created by ...") say nothing
    // about the data: passed over, as comments are.
    return true;
}

bool read_header(std::string_view bytes, Header& h, ModelError& error) {
    if (bytes.substr(0, 4) != "ply\n" && bytes.substr(0, 5) != "ply\r\n") {
        error.message = "not a PLY file (it does not start with 'ply')";
        return false;
    }
    bool format_seen = false;
    std::size_t pos = bytes.find('\n') + 1;
    long line = 2;
    for (;; ++line) {
        const std::size_t nl = bytes.find('\n', pos);
        if (nl == std::string_view::npos || nl > kMaxHeader) {
            error.message = "the header has no 'end_header' line (in its first MB)";
            return false;
        }
        std::string_view l = bytes.substr(pos, nl - pos);
        if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
        pos = nl + 1;
        if (l == "end_header") break;
        if (l.find('\0') != std::string_view::npos || !header_line(words(l), h, format_seen, error)) {
            if (error.message.empty()) error.message = "a NUL byte in the header";
            error.line = line;
            return false;
        }
    }
    if (!format_seen) {
        error.message = "the header has no 'format' line";
        return false;
    }
    h.body = pos;
    h.body_line = line + 1;
    return true;
}

// The records of the body, value by value, in ASCII or binary.
class Body {
public:
    Body(std::string_view bytes, const Header& h) : b_(bytes), pos_(h.body), line_(h.body_line), format_(h.format) {}
    std::size_t left() const { return b_.size() - pos_; }
    long line() const { return line_; }
    bool ascii() const { return format_ == Format::Ascii; }
    bool big_endian() const { return format_ == Format::Big; }
    // The bytes not read yet, for the fast paths that read whole records at once, and
    // the step past what they read.
    const unsigned char* here() const { return reinterpret_cast<const unsigned char*>(b_.data() + pos_); }
    void skip(std::size_t n) { pos_ += n; }

    // The next value, read as `t`. False at the end of the data or on a word that is no number.
    bool value(Type t, double& v, std::string& bad) {
        if (!ascii()) return binary(t, v);
        std::string_view w;
        if (!word(w)) return false;
        const char* end = w.data() + w.size();
        if (std::from_chars(w.data(), end, v).ptr != end) {
            bad = shown(w);
            return false;
        }
        return true;
    }

private:
    bool word(std::string_view& w) {
        while (pos_ < b_.size() && (b_[pos_] == ' ' || b_[pos_] == '\t' || b_[pos_] == '\n' || b_[pos_] == '\r')) {
            if (b_[pos_] == '\n') ++line_;
            ++pos_;
        }
        const std::size_t start = pos_;
        while (pos_ < b_.size() && b_[pos_] != ' ' && b_[pos_] != '\t' && b_[pos_] != '\n' && b_[pos_] != '\r') ++pos_;
        w = b_.substr(start, pos_ - start);
        return !w.empty();
    }
    template <class T>
    T raw() {
        unsigned char c[sizeof(T)];
        std::memcpy(c, b_.data() + pos_, sizeof c);
        pos_ += sizeof c;
        if (format_ == Format::Big) std::reverse(c, c + sizeof c);
        T v;
        std::memcpy(&v, c, sizeof v);
        return v;
    }
    bool binary(Type t, double& v) {
        if (left() < std::size_t(size_of(t))) return false;
        switch (t) {
            case Type::Int8: v = raw<std::int8_t>(); break;
            case Type::UInt8: v = raw<std::uint8_t>(); break;
            case Type::Int16: v = raw<std::int16_t>(); break;
            case Type::UInt16: v = raw<std::uint16_t>(); break;
            case Type::Int32: v = raw<std::int32_t>(); break;
            case Type::UInt32: v = raw<std::uint32_t>(); break;
            case Type::Float32: v = raw<float>(); break;
            case Type::Float64: v = raw<double>(); break;
        }
        return true;
    }

    std::string_view b_;
    std::size_t pos_;
    long line_;
    Format format_;
};

// A 4-byte value of the file's byte order at p.
template <class T>
inline T load4(const unsigned char* p, bool big) {
    static_assert(sizeof(T) == 4, "four bytes");
    std::uint32_t u;
    std::memcpy(&u, p, 4);
    if (big) u = __builtin_bswap32(u);
    T v;
    std::memcpy(&v, &u, 4);
    return v;
}

struct PlyReader {
    const Header& h;
    Body body;
    MeshData& out;
    ModelError& error;
    std::vector<std::uint32_t> poly;

    bool fail(std::string message, std::uint64_t record, const char* what) {
        if (body.ascii()) {
            error.line = body.line();
            error.message = std::move(message);
        } else {
            error.message = std::string(what) + " " + std::to_string(record + 1) + ": " + message;
        }
        return false;
    }
    bool short_of_data(std::uint64_t record, const char* what, const std::string& bad) {
        if (!bad.empty()) return fail(bad + " is not a number", record, what);
        error.message = "the file ends in " + std::string(what) + " " + std::to_string(record + 1) +
                        " (truncated, or the header's counts are wrong)";
        return false;
    }

    // Whether `count` records of e can be in the bytes left: at least one byte a value
    // in binary, two in ASCII (a digit and a space), lists counting their count only.
    bool fits(const Element& e) {
        std::uint64_t least = 0;
        for (const Property& p : e.props) least += body.ascii() ? 2 : std::uint64_t(size_of(p.list ? p.count_type : p.type));
        // (In ASCII the last value needs no space after it.)
        const std::uint64_t most = least == 0 ? e.count : (body.left() + (body.ascii() ? 1 : 0)) / least;
        if (e.count <= most) return true;
        error.message = "the header claims " + std::to_string(e.count) + " " + e.name + " records, but the " +
                        std::to_string(body.left()) + " bytes after it hold at most " + std::to_string(most);
        return false;
    }

    bool skip_element(const Element& e) {
        if (e.props.empty()) return true;  // nothing to read, however many it claims
        std::string bad;
        double v;
        for (std::uint64_t r = 0; r < e.count; ++r)
            for (const Property& p : e.props) {
                double n = 1;
                if (p.list && (!body.value(p.count_type, n, bad) || !(n >= 0 && n <= 1e9 && n == std::floor(n))))
                    return short_of_data(r, e.name.c_str(), bad);
                for (double k = 0; k < n; ++k)
                    if (!body.value(p.type, v, bad)) return short_of_data(r, e.name.c_str(), bad);
            }
        return true;
    }

    std::vector<float> vertex_uv;  // u v per vertex, when the file gives them
    bool vertices(const Element& e);
    bool faces(const Element& e, std::size_t list);
    std::uint64_t fast_vertices(const Element& e, const int slot[6], bool normals);
    std::uint64_t fast_faces(const Element& e);
    bool face(std::uint64_t r, const Element& e, std::size_t list, std::string& bad);
};

// The common binary layouts read whole records at a time: vertices of fixed-size
// records whose x, y, z (and nx, ny, nz) are floats, and faces that are only a list of
// int indices counted by a byte. They stop at the first record that needs more than
// that (another size of face, a bad value, the data's end) and the general reader goes
// on from there, so its messages are the same. Both return the records read.
std::uint64_t PlyReader::fast_vertices(const Element& e, const int slot[6], bool normals) {
    if (body.ascii()) return 0;
    std::size_t size = 0, at[6] = {};
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        if (e.props[i].list) return 0;
        for (int k = 0; k < 6; ++k)
            if (slot[k] == int(i)) {
                if (e.props[i].type != Type::Float32) return 0;
                at[k] = size;
            }
        size += std::size_t(size_of(e.props[i].type));
    }
    const std::uint64_t n = std::min<std::uint64_t>(e.count, body.left() / size);
    const bool big = body.big_endian();
    out.positions.resize(3 * n);
    if (normals) out.normals.resize(3 * n);
    float* pos = out.positions.data();
    std::uint64_t r = 0;
    for (const unsigned char* p = body.here(); r < n; ++r, p += size) {
        const float x = load4<float>(p + at[0], big), y = load4<float>(p + at[1], big), z = load4<float>(p + at[2], big);
        if (!(std::fabs(x) <= ModelLimits::max_coordinate && std::fabs(y) <= ModelLimits::max_coordinate &&
              std::fabs(z) <= ModelLimits::max_coordinate))
            break;
        pos[3 * r] = x, pos[3 * r + 1] = y, pos[3 * r + 2] = z;
        if (normals)
            for (int k = 0; k < 3; ++k) out.normals[3 * r + std::size_t(k)] = load4<float>(p + at[3 + k], big);
    }
    out.positions.resize(3 * r);
    if (normals) out.normals.resize(3 * r);
    body.skip(r * size);
    return r;
}

std::uint64_t PlyReader::fast_faces(const Element& e) {
    const Property& p = e.props[0];
    if (body.ascii() || e.props.size() != 1 || size_of(p.count_type) != 1 ||
        (p.type != Type::Int32 && p.type != Type::UInt32))
        return 0;
    const std::uint64_t n = std::min<std::uint64_t>(e.count, body.left() / 13);
    const std::uint32_t vertices = std::uint32_t(out.positions.size() / 3);
    const bool big = body.big_endian();
    const std::size_t before = out.triangles.size();
    out.triangles.resize(before + 3 * n);
    std::uint32_t* t = out.triangles.data() + before;
    std::uint64_t r = 0;
    // (An Int32 index below 0 is a huge uint32: out of range too.)
    for (const unsigned char* q = body.here(); r < n; ++r, q += 13) {
        if (q[0] != 3) break;
        const std::uint32_t a = load4<std::uint32_t>(q + 1, big), b = load4<std::uint32_t>(q + 5, big),
                            c = load4<std::uint32_t>(q + 9, big);
        if (a >= vertices || b >= vertices || c >= vertices) break;
        t[3 * r] = a, t[3 * r + 1] = b, t[3 * r + 2] = c;
    }
    out.triangles.resize(before + 3 * r);
    body.skip(r * 13);
    return r;
}

bool PlyReader::vertices(const Element& e) {
    if (e.count > ModelLimits::max_vertices)
        return fail("too many vertices (" + std::to_string(e.count) + ", limit " +
                        std::to_string(ModelLimits::max_vertices) + ")", 0, "vertex");
    // x y z nx ny nz, then (New:) texture coordinates and colours: which property.
    int slot[11] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
    static constexpr const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
    static constexpr const char* extra[][5] = {{"u", "s", "texture_u", "texture_s", nullptr},
                                               {"v", "t", "texture_v", "texture_t", nullptr},
                                               {"red", "r", "diffuse_red", nullptr, nullptr},
                                               {"green", "g", "diffuse_green", nullptr, nullptr},
                                               {"blue", "b", "diffuse_blue", nullptr, nullptr}};
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        if (e.props[i].list) continue;
        for (int k = 0; k < 6; ++k)
            if (e.props[i].name == names[k]) slot[k] = int(i);
        for (int k = 0; k < 5; ++k)
            for (const char* const* n = extra[k]; *n; ++n)
                if (e.props[i].name == *n && slot[6 + k] < 0) slot[6 + k] = int(i);
    }
    if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0) {
        error.message = "the vertex element has no x, y and z properties";
        return false;
    }
    const bool normals = slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
    const bool uvs = slot[6] >= 0 && slot[7] >= 0;
    const bool colours = slot[8] >= 0 && slot[9] >= 0 && slot[10] >= 0;
    out.positions.reserve(3 * e.count);
    if (normals) out.normals.reserve(3 * e.count);
    if (uvs) vertex_uv.reserve(2 * e.count);
    if (colours) out.colours.reserve(3 * e.count);
    std::vector<double> rec(e.props.size());
    std::string bad;
    for (std::uint64_t r = uvs || colours ? 0 : fast_vertices(e, slot, normals); r < e.count; ++r) {
        for (std::size_t i = 0; i < e.props.size(); ++i) {
            double n = 1;
            const Property& p = e.props[i];
            if (p.list && (!body.value(p.count_type, n, bad) || !(n >= 0 && n <= 1e9 && n == std::floor(n)))) return short_of_data(r, "vertex", bad);
            for (double k = 0; k < n; ++k)
                if (!body.value(p.type, rec[i], bad)) return short_of_data(r, "vertex", bad);
        }
        for (int k = 0; k < 3; ++k) {
            const double v = rec[std::size_t(slot[k])];
            if (!(std::fabs(v) <= ModelLimits::max_coordinate))
                return fail(std::string("coordinate ") + names[k] + (std::isnan(v) ? " is not a number" : " is out of range (magnitude at most 1e15)"),
                            r, "vertex");
            out.positions.push_back(float(v));
        }
        if (normals)
            for (int k = 3; k < 6; ++k) out.normals.push_back(float(rec[std::size_t(slot[k])]));
        if (uvs)
            for (int k = 6; k < 8; ++k) {
                const double v = rec[std::size_t(slot[k])];
                vertex_uv.push_back(std::isfinite(v) ? float(v) : 0.0f);
            }
        if (colours)
            for (int k = 8; k < 11; ++k) {
                // Integers count from 0 to their type's largest; floats are 0..1. Both are
                // display (sRGB) values.
                const Type t = e.props[std::size_t(slot[k])].type;
                const double top = t == Type::UInt8 || t == Type::Int8 ? 255
                                   : t == Type::UInt16 || t == Type::Int16 ? 65535
                                   : t == Type::Float32 || t == Type::Float64 ? 1 : 4294967295.0;
                const double v = rec[std::size_t(slot[k])] / top;
                out.colours.push_back(float(srgb_to_linear(std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 0.0)));
            }
    }
    for (float n : out.normals)
        if (!std::isfinite(n)) return out.normals.clear(), true;  // unusable: computed instead
    return true;
}

bool PlyReader::face(std::uint64_t r, const Element& e, std::size_t list, std::string& bad) {
    const std::uint64_t vertices = out.positions.size() / 3;
    for (std::size_t i = 0; i < e.props.size(); ++i) {
        const Property& p = e.props[i];
        double n = 1, v;
        if (p.list && (!body.value(p.count_type, n, bad) || !(n >= 0 && n <= 1e9 && n == std::floor(n)))) return short_of_data(r, "face", bad);
        if (i == list) {
            if (n < 3) return fail("a face needs at least 3 vertices, this one has " + index_text(n), r, "face");
            if (n > double(ModelLimits::max_polygon))
                return fail("a face of " + index_text(n) + " vertices (limit " + std::to_string(ModelLimits::max_polygon) + ")", r, "face");
            poly.clear();
        }
        for (double k = 0; k < n; ++k) {
            if (!body.value(p.type, v, bad)) return short_of_data(r, "face", bad);
            if (i != list) continue;
            if (!(v >= 0 && v < double(vertices) && v == std::floor(v)))
                return fail("face index " + index_text(v) +
                                " out of range (" + std::to_string(vertices) + (vertices == 1 ? " vertex)" : " vertices)"),
                            r, "face");
            poly.push_back(std::uint32_t(v));
        }
    }
    if (poly.size() == 3) {
        out.triangles.insert(out.triangles.end(), poly.begin(), poly.end());
    } else {
        triangulate(out.positions, poly.data(), poly.size(), out.triangles);
    }
    if (out.triangles.size() / 3 > ModelLimits::max_triangles)
        return fail("too many triangles (limit " + std::to_string(ModelLimits::max_triangles) + ")", r, "face");
    return true;
}

bool PlyReader::faces(const Element& e, std::size_t list) {
    if (e.count > ModelLimits::max_triangles)
        return fail("too many faces (" + std::to_string(e.count) + ", limit " + std::to_string(ModelLimits::max_triangles) + ")",
                    0, "face");
    out.triangles.reserve(3 * e.count);
    std::string bad;
    for (std::uint64_t r = list == 0 ? fast_faces(e) : 0; r < e.count; ++r)
        if (!face(r, e, list, bad)) return false;
    return true;
}

}  // namespace

bool read_ply(std::string_view bytes, MeshData& out, ModelError& error) {
    Header h;
    if (!read_header(bytes, h, error)) return false;
    PlyReader r{h, Body(bytes, h), out, error, {}, {}};
    bool vertices_read = false;
    for (const Element& e : h.elements) {
        if (!r.fits(e)) return false;
        std::size_t list = e.props.size();
        for (std::size_t i = 0; i < e.props.size(); ++i)
            if (e.props[i].list && (e.props[i].name == "vertex_indices" || e.props[i].name == "vertex_index")) list = i;
        bool ok;
        if (e.name == "vertex" && !vertices_read) {
            ok = r.vertices(e);
            vertices_read = true;
        } else if (e.name == "face" && list < e.props.size()) {
            if (!vertices_read) {
                error.message = "the face element comes before the vertex element";
                return false;
            }
            ok = r.faces(e, list);
        } else {
            ok = r.skip_element(e);
        }
        if (!ok) return false;
    }
    // Texture coordinates per corner, as shading takes them.
    if (!r.vertex_uv.empty() && r.vertex_uv.size() == 2 * (out.positions.size() / 3)) {
        out.corner_uv.resize(2 * out.triangles.size());
        for (std::size_t c = 0; c < out.triangles.size(); ++c) {
            out.corner_uv[2 * c] = r.vertex_uv[2 * std::size_t(out.triangles[c])];
            out.corner_uv[2 * c + 1] = r.vertex_uv[2 * std::size_t(out.triangles[c]) + 1];
        }
    }
    return check_mesh(out, error);
}

}  // namespace rt
