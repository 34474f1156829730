// The status bar: the message, the load's progress, the render's numbers and the
// pixel readout, on one row (cut with "..." where it does not fit; see panels.h).
#include "panels.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "camera_control.h"
#include "item_fields.h"
#include "imgui_common.h"
#include "number_field.h"
#include "layout.h"
#include "panel_widgets.h"
#include "probe.h"
#include "scene_schema.h"
#include "readout.h"
#include "render_request.h"
#include "scene_text.h"
#include "scene_writer.h"
#include "shown_numbers.h"

namespace rtview {

namespace {

// A piece of status-bar text and the separator before it.
struct StatusPiece {
    std::string text;
    std::string sep;
};

// The text in pieces at runs of two or more spaces (the statistics' parts; a pixel
// readout's groups, "RGB 0.107 0.107 0.125", three spaces apart), which a narrow bar
// shows or leaves out whole.
void add_status_line(std::vector<StatusPiece>& pieces, const std::string& text) {
    const std::string& rest = text;
    std::string sep;
    std::size_t start = 0;
    while (start <= rest.size()) {
        std::size_t at = rest.find("  ", start);
        if (at == std::string::npos) at = rest.size();
        pieces.push_back({rest.substr(start, at - start), sep});
        std::size_t end = at;
        while (end < rest.size() && rest[end] == ' ') ++end;
        sep = rest.substr(at, end - at);
        if (at == rest.size()) break;
        start = end;
    }
}

// The status bar's window padding (unscaled, as its one row always had).
const ImVec2 kStatusPadding(6, 4);

// The progress bar's width at most: two fifths of what is left beside the button, so a
// narrow bar (a small window at a large UI scale) still shows some text.
float narrow_share(float avail) { return std::max(ImGui::GetFontSize() * 3, avail * 0.4f); }

}  // namespace

void Panels::draw_status_bar(const LoadStatus& load) {
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(0, io.DisplaySize.y - layout_.status_h));
    ImGui::SetNextWindowSize(ImVec2(float(layout_.area.w), layout_.status_h));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, kStatusPadding);
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                             ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                             ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoBringToFrontOnFocus;
    if (ImGui::Begin("##status", nullptr, flags)) {
        if (load.active) {
            // Loading in the background: its progress replaces the render's.
            if (ImGui::Button("Cancel", ImVec2(ImGui::GetFontSize() * 4.5f, 0))) commands_.run(Command::CancelLoad);
            ImGui::SameLine();
            ImGui::ProgressBar(float(load.fraction),
                               ImVec2(std::min(ImGui::GetFontSize() * 8, narrow_share(ImGui::GetContentRegionAvail().x)), 0));
            ImGui::SameLine();
            status_text(load.text + " (Esc cancels)", true);
        } else {
            draw_render_status();
        }
    }
    ImGui::End();
    ImGui::PopStyleVar();
}

// The render's part of the bar: Pause, its progress, its numbers (or the readout of
// the pixel under the cursor) and the last message.
void Panels::draw_render_status() {
    rt::RenderProgress p = render_.progress();
    if (ImGui::Button(render_.paused() ? "Resume" : "Pause", ImVec2(ImGui::GetFontSize() * 4.5f, 0)))
        commands_.run(Command::TogglePause);
    ImGui::SameLine();
    double elapsed = p.done && render_.done_generation() == p.generation ? render_.done_elapsed() : p.elapsed;
    double frac = p.refining >= 0 ? rt::progress_fraction(p, render_.max_samples())
                                  : std::clamp((p.samples + p.pass_fraction) / std::max(1, render_.max_samples()), 0.0, 1.0);
    if (render_.time_limit() > 0) frac = std::max(frac, std::min(1.0, elapsed / render_.time_limit()));
    if (p.done) frac = 1;
    char buf[64];
    // Adaptive: how many pixels have not settled yet, until every one has.
    // (Thousands above 9999, rounded up: "305k px refining" fits the bar.)
    if (p.refining > 9999)
        std::snprintf(buf, sizeof buf, "%lldk px refining", static_cast<long long>((p.refining + 999) / 1000));
    else if (p.refining > 0) std::snprintf(buf, sizeof buf, "%lld px refining", static_cast<long long>(p.refining));
    else if (p.refining == 0) std::snprintf(buf, sizeof buf, "settled");
    else std::snprintf(buf, sizeof buf, "%d / %d spp", p.samples, render_.max_samples());
    if (render_.showing_preview()) {  // the view moves: the last render's state is not the picture's
        std::snprintf(buf, sizeof buf, "moving");
        frac = 0;
    }
    // The picture is still the scene as it was (its world compiles, or its new
    // render has not reached the screen): never "settled" or "done" over it.
    const Document& doc = editor_.doc();
    const bool stale = doc.has_scene() && !render_.showing_preview() && !render_.picture_current(doc.content_version());
    if (stale) {
        std::snprintf(buf, sizeof buf, "updating");
        frac = 0;
    }
    // As wide as its longest usual text (up to 100M pixels refining), at any UI
    // scale, so it keeps its width; in a narrow bar, as wide as this label, within
    // a share that leaves the text room, and the percentage if not even that.
    const float pad = ImGui::GetStyle().FramePadding.x;
    const float usual = std::max(ImGui::GetFontSize() * 8, ImGui::CalcTextSize("99999k px refining").x + pad * 4);
    const float share = narrow_share(ImGui::GetContentRegionAvail().x);
    const float bar_w = usual <= share ? usual
                                       : std::min(share, std::max(ImGui::GetFontSize() * 3,
                                                                  ImGui::CalcTextSize(buf).x + pad * 4));
    if (ImGui::CalcTextSize(buf).x + 2 * pad > bar_w)
        std::snprintf(buf, sizeof buf, "%d%%", int(std::floor(frac * 100)));
    ImGui::ProgressBar(float(frac), ImVec2(bar_w, 0), buf);
    ImGui::SameLine();
    double rate = elapsed > 0 ? double(p.rays) / elapsed : 0;
    const char* state = render_.paused() ? "paused"
                        : p.done         ? "done"
                        : render_.building() ? "building"
                        : p.running      ? "rendering"
                                         : "idle";
    char preview[32] = "";
    if (render_.showing_preview())
        std::snprintf(preview, sizeof preview, "preview %dx%d", render_.last_preview_block(),
                      render_.last_preview_block());
    const char* shown = render_.showing_preview() ? preview : stale ? "updating the picture..." : state;
    // Over the picture: the readout of the pixel under the cursor instead of the
    // statistics; the last message stays beside it (a screenshot's path, an error).
    // The readout first: in a narrow bar it is what is cut last.
    char line[512];
    if (!tools_.readout_line().empty())
        std::snprintf(line, sizeof line, "%s  |  %s", tools_.readout_line().c_str(), shown);
    else
        std::snprintf(line, sizeof line, "%.2f Mrays/s  %.1f s  %s  |  %s", rate / 1e6, elapsed, shown,
                      layout_.fit == FitMode::Picture ? "picture frame" : "fill window");
    // Over the picture the readout is what the user looks for: the message gets less.
    status_text(line, true, tools_.readout_line().empty() ? 0.4f : 0.25f);
}

