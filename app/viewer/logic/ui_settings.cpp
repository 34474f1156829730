// UI settings, font discovery and contrast (see ui_settings.h).
#include "ui_settings.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <sstream>

#include "image_io.h"
#include "recent_files.h"

namespace rtview {

namespace {

const double kSteps[] = {0.75, 1, 1.25, 1.5, 1.75, 2, 2.5, 3};

bool is_file(const std::string& p) {
    std::error_code ec;
    return !p.empty() && std::filesystem::is_regular_file(p, ec);
}

double linear_channel(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

double luminance(const Rgb& c) {
    return 0.2126 * linear_channel(c.r) + 0.7152 * linear_channel(c.g) + 0.0722 * linear_channel(c.b);
}

}  // namespace

std::string UiSettings::default_path() {
    std::string recent = RecentFiles::default_path();
    if (recent.empty()) return {};
    return std::filesystem::path(recent).parent_path().string() + "/settings.txt";
}

UiSettings::UiSettings(std::string file) : file_(file.empty() ? default_path() : std::move(file)) { load(); }

void UiSettings::load() {
    ui_scale_ = 1;
    sidebar_share_ = 0;
    other_lines_.clear();
    if (file_.empty()) return;
    std::string text;
    if (!rt::read_file(file_, text, 1 << 20).ok()) return;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string key;
        double v = 0;
        if (words >> key && key == "ui_scale") {
            if (words >> v && std::isfinite(v)) ui_scale_ = std::clamp(v, kMinScale, kMaxScale);
        } else if (key == "sidebar_share") {
            if (words >> v && std::isfinite(v) && v > 0)
                sidebar_share_ = std::clamp(v, kMinSidebarShare, kMaxSidebarShare);
        } else if (key == "sidebar_width") {
            // (An absolute width of earlier versions: dropped, the layout chooses.)
        } else if (!line.empty()) {
            other_lines_.push_back(line);
        }
    }
}

rt::Status UiSettings::save() const {
    std::ostringstream out;
    out << "ui_scale " << ui_scale_ << "\n";
    if (sidebar_share_ > 0) out << "sidebar_share " << sidebar_share_ << "\n";
    for (const std::string& l : other_lines_) out << l << "\n";
    return save_config_file(file_, out.str());
}

rt::Status UiSettings::set_ui_scale(double scale) {
    if (!std::isfinite(scale)) return {};
    ui_scale_ = std::clamp(scale, kMinScale, kMaxScale);
    return save();
}

rt::Status UiSettings::set_sidebar_share(double share, bool keep) {
    if (!std::isfinite(share) || share <= 0) return {};
    sidebar_share_ = std::clamp(share, kMinSidebarShare, kMaxSidebarShare);
    return keep ? save() : rt::Status{};
}

double next_ui_scale(double scale, int direction) {
    if (direction > 0) {
        for (double s : kSteps)
            if (s > scale + 1e-9) return s;
        return kSteps[std::size(kSteps) - 1];
    }
    if (direction < 0) {
        for (auto it = std::rbegin(kSteps); it != std::rend(kSteps); ++it)
            if (*it < scale - 1e-9) return *it;
        return kSteps[0];
    }
    return scale;
}

std::string find_font_in(const std::vector<std::string>& data_dirs, FontFace face) {
    static const char* const kUi[] = {
        "fonts/truetype/dejavu/DejaVuSans.ttf",  // Debian's fonts-dejavu-core
        "fonts/dejavu/DejaVuSans.ttf",            // Fedora, Arch
        "fonts/TTF/DejaVuSans.ttf",
    };
    static const char* const kMono[] = {
        "fonts/truetype/dejavu/DejaVuSansMono.ttf",  // fonts-dejavu-core, beside DejaVu Sans
        "fonts/dejavu/DejaVuSansMono.ttf",
        "fonts/TTF/DejaVuSansMono.ttf",
        "fonts/truetype/liberation/LiberationMono-Regular.ttf",
        "fonts/truetype/noto/NotoSansMono-Regular.ttf",
    };
    const bool mono = face == FontFace::Mono;
    for (const std::string& dir : data_dirs) {
        if (dir.empty()) continue;
        for (std::size_t k = 0; k < (mono ? std::size(kMono) : std::size(kUi)); ++k) {
            std::string p = dir + (dir.back() == '/' ? "" : "/") + (mono ? kMono[k] : kUi[k]);
            if (is_file(p)) return p;
        }
    }
    return {};
}

namespace {

std::string find_font(const char* env, FontFace face) {
    if (const char* f = std::getenv(env); f && is_file(f)) return f;
    std::vector<std::string> dirs;
    if (const char* home = std::getenv("HOME"); home && *home) dirs.push_back(std::string(home) + "/.local/share");
    const char* xdg = std::getenv("XDG_DATA_DIRS");
    std::string list = xdg && *xdg ? xdg : "/usr/local/share:/usr/share";
    std::istringstream in(list);
    std::string d;
    while (std::getline(in, d, ':')) dirs.push_back(d);
    // Always look in the system folder too: XDG_DATA_DIRS may list only a Flatpak's.
    dirs.push_back("/usr/share");
    return find_font_in(dirs, face);
}

}  // namespace

std::string find_ui_font() { return find_font("RAYTRACER_VIEW_FONT", FontFace::Ui); }
std::string find_mono_font() { return find_font("RAYTRACER_VIEW_MONO_FONT", FontFace::Mono); }

double contrast_ratio(const Rgb& a, const Rgb& b) {
    double la = luminance(a), lb = luminance(b);
    if (la < lb) std::swap(la, lb);
    return (la + 0.05) / (lb + 0.05);
}

}  // namespace rtview
