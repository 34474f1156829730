// Render region (see region.h).
#include "region.h"

#include <algorithm>
#include <cmath>

namespace rtview {

PixelRect region_from_drag(const ViewTransform& t, int film_w, int film_h, double ax, double ay, double bx, double by) {
    double u0 = std::floor(t.to_picture_x(std::min(ax, bx))), u1 = std::floor(t.to_picture_x(std::max(ax, bx)));
    double v0 = std::floor(t.to_picture_y(std::min(ay, by))), v1 = std::floor(t.to_picture_y(std::max(ay, by)));
    PixelRect r;
    r.x0 = int(std::clamp(u0, 0.0, double(film_w)));
    r.y0 = int(std::clamp(v0, 0.0, double(film_h)));
    r.x1 = int(std::clamp(u1 + 1, 0.0, double(film_w)));
    r.y1 = int(std::clamp(v1 + 1, 0.0, double(film_h)));
    if (r.empty()) return {};
    return r;
}

void paste_region(const RegionPicture& reg, rt::Image& full) {
    const PixelRect& r = reg.rect;
    if (r.empty() || r.x1 > full.width || r.y1 > full.height || r.x0 < 0 || r.y0 < 0) return;
    for (int y = r.y0; y < r.y1; ++y) {
        if (reg.row_samples[std::size_t(y - r.y0)] == 0) continue;
        const float* src = &reg.image.rgb[3 * std::size_t(y - r.y0) * r.width()];
        std::copy(src, src + 3 * r.width(), &full.rgb[3 * (std::size_t(y) * full.width + r.x0)]);
    }
}

void paste_region_rgba8(const RegionPicture& reg, const DisplaySettings& s, int width, std::vector<std::uint8_t>& rgba) {
    const PixelRect& r = reg.rect;
    if (r.empty() || r.x0 < 0 || r.y0 < 0 || r.x1 > width || rgba.size() < 4 * std::size_t(width) * r.y1) return;
    std::vector<std::uint8_t> local;
    map_to_rgba8(reg.image, s, local);
    for (int y = r.y0; y < r.y1; ++y) {
        if (reg.row_samples[std::size_t(y - r.y0)] == 0) continue;
        const std::uint8_t* src = &local[4 * std::size_t(y - r.y0) * r.width()];
        std::copy(src, src + 4 * r.width(), &rgba[4 * (std::size_t(y) * width + r.x0)]);
    }
}

void RegionRenderer::start(std::shared_ptr<const rt::World> world, const rt::Camera& camera, int width, int height,
                           const PixelRect& rect, int max_samples, double time_limit) {
    cancel();
    if (!world || rect.empty() || rect.x0 < 0 || rect.y0 < 0 || rect.x1 > width || rect.y1 > height) return;
    rt::RenderSettings st;
    st.width = width;
    st.height = height;
    st.camera = camera;
    st.crop = rect;
    st.max_samples = std::max(1, max_samples);
    st.time_limit = time_limit;
    rect_ = rect;
    active_ = true;
    renderer_.start(std::move(world), st);
}

void RegionRenderer::cancel() {
    active_ = false;
    renderer_.cancel();
}

bool RegionRenderer::raise_samples(int max_samples) { return active() && renderer_.raise_samples(max_samples); }

bool RegionRenderer::done() const { return active() && renderer_.progress().done; }

std::string RegionRenderer::error() const { return active() ? renderer_.progress().error : std::string(); }

int RegionRenderer::samples() const { return active() ? renderer_.progress().samples : 0; }

bool RegionRenderer::snapshot(RegionPicture& out, std::uint64_t& version) const {
    if (!active() || renderer_.film_version() == version) return false;
    std::vector<std::uint32_t> counts;
    out.samples = renderer_.progress().samples;
    version = renderer_.snapshot_window(rect_, out.image, counts);
    out.rect = rect_;
    const int w = rect_.width();
    out.row_samples.assign(std::size_t(rect_.height()), 0);
    for (int r = 0; r < rect_.height(); ++r) {
        const auto row = counts.begin() + std::ptrdiff_t(r) * w;
        out.row_samples[std::size_t(r)] = int(*std::min_element(row, row + w));
    }
    return true;
}

}  // namespace rtview
