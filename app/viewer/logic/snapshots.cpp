// Snapshot store, scene change descriptions and difference images (see snapshots.h).
#include "snapshots.h"

#include <algorithm>
#include <cmath>

namespace rtview {

std::size_t object_bytes(const rt::Object& o) {
    std::size_t n = sizeof(rt::Object);
    if (auto* g = std::get_if<rt::Csg>(&o.shape))
        for (const rt::Object& k : g->operands) n += object_bytes(k);
    return n;
}

std::size_t Snapshot::bytes() const {
    std::size_t n = sizeof(Snapshot) + image.rgb.size() * sizeof(float) + change.size();
    for (const rt::Object& o : scene.objects) n += object_bytes(o);
    n += scene.planes.size() * sizeof(rt::Plane) + scene.lights.size() * sizeof(rt::Light);
    return n;
}

const Snapshot* SnapshotStore::add(rt::Image image, int samples, const rt::Scene& scene, std::time_t time) {
    Snapshot s;
    s.image = std::move(image);
    s.samples = samples;
    s.time = time;
    s.scene = scene;
    if (!items_.empty()) s.change = describe_change(items_.back().scene, scene);
    std::size_t need = s.bytes();
    if (need > max_bytes_ || max_count_ == 0) return nullptr;
    while (!items_.empty() && (items_.size() + 1 > max_count_ || bytes() + need > max_bytes_))
        items_.erase(items_.begin());
    s.id = next_id_++;
    items_.push_back(std::move(s));
    return &items_.back();
}

const Snapshot* SnapshotStore::find(int id) const {
    for (const Snapshot& s : items_)
        if (s.id == id) return &s;
    return nullptr;
}

bool SnapshotStore::remove(int id) {
    auto it = std::find_if(items_.begin(), items_.end(), [&](const Snapshot& s) { return s.id == id; });
    if (it == items_.end()) return false;
    items_.erase(it);
    return true;
}

std::size_t SnapshotStore::bytes() const {
    std::size_t n = 0;
    for (const Snapshot& s : items_) n += s.bytes();
    return n;
}

std::string describe_change(const rt::Scene& a, const rt::Scene& b, int max_items) {
    std::vector<std::string> items;
    if (!(a.camera == b.camera)) items.push_back("camera");
    if (a.width != b.width || a.height != b.height) items.push_back("picture size");
    auto list = [&](const auto& xs, const auto& ys, const char* noun, auto&& detail) {
        if (xs.size() != ys.size()) {
            items.push_back(std::string(noun) + "s " + std::to_string(xs.size()) + " -> " + std::to_string(ys.size()));
            return;
        }
        for (std::size_t k = 0; k < xs.size(); ++k)
            if (!(xs[k] == ys[k])) items.push_back(detail(xs[k], ys[k]) + std::string(noun) + " " + std::to_string(k + 1));
    };
    list(a.objects, b.objects, "object", [](const rt::Object& x, const rt::Object& y) {
        return x.shape == y.shape ? std::string("material of ") : std::string();
    });
    list(a.planes, b.planes, "plane", [](const rt::Plane& x, const rt::Plane& y) {
        bool same_place = std::equal(std::begin(x.point), std::end(x.point), std::begin(y.point)) && x.chess == y.chess;
        return same_place ? std::string("material of ") : std::string();
    });
    list(a.lights, b.lights, "light", [](const rt::Light&, const rt::Light&) { return std::string(); });
    if (items.empty()) return "no change";
    std::string s;
    int shown = 0;
    for (const std::string& it : items) {
        if (shown == max_items) {
            s += "; " + std::to_string(items.size() - std::size_t(shown)) + " more";
            break;
        }
        if (shown++) s += "; ";
        s += it;
    }
    return s;
}

bool difference_rgba8(const rt::Image& a, const rt::Image& b, double scale, std::vector<std::uint8_t>& rgba,
                      DiffStats* stats) {
    if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size()) return false;
    const std::size_t n = std::size_t(a.width) * a.height;
    rgba.resize(4 * n);
    DiffStats st;
    double total = 0;
    for (std::size_t i = 0; i < n; ++i) {
        bool differs = false;
        for (int c = 0; c < 3; ++c) {
            double d = std::fabs(double(a.rgb[3 * i + c]) - double(b.rgb[3 * i + c]));
            if (std::isnan(d)) d = 0;  // NaN on one side only: nothing to measure
            differs |= d > 0;
            st.max_abs = std::max(st.max_abs, d);
            total += d;
            rgba[4 * i + c] = rt::to_byte(d * scale);
        }
        rgba[4 * i + 3] = 255;
        st.differing += differs;
    }
    st.mean_abs = n ? total / double(3 * n) : 0;
    if (stats) *stats = st;
    return true;
}

rt::Image resample_nearest(const rt::Image& img, int width, int height) {
    rt::Image out;
    out.width = std::max(0, width);
    out.height = std::max(0, height);
    out.rgb.assign(std::size_t(out.width) * out.height * 3, 0.f);
    if (img.width < 1 || img.height < 1) return out;
    for (int y = 0; y < out.height; ++y) {
        int sy = std::min(img.height - 1, int((y + 0.5) * img.height / out.height));
        for (int x = 0; x < out.width; ++x) {
            int sx = std::min(img.width - 1, int((x + 0.5) * img.width / out.width));
            const float* p = &img.rgb[3 * (std::size_t(sy) * img.width + sx)];
            std::copy(p, p + 3, &out.rgb[3 * (std::size_t(y) * out.width + x)]);
        }
    }
    return out;
}

}  // namespace rtview
