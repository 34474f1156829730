// The tables of the scene language (see scene_schema.h). Defaults are not repeated here:
// each block's make() returns the struct of scene.h as its initialisers leave it.
#include "scene_schema.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <variant>

#include "camera.h"

namespace rt::schema {
namespace {

template <class S>
S& shape(Object& o) {
    return std::get<S>(o.shape);
}

template <class S>
Object object_of(S s) {
    Object o;
    o.shape = std::move(s);
    return o;
}

template <class T>
Key<T> number_key(std::string_view name, double& (*f)(T&, int), Range range = {}) {
    Key<T> k{name, Kind::Number, {}};
    k.access.number = f;
    k.range = range;
    return k;
}

template <class T>
Key<T> vec3_key(std::string_view name, Vec3& (*f)(T&, int), bool required = false) {
    Key<T> k{name, Kind::Vec3, {}};
    k.access.vec3 = f;
    k.required = required;
    return k;
}

template <class T>
Key<T> material_key(Material& (*m)(T&, int), bool& (*has)(T&, int)) {
    Key<T> k{"material", Kind::Material, {}};
    k.access.material = m;
    k.access.has_material = has;
    k.lead = true;  // what an item is made of reads best before where it is
    return k;
}

Key<Object> object_material() {
    return material_key<Object>([](Object& o, int) -> Material& { return o.material; },
                                [](Object& o, int) -> bool& { return o.has_material; });
}

Range positive(const char* message) { return {Range::Rule::Error, 0, 1e300, true, message}; }
Range not_negative(const char* message) { return {Range::Rule::Error, 0, 1e300, false, message}; }

// A key of the format's later additions (New:): written only when not at its default.
template <class T>
Key<T> optional(Key<T> k) {
    k.optional = true;
    return k;
}

Problem error(std::string message) { return {Problem::Severity::Error, std::move(message)}; }
Problem warning(std::string message) { return {Problem::Severity::Warning, std::move(message)}; }

// ---- objects ----------------------------------------------------------------------

// New: the placement keys of every object (scene.h's Transform), after its own keys.
// A mesh has its own rotation and scale (the same meaning), so it takes translate only.
Key<Object> translate_key() {
    Key<Object> k = optional(vec3_key<Object>("translate", [](Object& o, int) -> Vec3& { return o.transform.edit().translate; }));
    k.access.vec3_read = [](const Object& o, int) -> const Vec3& { return o.transform.get().translate; };
    return k;
}

Block<Object> placed(Block<Object> b) {
    Key<Object> rotation =
        optional(vec3_key<Object>("rotation", [](Object& o, int) -> Vec3& { return o.transform.edit().rotation; }));
    rotation.access.vec3_read = [](const Object& o, int) -> const Vec3& { return o.transform.get().rotation; };
    Key<Object> scale = optional(vec3_key<Object>("scale", [](Object& o, int) -> Vec3& { return o.transform.edit().scale; }));
    scale.access.vec3_read = [](const Object& o, int) -> const Vec3& { return o.transform.get().scale; };
    scale.one_or_three = true;
    // Mirroring (a negative scale) is refused: it would turn the solids inside out.
    scale.range = {Range::Rule::Error, 1e-9, 1e9, false,
                   "scale must be 1e-9 .. 1e9 on every axis (0 and negative scales, mirrors, are refused)"};
    b.keys.push_back(rotation);
    b.keys.push_back(scale);
    b.keys.push_back(translate_key());
    return b;
}

Block<Object> sphere() {
    return {"sphere",
            {vec3_key<Object>("position", [](Object& o, int) -> Vec3& { return shape<Sphere>(o).position; }),
             number_key<Object>("radius", [](Object& o, int) -> double& { return shape<Sphere>(o).radius; },
                                positive("sphere radius must be greater than 0")),
             object_material()},
            [] { return object_of(Sphere{}); }};
}

Block<Object> tetrahedron() {
    auto corner = [](std::string_view name, Vec3& (*f)(Object&, int)) { return vec3_key<Object>(name, f); };
    return {"tetrahedron",
            {corner("vect1", [](Object& o, int) -> Vec3& { return shape<Tetrahedron>(o).v[0]; }),
             corner("vect2", [](Object& o, int) -> Vec3& { return shape<Tetrahedron>(o).v[1]; }),
             corner("vect3", [](Object& o, int) -> Vec3& { return shape<Tetrahedron>(o).v[2]; }),
             corner("vect4", [](Object& o, int) -> Vec3& { return shape<Tetrahedron>(o).v[3]; }), object_material()},
            [] { return object_of(Tetrahedron{}); },
            [](const Object& o) {
                const Tetrahedron& s = std::get<Tetrahedron>(o.shape);
                Vec3 e1 = s.v[1] - s.v[0], e2 = s.v[2] - s.v[0], e3 = s.v[3] - s.v[0];
                double vol = std::fabs(dot(cross(e1, e2), e3));
                double scale = std::max({length2(e1), length2(e2), length2(e3)});
                if (!(vol > 1e-12 * scale * std::sqrt(scale)) || scale == 0)
                    return error("tetrahedron is flat: its four corners lie in one plane");
                return Problem{};
            }};
}

// The keys of a shape between two points (cylinder, cone): end_1, end_2, then `more`,
// then the material.
template <class S>
std::vector<Key<Object>> ends_then(std::vector<Key<Object>> more) {
    std::vector<Key<Object>> keys{vec3_key<Object>("end_1", [](Object& o, int) -> Vec3& { return shape<S>(o).end1; }),
                                  vec3_key<Object>("end_2", [](Object& o, int) -> Vec3& { return shape<S>(o).end2; })};
    keys.insert(keys.end(), more.begin(), more.end());
    keys.push_back(object_material());
    return keys;
}

Block<Object> cylinder() {
    return {"cylinder",
            ends_then<Cylinder>({number_key<Object>("radius", [](Object& o, int) -> double& { return shape<Cylinder>(o).radius; },
                                                    positive("cylinder radius must be greater than 0"))}),
            [] { return object_of(Cylinder{}); },
            [](const Object& o) {
                const Cylinder& s = std::get<Cylinder>(o.shape);
                return s.end1 == s.end2 ? error("cylinder end_1 and end_2 are the same point") : Problem{};
            }};
}

Block<Object> torus() {
    return {"torus",
            {vec3_key<Object>("position", [](Object& o, int) -> Vec3& { return shape<Torus>(o).position; }),
             vec3_key<Object>("direction", [](Object& o, int) -> Vec3& { return shape<Torus>(o).direction; }),
             number_key<Object>("major", [](Object& o, int) -> double& { return shape<Torus>(o).major; },
                                {Range::Rule::Error, 0, 1e300, false, "torus major radius must not be negative"}),
             number_key<Object>("minor", [](Object& o, int) -> double& { return shape<Torus>(o).minor; },
                                positive("torus minor radius must be greater than 0")),
             object_material()},
            [] { return object_of(Torus{}); },
            [](const Object& o) {
                return length2(std::get<Torus>(o.shape).direction) == 0 ? error("torus direction must not be 0 0 0")
                                                                        : Problem{};
            }};
}

Block<Object> box() {
    return {"box",
            {vec3_key<Object>("corner_1", [](Object& o, int) -> Vec3& { return shape<Box>(o).corner1; }),
             vec3_key<Object>("corner_2", [](Object& o, int) -> Vec3& { return shape<Box>(o).corner2; }),
             object_material()},
            [] { return object_of(Box{}); },
            [](const Object& o) {
                const Box& b = std::get<Box>(o.shape);
                if (b.corner1 == b.corner2) return error("box corner_1 and corner_2 are the same point");
                if (b.corner1.x == b.corner2.x || b.corner1.y == b.corner2.y || b.corner1.z == b.corner2.z)
                    return error("box is flat: corner_1 and corner_2 must differ in x, in y and in z");
                return Problem{};
            }};
}

Block<Object> cone() {
    return {"cone",
            ends_then<Cone>({number_key<Object>("radius_1", [](Object& o, int) -> double& { return shape<Cone>(o).radius1; },
                                                not_negative("cone radius_1 must not be negative")),
                             number_key<Object>("radius_2", [](Object& o, int) -> double& { return shape<Cone>(o).radius2; },
                                                not_negative("cone radius_2 must not be negative"))}),
            [] { return object_of(Cone{}); },
            [](const Object& o) {
                const Cone& c = std::get<Cone>(o.shape);
                if (c.end1 == c.end2) return error("cone end_1 and end_2 are the same point");
                if (c.radius1 == 0 && c.radius2 == 0) return error("cone radius_1 and radius_2 are both 0: it would be a line");
                return Problem{};
            }};
}

Block<Object> instance() {
    Key<Object> object{"object", Kind::File, {}};
    object.access.text = [](Object& o, int) -> std::string& { return shape<Instance>(o).object; };
    object.placeholder = "NAME";
    object.bare = true;
    object.lead = true;
    return {"instance", {object, object_material()}, [] { return object_of(Instance{}); },
            [](const Object& o) {
                return std::get<Instance>(o.shape).object.empty() ? error("instance needs an 'object' (the name of a defined object)")
                                                                   : Problem{};
            }};
}

const Choice kCsgType{{{"U", int(CsgType::Union)}, {"I", int(CsgType::Intersection)}, {"C", int(CsgType::Difference)}},
                      -1,
                      "U, I or C",
                      "CSG type must be U, I or C, got ",
                      nullptr,
                      true};

Object* side(Object& o, std::size_t i) {
    std::vector<Object>& operands = shape<Csg>(o).operands;
    return i < operands.size() ? &operands[i] : nullptr;
}

Block<Object> csg() {
    auto operand = [](std::string_view name, Object* (*f)(Object&, int)) {
        Key<Object> k{name, Kind::Operand, {}};
        k.access.operand = f;
        k.required = true;
        return k;
    };
    Key<Object> type{"type", Kind::Choice, {}};
    type.access.get_choice = [](const Object& o) { return int(std::get<Csg>(o.shape).type); };
    type.access.set_choice = [](Object& o, int v) { shape<Csg>(o).type = CsgType(v); };
    type.choice = &kCsgType;
    type.lead = true;
    return {"constructive_solid_geometry",
            {operand("left", [](Object& o, int) { return side(o, 0); }),
             operand("right", [](Object& o, int) { return side(o, 1); }), type,
             object_material()},
            [] {
                Csg s;
                s.operands.resize(2);
                return object_of(std::move(s));
            }};
}

Block<Object> mesh() {
    Key<Object> file{"file", Kind::File, {}};
    file.access.text = [](Object& o, int) -> std::string& { return shape<Mesh>(o).file; };
    file.placeholder = "MODEL.obj";
    file.lead = true;
    Key<Object> scale = vec3_key<Object>("scale", [](Object& o, int) -> Vec3& { return shape<Mesh>(o).scale; });
    scale.one_or_three = true;
    Key<Object> smooth{"smooth", Kind::Integer, {}};
    smooth.access.integer = [](Object& o, int) -> int& { return shape<Mesh>(o).smooth; };
    smooth.range = {Range::Rule::Error, 0, 1, false, "smooth must be 0 (flat triangles) or 1 (smooth)"};
    return {"mesh",
            {file, vec3_key<Object>("position", [](Object& o, int) -> Vec3& { return shape<Mesh>(o).position; }),
             scale, vec3_key<Object>("rotation", [](Object& o, int) -> Vec3& { return shape<Mesh>(o).rotation; }),
             smooth, object_material(), translate_key()},
            [] { return object_of(Mesh{}); },
            [](const Object& o) {
                const Mesh& m = std::get<Mesh>(o.shape);
                if (m.file.empty()) return error("mesh needs a 'file' (the model to show)");
                if (m.scale.x == 0 || m.scale.y == 0 || m.scale.z == 0) return error("mesh scale must not be 0 on any axis");
                return Problem{};
            }};
}

// ---- planes and lights --------------------------------------------------------------

Key<Plane> plane_point() {
    Key<Plane> k = vec3_key<Plane>("point", [](Plane& p, int i) -> Vec3& { return p.point[i]; });
    k.count = 4;
    k.count_error = "point number must be 1..4";
    return k;
}

Problem plane_check(const Plane& p) {
    const std::string name = p.chess ? "chess_plane" : "plane";
    Vec3 e1 = p.point[1] - p.point[0], e2 = p.point[2] - p.point[0];
    Vec3 n = cross(e1, e2);
    if (!(length2(n) > 1e-24 * length2(e1) * length2(e2)) || length2(n) == 0)
        return error(name + ": points 1, 2 and 3 lie on one line");
    if (std::fabs(dot(normalize(n), p.point[3] - p.point[0])) <= 1.5e-5)
        return warning(name + ": point 4 lies in the plane, so the lit side is arbitrary" +
                       (p.chess ? " and every cell gets material 1" : ""));
    return {};
}

Block<Plane> plane() {
    return {"plane",
            {plane_point(), material_key<Plane>([](Plane& p, int) -> Material& { return p.material; },
                                                [](Plane& p, int) -> bool& { return p.has_material; })},
            [] { return Plane{}; },
            plane_check};
}

Block<Plane> chess_plane() {
    Key<Plane> material = material_key<Plane>(
        [](Plane& p, int i) -> Material& { return i == 0 ? p.material : p.material2; },
        [](Plane& p, int i) -> bool& { return i == 0 ? p.has_material : p.has_material2; });
    material.count = 2;
    material.count_error = "material number must be 1 or 2";
    return {"chess_plane", {plane_point(), material},
            [] {
                Plane p;
                p.chess = true;
                return p;
            },
            plane_check};
}

std::vector<Key<Light>> light_keys(bool lamp) {
    std::vector<Key<Light>> keys = {
        vec3_key<Light>("position", [](Light& l, int) -> Vec3& { return l.position; }),
        vec3_key<Light>("colour", [](Light& l, int) -> Vec3& { return l.colour; }),
    };
    if (lamp) keys.push_back(number_key<Light>("size", [](Light& l, int) -> double& { return l.size; }));
    keys.push_back(optional(number_key<Light>("radius", [](Light& l, int) -> double& { return l.radius; },
                                              not_negative("light radius must not be negative"))));
    return keys;
}

// ---- material, camera, picture size -------------------------------------------------

Key<Material> texture_key() {
    Key<Material> k{"texture", Kind::File, {}};
    k.access.text = [](Material& m, int) -> std::string& { return m.texture; };
    k.placeholder = "IMAGE.png";
    k.default_text = "no texture";
    return k;
}

Block<Material> material() {
    auto weight = [](std::string_view name, double& (*f)(Material&, int), Range r = {}) {
        return number_key<Material>(name, f, r);
    };
    return {"material",
            {weight("reflection", [](Material& m, int) -> double& { return m.reflection; }),
             weight("refraction", [](Material& m, int) -> double& { return m.refraction; }),
             weight("scattering", [](Material& m, int) -> double& { return m.scattering; }),
             weight("translusans", [](Material& m, int) -> double& { return m.translusans; },
                    {Range::Rule::Clamp, 0, 1}),
             weight("refractive_index", [](Material& m, int) -> double& { return m.refractive_index; },
                    {Range::Rule::Clamp, 1, 1e300}),
             vec3_key<Material>("colour", [](Material& m, int) -> Vec3& { return m.colour; }),
             optional(weight("specular", [](Material& m, int) -> double& { return m.specular; },
                             {Range::Rule::Error, 0, 1, false, "specular must be 0..1"})),
             optional(weight("shininess", [](Material& m, int) -> double& { return m.shininess; },
                             {Range::Rule::Error, 1, 10000, false, "shininess must be 1..10000"})),
             optional(texture_key()),
             optional(weight("texture_scale", [](Material& m, int) -> double& { return m.texture_scale; },
                             positive("texture_scale must be greater than 0")))},
            [] { return Material{}; },
            [](const Material& m) {
                if (m.reflection + m.refraction + m.scattering != 0) {
                    // Read as written, as the 2013 program did; the format means 0 or more.
                    std::string negative;
                    for (const auto& [name, w] : {std::pair<const char*, double>{"reflection", m.reflection},
                                                  {"refraction", m.refraction}, {"scattering", m.scattering}})
                        if (w < 0) negative += (negative.empty() ? "" : ", ") + std::string(name);
                    if (negative.empty()) return Problem{};
                    return warning("material " + negative + (negative.find(',') == std::string::npos ? " is" : " are") +
                                   " negative: weights are 0 or more (the picture is not what the format means)");
                }
                return warning(m.reflection == 0 && m.refraction == 0
                                   ? "material weights reflection, refraction and scattering are all 0: the "
                                     "surface renders black"
                                   : "material weights reflection, refraction and scattering add up to 0: the "
                                     "surface renders black");
            }};
}

const Choice kProjection{{{"linear", int(Projection::Linear)},
                          {"polar", int(Projection::Polar)},
                          {"1", int(Projection::Polar)},
                          {"angular", int(Projection::Polar)}},
                         int(Projection::Linear),
                         "a projection",
                         "projection must be 'linear', 'polar' (or 1), or a single character for linear; got ",
                         "expected a projection (linear, polar or a single character) after 'projection', got ",
                         false};

Key<Camera> focus_key() {
    Key<Camera> k = optional(number_key<Camera>("focus_distance", [](Camera& c, int) -> double& { return c.focus_distance; },
                                                positive("focus_distance must be greater than 0")));
    k.default_text = "the distance from position to centre";
    return k;
}

Block<Camera> camera() {
    auto point = [](std::string_view name, Vec3& (*f)(Camera&, int)) { return vec3_key<Camera>(name, f, true); };
    auto angle = [](std::string_view name, double& (*f)(Camera&, int)) {
        Key<Camera> k = number_key<Camera>(name, f);
        k.required = true;
        return k;
    };
    Key<Camera> projection{"projection", Kind::Choice, {}};
    projection.access.get_choice = [](const Camera& c) { return int(c.projection); };
    projection.access.set_choice = [](Camera& c, int v) { c.projection = Projection(v); };
    projection.choice = &kProjection;
    return {"camera",
            {point("position", [](Camera& c, int) -> Vec3& { return c.position; }),
             point("centre", [](Camera& c, int) -> Vec3& { return c.centre; }),
             point("up", [](Camera& c, int) -> Vec3& { return c.up; }), projection,
             angle("angle_x", [](Camera& c, int) -> double& { return c.angle_x; }),
             angle("angle_y", [](Camera& c, int) -> double& { return c.angle_y; }),
             optional(number_key<Camera>("aperture", [](Camera& c, int) -> double& { return c.aperture; },
                                         not_negative("aperture must not be negative"))),
             focus_key(),
             optional(vec3_key<Camera>("background", [](Camera& c, int) -> Vec3& { return c.background; }))},
            [] { return Camera{}; },
            [](const Camera& c) {
                const char* why = camera_problem(c);
                return why ? error(std::string("camera: ") + why) : Problem{};
            }};
}

Block<Scene> picture_size() {
    auto side = [](std::string_view name, int& (*f)(Scene&, int)) {
        Key<Scene> k{name, Kind::Integer, {}};
        k.access.integer = f;
        k.range = {Range::Rule::Error, 1, double(Limits::max_picture_side), false,
                   "picture size must be 1..16384 pixels on each side"};
        k.required = true;
        return k;
    };
    return {"picture_size",
            {side("x_max", [](Scene& s, int) -> int& { return s.width; }),
             side("y_max", [](Scene& s, int) -> int& { return s.height; })},
            [] { return Scene{}; }};
}

}  // namespace

std::string_view Choice::word_for(int value) const {
    for (const Word& w : words)
        if (w.value == value) return w.word;
    return {};
}

bool Choice::find(std::string_view word, int& value) const {
    for (const Word& w : words)
        if (w.word == word) return value = w.value, true;
    if (any_single_char >= 0 && word.size() == 1) return value = any_single_char, true;
    return false;
}

const std::vector<Block<Object>>& object_blocks() {
    static const std::vector<Block<Object>> blocks = {placed(sphere()), placed(tetrahedron()), placed(cylinder()),
                                                                 placed(torus()),  placed(box()),         placed(cone()),
                                                                 placed(csg()),    mesh(),                placed(instance())};
    return blocks;
}

const Block<Object>* object_block(std::string_view name) {
    for (const Block<Object>& b : object_blocks())
        if (same_word(b.name, name)) return &b;
    return nullptr;
}

// The block of each of the variant's alternatives (the solids first in the lists).
const Block<Object>& object_block(const Object& o) {
    static constexpr std::size_t kBlock[] = {0, 1, 2, 3, 6, 7, 4, 5, 8};  // Csg, Mesh, Box, Cone, Instance
    static_assert(std::size(kBlock) == std::variant_size_v<Shape>, "a block for each shape");
    return object_blocks()[kBlock[o.shape.index()]];
}

const std::vector<Block<Plane>>& plane_blocks() {
    static const std::vector<Block<Plane>> blocks = {plane(), chess_plane()};
    return blocks;
}
const Block<Plane>& plane_block(const Plane& p) { return plane_blocks()[p.chess ? 1 : 0]; }

const std::vector<Block<Light>>& light_blocks() {
    static const std::vector<Block<Light>> blocks = {
        {"lamp", light_keys(true),
         [] {
             Light l;
             l.lamp = true;
             return l;
         }},
        {"spotlight", light_keys(false), [] { return Light{}; }}};
    return blocks;
}
const Block<Light>& light_block(const Light& l) { return light_blocks()[l.lamp ? 0 : 1]; }

const Block<Material>& material_block() {
    static const Block<Material> b = material();
    return b;
}
const Block<Camera>& camera_block() {
    static const Block<Camera> b = camera();
    return b;
}
const Block<Scene>& picture_size_block() {
    static const Block<Scene> b = picture_size();
    return b;
}

const std::vector<Section>& sections() {
    static const std::vector<Section> s = {{"include", SectionKind::Include, nullptr},
                                           {"define", SectionKind::Define, "definition"},
                                           {"thing", SectionKind::Things, "object"},
                                           {"special_thing", SectionKind::Specials, "special thing"},
                                           {"light", SectionKind::Lights, "light"},
                                           {"camera", SectionKind::Camera, nullptr},
                                           {"picture_size", SectionKind::PictureSize, nullptr},
                                           {"end", SectionKind::End, nullptr}};
    return s;
}

const Section* find_section(std::string_view name) {
    for (const Section& s : sections())
        if (same_word(s.name, name)) return &s;
    return nullptr;
}

std::string section_list() {
    std::string out;
    const auto& all = sections();
    for (std::size_t i = 0; i < all.size(); ++i) {
        if (i > 0) out += i + 1 == all.size() ? " or " : ", ";
        out += all[i].name;
    }
    return out;
}

}  // namespace rt::schema
