// Frames shown through GLX (see glx_present.h).
#include "glx_present.h"

#include <GLFW/glfw3.h>
#include <GL/glx.h>

#include <cstdlib>
#include <cstring>

namespace rtview {

namespace {

// Mesa's rasterisers that run on the processors.
bool software_renderer(const char* name) {
    return name && (std::strstr(name, "llvmpipe") || std::strstr(name, "softpipe") || std::strstr(name, "swrast"));
}

}  // namespace

WindowPresenter::WindowPresenter(GLFWwindow* window) : window_(window) {
    const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    renderer_ = r ? r : "";
    const char* env = std::getenv("RAYTRACER_VIEW_DAMAGE");
    const bool wanted = env ? std::strcmp(env, "0") != 0 : software_renderer(r);
    check_ = env && std::strcmp(env, "check") == 0;
    Display* dpy = glXGetCurrentDisplay();
    if (!wanted || !dpy) return;
    const char* ext = glXQueryExtensionsString(dpy, DefaultScreen(dpy));
    if (!ext || !std::strstr(ext, "GLX_MESA_copy_sub_buffer")) return;
    auto fn = glXGetProcAddressARB(reinterpret_cast<const GLubyte*>("glXCopySubBufferMESA"));
    if (!fn) return;
    display_ = dpy;
    drawable_ = glXGetCurrentDrawable();
    copy_ = reinterpret_cast<void (*)(void*, unsigned long, int, int, int, int)>(fn);
}

void WindowPresenter::present(const std::vector<PixelBox>& boxes, int height) const {
    if (!copy_) {
        glfwSwapBuffers(window_);
        return;
    }
    // GLX counts rows from the bottom.
    for (const PixelBox& b : boxes) copy_(display_, drawable_, b.x0, height - b.y1, b.x1 - b.x0, b.y1 - b.y0);
}

}  // namespace rtview
