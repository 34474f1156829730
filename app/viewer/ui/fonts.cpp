// UI font and style (see fonts.h).
#include "fonts.h"

#include <imgui.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "ui_settings.h"

namespace rtview {

namespace {

// A TrueType or OpenType file by its first four bytes: ImGui 1.86 asserts on other data.
bool looks_like_font(const std::vector<char>& data) {
    if (data.size() < 12) return false;
    const unsigned char* p = reinterpret_cast<const unsigned char*>(data.data());
    return (p[0] == 0 && p[1] == 1 && p[2] == 0 && p[3] == 0) || std::memcmp(p, "true", 4) == 0 ||
           std::memcmp(p, "OTTO", 4) == 0;
}

ImVec4 colour(const Rgb& c, float alpha = 1) { return ImVec4(c.r, c.g, c.b, alpha); }

void style_for(float scale) {
    ImGuiStyle& style = ImGui::GetStyle();
    style = ImGuiStyle();
    ImGui::StyleColorsDark(&style);
    // White text on ImGui's yellow progress bar is hard to read (contrast 1.9):
    // a blue with 6:1 against white. Hints were mid grey on black: lighter now.
    style.Colors[ImGuiCol_PlotHistogram] = colour(kProgressFill);
    style.Colors[ImGuiCol_PlotHistogramHovered] = colour(kProgressFill);
    style.Colors[ImGuiCol_TextDisabled] = colour(kHintText);
    style.ScaleAllSizes(scale);
}

}  // namespace

UiFont build_ui_font_and_style(float scale) {
    if (!(scale > 0.1f)) scale = 1;
    ImGuiIO& io = ImGui::GetIO();
    io.Fonts->Clear();
    UiFont result;
    std::string path = find_ui_font();
    if (!path.empty()) {
        std::ifstream in(path, std::ios::binary);
        std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (looks_like_font(data) && data.size() < (64u << 20)) {
            // The atlas takes ownership of memory from ImGui's allocator.
            void* mem = IM_ALLOC(data.size());
            std::memcpy(mem, data.data(), data.size());
            ImFontConfig cfg;
            cfg.OversampleH = 2;
            cfg.PixelSnapH = true;
            float px = std::round(kUiFontPixels * scale);
            if (io.Fonts->AddFontFromMemoryTTF(mem, int(data.size()), px, &cfg) && io.Fonts->Build()) {
                result.path = path;
                result.pixels = px;
            } else {
                io.Fonts->Clear();
            }
        }
    }
    if (result.path.empty()) {
        ImFontConfig cfg;
        cfg.SizePixels = std::round(kFallbackFontPixels * scale);
        io.Fonts->AddFontDefault(&cfg);
        io.Fonts->Build();
        result.pixels = cfg.SizePixels;
    }
    style_for(scale);
    return result;
}

}  // namespace rtview
