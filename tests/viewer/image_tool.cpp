// rtview-imgtool: the few image measurements the viewer's screenshot tests need
// (region comparisons, colour counts), so the shell scripts need no ImageMagick
// arithmetic. Reads PNG (stb_image) and PPM. Regions are x y w h in pixels.
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "image_io.h"

namespace {

struct Img {
    int w = 0, h = 0;
    std::vector<unsigned char> rgb;
    const unsigned char* at(int x, int y) const { return &rgb[(std::size_t(y) * w + x) * 3]; }
};

bool load(const std::string& path, Img& img) {
    if (rt::format_from_path(path) == rt::ImageFormat::Ppm) {
        std::string err = rt::read_ppm(path, img.w, img.h, img.rgb).message();
        if (!err.empty()) std::fprintf(stderr, "%s: %s\n", path.c_str(), err.c_str());
        return err.empty();
    }
    int n = 0;
    unsigned char* p = stbi_load(path.c_str(), &img.w, &img.h, &n, 3);
    if (!p) {
        std::fprintf(stderr, "%s: cannot read\n", path.c_str());
        return false;
    }
    img.rgb.assign(p, p + std::size_t(img.w) * img.h * 3);
    stbi_image_free(p);
    return true;
}

struct Region {
    int x = 0, y = 0, w = 0, h = 0;
};

bool region(char** a, const Img& img, Region& r) {
    r = {std::atoi(a[0]), std::atoi(a[1]), std::atoi(a[2]), std::atoi(a[3])};
    if (r.x < 0 || r.y < 0 || r.w < 1 || r.h < 1 || r.x + r.w > img.w || r.y + r.h > img.h) {
        std::fprintf(stderr, "region %d %d %d %d outside the %dx%d image\n", r.x, r.y, r.w, r.h, img.w, img.h);
        return false;
    }
    return true;
}

// REF resampled to w x h as the viewer's texture is drawn over a quad of that size with
// linear filtering and no mipmaps (texel centres at half-integers, clamped at the edges):
// what the screen shows of a picture_size film fitted into the picture frame.
Img bilinear(const Img& ref, int w, int h) {
    Img out;
    out.w = w;
    out.h = h;
    out.rgb.resize(std::size_t(w) * h * 3);
    auto coord = [](int k, int n, int m, int& i0, int& i1, double& f) {
        const double u = (k + 0.5) * m / n - 0.5;
        const double fl = std::floor(u);
        f = u - fl;
        i0 = std::clamp(int(fl), 0, m - 1);
        i1 = std::clamp(int(fl) + 1, 0, m - 1);
    };
    for (int y = 0; y < h; ++y) {
        int y0, y1;
        double fy;
        coord(y, h, ref.h, y0, y1, fy);
        for (int x = 0; x < w; ++x) {
            int x0, x1;
            double fx;
            coord(x, w, ref.w, x0, x1, fx);
            for (int c = 0; c < 3; ++c) {
                const double top = ref.at(x0, y0)[c] * (1 - fx) + ref.at(x1, y0)[c] * fx;
                const double bottom = ref.at(x0, y1)[c] * (1 - fx) + ref.at(x1, y1)[c] * fx;
                out.rgb[(std::size_t(y) * w + x) * 3 + c] = (unsigned char)std::lround(top * (1 - fy) + bottom * fy);
            }
        }
    }
    return out;
}

// The region of SHOT against REF of the same size: 0 when equal within the display
// path's rounding, 1 when not (with the numbers on stdout).
int compare(const Img& shot, const Region& r, const Img& ref) {
    long big = 0;
    double sum = 0;
    int worst = 0;
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x) {
            const unsigned char* a = shot.at(r.x + x, r.y + y);
            const unsigned char* b = ref.at(x, y);
            for (int c = 0; c < 3; ++c) {
                int d = std::abs(int(a[c]) - int(b[c]));
                sum += d;
                worst = std::max(worst, d);
                if (d > 3) ++big;
            }
        }
    double n = double(r.w) * r.h * 3;
    std::printf("mean abs diff %.4f, max %d, values off by more than 3: %.4f%%\n", sum / n, worst, 100 * big / n);
    // Small tolerance: the display path may round differently than the file writer.
    return (sum / n < 0.5 && big / n < 0.002) ? 0 : 1;
}

