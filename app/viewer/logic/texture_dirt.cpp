// The film texture's unsent rows (see texture_dirt.h).
#include "texture_dirt.h"

#include <algorithm>

namespace rtview {

void TextureDirt::reset(int width, int height) {
    width_ = std::max(0, width);
    height_ = std::max(0, height);
    x0_.assign(std::size_t(height_), 0);
    x1_.assign(std::size_t(height_), width_);
    rows_ = width_ > 0 ? height_ : 0;
    next_ = 0;
    if (width_ == 0) x1_.assign(std::size_t(height_), 0);
}

void TextureDirt::add(const Box& b) {
    const int x0 = std::max(b[0], 0), y0 = std::max(b[1], 0);
    const int x1 = std::min(b[2], width_), y1 = std::min(b[3], height_);
    if (x0 >= x1 || y0 >= y1) return;
    for (int y = y0; y < y1; ++y) {
        int& a = x0_[std::size_t(y)];
        int& e = x1_[std::size_t(y)];
        if (a >= e) {
            a = x0, e = x1;
            ++rows_;
        } else {
            a = std::min(a, x0), e = std::max(e, x1);
        }
    }
}

std::int64_t TextureDirt::pending() const {
    std::int64_t n = 0;
    for (int y = 0; y < height_; ++y) n += std::max(0, x1_[std::size_t(y)] - x0_[std::size_t(y)]);
    return n;
}

std::vector<TextureDirt::Box> TextureDirt::take(std::int64_t budget) {
    std::vector<Box> bands;
    if (rows_ == 0) return bands;
    std::int64_t sent = 0;
    // From next_ round to next_ again: runs of dirty rows, each run one band of its
    // rows' joint x range, until the budget is spent.
    int y = next_ % height_, seen = 0;
    while (seen < height_ && rows_ > 0 && (sent < budget || bands.empty())) {
        const std::size_t i = std::size_t(y);
        if (x0_[i] >= x1_[i]) {
            y = (y + 1) % height_;
            ++seen;
            continue;
        }
        Box band{x0_[i], y, x1_[i], y + 1};
        // Grow the band downwards while its rows are dirty, the budget lasts and the
        // texture's bottom is not reached (the next round starts at the top).
        for (;;) {
            sent += band[2] - band[0];
            x0_[std::size_t(band[3] - 1)] = x1_[std::size_t(band[3] - 1)] = 0;
            --rows_;
            ++seen;
            const int ny = band[3];
            if (ny >= height_ || x0_[std::size_t(ny)] >= x1_[std::size_t(ny)]) break;
            // Joining the row widens the band to both rows' spans: the rows already in
            // it then send more too. Only while the whole stays within the budget.
            const int nx0 = std::min(band[0], x0_[std::size_t(ny)]), nx1 = std::max(band[2], x1_[std::size_t(ny)]);
            const std::int64_t wider = std::int64_t(band[3] - band[1]) * ((nx1 - nx0) - (band[2] - band[0]));
            if (sent + wider + (nx1 - nx0) > budget) break;
            sent += wider;
            band[0] = nx0, band[2] = nx1, band[3] = ny + 1;
        }
        bands.push_back(band);
        y = band[3] % height_;
    }
    next_ = y;
    return bands;
}

}  // namespace rtview
