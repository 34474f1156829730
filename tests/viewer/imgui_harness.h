// A window-less ImGui context for driving widgets in tests and benchmarks: frames are
// built and rendered to draw lists (no GL), keys and the mouse are set by hand.
#pragma once

#include <imgui.h>

#include <functional>

namespace rtview_test {

class ImGuiHarness {
public:
    // Key indices as GLFW numbers them, which is what the viewer's backend uses.
    enum : int { kTab = 258, kEnter = 257, kEscape = 256, kBackspace = 259, kDelete = 261, kRight = 262, kLeft = 263,
                 kDown = 264, kUp = 265, kPageUp = 266, kPageDown = 267, kHome = 268, kEnd = 269, kCtrl = 341, kShift = 340 };

    explicit ImGuiHarness(float w = 1000, float h = 700) {
        ctx_ = ImGui::CreateContext();
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(w, h);
        io.DeltaTime = 1.f / 60;
        io.IniFilename = nullptr;
        unsigned char* px = nullptr;
        int tw = 0, th = 0;
        io.Fonts->GetTexDataAsRGBA32(&px, &tw, &th);
        const int named[][2] = {{ImGuiKey_Tab, kTab},           {ImGuiKey_LeftArrow, kLeft}, {ImGuiKey_RightArrow, kRight},
                                {ImGuiKey_UpArrow, kUp},        {ImGuiKey_DownArrow, kDown}, {ImGuiKey_PageUp, kPageUp},
                                {ImGuiKey_PageDown, kPageDown}, {ImGuiKey_Home, kHome},      {ImGuiKey_End, kEnd},
                                {ImGuiKey_Delete, kDelete},     {ImGuiKey_Backspace, kBackspace}, {ImGuiKey_Enter, kEnter},
                                {ImGuiKey_Escape, kEscape},     {ImGuiKey_A, 'A'},          {ImGuiKey_C, 'C'},
                                {ImGuiKey_V, 'V'},              {ImGuiKey_X, 'X'},          {ImGuiKey_Y, 'Y'},
                                {ImGuiKey_Z, 'Z'}};
        for (const auto& k : named) io.KeyMap[k[0]] = k[1];
    }
    ~ImGuiHarness() { ImGui::DestroyContext(ctx_); }
    ImGuiHarness(const ImGuiHarness&) = delete;
    ImGuiHarness& operator=(const ImGuiHarness&) = delete;

    // One frame with `body` inside a full-screen window.
    void frame(const std::function<void()>& body) {
        ImGui::NewFrame();
        ImGui::SetNextWindowPos(ImVec2(0, 0));
        ImGui::SetNextWindowSize(ImGui::GetIO().DisplaySize);
        ImGui::Begin("harness", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
        body();
        ImGui::End();
        ImGui::Render();
        ++frames_;
    }
    // A key held for exactly one frame, then released in the next one.
    void tap(int key, bool ctrl, bool shift, const std::function<void()>& body) {
        ImGuiIO& io = ImGui::GetIO();
        io.KeyCtrl = ctrl;
        io.KeyShift = shift;
        io.KeysDown[key] = true;
        frame(body);
        io.KeysDown[key] = false;
        io.KeyCtrl = io.KeyShift = false;
        frame(body);
    }
    void click(ImVec2 at, const std::function<void()>& body) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = at;
        io.MouseDown[0] = true;
        frame(body);
        io.MouseDown[0] = false;
        frame(body);
    }
    void type(const char* s) { ImGui::GetIO().AddInputCharactersUTF8(s); }
    int frames() const { return frames_; }

private:
    ImGuiContext* ctx_ = nullptr;
    int frames_ = 0;
};

}  // namespace rtview_test
