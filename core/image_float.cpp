// Float pictures (New: .pfm and .exr): the film's linear values, before the byte
// rounding of docs/rendering.md §9 (no clamp, no gamma), for tone mapping or denoising
// elsewhere. PFM: little-endian 32-bit floats, bottom row first, as the format has it.
// EXR: half-float RGB through OpenEXR, written into memory and then, like every
// output, to a temporary file renamed over the target.
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfRgbaFile.h>

#include <cmath>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "image_io.h"

namespace rt {

namespace {

// An OpenEXR output stream into a string.
class StringStream : public Imf::OStream {
public:
    StringStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        if (pos_ + std::size_t(n) > data.size()) data.resize(pos_ + std::size_t(n));
        std::memcpy(&data[pos_], c, std::size_t(n));
        pos_ += std::size_t(n);
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = std::size_t(pos); }
    std::string data;

private:
    std::size_t pos_ = 0;
};

// A channel as a float file holds it: non-finite values are the same as in pixels
// (NaN 0, -inf 0, +inf 1e30, docs/rendering.md §9), then clamped to what the type holds.
float finite_value(float v, float max) {
    if (std::isnan(v) || v == -INFINITY) return 0;
    if (v > max) return max;
    if (v < -max) return -max;
    return v;
}

}  // namespace

std::string encode_pfm(const Image& img) {
    std::string out = "PF\n" + std::to_string(img.width) + " " + std::to_string(img.height) + "\n-1.0\n";
    const std::size_t row = 3 * std::size_t(img.width);
    const std::size_t header = out.size();
    out.resize(header + row * std::size_t(img.height) * sizeof(float));
    char* p = &out[header];
    for (int y = img.height; y-- > 0;) {
        for (std::size_t k = 0; k < row; ++k, p += sizeof(float)) {
            const float v = finite_value(img.rgb[std::size_t(y) * row + k], 1e30f);
            std::memcpy(p, &v, sizeof v);  // (x86: already little-endian)
        }
    }
    return out;
}

Status encode_exr(const Image& img, std::string& out) {
    try {
        std::vector<Imf::Rgba> px(std::size_t(img.width) * std::size_t(img.height));
        for (std::size_t i = 0; i < px.size(); ++i) {
            const float* c = &img.rgb[3 * i];
            px[i] = Imf::Rgba(finite_value(c[0], 65504.0f), finite_value(c[1], 65504.0f), finite_value(c[2], 65504.0f), 1);
        }
        StringStream stream;
        Imf::Header header(img.width, img.height);
        Imf::RgbaOutputFile file(stream, header, Imf::WRITE_RGB, 1);
        file.setFrameBuffer(px.data(), 1, std::size_t(img.width));
        file.writePixels(img.height);
        out = std::move(stream.data);
    } catch (const std::exception& e) {
        return Status::error(std::string("EXR encoding failed: ") + e.what(), kExitUsage);
    }
    return {};
}

}  // namespace rt
