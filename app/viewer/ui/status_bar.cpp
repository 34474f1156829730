// The status bar: the message, the load's progress, the render's numbers and the
// pixel readout, flowed into as many rows as they need (see panels.h).
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

// Pieces of status-bar text flowed into rows: a piece stays on the current row if it
// fits (with its separator), else it starts a row of its own at the left, broken at
// spaces where it is wider than the bar (never inside a number), and what follows goes
// on after it. Returns the height of the rows below the first; draws them when `draw`,
// and gives their text in `shown` (for --print-layout).
struct StatusPiece {
    std::string text;
    const char* sep = "";
    const ImVec4* colour = nullptr;
};

float flow_status(const std::vector<StatusPiece>& pieces, float x, float left, float right, bool draw,
                  std::vector<std::string>* shown = nullptr) {
    const ImGuiStyle& st = ImGui::GetStyle();
    const auto measure = [](std::string_view t) { return ImGui::CalcTextSize(t.data(), t.data() + t.size()).x; };
    float extra = 0;
    bool first = true;
    for (const StatusPiece& p : pieces) {
        const std::string joined = p.sep + p.text;
        const float w = measure(joined);
        const bool fits = x + w <= right;
        const std::vector<std::string> rows = fits ? std::vector<std::string>{joined} : wrap_words(p.text, right - left, measure);
        if (shown) {
            if (fits && !shown->empty()) shown->back() += (first ? "" : " ") + joined;
            else shown->insert(shown->end(), rows.begin(), rows.end());
        }
        if (draw) {
            if (p.colour) ImGui::PushStyleColor(ImGuiCol_Text, *p.colour);
            for (std::size_t k = 0; k < rows.size(); ++k) {
                if (fits && !first) ImGui::SameLine();
                if (!fits && first && k == 0) ImGui::NewLine();
                if (!fits) ImGui::SetCursorPosX(left);
                ImGui::TextUnformatted(rows[k].c_str());
            }
            if (p.colour) ImGui::PopStyleColor();
        }
        if (fits) {
            x += w + st.ItemSpacing.x;
        } else {
            extra += float(rows.size()) * (ImGui::GetTextLineHeight() + st.ItemSpacing.y);
            x = left + measure(rows.back()) + st.ItemSpacing.x;
        }
        first = false;
    }
    return extra;
}

// "spp" names the progress bar's numbers: it stays beside them. The groups of a
// pixel readout ("RGB 0.107 0.107 0.125", three spaces apart) each move to the next
// row whole.
void add_status_line(std::vector<StatusPiece>& pieces, const std::string& text) {
    std::string rest = text;
    const char* sep = "";
    if (text.rfind("spp  ", 0) == 0) {
        pieces.push_back({"spp"});
        rest = text.substr(5);
        sep = " ";
    }
    for (std::size_t at = rest.find("   "); at != std::string::npos; at = rest.find("   ")) {
        pieces.push_back({rest.substr(0, at), sep});
        rest.erase(0, at + 3);
        sep = "   ";
    }
    pieces.push_back({rest, sep});
}

// The status bar's window padding (unscaled, as its one row always had).
const ImVec2 kStatusPadding(6, 4);

// The pieces of the status bar's usual contents at their usual width: the statistics
// with the message, and a pixel readout (a longer one makes the bar grow while the
// message stays: status_more_).
std::vector<StatusPiece> usual_stats() {
    std::vector<StatusPiece> p;
    add_status_line(p, "spp  00.00 Mrays/s  000.0 s  rendering  |  picture frame");
    return p;
}
std::vector<StatusPiece> usual_readout() {
    std::vector<StatusPiece> p;
    add_status_line(p, "spp  rendering  | x 000 y 000   RGB 0.000 0.000 0.000   64 spp   object 10 (sphere) at 0.00");
    return p;
}

// Where the text starts on the first row: after the button and the progress bar.
float status_text_x() {
    const float spacing = ImGui::GetStyle().ItemSpacing.x;
    return kStatusPadding.x + ImGui::GetFontSize() * (4.5f + 8) + 2 * spacing;
}

