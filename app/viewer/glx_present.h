// Showing a painted frame in the GLFW window. With Mesa's software rasteriser
// (llvmpipe, softpipe: Xvfb, machines without a GPU driver) every pixel painted costs
// processor time, so a frame paints only what changed (frame_paint.h) and shows only
// those boxes with GLX_MESA_copy_sub_buffer, which leaves the back buffer as it was:
// the next frame starts from this one. Elsewhere (a GPU) frames are painted whole
// and swapped as usual. RAYTRACER_VIEW_DAMAGE=0 in the environment turns the boxes
// off (to compare), =1 uses them with any renderer that has the extension, and
// =check checks every partial frame against the whole one (FramePainter).
#pragma once

#include <vector>

#include "frame_damage.h"

struct GLFWwindow;

namespace rtview {

class WindowPresenter {
public:
    // Looks at the window's current context.
    explicit WindowPresenter(GLFWwindow* window);
    // Whether frames may paint and show only boxes.
    bool partial() const { return copy_ != nullptr; }
    // RAYTRACER_VIEW_DAMAGE=check.
    bool check() const { return check_; }
    // Shows the boxes painted (top row 0) of a framebuffer `height` pixels high: none
    // shows nothing new; without partial frames, swaps.
    void present(const std::vector<PixelBox>& boxes, int height) const;
    // The renderer's name, as GL says it.
    const char* renderer() const { return renderer_; }

private:
    GLFWwindow* window_;
    const char* renderer_ = "";
    bool check_ = false;
    void* display_ = nullptr;
    unsigned long drawable_ = 0;
    void (*copy_)(void*, unsigned long, int, int, int, int) = nullptr;
};

}  // namespace rtview
