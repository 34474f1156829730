// The scene File > New starts from: the smallest scene that shows something (a sphere
// on a chess floor under a lamp, seen by a camera), each block a pattern to copy.
#pragma once

namespace rtview {
extern const char* const kNewScene;
extern const char* const kNewSceneName;  // its name until it is saved
}  // namespace rtview