// The pieces followed by the last message, if there is one.
std::vector<StatusPiece> with_message(const StatusLine& status, std::vector<StatusPiece> pieces) {
    static const ImVec4 grey(0.75f, 0.75f, 0.75f, 1);
    if (!status.text().empty()) pieces.push_back({status.text(), "| ", status.error() ? &kErrorColour : &grey});
    return pieces;
}

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
            ImGui::ProgressBar(float(load.fraction), ImVec2(ImGui::GetFontSize() * 8, 0));
            ImGui::SameLine();
            status_text(load.text + " (Esc cancels)", true);
        } else {
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
            else std::snprintf(buf, sizeof buf, "%d / %d", p.samples, render_.max_samples());
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
            // As wide as its longest usual text (up to 100M pixels refining), at any UI scale.
            const float bar_w = std::max(ImGui::GetFontSize() * 8,
                                         ImGui::CalcTextSize("99999k px refining").x + ImGui::GetStyle().FramePadding.x * 4);
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
            char line[512];
            const char* unit = p.refining >= 0 ? "" : "spp  ";  // (an adaptive bar counts pixels)
            if (!tools_.readout_line().empty())
                std::snprintf(line, sizeof line, "%s%s  | %s", unit, shown, tools_.readout_line().c_str());
            else
                std::snprintf(line, sizeof line, "%s%.2f Mrays/s  %.1f s  %s  |  %s", unit, rate / 1e6, elapsed, shown,
                              layout_.fit == FitMode::Picture ? "picture frame" : "fill window");
            status_text(line, true);
        }
    }
    ImGui::End();
    ImGui::PopStyleVar();
}

// The rows below the first that the status bar's usual contents need in a window
// `width` wide: the statistics, or a readout, with the message (the current one, and one
// of the usual length, so that the next message rarely changes the bar's height).
float Panels::usual_status_extra(float width) const {
    const float left = kStatusPadding.x, right = width - kStatusPadding.x, x = status_text_x();
    StatusLine typical;
    typical.set("The scene camera is now the view (Ctrl+Z undoes)");
    return std::max({flow_status(with_message(status_, usual_stats()), x, left, right, false),
                     flow_status(with_message(typical, usual_stats()), x, left, right, false),
                     flow_status(with_message(status_, usual_readout()), x, left, right, false),
                     flow_status(with_message(typical, usual_readout()), x, left, right, false)});
}

// The status bar's height in a window `width` wide: what its usual contents need
// rather than what it shows now, so the image area keeps its size when the mouse moves
// onto the picture, a dialog opens or a message comes. Known before the bar is drawn:
// the first frame has it right.
float Panels::status_height(float width) {
    float extra = usual_status_extra(width);
    // Shown text that needed more (a long object name), while the message and width last.
    if (status_more_.width == width && status_more_.font == ImGui::GetFontSize() && status_more_.text == status_.text())
        extra = std::max(extra, status_more_.extra);
    return std::ceil(ImGui::GetFrameHeight() + 8 * ImGui::GetFontSize() / 13.f + extra);
}

// The status bar's text right of the button and the progress bar, then the last message
// (`show_message`). What does not fit on the row goes on rows of its own below rather
// than being cut at the bar's edge (status_height() leaves room for them).
void Panels::status_text(const std::string& text, bool show_message) {
    std::vector<StatusPiece> shown;
    add_status_line(shown, text);
    if (show_message) shown = with_message(status_, std::move(shown));
    std::vector<std::string> rows;
    const float extra = flow_status(shown, ImGui::GetCursorPosX(), ImGui::GetWindowContentRegionMin().x,
                                    ImGui::GetWindowContentRegionMax().x, true, &rows);
    std::string all, drawn;
    for (const StatusPiece& p : shown) all += p.sep + p.text;
    for (const std::string& r : rows) drawn += (drawn.empty() ? "" : " || ") + r;
    probe("status_bar", all);
    if (show_message && status_.error()) {
        // Errors stay until the next message or until dismissed here.
        ImGui::SameLine();
        if (ImGui::SmallButton("x##dismiss")) status_.set("");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("Dismiss this message");
    }
    probe("status_rows", drawn);
    const float width = ImGui::GetWindowWidth();
    if (extra > usual_status_extra(width)) status_more_ = {width, ImGui::GetFontSize(), status_.text(), extra};
}

}  // namespace rtview
