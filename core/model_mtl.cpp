// Wavefront MTL files (the materials an OBJ names with mtllib), read line by line into
// the scene's materials:
//   Kd r [g b]  -> colour                 Ks r [g b] -> specular (largest, 0..1)
//   Ns n        -> shininess (1..10000)   d a        -> refraction 1 - a
//   Tr t        -> refraction t           Ni n       -> refractive_index (at least 1)
//   map_Kd [options] FILE -> texture
// A material with refraction scatters the rest (scattering 1 - refraction).
#include <algorithm>
#include <charconv>
#include <cmath>

#include "model_readers.h"

namespace rt {

namespace {

std::vector<std::string_view> words(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < line.size() && out.size() < 64) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        std::size_t j = i;
        while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
        if (j > i) out.push_back(line.substr(i, j - i));
        i = j;
    }
    return out;
}

bool number(std::string_view w, double& v) {
    if (!w.empty() && w[0] == '+') w.remove_prefix(1);
    const auto r = std::from_chars(w.data(), w.data() + w.size(), v);
    return r.ec == std::errc() && r.ptr == w.data() + w.size() && std::isfinite(v) && std::fabs(v) <= 1e15;
}

bool same(std::string_view a, std::string_view b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
    return true;
}

// map_Kd's options and how many values each takes (at most; -o, -s and -t take 1 to 3).
int option_values(std::string_view o) {
    static constexpr std::pair<std::string_view, int> table[] = {
        {"-blendu", 1}, {"-blendv", 1}, {"-boost", 1}, {"-cc", 1}, {"-clamp", 1}, {"-imfchan", 1}, {"-texres", 1},
        {"-bm", 1},     {"-mm", 2},     {"-o", 3},     {"-s", 3},  {"-t", 3},     {"-type", 1}};
    for (const auto& [name, n] : table)
        if (same(name, o)) return n;
    return -1;
}

// `map_Kd [options] FILE`: the file name after the options (the rest of the line, so
// it may hold spaces), backslashes made slashes. Empty with `why` set if unusable.
std::string map_file(std::string_view line, const std::vector<std::string_view>& w, std::string& why) {
    std::size_t i = 1;
    while (i < w.size() && w[i].size() > 1 && w[i][0] == '-' && option_values(w[i]) >= 0) {
        const int n = option_values(w[i]);
        ++i;
        double v;
        for (int k = 0; k < n && i + 1 < w.size() && (number(w[i], v) || n == 1); ++k) ++i;
    }
    if (i >= w.size()) return why = "map_Kd needs a file name", "";
    std::string_view file = line.substr(std::size_t(w[i].data() - line.data()));
    while (!file.empty() && (file.back() == ' ' || file.back() == '\t')) file.remove_suffix(1);
    if (file.size() > 4096) return why = "map_Kd file name too long", "";
    std::string f(file);
    std::replace(f.begin(), f.end(), '\\', '/');
    for (char c : f)
        if (static_cast<unsigned char>(c) < 0x20) return why = "map_Kd file name holds a control character", "";
    return f;
}

// A statement of numbers (Kd, Ks, Ns, d, Tr, Ni) into `m`; false with `why` set.
bool numbers(std::string_view key, const std::vector<std::string_view>& w, Material& m, std::string& why) {
    std::vector<double> v;
    for (std::size_t i = 1; i < w.size(); ++i) {
        double x;
        if (!number(w[i], x)) {
            why = std::string(key) + " value '" + std::string(w[i].substr(0, 40)) + "' is not a number" +
                  (same(w[i], "spectral") || same(w[i], "xyz") ? " (spectral and xyz colours are not read)" : "");
            return false;
        }
        v.push_back(x);
    }
    const bool colour = same(key, "Kd") || same(key, "Ks");
    if (colour ? (v.size() != 1 && v.size() != 3) : v.size() != 1) {
        why = std::string(key) + (colour ? " needs 1 or 3 numbers" : " needs 1 number");
        return false;
    }
    if (v.size() == 1) v.resize(3, v[0]);
    if (same(key, "Kd")) {
        m.colour = {v[0], v[1], v[2]};
    } else if (same(key, "Ks")) {
        m.specular = std::clamp(std::max({v[0], v[1], v[2]}), 0.0, 1.0);
    } else if (same(key, "Ns")) {
        m.shininess = std::clamp(v[0], 1.0, 10000.0);
    } else if (same(key, "d")) {
        m.refraction = std::clamp(1 - v[0], 0.0, 1.0);
    } else if (same(key, "Tr")) {
        m.refraction = std::clamp(v[0], 0.0, 1.0);
    } else {
        m.refractive_index = std::max(1.0, v[0]);
    }
    m.scattering = 1 - m.refraction;
    return true;
}

}  // namespace

bool read_mtl(std::string_view text, std::vector<MtlMaterial>& out, ModelError& error) {
    out.clear();
    long line_no = 0;
    MtlMaterial* cur = nullptr;
    std::string why;
    auto fail = [&](std::string message) {
        error.line = line_no;
        error.message = std::move(message);
        return false;
    };
    for (std::size_t at = 0; at <= text.size();) {
        std::size_t end = at;
        while (end < text.size() && text[end] != '\n' && text[end] != '\r') ++end;
        std::string_view line = text.substr(at, end - at);
        ++line_no;
        at = end + 1;
        if (end < text.size() && text[end] == '\r' && at < text.size() && text[at] == '\n') ++at;
        if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
        const std::vector<std::string_view> w = words(line);
        if (w.empty()) continue;
        const std::string_view key = w[0];
        if (same(key, "newmtl")) {
            if (out.size() >= MeshData::max_materials)
                return fail("too many materials (limit " + std::to_string(MeshData::max_materials) + ")");
            // The name is the rest of the line (names may hold spaces; Blender writes
            // an empty one, which `usemtl` with no name uses).
            std::string_view name = w.size() < 2 ? std::string_view() : line.substr(std::size_t(w[1].data() - line.data()));
            while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
            out.emplace_back();
            out.back().name = std::string(name.substr(0, 4096));
            cur = &out.back();
            continue;
        }
        const bool map = same(key, "map_Kd");
        if (!map && !same(key, "Kd") && !same(key, "Ks") && !same(key, "Ns") && !same(key, "d") && !same(key, "Tr") &&
            !same(key, "Ni"))
            continue;  // Ka, Ke, illum, other maps...: not used
        if (!cur) return fail(std::string(key) + " before any newmtl");
        if (map) {
            cur->texture = map_file(line, w, why);
            if (cur->texture.empty()) return fail(why);
            cur->texture_line = line_no;
        } else if (!numbers(key, w, cur->material, why)) {
            return fail(why);
        }
    }
    return true;
}

}  // namespace rt
