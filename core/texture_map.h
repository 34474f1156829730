// Texture coordinates of a hit on each kind of surface, and the colour a textured
// (or model-coloured) surface has there: the material's colour times the texel.
// Untextured surfaces never come here: their colour is the material's, bit for bit.
#pragma once

#include <cstdint>

#include "math.h"
#include "shapes.h"
#include "world.h"

namespace rt {

struct Uv {
    double u = 0, v = 0;
};

// The texture coordinates of point p on primitive node `n` (not a mesh or a CSG) on
// its surface `face`; `scale`: scene units per repeat, for the flat mappings.
//   sphere:      u = longitude about z from +x / 2 pi, v = latitude / pi + 1/2
//   cylinder:    u = angle about the axis / 2 pi, v = height from end_1 / length; on
//                the caps v = distance from the axis / radius
//   torus:       u = angle about the axis / 2 pi, v = angle about the tube / 2 pi
//   tetrahedron: the face's own plane axes (a frame about its normal) / scale
Uv primitive_uv(const Geometry& g, std::uint32_t n, std::uint8_t face, const Vec3& p, double scale);
// A plane's: along point 1 -> 2 and point 1 -> 3, in scene units / scale.
Uv plane_uv(const PlaneShape& pl, const Vec3& p, double scale);

// The material and colour at the hit `e` of object `obj` at p, for a material with a
// texture or a model's own materials (m->texture or m->file set): `m` may become the
// face's material of the model, `cp` is its colour there.
void object_look(const Geometry& g, std::uint32_t obj, const SpanEnd& e, const Vec3& p, const ShadeMaterial*& m,
                 Colour& cp);
// A textured plane's colour at p.
Colour plane_look(const PlaneShape& pl, const ShadeMaterial& m, const Vec3& p);

}  // namespace rt
