// What of the film texture is still to be sent, row by row, and how much of it to send
// this frame: the film changes where tiles land (and everywhere at once after a coarse
// pass, an exposure change or a new size), but a frame sends at most a bounded number
// of pixels, so no frame waits for a whole large texture. Rows are sent round-robin,
// so every changed row arrives within (changed pixels / budget) frames.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace rtview {

class TextureDirt {
public:
    using Box = std::array<int, 4>;  // {x0, y0, x1, y1}

    // A texture of this size, all of it to be sent.
    void reset(int width, int height);
    // Pixels of `box` (clipped to the texture) changed.
    void add(const Box& box);
    bool empty() const { return rows_ == 0; }
    // Pixels still to be sent (each dirty row counted from its first to its last
    // changed pixel).
    std::int64_t pending() const;
    // The bands to send now, each rows of one x range, about `budget` pixels in all
    // (at least one row), taken from what is pending.
    std::vector<Box> take(std::int64_t budget);

private:
    int width_ = 0, height_ = 0;
    std::vector<int> x0_, x1_;  // per row: the changed span [x0, x1) (empty: x0 >= x1)
    int rows_ = 0;              // rows with a span
    int next_ = 0;              // where the next take() starts
};

}  // namespace rtview
