// The file browser in a dialog (see file_dialog.h).
#include "file_dialog.h"

#include <imgui.h>

#include <algorithm>
#include <climits>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "bounded_input.h"
#include "imgui_common.h"
#include "probe.h"

namespace rtview {

namespace {

namespace fs = std::filesystem;

std::string size_text(std::uintmax_t b) {
    char buf[32];
    if (b < 1024) std::snprintf(buf, sizeof buf, "%ju B", b);
    else if (b < (1u << 20)) std::snprintf(buf, sizeof buf, "%.1f KB", double(b) / 1024);
    else if (b < (1u << 30)) std::snprintf(buf, sizeof buf, "%.1f MB", double(b) / (1 << 20));
    else std::snprintf(buf, sizeof buf, "%.1f GB", double(b) / (1 << 30));
    return buf;
}

// Tab in the name field: the browser completes the text (ImGui's callback).
int complete_callback(ImGuiInputTextCallbackData* data) {
    if (data->EventFlag != ImGuiInputTextFlags_CallbackCompletion) return 0;
    auto* self = static_cast<std::pair<const FileBrowser*, std::vector<std::string>*>*>(data->UserData);
    const std::string typed(data->Buf, std::size_t(data->BufTextLen));
    const std::string done = self->first->complete(typed, self->second);
    if (done != typed) {
        data->DeleteChars(0, data->BufTextLen);
        data->InsertChars(0, done.c_str(), done.c_str() + done.size());
    }
    return 0;
}

}  // namespace

void FileDialog::start(Mode mode, std::vector<std::string> extensions, const std::string& filter,
                       const std::string& initial) {
    mode_ = mode;
    filter_ = filter;
    std::error_code ec;
    std::string folder, name;
    if (!initial.empty() && fs::is_directory(initial, ec)) {
        folder = initial;
    } else if (!initial.empty()) {
        fs::path p(initial);
        folder = p.has_parent_path() ? p.parent_path().string() : std::string();
        name = p.filename().string();
    }
    browser_ = std::make_unique<FileBrowser>(std::move(extensions), folder);
    typed_ = name;
    chosen_.clear();
    message_.clear();
    candidates_.clear();
    confirm_replace_.clear();
    focus_field_ = true;
}

std::string FileDialog::filter_label() const { return filter_.empty() ? "All files" : filter_; }

void FileDialog::draw_folder_row() {
    if (ImGui::Button("Up")) browser_->up();
    ImGui::SameLine();
    if (ImGui::Button("Home")) browser_->go("~");
    ImGui::SameLine();
    ImGui::TextUnformatted(browser_->folder().c_str());
    probe("browser_folder", browser_->folder());
}

void FileDialog::draw_entries(Result& result) {
    const float fs = ImGui::GetFontSize();
    ImGui::BeginChild("entries", ImVec2(fs * 36, fs * 16), true);
    const std::vector<FileEntry> entries = browser_->entries();  // a click may list another folder
    ImGuiListClipper clipper;
    clipper.Begin(int(entries.size()));
    while (clipper.Step()) {
        for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
            const FileEntry& e = entries[std::size_t(i)];
            const std::string label = (e.folder ? e.name + "/" : e.name) + "##" + std::to_string(i);
            ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(e.readable ? ImGuiCol_Text : ImGuiCol_TextDisabled));
            const bool picked = ImGui::Selectable(label.c_str(), !e.folder && e.name == typed_,
                                                  ImGuiSelectableFlags_AllowDoubleClick);
            ImGui::PopStyleColor();
            if (!e.folder) {
                ImGui::SameLine(fs * 26);
                ImGui::TextDisabled("%s", size_text(e.size).c_str());
            }
            if (!picked) continue;
            const bool twice = ImGui::IsMouseDoubleClicked(0);
            if (e.folder) {
                if (browser_->go(e.name)) typed_.clear();
                focus_field_ = true;
            } else {
                typed_ = e.name;
                if (twice) result = choose(typed_);
            }
        }
    }
    if (entries.empty()) ImGui::TextDisabled(browser_->error().empty() ? "(no %s here)" : "%s",
                                             browser_->error().empty() ? filter_label().c_str() : browser_->error().c_str());
    if (browser_->truncated()) ImGui::TextDisabled("(only the first %zu entries)", FileBrowser::kMaxEntries);
    ImGui::EndChild();
}

