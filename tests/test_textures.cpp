// Texture files: decoding (PNG of every bit depth and colour type, JPEG baseline,
// progressive and CMYK), sRGB to linear, bilinear repeating samples, the refusals of
// hostile files, the store's sharing, and the scene's `texture` key.
#include <doctest/doctest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "parallel.h"
#include "scene_parser.h"
#include "texture.h"
#include "test_util.h"
#include "test_textures.h"

using namespace rt;
using rt_test::TempDir;
using rt_test::put;

namespace {

// sRGB to linear by the standard's formula, written out again (not the core's).
double lin(double v8) {
    const double c = v8 / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

void check_colour(const Colour& got, const Colour& want, double eps = 1e-6) {
    CHECK(got.x == doctest::Approx(want.x).epsilon(eps));
    CHECK(got.y == doctest::Approx(want.y).epsilon(eps));
    CHECK(got.z == doctest::Approx(want.z).epsilon(eps));
}

std::shared_ptr<Texture> decode_ok(const std::string& bytes) {
    std::string error;
    std::shared_ptr<Texture> t = decode_texture(bytes, error);
    INFO(error);
    REQUIRE(t);
    return t;
}

std::string refused(const std::string& bytes) {
    std::string error;
    CHECK_FALSE(decode_texture(bytes, error));
    CHECK_FALSE(error.empty());
    return error;
}

// A lamp, a camera and an 8x6 picture: what a scene of a few things needs after them.
const std::string kSmallTail =
    "light { lamp { position 0 0 5 colour 1 1 1 } }\n"
    "camera { position 0 -5 1 centre 0 0 0 up 0 0 1 angle_x 40 angle_y 30 }\n"
    "picture_size { x_max 8 y_max 6 }\nend\n";

}  // namespace

TEST_CASE("textures: 8-bit RGB PNG texels are the file's values decoded from sRGB, rows from the top") {
    // 2 x 2: red, green on the top row; blue, (64, 128, 192) below.
    const auto t = decode_ok(rt_test::png_rgb8(2, 2, {255, 0, 0, 0, 255, 0, 0, 0, 255, 64, 128, 192}));
    CHECK(t->width() == 2);
    CHECK(t->height() == 2);
    check_colour(t->texel(0, 0), {1, 0, 0});
    check_colour(t->texel(1, 0), {0, 1, 0});
    check_colour(t->texel(0, 1), {0, 0, 1});
    check_colour(t->texel(1, 1), {lin(64), lin(128), lin(192)});
    // Wrapping.
    check_colour(t->texel(-1, 2), t->texel(1, 0));
}

TEST_CASE("textures: 8-bit texels are kept as bytes, read through a table of exactly the floats of the formula") {
    // Every level in each channel: a 256 x 1 image, red rising, green falling, blue
    // the level times 7 (mod 256).
    std::vector<unsigned char> rgb;
    for (int i = 0; i < 256; ++i) rgb.push_back((unsigned char)i), rgb.push_back((unsigned char)(255 - i)),
                                  rgb.push_back((unsigned char)(i * 7 % 256));
    const auto t = decode_ok(rt_test::png_rgb8(256, 1, rgb));
    REQUIRE(t->srgb8() != nullptr);
    CHECK(t->memory_bytes() == 256 * 3);  // a byte a channel, not a float
    const std::vector<float> f = t->texels();
    REQUIRE(f.size() == 256 * 3);
    for (int i = 0; i < 256; ++i) {
        INFO(i);
        // The very float that decoding into floats stored: the formula's value, rounded once.
        const Colour c = t->texel(i, 0);
        CHECK(c.x == double(float(lin(i))));
        CHECK(c.y == double(float(lin(255 - i))));
        CHECK(c.z == double(float(lin(i * 7 % 256))));
        CHECK(Texture::srgb8_table()[i] == float(lin(i)));
        CHECK(f[3 * std::size_t(i)] == float(lin(i)));
        CHECK(f[3 * std::size_t(i) + 2] == float(lin(i * 7 % 256)));
    }
    // The same texels as floats give the same samples, bit for bit, everywhere.
    const Texture floats(256, 1, f);
    CHECK(floats.srgb8() == nullptr);
    CHECK(floats.memory_bytes() == 256 * 3 * sizeof(float));
    for (double u = -1.3; u < 2; u += 0.0137) {
        const Colour a = t->sample(u, 0.5), b = floats.sample(u, 0.5);
        CHECK(a.x == b.x);
        CHECK(a.y == b.y);
        CHECK(a.z == b.z);
    }
    // Made from bytes: the same texels; missing bytes read black.
    const Texture bytes(256, 2, std::vector<std::uint8_t>(rgb.begin(), rgb.end()));
    for (int i = 0; i < 256; i += 5) {
        CHECK(bytes.texel(i, 0).x == t->texel(i, 0).x);
        CHECK(bytes.texel(i, 0).y == t->texel(i, 0).y);
        CHECK(bytes.texel(i, 1).x == 0);
        CHECK(bytes.texel(i, 1).z == 0);
    }
    // A 16-bit image keeps floats (its levels are too many for a table of 256).
    const auto deep = decode_ok(rt_test::png_raw(1, 1, 16, 2, {0xff, 0xff, 0x80, 0x00, 0x00, 0x00}));
    CHECK(deep->srgb8() == nullptr);
    CHECK(deep->memory_bytes() == 3 * sizeof(float));
}

TEST_CASE("textures: samples wrap at every edge as texel() does") {
    // 3 x 2 of distinct bytes: each sample near an edge is the bilinear mix of the four
    // texels around it, found through texel()'s general wrapping.
    std::vector<unsigned char> rgb;
    for (int i = 0; i < 18; ++i) rgb.push_back((unsigned char)(i * 14 + 3));
    const auto t = decode_ok(rt_test::png_rgb8(3, 2, rgb));
    for (double u : {0.0, 0.01, 1.0 / 6, 0.5, 0.99, 0.999999, 1.0, -1e-300, 5.2, -7.9})
        for (double v : {0.0, 0.01, 0.25, 0.74, 0.99, 1.0, -1e-300, -3.6}) {
            INFO(u << " " << v);
            const double uu = u - std::floor(u), vv = v - std::floor(v);
            const double x = uu * 3 - 0.5, y = (1 - vv) * 2 - 0.5, fx = std::floor(x), fy = std::floor(y);
            const double ax = x - fx, ay = y - fy;
            const long x0 = long(fx), y0 = long(fy);
            const Colour want = (t->texel(x0, y0) * (1 - ax) + t->texel(x0 + 1, y0) * ax) * (1 - ay) +
                                (t->texel(x0, y0 + 1) * (1 - ax) + t->texel(x0 + 1, y0 + 1) * ax) * ay;
            const Colour got = t->sample(u, v);
            CHECK(got.x == want.x);
            CHECK(got.y == want.y);
            CHECK(got.z == want.z);
        }
}

TEST_CASE("textures: samples are bilinear between texel centres and repeat") {
    // 2 x 1: black, then 255 (linear 1). v does not matter in a one-row image.
    const auto t = decode_ok(rt_test::png_rgb8(2, 1, {0, 0, 0, 255, 255, 255}));
    // Texel centres at u = 1/4 and 3/4.
    check_colour(t->sample(0.25, 0.5), {0, 0, 0});
    check_colour(t->sample(0.75, 0.5), {1, 1, 1});
    check_colour(t->sample(0.5, 0.1), {0.5, 0.5, 0.5});
    // u = 0: halfway between the last texel (white, wrapped) and the first.
    check_colour(t->sample(0.0, 0.5), {0.5, 0.5, 0.5});
    check_colour(t->sample(0.375, 0.5), {0.25, 0.25, 0.25});
    // Repeating: any whole number of repeats away, negative too.
    check_colour(t->sample(0.375 + 7, 0.5), {0.25, 0.25, 0.25});
    check_colour(t->sample(0.375 - 3, 0.5), {0.25, 0.25, 0.25});
    // Not finite: read as 0.
    check_colour(t->sample(NAN, INFINITY), t->sample(0, 0));
    // v runs bottom to top: in a 1 x 2 image, the top texel is v = 3/4.
    const auto col = decode_ok(rt_test::png_rgb8(1, 2, {255, 255, 255, 0, 0, 0}));
    check_colour(col->sample(0.5, 0.75), {1, 1, 1});
    check_colour(col->sample(0.5, 0.25), {0, 0, 0});
}

TEST_CASE("textures: 16-bit, grey, grey + alpha and RGBA PNG (alpha ignored)") {
    // 16-bit RGB: 65535, 32768, 0.
    {
        const auto t = decode_ok(rt_test::png_raw(1, 1, 16, 2, {0xff, 0xff, 0x80, 0x00, 0x00, 0x00}));
        const double half = 32768 / 65535.0;
        check_colour(t->texel(0, 0), {1, std::pow((half + 0.055) / 1.055, 2.4), 0});
    }
    // 16-bit grey.
    {
        const auto t = decode_ok(rt_test::png_raw(1, 1, 16, 0, {0x40, 0x00}));
        const double g = lin(0x4000 / 65535.0 * 255.0);
        check_colour(t->texel(0, 0), {g, g, g}, 1e-5);
    }
    // 8-bit grey + alpha: the alpha is dropped, the grey spread.
    {
        const auto t = decode_ok(rt_test::png_raw(2, 1, 8, 4, {100, 0, 200, 255}));
        check_colour(t->texel(0, 0), {lin(100), lin(100), lin(100)});
        check_colour(t->texel(1, 0), {lin(200), lin(200), lin(200)});
    }
    // RGBA: alpha 0 changes nothing.
    {
        const auto t = decode_ok(rt_test::png_raw(1, 1, 8, 6, {10, 20, 30, 0}));
        check_colour(t->texel(0, 0), {lin(10), lin(20), lin(30)});
    }
}

TEST_CASE("textures: progressive and CMYK JPEG decode to the colour they were made of") {
    // Both 16 x 16 of sRGB (200, 100, 50), written by ImageMagick (CMYK: converted).
    for (const char* name : {"progressive.jpg", "cmyk.jpg"}) {
        INFO(name);
        std::string error;
        const auto t = read_texture(std::string(RT_SOURCE_DIR "/tests/textures/") + name, error);
        INFO(error);
        REQUIRE(t);
        CHECK(t->width() == 16);
        CHECK(t->height() == 16);
        // JPEG is lossy, and CMYK goes through ImageMagick's conversion: a few levels.
        const Colour c = t->texel(7, 7);
        CHECK(std::fabs(c.x - lin(200)) < 0.03);
        CHECK(std::fabs(c.y - lin(100)) < 0.03);
        CHECK(std::fabs(c.z - lin(50)) < 0.03);
    }
}

TEST_CASE("textures: hostile bytes are refused with the reason, huge headers before anything is allocated") {
    CHECK(refused("").find("empty") != std::string::npos);
    CHECK(refused("hello, not an image at all").find("not a PNG or JPEG") != std::string::npos);
    // TGA has no signature: stb would take these bytes as one; they are refused first.
    CHECK(refused(std::string("\0\0\2\0\0\0\0\0\0\0\0\0\1\0\1\0\x18\0\1\2\3", 21)).find("not a PNG") !=
          std::string::npos);
    const std::string good = rt_test::png_rgb8(4, 4, std::vector<unsigned char>(48, 77));
    // Truncated anywhere: refused (or, cut in the trailer only, decoded whole).
    for (std::size_t n = 1; n < good.size(); n += 3) {
        std::string error;
        const auto t = decode_texture(good.substr(0, n), error);
        if (!t) CHECK_FALSE(error.empty());
        if (t) CHECK(t->width() == 4);
    }
    // A header claiming 100000 x 100000 pixels, with no data: refused by its size,
    // which the message names.
    const std::string huge = rt_test::png_header_only(100000, 100000);
    const std::string e = refused(huge);
    CHECK(e.find("100000 x 100000") != std::string::npos);
    CHECK(e.find("too large") != std::string::npos);
    // Within the side limit but over the texel limit.
    CHECK(refused(rt_test::png_header_only(16384, 16384)).find("16384 x 16384") != std::string::npos);
    // A data chunk claiming 2 GB in a file of a few bytes (stb_image would allocate
    // the 2 GB before reading): refused first.
    std::string claim = good.substr(0, 33) + std::string("\x7f\xff\xff\xf0IDAT", 8) + "xxxx";
    CHECK(refused(claim).find("a chunk runs past the end") != std::string::npos);
    // A JPEG start and nothing more.
    CHECK(refused("\xff\xd8\xff").find("JPEG") != std::string::npos);
    // A Huffman table claiming 16 x 255 codes (stb_image would write past its tables):
    // refused before stb_image reads it, by decode_texture and image_size alike.
    std::string dht = std::string("\xff\xd8\xff\xc4\x00\x13\x00", 7) + std::string(16, '\xff');
    CHECK(refused(dht).find("Huffman table") != std::string::npos);
    long long w = 0, h = 0;
    CHECK_FALSE(image_size(dht, w, h));
    // The inputs fuzz_texture found it with: one table of 1,900 codes; one whose
    // segment ends within its counts, which stb_image reads on past the segment.
    // And a scan using a table no DHT defined (stb_image decodes it with whatever
    // its memory held: an assertion of its own fired, depending on earlier inputs).
    for (const char* name : {"jpeg-huffman-over-256", "jpeg-huffman-past-segment", "jpeg-undefined-huffman-table"}) {
        const std::string found = rt_test::slurp(std::string(RT_SOURCE_DIR "/tests/fuzz/regressions/") + name);
        REQUIRE_FALSE(found.empty());
        CHECK(refused(found).find("Huffman table") != std::string::npos);
    }
    // A table of exactly 256 codes (255 of 8 bits, 1 of 9) is not refused by that
    // check: what else is wrong with the file is stb_image's to say.
    dht = std::string("\xff\xd8\xff\xc4\x01\x13\x00", 7) + std::string(7, '\0') + "\xff\x01" +
          std::string(7, '\0') + std::string(256, '\x05');
    CHECK(refused(dht).find("Huffman table") == std::string::npos);
}

TEST_CASE("textures: special files are refused at once, never waited on") {
    TempDir dir("rt-tex");
    std::string error;
    CHECK_FALSE(read_texture(dir.path.string(), error));
    CHECK(error.find("folder") != std::string::npos);
    CHECK_FALSE(read_texture("/dev/zero", error));
    CHECK(error.find("not a regular file") != std::string::npos);
    const std::string fifo = (dir / "pipe.png").string();
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    CHECK_FALSE(read_texture(fifo, error));  // would block in open() or read() if it waited
    CHECK(error.find("not a regular file") != std::string::npos);
    CHECK_FALSE(read_texture((dir / "missing.png").string(), error));
    CHECK(error.find("No such file") != std::string::npos);
    put(dir / "empty.png", "");
    CHECK_FALSE(read_texture((dir / "empty.png").string(), error));
    CHECK(error.find("empty") != std::string::npos);
}

TEST_CASE("textures: the store decodes a file once while it is held, again when it changes") {
    TempDir dir("rt-tex");
    const std::string path = (dir / "a.png").string();
    put(path, rt_test::png_rgb8(1, 1, {255, 0, 0}));
    TextureStore store;
    TextureStore::Loaded a = store.load(path), b = store.load(path);
    REQUIRE(a.texture);
    CHECK(a.texture == b.texture);
    CHECK(a.texture->unchanged_on_disk());
    // A different size on disk: read again.
    put(path, rt_test::png_rgb8(2, 1, {0, 255, 0, 0, 255, 0}));
    CHECK_FALSE(a.texture->unchanged_on_disk());
    TextureStore::Loaded c = store.load(path);
    REQUIRE(c.texture);
    CHECK(c.texture != a.texture);
    CHECK(c.texture->width() == 2);
}

TEST_CASE("textures: a scene's materials naming one file share one decoded copy; errors at the file name") {
    TempDir dir("rt-tex");
    put(dir / "wood.png", rt_test::png_rgb8(2, 2, std::vector<unsigned char>(12, 200)));
    put(dir / "bad.png", "not an image");
    ParseOptions o;
    o.base_dir = dir.path.string();
    const std::string& tail = kSmallTail;
    {
        const ParseResult r = parse_scene(
            "thing { sphere { position 0 0 0 radius 1 material { texture \"wood.png\" } }\n"
            "        sphere { position 3 0 0 radius 1 material { texture wood.png texture_scale 2 } } }\n"
            "special_thing { plane { material { texture \"wood.png\" } } }\n" + tail,
            o);
        REQUIRE(r.ok());
        const auto& a = r.scene.objects[0].material.texture_image;
        REQUIRE(a);
        CHECK(a == r.scene.objects[1].material.texture_image);
        CHECK(a == r.scene.planes[0].material.texture_image);
        CHECK(r.scene.objects[1].material.texture_scale == 2);
    }
    auto first_error = [&](const std::string& text) {
        const ParseResult r = parse_scene(text + tail, o);
        REQUIRE_FALSE(r.ok());
        return format_diagnostic("s.txt", r.diagnostics.front());
    };
    CHECK(first_error("thing { sphere { material { texture \"bad.png\" } } }\n") ==
          "s.txt:1:37: error: bad.png: not a PNG or JPEG image");
    CHECK(first_error("thing { sphere { material { colour 1 1 1\n  texture missing.png } } }\n")
              .rfind("s.txt:2:11: error: missing.png: No such file", 0) == 0);
    CHECK(first_error("thing { sphere { material { texture_scale -1 } } }\n").find("texture_scale must be greater than 0") !=
          std::string::npos);
    // Not read when the options say so: the name stays, the image is null.
    o.read_textures = false;
    const ParseResult r = parse_scene("thing { sphere { material { texture \"bad.png\" } } }\n" + tail, o);
    CHECK(r.ok());
    CHECK(r.scene.objects[0].material.texture == "bad.png");
    CHECK_FALSE(r.scene.objects[0].material.texture_image);
    // Nor when models are not read: text checks read no files.
    o.read_textures = true;
    o.read_models = false;
    CHECK(parse_scene("thing { sphere { material { texture \"bad.png\" } } }\n" + tail, o).ok());
}

namespace {

// A PNG whose structure and header are sound but whose compressed data is not: only
// decoding it finds that out.
std::string png_bad_data() {
    std::string png = rt_test::png_rgb8(4, 4, std::vector<unsigned char>(48, 77));
    const std::size_t idat = png.find("IDAT");
    REQUIRE(idat != std::string::npos);
    png[idat + 4] = '\x78', png[idat + 5] = '\x00';  // a zlib header whose check bits are wrong
    return png;
}

}  // namespace

TEST_CASE("textures: read later, decoded on the pool: the same texels, and a late failure said by wait()") {
    TempDir dir("rt-tex-later");
    std::vector<unsigned char> rgb;
    for (int i = 0; i < 64 * 48 * 3; ++i) rgb.push_back((unsigned char)(i * 31 % 256));
    put(dir / "big.png", rt_test::png_rgb8(64, 48, rgb));
    put(dir / "bad-data.png", png_bad_data());
    std::string error;
    const auto now = read_texture((dir / "big.png").string(), error);
    REQUIRE(now);
    for (int round = 0; round < 20; ++round) {
        const auto later = read_texture((dir / "big.png").string(), error, true);
        REQUIRE(later);
        // The size at once, from the header.
        CHECK(later->width() == 64);
        CHECK(later->height() == 48);
        // Waited for by several threads at once (or, on odd rounds, first read by a
        // sample, which waits itself): each finds the same texels.
        std::vector<std::string> said(3);
        if (round % 2) CHECK(later->sample(0.3, 0.6).x == now->sample(0.3, 0.6).x);
        process_pool().parallel_for(3, [&](int k) { said[std::size_t(k)] = later->wait(); });
        for (const std::string& e : said) CHECK(e.empty());
        CHECK(later->decoded());
        CHECK(later->texels() == now->texels());
        CHECK(later->memory_bytes() == now->memory_bytes());
        CHECK(later->file_id() == now->file_id());
    }
    // Sound on the outside, bad inside: read, then refused by wait(); reads black.
    const auto bad = read_texture((dir / "bad-data.png").string(), error, true);
    REQUIRE(bad);
    const std::string e = bad->wait();
    CHECK(e.find("cannot be decoded") != std::string::npos);
    CHECK(bad->wait() == e);
    CHECK(bad->texel(1, 1).x == 0);
    CHECK(bad->sample(0.5, 0.5).y == 0);
    CHECK(bad->texels().empty());
    // Read now, the same file is refused at once with the same reason.
    CHECK_FALSE(read_texture((dir / "bad-data.png").string(), error));
    CHECK(error == e);
    // Through the store: a `later` load hands out the texture; a plain one waits and
    // gives the failure as its error.
    TextureStore store;
    const TextureStore::Loaded l = store.load((dir / "bad-data.png").string(), true);
    REQUIRE(l.texture);
    const TextureStore::Loaded plain = store.load((dir / "bad-data.png").string());
    CHECK_FALSE(plain.texture);
    CHECK(plain.error == e);
}

TEST_CASE("textures: the scene's textures decode while it is read; a late failure is an error at the file name") {
    TempDir dir("rt-tex-late");
    put(dir / "wood.png", rt_test::png_rgb8(2, 2, std::vector<unsigned char>(12, 200)));
    put(dir / "bad-data.png", png_bad_data());
    put(dir / "part.txt", "\nthing { sphere { material {\n  texture \"bad-data.png\" } } }\n");
    ParseOptions o;
    o.base_dir = dir.path.string();
    const std::string& tail = kSmallTail;
    {
        const ParseResult r = parse_scene("thing { sphere { material { texture \"wood.png\" } } }\n" + tail, o);
        REQUIRE(r.ok());
        const auto& t = r.scene.objects[0].material.texture_image;
        REQUIRE(t);
        CHECK(t->decoded());  // the parse has waited
        CHECK(t->texel(1, 1).x == double(float(lin(200))));
    }
    auto errors = [&](const std::string& text) {
        const ParseResult r = parse_scene(text + tail, o);
        std::string out;
        for (const Diagnostic& d : r.diagnostics)
            if (d.is_error()) out += format_diagnostic("s.txt", d) + "\n";
        return out;
    };
    const std::string why = [&] {
        std::string e;
        read_texture((dir / "bad-data.png").string(), e);
        return e;
    }();
    REQUIRE_FALSE(why.empty());
    // In the scene file, in the order of the file with the other errors.
    CHECK(errors("thing { sphere { material { texture \"bad-data.png\" } } }\n"
                 "thing { sphere { radius -1 } }\n") ==
          "s.txt:1:37: error: bad-data.png: " + why + "\ns.txt:2:25: error: sphere radius must be greater than 0\n");
    // In an included file: there, with the include.
    CHECK(errors("include \"part.txt\"\n") ==
          (dir / "part.txt").string() + ":3:11: error: bad-data.png: " + why + " (included from s.txt:1:1)\n");
}
