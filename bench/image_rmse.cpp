// image_rmse: how far one picture is from another, for the anti-aliasing benchmark
// (bench/run.sh compares each program's picture with its own converged one).
//
//   image_rmse A B      prints "rmse R max M differ P%" for two pictures of one size
//
// R is the root mean square difference over every channel of every pixel, in 8-bit
// units (0..255); M the largest difference of one channel; P the share of channel
// values that differ at all. A and B are anything stb_image reads (PNG, binary PPM).
#include <stb/stb_image.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace {

struct Picture {
    int w = 0, h = 0;
    std::unique_ptr<unsigned char, void (*)(void*)> px{nullptr, stbi_image_free};
};

bool load(const char* path, Picture& p) {
    int channels = 0;
    p.px.reset(stbi_load(path, &p.w, &p.h, &channels, 3));
    if (!p.px) std::fprintf(stderr, "image_rmse: cannot read '%s': %s\n", path, stbi_failure_reason());
    return bool(p.px);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: image_rmse A B\n");
        return 2;
    }
    Picture a, b;
    if (!load(argv[1], a) || !load(argv[2], b)) return 2;
    if (a.w != b.w || a.h != b.h) {
        std::fprintf(stderr, "image_rmse: %dx%d against %dx%d\n", a.w, a.h, b.w, b.h);
        return 2;
    }
    const std::size_t n = std::size_t(a.w) * a.h * 3;
    double sq = 0;
    int max = 0;
    std::size_t differ = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const int d = std::abs(int(a.px.get()[i]) - int(b.px.get()[i]));
        sq += double(d) * d;
        max = d > max ? d : max;
        differ += d != 0;
    }
    std::printf("rmse %.4f max %d differ %.3f%%\n", std::sqrt(sq / double(n)), max, 100.0 * double(differ) / double(n));
    return 0;
}