// The name (or path) field; true on Enter.
bool FileDialog::draw_name_field() {
    const float fs = ImGui::GetFontSize();
    if (focus_field_) ImGui::SetKeyboardFocusHere();
    focus_field_ = false;
    // The filter's choice is as wide as its longer label (never cut, at any UI scale);
    // the name field has the rest of the dialog's usual width.
    const ImGuiStyle& st = ImGui::GetStyle();
    const float filter_w = std::max(ImGui::CalcTextSize(filter_label().c_str()).x, ImGui::CalcTextSize("All files").x) +
                           2 * st.FramePadding.x + ImGui::GetFrameHeight();
    ImGui::SetNextItemWidth(std::max(fs * 12, fs * 39 - filter_w - st.ItemSpacing.x));
    std::pair<const FileBrowser*, std::vector<std::string>*> data{browser_.get(), &candidates_};
    const bool enter = bounded_input(
        "##name", mode_ == Mode::Open ? "file name or path (Tab completes)" : "new file name or path (Tab completes)",
        typed_, PATH_MAX, ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_CallbackCompletion, complete_callback,
        &data);
    probe_item("browser_name");
    probe("browser_field", ImGui::IsItemActive() ? "active" : "idle");
    ImGui::SameLine();
    bool all = browser_->show_all();
    ImGui::SetNextItemWidth(filter_w);
    if (ImGui::BeginCombo("##filter", all ? "All files" : filter_label().c_str())) {
        if (ImGui::Selectable(filter_label().c_str(), !all)) browser_->set_show_all(false);
        if (ImGui::Selectable("All files", all)) browser_->set_show_all(true);
        ImGui::EndCombo();
    }
    if (!candidates_.empty()) {
        std::string list;
        for (std::size_t k = 0; k < candidates_.size() && k < 12; ++k) list += (k ? "  " : "") + candidates_[k];
        if (candidates_.size() > 12) list += "  ...";
        ImGui::PushTextWrapPos(fs * 36);
        ImGui::TextDisabled("%s", list.c_str());
        ImGui::PopTextWrapPos();
    }
    return enter;
}

// The typed text chosen: a folder is entered, a file is the answer (Open: one that
// exists; Save: one that may, after the user confirms).
FileDialog::Result FileDialog::choose(const std::string& typed) {
    const std::string path = browser_->resolve(typed);
    std::error_code ec;
    message_.clear();
    if (typed.empty()) return Result::None;
    focus_field_ = true;  // Enter left the field: the next name is typed there too
    if (fs::is_directory(path, ec)) {
        if (browser_->go(path)) typed_.clear();
        else message_ = browser_->error();
        return Result::None;
    }
    const bool exists = fs::exists(path, ec);
    if (mode_ == Mode::Open && !exists) {
        message_ = "There is no " + path;
        return Result::None;
    }
    if (mode_ == Mode::Save && exists && confirm_replace_ != path) {
        confirm_replace_ = path;
        return Result::None;
    }
    chosen_ = path;
    return Result::Go;
}

FileDialog::Result FileDialog::draw(const char* button) {
    if (!browser_) return Result::Cancel;
    Result result = Result::None;
    draw_folder_row();
    draw_entries(result);
    if (draw_name_field()) result = choose(typed_);
    if (!message_.empty()) {
        // (Wrapped at the entries' width: a long path would widen the dialog.)
        ImGui::PushStyleColor(ImGuiCol_Text, kErrorColour);
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + ImGui::GetFontSize() * 36);
        ImGui::TextWrapped("%s", message_.c_str());
        ImGui::PopTextWrapPos();
        ImGui::PopStyleColor();
    }
    probe("browser_message", message_.empty() ? "none" : message_);
    if (!confirm_replace_.empty() && browser_->resolve(typed_) == confirm_replace_) {
        probe("browser_confirm", confirm_replace_);
        ImGui::TextColored(ImVec4(1.0f, 0.80f, 0.35f, 1.0f), "%s exists: %s again (or Enter) replaces it.",
                           confirm_replace_.c_str(), button);
    }
    if (ImGui::Button(button)) result = choose(typed_);
    probe_item("browser_go");
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || escape_pressed()) result = Result::Cancel;
    probe("browser", (mode_ == Mode::Open ? "open " : "save ") + browser_->resolve(typed_));
    return result;
}

}  // namespace rtview
