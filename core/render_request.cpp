// A render to a file's settings (see render_request.h).
#include "render_request.h"

namespace rt {

int max_samples(const RenderRequest& r) {
    if (r.samples) return *r.samples;
    if (r.time_limit > 0) return kMaxSamples;
    return r.aa_threshold ? kDefaultAaMaxSamples : 1;
}

RenderSettings final_settings(const RenderRequest& r, int width, int height) {
    RenderSettings s;
    s.width = width;
    s.height = height;
    s.coarse = false;
    s.mirror = r.mirror;
    s.time_limit = r.time_limit;
    s.max_samples = max_samples(r);
    s.aa_threshold = r.aa_threshold.value_or(-1);
    if (r.time_limit <= 0) s.samples_per_pass = s.max_samples;
    return s;
}

}  // namespace rt
