// Film bytes for the texture (see film_view.h).
#include "film_view.h"

#include <algorithm>

namespace rtview {

namespace {

using Box = std::array<int, 4>;

bool empty_box(const Box& b) { return b[0] >= b[2] || b[1] >= b[3]; }

Box unite(const Box& a, const Box& b) {
    if (empty_box(a)) return b;
    if (empty_box(b)) return a;
    return {std::min(a[0], b[0]), std::min(a[1], b[1]), std::max(a[2], b[2]), std::max(a[3], b[3])};
}

Box box_of(const PixelRect& r) { return r.empty() ? Box{0, 0, 0, 0} : Box{r.x0, r.y0, r.x1, r.y1}; }

}  // namespace

void FilmView::refresh_linear(const rt::Renderer& renderer, double now) {
    linear_ = renderer.snapshot();
    linear_version_ = fast_version_;
    linear_time_ = now;
}

bool FilmView::update(const rt::Renderer& renderer, const DisplaySettings& settings, const RegionRenderer* region,
                      double now, Box& changed) {
    bool r = update_inner(renderer, settings, region, now, changed);
    updates_ += r;
    return r;
}

bool FilmView::update_inner(const rt::Renderer& renderer, const DisplaySettings& settings, const RegionRenderer* region,
                            double now, Box& changed) {
    const bool settings_changed = !have_settings_ || settings != settings_;
    const bool was_fast = uses_fast();
    settings_ = settings;
    have_settings_ = true;

    int w = width_, h = height_;
    Box rect{0, 0, 0, 0};
    const bool film_changed = renderer.snapshot_rgba8(fast_, w, h, fast_version_, &rect);
    film_changed_ = film_changed;
    const bool resized = film_changed && (w != width_ || h != height_);
    if (film_changed) {
        width_ = w;
        height_ = h;
        pending_ = resized ? Box{0, 0, w, h} : unite(pending_, rect);
    }
    const bool done = renderer.progress().done;

    // The region: its new pixels (as often as the mapped film), or its end.
    Box region_box{0, 0, 0, 0};
    if (region && !region->rect().empty()) {
        RegionPicture pic;
        std::uint64_t v = region_version_;
        if ((now - region_time_ >= kMappedInterval || region->done()) && region->snapshot(pic, v) &&
            pic.rect.x1 <= width_ && pic.rect.y1 <= height_) {
            region_box = unite(box_of(region_.rect), box_of(pic.rect));  // the old rectangle is restored
            region_ = std::move(pic);
            region_version_ = v;
            region_time_ = now;
        }
    } else if (!region_.rect.empty()) {
        region_box = box_of(region_.rect);
        region_ = RegionPicture{};
        region_version_ = 0;
    }
    if (resized && !region_.rect.empty() && (region_.rect.x1 > width_ || region_.rect.y1 > height_)) region_ = {};

    if (uses_fast()) {
        if (was_fast && !film_changed) return false;
        changed = was_fast && !resized ? rect : Box{0, 0, width_, height_};
        return width_ > 0;
    }

    // Mapped: the whole picture when the mapping or the buffer changed, else what the
    // renderer changed since the last mapping (no more often than kMappedInterval
    // while rendering: a float copy of the film each time) and the region.
    if (width_ < 1) return false;
    const bool whole = settings_changed || was_fast || resized || mapped_.size() != std::size_t(width_) * height_ * 4;
    const bool film_due = !empty_box(pending_) && (done || now - mapped_time_ >= kMappedInterval);
    Box r = whole ? Box{0, 0, width_, height_} : unite(film_due ? pending_ : Box{0, 0, 0, 0}, region_box);
    if (empty_box(r)) return false;

    if (settings_.identity()) {
        // Renderer bytes with a region over them: no float copy needed.
        mapped_.resize(fast_.size());
        for (int y = r[1]; y < r[3]; ++y)
            std::copy(&fast_[4 * (std::size_t(y) * width_ + r[0])], &fast_[4 * (std::size_t(y) * width_ + r[2])],
                      &mapped_[4 * (std::size_t(y) * width_ + r[0])]);
    } else {
        if (linear_version_ != fast_version_ || linear_.width != width_ || linear_.height != height_)
            refresh_linear(renderer, now);
        if (linear_.width != width_ || linear_.height != height_) return false;  // a new render started meanwhile
        map_to_rgba8(linear_, settings_, r, mapped_);
    }
    paste_region_rgba8(region_, settings_, width_, mapped_);
    changed = unite(r, box_of(region_.rect));
    if (whole || film_due) {
        pending_ = {0, 0, 0, 0};
        mapped_time_ = now;
    }
    return true;
}

bool FilmView::linear_at(const rt::Renderer& renderer, double now, double max_age, int x, int y, rt::Colour& c) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return false;
    const PixelRect& r = region_.rect;
    if (!r.empty() && x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1 && region_.row_samples[std::size_t(y - r.y0)] > 0) {
        c = region_.image.at(x - r.x0, y - r.y0);
        return true;
    }
    // The renderer's own pixel: a float copy of a large film costs the UI thread
    // milliseconds (and holds the render's lock meanwhile).
    if (renderer.pixel(x, y, width_, height_, c)) return true;
    bool stale = linear_version_ != fast_version_ || linear_.width != width_ || linear_.height != height_;
    if (stale && (now - linear_time_ >= max_age || linear_.width != width_ || linear_.height != height_))
        refresh_linear(renderer, now);
    if (x >= linear_.width || y >= linear_.height) return false;
    c = linear_.at(x, y);
    return true;
}

rt::Image FilmView::linear_picture(const rt::Renderer& renderer, double now) {
    refresh_linear(renderer, now);
    rt::Image img = linear_;
    if (!region_.rect.empty() && region_.rect.x1 <= img.width && region_.rect.y1 <= img.height) paste_region(region_, img);
    return img;
}

int FilmView::samples_at(int x, int y, int film_samples) const {
    const PixelRect& r = region_.rect;
    if (!r.empty() && x >= r.x0 && x < r.x1 && y >= r.y0 && y < r.y1) return region_.row_samples[std::size_t(y - r.y0)];
    return film_samples;
}

}  // namespace rtview