int usage() {
    std::fputs("usage: rtview-imgtool match SHOT X Y W H REF     region of SHOT equals REF (same size) within tolerance\n"
               "       rtview-imgtool match-scaled SHOT X Y W H REF  the same, REF drawn at the region's size with\n"
               "                                                 linear filtering (a film shown fitted)\n"
               "       rtview-imgtool diff A B X Y W H           fraction of pixels differing by more than 8\n"
               "       rtview-imgtool colours IMG X Y W H        number of distinct colours\n"
               "       rtview-imgtool near IMG X Y W H R G B T   pixels within T of colour R G B\n"
               "       rtview-imgtool ink IMG X Y W H            x extent (first last) of the pixels that differ\n"
               "                                                 from the region's commonest colour by more than 48\n",
               stderr);
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage();
    std::string cmd = argv[1];
    if (cmd == "match" && argc == 8) {
        Img shot, ref;
        Region r;
        if (!load(argv[2], shot) || !load(argv[7], ref) || !region(argv + 3, shot, r)) return 2;
        if (ref.w != r.w || ref.h != r.h) {
            std::fprintf(stderr, "reference is %dx%d, region %dx%d\n", ref.w, ref.h, r.w, r.h);
            return 1;
        }
        return compare(shot, r, ref);
    }
    if (cmd == "match-scaled" && argc == 8) {
        Img shot, ref;
        Region r;
        if (!load(argv[2], shot) || !load(argv[7], ref) || !region(argv + 3, shot, r)) return 2;
        return compare(shot, r, bilinear(ref, r.w, r.h));
    }
    if (cmd == "diff" && argc == 8) {
        Img a, b;
        Region r;
        if (!load(argv[2], a) || !load(argv[3], b) || !region(argv + 4, a, r) || !region(argv + 4, b, r)) return 2;
        long n = 0;
        for (int y = r.y; y < r.y + r.h; ++y)
            for (int x = r.x; x < r.x + r.w; ++x) {
                const unsigned char *p = a.at(x, y), *q = b.at(x, y);
                if (std::abs(p[0] - q[0]) > 8 || std::abs(p[1] - q[1]) > 8 || std::abs(p[2] - q[2]) > 8) ++n;
            }
        std::printf("%.6f\n", double(n) / (double(r.w) * r.h));
        return 0;
    }
    if (cmd == "colours" && argc == 7) {
        Img a;
        Region r;
        if (!load(argv[2], a) || !region(argv + 3, a, r)) return 2;
        std::set<unsigned> seen;
        for (int y = r.y; y < r.y + r.h; ++y)
            for (int x = r.x; x < r.x + r.w; ++x) {
                const unsigned char* p = a.at(x, y);
                seen.insert(unsigned(p[0]) << 16 | unsigned(p[1]) << 8 | p[2]);
            }
        std::printf("%zu\n", seen.size());
        return 0;
    }
    if (cmd == "near" && argc == 11) {
        Img a;
        Region r;
        if (!load(argv[2], a) || !region(argv + 3, a, r)) return 2;
        int R = std::atoi(argv[7]), G = std::atoi(argv[8]), B = std::atoi(argv[9]), T = std::atoi(argv[10]);
        long n = 0;
        for (int y = r.y; y < r.y + r.h; ++y)
            for (int x = r.x; x < r.x + r.w; ++x) {
                const unsigned char* p = a.at(x, y);
                if (std::abs(p[0] - R) <= T && std::abs(p[1] - G) <= T && std::abs(p[2] - B) <= T) ++n;
            }
        std::printf("%ld\n", n);
        return 0;
    }
    if (cmd == "ink" && argc == 7) {
        Img a;
        Region r;
        if (!load(argv[2], a) || !region(argv + 3, a, r)) return 2;
        std::map<unsigned, long> count;
        for (int y = r.y; y < r.y + r.h; ++y)
            for (int x = r.x; x < r.x + r.w; ++x) {
                const unsigned char* p = a.at(x, y);
                ++count[unsigned(p[0]) << 16 | unsigned(p[1]) << 8 | p[2]];
            }
        unsigned bg = 0;
        long most = -1;
        for (const auto& [c, n] : count)
            if (n > most) most = n, bg = c;
        const int R = int(bg >> 16), G = int(bg >> 8 & 255), B = int(bg & 255);
        int first = -1, last = -1;
        for (int y = r.y; y < r.y + r.h; ++y)
            for (int x = r.x; x < r.x + r.w; ++x) {
                const unsigned char* p = a.at(x, y);
                if (std::abs(p[0] - R) + std::abs(p[1] - G) + std::abs(p[2] - B) <= 48) continue;
                if (first < 0 || x < first) first = x;
                last = std::max(last, x);
            }
        std::printf("%d %d\n", first, last);
        return 0;
    }
    return usage();
}
