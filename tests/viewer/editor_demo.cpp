// The text editor widget alone in a GLFW window, on a scene file, with the parser's
// diagnostics in its gutter: for looking at it (and driving it with xdotool under
// Xvfb) before and apart from its place in raytracer-view.
//
//   rtview-editor-demo SCENE [--wrap] [--scale S]
// Key and character events go to the editor through its own queue (push_key,
// push_char), as a host with a once-a-frame input backend should do.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl2.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "scene_parser.h"
#include "text_editor.h"

namespace {

rtview::TextEditor* g_editor = nullptr;

void key_callback(GLFWwindow* w, int key, int scancode, int action, int mods) {
    ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
    if (!g_editor || action == GLFW_RELEASE) return;
    using K = rtview::TextEditor::Key;
    K k;
    switch (key) {
    case GLFW_KEY_LEFT: k = K::Left; break;
    case GLFW_KEY_RIGHT: k = K::Right; break;
    case GLFW_KEY_UP: k = K::Up; break;
    case GLFW_KEY_DOWN: k = K::Down; break;
    case GLFW_KEY_HOME: k = K::Home; break;
    case GLFW_KEY_END: k = K::End; break;
    case GLFW_KEY_PAGE_UP: k = K::PageUp; break;
    case GLFW_KEY_PAGE_DOWN: k = K::PageDown; break;
    case GLFW_KEY_BACKSPACE: k = K::Backspace; break;
    case GLFW_KEY_DELETE: k = K::Delete; break;
    case GLFW_KEY_ENTER: k = K::Enter; break;
    case GLFW_KEY_TAB: k = K::Tab; break;
    case GLFW_KEY_ESCAPE: k = K::Escape; break;
    case GLFW_KEY_A: k = K::A; break;
    case GLFW_KEY_C: k = K::C; break;
    case GLFW_KEY_V: k = K::V; break;
    case GLFW_KEY_X: k = K::X; break;
    case GLFW_KEY_Y: k = K::Y; break;
    case GLFW_KEY_Z: k = K::Z; break;
    case GLFW_KEY_F: k = K::F; break;
    case GLFW_KEY_G: k = K::G; break;
    default: return;
    }
    // Letters only as shortcuts: typed letters arrive as characters.
    bool ctrl = (mods & GLFW_MOD_CONTROL) != 0;
    if (k >= K::A && !ctrl) return;
    g_editor->push_key(k, (mods & GLFW_MOD_SHIFT) != 0, ctrl);
}

void char_callback(GLFWwindow* w, unsigned c) {
    ImGui_ImplGlfw_CharCallback(w, c);
    if (g_editor) g_editor->push_char(c);
}

}  // namespace

int main(int argc, char** argv) {
    std::string path;
    bool wrap = false;
    float scale = 1;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--wrap") == 0) wrap = true;
        else if (std::strcmp(argv[i], "--scale") == 0 && i + 1 < argc) scale = float(std::atof(argv[++i]));
        else path = argv[i];
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "usage: rtview-editor-demo SCENE [--wrap] [--scale S]\n");
        return 2;
    }
    std::stringstream ss;
    ss << in.rdbuf();

    if (!glfwInit()) return 1;
    GLFWwindow* window = glfwCreateWindow(1000, 700, "editor demo", nullptr, nullptr);
    if (!window) return 1;
    glfwMakeContextCurrent(window);
    glfwSwapInterval(1);
    ImGui::CreateContext();
    ImGui::StyleColorsDark();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    if (scale > 1.05f) {
        ImGui::GetStyle().ScaleAllSizes(scale);
        ImFontConfig cfg;
        cfg.SizePixels = 13.f * scale;
        io.Fonts->AddFontDefault(&cfg);
    }
    ImGui_ImplGlfw_InitForOpenGL(window, false);
    ImGui_ImplOpenGL2_Init();
    glfwSetKeyCallback(window, key_callback);
    glfwSetCharCallback(window, char_callback);
    glfwSetMouseButtonCallback(window, ImGui_ImplGlfw_MouseButtonCallback);
    glfwSetScrollCallback(window, ImGui_ImplGlfw_ScrollCallback);

    rtview::TextEditor ed;
    g_editor = &ed;
    ed.set_text(ss.str());
    ed.set_wrap(wrap);
    std::uint64_t checked = 0;
    double check_at = 0;
    while (!glfwWindowShouldClose(window)) {
        glfwWaitEventsTimeout(0.1);
        ImGui_ImplOpenGL2_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(io.DisplaySize);
        ImGui::Begin("demo", nullptr, ImGuiWindowFlags_NoDecoration);
        bool w = ed.wrap();
        if (ImGui::Checkbox("wrap", &w)) ed.set_wrap(w);
        ImGui::SameLine();
        ImGui::Text("line %d, column %d   %s", ed.buffer().cursor().line + 1, ed.buffer().cursor().col + 1,
                    ed.focused() ? "(typing here)" : "");
        if (ed.draw("editor", ImVec2(0, 0))) check_at = ImGui::GetTime() + 0.3;
        ImGui::End();
        // Diagnostics once typing pauses, as the viewer's live check does.
        if (ed.buffer().version() != checked && ImGui::GetTime() >= check_at) {
            rt::ParseResult r = rt::parse_scene(ed.text());
            std::vector<rtview::LineMark> marks;
            for (const rt::Diagnostic& d : r.diagnostics) marks.push_back({d.line, d.is_error(), d.message});
            ed.set_marks(std::move(marks));
            checked = ed.buffer().version();
        }
        ImGui::Render();
        int fw, fh;
        glfwGetFramebufferSize(window, &fw, &fh);
        glViewport(0, 0, fw, fh);
        glClearColor(0.1f, 0.1f, 0.1f, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());
        glfwSwapBuffers(window);
    }
    g_editor = nullptr;
    ImGui_ImplOpenGL2_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return 0;
}