// The status bar's height: one row at any width (what does not fit is cut with "...",
// the whole text on hover), so the image area keeps its size whatever it says.
float Panels::status_height(float) {
    return std::ceil(ImGui::GetFrameHeight() + 8 * ImGui::GetFontSize() / 13.f);
}

// The status bar's text right of the button and the progress bar, then the last message
// (`show_message`), on one row: when they do not fit, the message keeps its share of
// it, the statistics or readout lose whole groups from their end, and each part cut
// ends in "..." (a message with a path has it in the middle); hovering shows all of it.
void Panels::status_text(const std::string& text, bool show_message, float message_share) {
    std::vector<StatusPiece> pieces;
    add_status_line(pieces, text);
    std::vector<std::pair<std::string, std::string>> parts;
    std::string stats;
    for (const StatusPiece& p : pieces) {
        parts.emplace_back(p.sep, p.text);
        stats += p.sep + p.text;
    }
    const std::string message = show_message ? status_.text() : std::string();
    const ImGuiStyle& st = ImGui::GetStyle();
    const auto measure = [](std::string_view t) { return ImGui::CalcTextSize(t.data(), t.data() + t.size()).x; };
    const bool dismiss = show_message && status_.error() && !message.empty();
    float room = ImGui::GetWindowContentRegionMax().x - ImGui::GetCursorPosX();
    if (dismiss) room -= measure("x") + 2 * st.FramePadding.x + st.ItemSpacing.x;
    const std::string said = message.empty() ? std::string() : "| " + message;
    if (!said.empty()) room -= st.ItemSpacing.x;
    const float stats_w = measure(stats), said_w = said.empty() ? 0 : measure(said);
    std::string shown_stats = stats, shown_said = said;
    if (stats_w + said_w > room) {
        const float said_room = said.empty() ? 0 : std::min(said_w, std::max(room * message_share, room - stats_w));
        shown_stats = elide_pieces(parts, room - said_room, measure);
        // A path's file name stays (cut in the middle), a sentence's start.
        if (!said.empty())
            shown_said = said.find('/') != std::string::npos ? elide_middle(said, room - measure(shown_stats), measure)
                                                             : elide_end(said, room - measure(shown_stats), measure);
    }
    static const ImVec4 grey(0.75f, 0.75f, 0.75f, 1);
    ImGui::BeginGroup();
    ImGui::TextUnformatted(shown_stats.c_str());
    if (!shown_said.empty()) {
        ImGui::SameLine();
        ImGui::PushStyleColor(ImGuiCol_Text, status_.error() ? kErrorColour : grey);
        ImGui::TextUnformatted(shown_said.c_str());
        ImGui::PopStyleColor();
    }
    ImGui::EndGroup();
    const bool cut = shown_stats != stats || shown_said != said;
    if (cut && ImGui::IsItemHovered()) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(ImGui::GetIO().DisplaySize.x * 0.8f);
        ImGui::TextUnformatted(stats.c_str());
        if (!message.empty()) ImGui::TextUnformatted(message.c_str());
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    }
    probe("status_bar", stats + said);
    probe("status_rows", shown_stats + (shown_said.empty() ? "" : " " + shown_said));
    if (dismiss) {
        // Errors stay until the next message or until dismissed here.
        ImGui::SameLine();
        if (ImGui::SmallButton("x##dismiss")) status_.set("");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Dismiss this message");
    }
}

}  // namespace rtview
