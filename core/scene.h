// Plain scene data: what a scene file says, nothing more. The parser produces it,
// the renderer compiles it, the viewer edits it and the writer prints it.
// Materials are stored as written (after the format's clamps); the renderer
// normalises the weights when it compiles the scene.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "file_id.h"
#include "math.h"

namespace rt {

// 1-based line and column of the token an item started at (0 = not from a file).
struct SourceLoc {
    int line = 0;
    int col = 0;
};

class Texture;  // texture.h: a decoded image file

struct Material {
    double reflection = 0;
    double refraction = 0;
    double scattering = 1;
    double translusans = 1;       // clamped to [0,1] by the parser
    double refractive_index = 1;  // values below 1 become 1
    Colour colour{0.5, 0.5, 0.5};
    // New: a Blinn-Phong highlight of each light (0..1; 0: none, the 2013 look) and its
    // exponent (1..10000).
    double specular = 0;
    double shininess = 50;
    // New: an image multiplied into `colour` ("" = none): the file as written, relative
    // to the scene file's folder, and its decoded texels once the scene is parsed (null
    // until then, and when it could not be read). texture_scale: scene units per repeat
    // where the mapping has no scale of its own (planes).
    double texture_scale = 1;
    std::string texture;
    std::shared_ptr<const Texture> texture_image;
    // New: the named material (Scene::materials) this is a use of, its values copied
    // here; -1: written out in place.
    int named = -1;

    // An object with no material block at all: translusans 0 (scene-format §5).
    static Material object_default() {
        Material m;
        m.translusans = 0;
        return m;
    }
    bool operator==(const Material& o) const {
        return reflection == o.reflection && refraction == o.refraction && scattering == o.scattering &&
               translusans == o.translusans && refractive_index == o.refractive_index && colour == o.colour &&
               specular == o.specular && shininess == o.shininess && texture == o.texture &&
               texture_scale == o.texture_scale && texture_image == o.texture_image && named == o.named;
    }
    bool operator!=(const Material& o) const { return !(*this == o); }
    // The same numbers bit for bit (-0 is not 0, NaNs as they are) and the same texture:
    // materials that compile alike. (Big scenes repeat a few materials: cheaper than ==.)
    bool same_bits(const Material& o) const {
        static_assert(offsetof(Material, texture) == 11 * sizeof(double), "the numbers come first");
        return std::memcmp(this, &o, offsetof(Material, texture)) == 0 && texture_image == o.texture_image &&
               texture == o.texture;
    }
};

struct Sphere {
    Vec3 position{1, 1, 1};
    double radius = 1;
    bool operator==(const Sphere& o) const { return position == o.position && radius == o.radius; }
};

struct Tetrahedron {
    Vec3 v[4];
    bool operator==(const Tetrahedron& o) const {
        return v[0] == o.v[0] && v[1] == o.v[1] && v[2] == o.v[2] && v[3] == o.v[3];
    }
};

struct Cylinder {
    Vec3 end1{0, 0, 0};
    Vec3 end2{1, 1, 1};
    double radius = 1;
    bool operator==(const Cylinder& o) const { return end1 == o.end1 && end2 == o.end2 && radius == o.radius; }
};

struct Torus {
    Vec3 position{0, 0, 0};
    Vec3 direction{0, 0, 1};
    double major = 1;
    double minor = 2;
    bool operator==(const Torus& o) const {
        return position == o.position && direction == o.direction && major == o.major && minor == o.minor;
    }
};

// New: a box with faces along the axes, between two opposite corners (which must
// differ on every axis); a transform turns it.
struct Box {
    Vec3 corner1{0, 0, 0};
    Vec3 corner2{1, 1, 1};
    bool operator==(const Box& o) const { return corner1 == o.corner1 && corner2 == o.corner2; }
};

// New: a closed cone, or a cone cut straight across (a frustum): round end caps of
// radius1 at end1 and radius2 at end2; a radius of 0 makes that end a point.
struct Cone {
    Vec3 end1{0, 0, 0};
    Vec3 end2{0, 0, 1};
    double radius1 = 1;
    double radius2 = 0;
    bool operator==(const Cone& o) const {
        return end1 == o.end1 && end2 == o.end2 && radius1 == o.radius1 && radius2 == o.radius2;
    }
};

class MeshModel;  // model.h

// A model file's triangles placed in the scene: scaled (per axis), turned about x, then
// y, then z (degrees), then moved to `position`. `model` is the file as read when the
// scene was parsed (null until then, and when it could not be read); two meshes are
// equal only if they hold the same read of the file, so a file changed on disk makes
// the scene different.
struct Mesh {
    std::string file;  // as written in the scene: relative to the scene file's folder
    Vec3 position{0, 0, 0};
    Vec3 scale{1, 1, 1};
    Vec3 rotation{0, 0, 0};
    int smooth = 0;  // 1: vertex normals interpolated across each triangle
    std::shared_ptr<const MeshModel> model;
    bool operator==(const Mesh& o) const {
        return file == o.file && position == o.position && scale == o.scale && rotation == o.rotation &&
               smooth == o.smooth && model == o.model;
    }
};

// New: where an object is placed. Its shape is scaled (per axis, about the origin),
// turned about x, then y, then z (degrees), then moved by `translate`: the order a
// mesh's own keys use. A CSG's applies to the whole, after its operands' own.
struct Transform {
    Vec3 rotation{0, 0, 0};
    Vec3 scale{1, 1, 1};
    Vec3 translate{0, 0, 0};
    bool operator==(const Transform& o) const {
        return rotation == o.rotation && scale == o.scale && translate == o.translate;
    }
    bool operator!=(const Transform& o) const { return !(*this == o); }
    bool identity() const { return *this == Transform{}; }
};

// An object's Transform, kept apart: most objects have none, and a big scene holds
// millions of objects (8 bytes each instead of 72). Copies copy the value; an absent
// one reads as the identity.
class TransformSlot {
public:
    TransformSlot() = default;
    TransformSlot(const TransformSlot& o) : p_(o.p_ ? std::make_unique<Transform>(*o.p_) : nullptr) {}
    TransformSlot(TransformSlot&&) noexcept = default;
    TransformSlot& operator=(const TransformSlot& o) {
        if (this != &o) p_ = o.p_ ? std::make_unique<Transform>(*o.p_) : nullptr;
        return *this;
    }
    TransformSlot& operator=(TransformSlot&&) noexcept = default;

