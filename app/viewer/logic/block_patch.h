// A panel edit written into one item's block of scene text by replacing only the
// values of the keys that changed (a key the block did not give is added before its
// closing brace). The user's comments, layout and other keys stay as typed, including
// the `// lamp size` note a spotlight keeps for switching back to a lamp. No GL.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "scene.h"

namespace rtview {

// `block` is the text of one item (from its name to its closing brace) that parses to
// `before`. Returns the block with the keys that differ in `after` rewritten, or
// nothing when that cannot be done in place (the block's kind changed, its tokens do
// not read as the schema says, or a check parse of the result disagrees): the caller
// then writes the whole block anew.
std::optional<std::string> patch_block(std::string_view block, const rt::Object& before, const rt::Object& after);
std::optional<std::string> patch_block(std::string_view block, const rt::Plane& before, const rt::Plane& after);
std::optional<std::string> patch_block(std::string_view block, const rt::Light& before, const rt::Light& after);
// `braces` is the `{ ... }` of a material (a named material's definition) that reads as
// `before`: the same with the values that differ in `after` rewritten (its comments and
// layout kept), or nothing when that cannot be done in place.
std::optional<std::string> patch_material(std::string_view braces, const rt::Material& before,
                                          const rt::Material& after);

}  // namespace rtview
