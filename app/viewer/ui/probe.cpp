// The frame's probe records (see probe.h).
#include "probe.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

namespace rtview {

namespace {
std::vector<std::pair<std::string, std::string>> g_probes;
}  // namespace

void probe(const std::string& name, const std::string& value) {
    std::string v = value.substr(0, 512);
    std::replace(v.begin(), v.end(), '\n', ' ');
    std::string key = name;
    std::replace(key.begin(), key.end(), ' ', '_');
    for (auto& p : g_probes)
        if (p.first == key) {
            p.second = std::move(v);
            return;
        }
    g_probes.emplace_back(key, std::move(v));
}

void probe_item(const std::string& key) {
    if (!ImGui::IsItemVisible()) return;  // (scrolled out of its window: not on the screen)
    const float fb = ImGui::GetIO().DisplayFramebufferScale.x > 0 ? ImGui::GetIO().DisplayFramebufferScale.x : 1.f;
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    probe(key, std::to_string(std::lround(a.x * fb)) + " " + std::to_string(std::lround(a.y * fb)) + " " +
                   std::to_string(std::lround((b.x - a.x) * fb)) + " " + std::to_string(std::lround((b.y - a.y) * fb)));
}

const std::vector<std::pair<std::string, std::string>>& probes() { return g_probes; }

void begin_probe_frame() { g_probes.clear(); }

}  // namespace rtview
