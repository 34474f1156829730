// Render to file (see image_tools.h): the dialog before the final render, its
// progress while it runs, and where the picture went.
#include "image_tools.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <climits>
#include <cstdio>
#include <ctime>

#include "bounded_input.h"
#include "image_io.h"
#include "imgui_common.h"
#include "probe.h"
#include "render_request.h"

namespace rtview {

namespace {

// "3 s", "1 min 20 s", "2 h 5 min": a time left as a person would say it.
std::string format_duration(double seconds) {
    char buf[48];
    const long t = std::lround(std::max(0.0, std::min(seconds, 1e7)));
    if (t < 60) std::snprintf(buf, sizeof buf, "%ld s", std::max(1L, t));
    else if (t < 3600) std::snprintf(buf, sizeof buf, "%ld min %ld s", t / 60, t % 60);
    else std::snprintf(buf, sizeof buf, "%ld h %ld min", t / 3600, (t % 3600) / 60);
    return buf;
}

}  // namespace

void ImageTools::open_render_dialog() {
    if (render_path_.empty()) {
        // "scene.txt" -> "scene.png", beside the scene.
        std::string base = f_.scene_path.empty() ? "render" : f_.scene_path;
        std::size_t dot = base.find_last_of('.'), slash = base.find_last_of('/');
        if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) base.resize(dot);
        render_path_ = base + ".png";
    }
    focus_render_path_ = true;
    render_samples_ = std::max(1, f_.max_samples);
    render_error_.clear();
    render_result_ = RenderResult::None;
    open_render_popup_ = true;
}

void ImageTools::draw_popups() {
    if (open_render_popup_) ImGui::OpenPopup("Render to file");
    open_render_popup_ = false;
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::BeginPopupModal("Render to file", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    if (final_.active()) draw_render_progress();
    else if (render_result_ != RenderResult::None) draw_render_result();
    else draw_render_setup();
    ImGui::EndPopup();
}

// While the final render runs: its progress, the time it will still take, Cancel.
void ImageTools::draw_render_progress() {
    const float fs = ImGui::GetFontSize();
    rt::RenderProgress p = final_.progress();
    const double f = final_.fraction();
    ImGui::Text("Rendering %s (%dx%d)", render_path_.c_str(), p.width, p.height);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%d%%  %.1f s", int(f * 100), p.elapsed);
    ImGui::ProgressBar(float(f), ImVec2(fs * 24, 0), buf);
    // From the pace of the last few seconds, once there is one to go by.
    if (const double left = final_.time_left(); left >= 0)
        ImGui::Text("about %s left", format_duration(left).c_str());
    else
        ImGui::TextDisabled("estimating the time left...");
    probe("render_dialog", "rendering " + std::to_string(int(f * 100)) + "%");
    if (ImGui::Button("Cancel") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) {
        final_.cancel();
        message("Render to file cancelled; " + render_path_ + " not written");
        ImGui::CloseCurrentPopup();
    }
}

// After the final render: where the picture went (or why it did not), until closed.
void ImageTools::draw_render_result() {
    const bool saved = render_result_ == RenderResult::Saved;
    if (saved) {
        ImGui::TextColored(ImVec4(0.55f, 0.85f, 0.55f, 1), "Saved to %s", render_path_.c_str());
        ImGui::TextDisabled("%s", render_result_text_.c_str());
    } else {
        ImGui::TextColored(ImVec4(1.0f, 0.42f, 0.42f, 1.0f), "Cannot write %s", render_path_.c_str());
        ImGui::TextWrapped("%s", render_result_text_.c_str());
    }
    probe("render_dialog", (saved ? "saved " : "failed ") + render_path_);
    if (ImGui::Button("Close") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape)) ||
        ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Enter))) {
        render_result_ = RenderResult::None;
        ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Render again...")) render_result_ = RenderResult::None;
}

// Before the final render: the file, the samples, the time limit.
void ImageTools::draw_render_setup() {
    const float fs = ImGui::GetFontSize();
    if (!f_.scene) {
        ImGui::TextUnformatted("The scene has errors: nothing to render.");
    } else {
        ImGui::Text("The scene at its picture_size, %dx%d, on the renderer of `raytracer`.", f_.scene->width,
                    f_.scene->height);
        ImGui::Checkbox("through the scene's camera (as `raytracer SCENE` renders it), not the view",
                        &render_scene_camera_);
    }
    ImGui::SetNextItemWidth(fs * 24);
    if (focus_render_path_) ImGui::SetKeyboardFocusHere();
    focus_render_path_ = false;
    bool go = bounded_input("##file", "picture.png, .ppm, .pfm or .exr", render_path_, PATH_MAX, ImGuiInputTextFlags_EnterReturnsTrue);
    probe("render_field", ImGui::IsItemActive() ? "active" : "idle");
    ImGui::SameLine();
    if (ImGui::Button("Browse...")) {
        render_browser_.start(FileDialog::Mode::Save, {".png", ".ppm"}, "Images (*.png, *.ppm)", render_path_);
        ImGui::OpenPopup("Choose the picture file");
    }
    ImGui::SameLine();
    ImGui::TextUnformatted("file");
    // (Escape there closes the browser only.)
    const bool browsing = ImGui::IsPopupOpen("Choose the picture file");
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (ImGui::BeginPopupModal("Choose the picture file", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        const FileDialog::Result r = render_browser_.draw("Choose");
        if (r == FileDialog::Result::Go) render_path_ = render_browser_.path();
        if (r != FileDialog::Result::None) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    ImGui::SetNextItemWidth(fs * 8);
    ImGui::InputInt("samples per pixel", &render_samples_);
    render_samples_ = std::clamp(render_samples_, 1, rt::kMaxSamples);
    ImGui::SetNextItemWidth(fs * 8);
    ImGui::InputDouble("time limit (s, 0: none)", &render_time_limit_, 1, 10, "%.1f");
    render_time_limit_ = std::clamp(render_time_limit_, 0.0, rt::kMaxTimeLimit);
    // Samples only where a pixel stands out or its samples disagree (raytracer --aa-threshold).
    ImGui::Checkbox("adaptive, threshold", &render_adaptive_);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(fs * 6);
    ImGui::InputDouble("##aa", &render_aa_threshold_, 0.01, 0.1, "%.3f");
    render_aa_threshold_ = std::clamp(render_aa_threshold_, 0.0, rt::kMaxAaThreshold);
    if (!render_error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.42f, 0.42f, 1.0f), "%s", render_error_.c_str());
    probe("render_dialog", "setup");
    go |= ImGui::Button("Render");
    ImGui::SameLine();
    if (ImGui::Button("Close") || (!browsing && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape)))) {
        ImGui::CloseCurrentPopup();
    } else if (go && f_.scene) {
        rt::Scene scene = *f_.scene;
        if (!render_scene_camera_) scene.camera = f_.render_camera;
        const rt::RenderRequest request =
            final_render_request(render_samples_, render_time_limit_, render_adaptive_ ? render_aa_threshold_ : -1);
        render_error_ = final_.start(scene, render_path_, request, f_.world.get()).message();
    }
}

}  // namespace rtview
