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

namespace {

// Adds the TrueType file at `path` to the atlas at `px` pixels; null if it is not a
// readable font.
ImFont* add_font_file(const std::string& path, float px) {
    if (path.empty()) return nullptr;
    std::ifstream in(path, std::ios::binary);
    std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!looks_like_font(data) || data.size() >= (64u << 20)) return nullptr;
    // The atlas takes ownership of memory from ImGui's allocator.
    void* mem = IM_ALLOC(data.size());
    std::memcpy(mem, data.data(), data.size());
    ImFontConfig cfg;
    cfg.OversampleH = 2;
    cfg.PixelSnapH = true;
    return ImGui::GetIO().Fonts->AddFontFromMemoryTTF(mem, int(data.size()), px, &cfg);
}

ImFont* add_builtin_font(float px) {
    ImFontConfig cfg;
    cfg.SizePixels = px;
    return ImGui::GetIO().Fonts->AddFontDefault(&cfg);
}

// Which of the atlas's fonts is the fixed-width one (an index, not a pointer: the
// atlas may be rebuilt or belong to another context by the time it is asked for).
int g_mono_index = -1;

int index_of(ImFont* f) {
    const ImVector<ImFont*>& fonts = ImGui::GetIO().Fonts->Fonts;
    for (int k = 0; k < fonts.Size; ++k)
        if (fonts[k] == f) return k;
    return -1;
}

}  // namespace

UiFont build_ui_font_and_style(float scale) {
    if (!(scale > 0.1f)) scale = 1;
    ImGuiIO& io = ImGui::GetIO();
    io.Fonts->Clear();
    g_mono_index = -1;
    UiFont result;
    // The UI's face first (ImGui's default font is the atlas's first), then the
    // fixed-width one, at the same size, so that text in either lines up.
    const float px = std::round(kUiFontPixels * scale);
    const std::string ui_path = find_ui_font(), mono_path = find_mono_font();
    ImFont* ui = add_font_file(ui_path, px);
    ImFont* mono = ui ? add_font_file(mono_path, px) : nullptr;
    if (ui && !mono) mono = add_builtin_font(px);  // fixed-width, if blurred when scaled
    if (ui && io.Fonts->Build()) {
        result.path = ui_path;
        result.mono_path = mono_path;
        result.pixels = px;
    } else {
        // No TrueType face (or one that does not build): ImGui's own bitmap font at
        // its native size serves as both.
        io.Fonts->Clear();
        const float bitmap_px = std::round(kFallbackFontPixels * scale);
        mono = add_builtin_font(bitmap_px);
        io.Fonts->Build();
        result.pixels = bitmap_px;
    }
    g_mono_index = index_of(mono);
    style_for(scale);
    return result;
}

ImFont* mono_font() {
    const ImVector<ImFont*>& fonts = ImGui::GetIO().Fonts->Fonts;
    if (g_mono_index >= 0 && g_mono_index < fonts.Size && fonts[g_mono_index]->IsLoaded()) return fonts[g_mono_index];
    return ImGui::GetFont();
}

}  // namespace rtview
