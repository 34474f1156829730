// The bytes the film texture shows, kept up to date each frame from the renderer:
// with the default display settings the renderer's own tile-incremental RGBA8 (no
// float copy of the film); with exposure, a tone curve or the clipped overlay, the
// linear film mapped by display.h (refreshed at most ~10 times a second while
// rendering); with a render region, its pixels over the last picture.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "display.h"
#include "film.h"
#include "region.h"
#include "renderer.h"

namespace rtview {

class FilmView {
public:
    static constexpr double kMappedInterval = 0.1;  // seconds between float snapshots while rendering

    // Brings rgba() up to date. `region` may be null. `now` is a clock in seconds.
    // True if rgba() changed; `changed` then receives the rectangle {x0, y0, x1, y1}
    // that may differ (the whole picture after a size change).
    bool update(const rt::Renderer& renderer, const DisplaySettings& settings, const RegionRenderer* region, double now,
                std::array<int, 4>& changed);
    const std::vector<std::uint8_t>& rgba() const { return uses_fast() ? fast_ : mapped_; }
    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return width_ < 1; }
    // How many updates changed rgba() so far; and whether the last update() saw new
    // film pixels (not only a display or region change).
    std::uint64_t updates() const { return updates_; }
    bool film_changed() const { return film_changed_; }
    const DisplaySettings& settings() const { return settings_; }
    // Film pixels are waiting to be mapped (at most kMappedInterval): keep updating.
    bool pending() const { return !uses_fast() && pending_[0] < pending_[2] && pending_[1] < pending_[3]; }

    // The linear value of pixel (x, y) as shown (the region's where it covers it): the
    // renderer's pixel, or (while its film has another size) from a float copy of the
    // film at most `max_age` seconds behind the renderer.
    // For the pixel readout; false outside the film.
    bool linear_at(const rt::Renderer& renderer, double now, double max_age, int x, int y, rt::Colour& c);
    // The whole picture as shown, linear, exactly now (for snapshots).
    rt::Image linear_picture(const rt::Renderer& renderer, double now);
    // Samples per pixel of the picture at (x, y): the region's where it covers it.
    int samples_at(int x, int y, int film_samples) const;

private:
    bool update_inner(const rt::Renderer& renderer, const DisplaySettings& settings, const RegionRenderer* region,
                      double now, std::array<int, 4>& changed);
    bool uses_fast() const { return settings_.identity() && region_.rect.empty(); }
    void refresh_linear(const rt::Renderer& renderer, double now);

    DisplaySettings settings_;
    bool have_settings_ = false;
    std::vector<std::uint8_t> fast_;    // snapshot_rgba8's buffer, always current
    std::vector<std::uint8_t> mapped_;  // display-mapped film (and region) when not identity
    int width_ = 0, height_ = 0;
    std::uint64_t fast_version_ = 0;
    std::array<int, 4> pending_{0, 0, 0, 0};  // changed in fast_ since mapped_ was made
    double mapped_time_ = -1e9;

    rt::Image linear_;                  // the renderer's film at linear_version_
    std::uint64_t linear_version_ = ~std::uint64_t(0);
    double linear_time_ = -1e9;

    RegionPicture region_;              // the last region pixels seen (empty rect: none)
    std::uint64_t region_version_ = 0;
    double region_time_ = -1e9;
    std::uint64_t updates_ = 0;
    bool film_changed_ = false;
};

}  // namespace rtview
