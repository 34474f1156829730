// The frame's probe records (see probe.h).
#include "probe.h"

#include <imgui.h>

#include <algorithm>
#include <cstdio>

namespace rtview {

namespace {
std::vector<std::pair<std::string, std::string>> g_probes;
}  // namespace

void probe(const std::string& key, const std::string& value) {
    std::string v = value.substr(0, 512);
    std::replace(v.begin(), v.end(), '\n', ' ');
    for (auto& p : g_probes)
        if (p.first == key) {
            p.second = std::move(v);
            return;
        }
    g_probes.emplace_back(key, std::move(v));
}

const std::vector<std::pair<std::string, std::string>>& probes() { return g_probes; }

void begin_probe_frame() { g_probes.clear(); }

void probe_item(const std::string& key) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    char rect[96];
    std::snprintf(rect, sizeof rect, "%.0f %.0f %.0f %.0f", a.x, a.y, b.x - a.x, b.y - a.y);
    probe(key, rect);
}

}  // namespace rtview
