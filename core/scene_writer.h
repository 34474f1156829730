// Scene -> text in the scene format. parse_scene(write_scene(s)) == s for every valid
// scene: numbers are printed with enough digits to round-trip exactly.
#pragma once

#include <string>

#include "scene.h"

namespace rt {

// New: named materials are written by name, an included file's items as the
// `include` line that brought them; `flatten`: every item and material written out in
// full, as if there were neither (what the renderer sees).
std::string write_scene(const Scene& scene, bool flatten = false);
// One `camera { ... }` block (for the viewer's "copy camera" button).
std::string write_camera(const Camera& camera);
// A material block's `{ ... }` as write_scene prints it (the New: keys only when set).
std::string write_material(const Material& m);
// The format in brief, from the schema: each section and block on a line with every
// key at its default (`material {...}` spelled out once), then the rules a value must
// keep. raytracer --help-format prints it; the viewer's Help shows it.
std::string format_reference();
// A number as the writer prints it: shortest text that reads back to the same double.
std::string format_number(double v);

}  // namespace rt
