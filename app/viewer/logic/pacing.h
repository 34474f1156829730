// Preview pacing: how coarse the first preview pass of a moving view must be so that
// it lands within a frame budget, from the measured cost of recent passes (dynamic
// resolution), and when a newer view may replace a render whose preview has not been
// shown yet. No window, no GL: unit-tested.
#pragma once

namespace rtview {

class PreviewPacer {
public:
    // The first preview of a film of `rays` primary rays took `seconds` (from start to
    // the end of the pass). Recent passes weigh most; a single slow outlier (another
    // process took the CPU for a moment) moves the estimate only part of the way.
    void measured(double rays, double seconds);
    // Seconds per primary ray, as estimated (0 before any measurement).
    double seconds_per_ray() const { return per_ray_; }

    // Block size (a power of 2, 2..64) of the first coarse pass of a w x h film so that
    // it is expected within `budget` seconds. Before any measurement: 8.
    int coarse_block(int width, int height, double budget) const;

    // May a render that started `running_for` seconds ago be replaced by a newer view?
    // Always once its preview is on screen. An unshown preview is thrown away only
    // when it is overdue (twice the budget) and, even then, at most once per picture
    // shown (`replaced_unshown`: one was already thrown away since the last picture):
    // under load a stream of input must not starve the picture.
    static bool may_replace(bool preview_shown, double running_for, double budget, bool replaced_unshown) {
        return preview_shown || (running_for >= 2 * budget && !replaced_unshown);
    }

private:
    double per_ray_ = 0;
};

}  // namespace rtview