    const Transform& get() const { return p_ ? *p_ : identity_; }
    Transform& edit() {
        if (!p_) p_ = std::make_unique<Transform>();
        return *p_;
    }
    // Whether it moves anything (a transform written at its defaults does not).
    bool set() const { return p_ && !p_->identity(); }
    bool operator==(const TransformSlot& o) const { return get() == o.get(); }

private:
    std::unique_ptr<Transform> p_;
    static inline const Transform identity_{};
};

struct Object;

// New: a placement of an object defined once by name (`define { object NAME { ... } }`):
// the name as written, and the definition it names, shared by every placement (one
// copy of its geometry, placed by the instance's own transform).
struct Instance {
    std::string object;
    std::shared_ptr<const Object> defined;  // null until the name is resolved
    bool operator==(const Instance& o) const;
};

enum class CsgType : char { Union = 'U', Intersection = 'I', Difference = 'C' };

// Exactly two operands once parsed: operands[0] is `left`, operands[1] is `right`.
// Operand materials are kept (they round-trip) but only the CSG's own is rendered.
struct Csg {
    CsgType type = CsgType::Union;
    std::vector<Object> operands;
    bool operator==(const Csg& o) const;
};

// (New shapes go at the end: the indices of the first six are relied on.)
using Shape = std::variant<Sphere, Tetrahedron, Cylinder, Torus, Csg, Mesh, Box, Cone, Instance>;

struct Object {
    Shape shape;
    Material material = Material::object_default();
    bool has_material = false;  // whether the file gave a material block
    SourceLoc loc;
    TransformSlot transform{};  // New: rotation, scale, translate (a mesh: translate only)
    std::uint16_t origin = 0;   // New: 0, or k: read from the file of Scene::includes[k - 1]
    bool operator==(const Object& o) const {
        return shape == o.shape && material == o.material && has_material == o.has_material &&
               transform == o.transform;
    }
};

inline bool Csg::operator==(const Csg& o) const { return type == o.type && operands == o.operands; }
inline bool Instance::operator==(const Instance& o) const {
    return object == o.object && (defined == o.defined || (defined && o.defined && *defined == *o.defined));
}

// New: an object defined once by name, to be placed by `instance` blocks.
struct NamedObject {
    std::string name;
    std::shared_ptr<const Object> object;
    std::uint16_t origin = 0;  // as Object::origin
    SourceLoc loc;
    bool operator==(const NamedObject& o) const {
        return name == o.name && origin == o.origin && (object == o.object || (object && o.object && *object == *o.object));
    }
};

// `plane` and `chess_plane` from special_thing.
struct Plane {
    bool chess = false;
    Vec3 point[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Material material = Material::object_default();   // `material` or `material 1`
    Material material2 = Material::object_default();  // `material 2` (chess only)
    bool has_material = false, has_material2 = false;
    SourceLoc loc;
    std::uint16_t origin = 0;  // as Object::origin
    bool operator==(const Plane& o) const {
        for (int i = 0; i < 4; ++i)
            if (point[i] != o.point[i]) return false;
        return chess == o.chess && material == o.material && material2 == o.material2 &&
               has_material == o.has_material && has_material2 == o.has_material2;
    }
};

struct Light {
    bool lamp = false;  // lamp: point light plus a glow sphere; spotlight: point light only
    Vec3 position{1, 1, 1};
    Colour colour{0.5, 0.5, 0.5};
    double size = 1;  // glow radius (lamp only); <= 0: no glow
    // New: the light emits from a sphere of this radius (soft shadows); 0: a point, the
    // 2013 light.
    double radius = 0;
    SourceLoc loc;
    std::uint16_t origin = 0;  // as Object::origin
    bool operator==(const Light& o) const {
        return lamp == o.lamp && position == o.position && colour == o.colour && size == o.size &&
               radius == o.radius;
    }
};

enum class Projection { Linear, Polar };

struct Camera {
    Vec3 position{0, 0, 0};
    Vec3 centre{1, 0, 0};
    Vec3 up{1, 0, 1};  // a POINT: the up hint is up - centre
    Projection projection = Projection::Linear;
    double angle_x = 60;  // full field of view, degrees
    double angle_y = 45;
    // New: a thin lens of this diameter (scene units; 0: the 2013 pinhole), sharp at
    // focus_distance from `position` (0: at `centre`'s distance).
    double aperture = 0;
    double focus_distance = 0;
    // New: the colour of rays that leave the scene (black: the 2013 picture).
    Colour background{0, 0, 0};
    bool operator==(const Camera& o) const {
        return position == o.position && centre == o.centre && up == o.up && projection == o.projection &&
               angle_x == o.angle_x && angle_y == o.angle_y && aperture == o.aperture &&
               focus_distance == o.focus_distance && background == o.background;
    }
};

// New: a material defined once by name (`define { material NAME { ... } }`) and used
// by name anywhere a material block goes.
struct NamedMaterial {
    std::string name;
    Material material;
    std::uint16_t origin = 0;  // as Object::origin
    SourceLoc loc;
    bool operator==(const NamedMaterial& o) const { return name == o.name && material == o.material && origin == o.origin; }
};

// New: `include "FILE"` in the scene file itself (those of included files are theirs):
// the file as written, and how many of the scene file's own items came before it, so
// that the scene is written back in the same order.
struct Include {
    std::string file;
    std::size_t objects = 0, planes = 0, lights = 0, materials = 0, defined = 0;  // before it, of origin 0
    SourceLoc loc;
    bool operator==(const Include& o) const {
        return file == o.file && objects == o.objects && planes == o.planes && lights == o.lights &&
               materials == o.materials && defined == o.defined;
    }
};

// New: a file an include read (at any depth), as it was when read, so that a program
// showing the scene can notice that it changed (not part of the scene's value).
struct FileRead {
    std::string path;  // as opened
    FileId id;         // the version read
};

struct Scene {
    std::vector<FileRead> files_read;      // New: by includes, in reading order
    std::vector<NamedMaterial> materials;  // New: every file's definitions, in reading order
    std::vector<NamedObject> defined;      // New: every file's object definitions, in reading order
    std::vector<Include> includes;         // New
    std::vector<Object> objects;
    std::vector<Plane> planes;
    std::vector<Light> lights;
    Camera camera;
    int width = 320;
    int height = 240;
    SourceLoc camera_loc;
    bool operator==(const Scene& o) const {
        return objects == o.objects && planes == o.planes && lights == o.lights && camera == o.camera &&
               width == o.width && height == o.height && materials == o.materials && includes == o.includes &&
               defined == o.defined;
    }
    bool operator!=(const Scene& o) const { return !(*this == o); }
};

// Limits that keep hostile input from exhausting the machine.
struct Limits {
    static constexpr int max_picture_side = 16384;
    static constexpr int max_csg_depth = 256;
    // Objects, CSG operands, planes and lights together. The smallest item ("plane{}")
    // peaks at ~370 bytes while parsing, so 10 million keep a hostile file near 4 GB.
    static constexpr std::size_t max_objects = 10'000'000;
    static constexpr std::size_t max_file_size = 256u << 20;  // bytes
    static constexpr std::size_t max_token_length = 256;
    static constexpr int max_include_depth = 64;     // files including files
    static constexpr std::size_t max_includes = 10'000;  // include lines in one scene file
};

}  // namespace rt
