// stb_image compiled into fuzz_texture with the fuzzer's coverage instrumentation
// (Debian's libstb is not instrumented, so libFuzzer would see nothing of the
// decoders it fuzzes). Linked before libstb, these definitions are the ones used.
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#include <stb/stb_image.h>
