// The scene the viewer opens when given none, compiled into the binaries.
#pragma once

namespace rt {
extern const char* const kDefaultScene;
extern const char* const kDefaultSceneName;
}  // namespace rt
