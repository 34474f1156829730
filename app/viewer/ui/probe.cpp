// The frame's probe records (see probe.h).
#include "probe.h"

#include <algorithm>

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

}  // namespace rtview
