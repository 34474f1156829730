// Looking at the picture: display controls (exposure, tone curve, clipped overlay),
// the pixel readout, zoom and pan apart from the camera, snapshots and A/B compare,
// the render region, "Render to file..." and the UI scale keys. One object the app
// owns and calls at fixed points of its frame; the logic lives in logic/ (display,
// image_view, snapshots, region, film_view, final_render, readout, ui_settings).
#pragma once

#include <cstdint>
#include <ctime>
#include <algorithm>
#include <memory>
#include <string>

#include "display.h"
#include "film_texture.h"
#include "file_dialog.h"
#include "film_view.h"
#include "final_render.h"
#include "image_view.h"
#include "options.h"
#include "readout.h"
#include "region.h"
#include "renderer.h"
#include "snapshots.h"
#include "ui_settings.h"
#include "viewport.h"

struct ImDrawList;

namespace rtview {

// "14:03:27": a time of day as the picture tools label snapshots.
std::string clock_time(std::time_t t);

// What the picture tools need from the app each frame.
struct ImageFrame {
    const rt::Renderer* renderer = nullptr;
    FilmView* film = nullptr;                // the film's bytes (the render controller keeps them current)
    FilmTexture* texture = nullptr;          // and their texture
    std::shared_ptr<const rt::World> world;  // compiled document scene; may be null
    const rt::Scene* scene = nullptr;        // the document's scene; null when it has errors
    rt::Camera view_camera;                  // the film's camera (fitted to the film in window mode)
    rt::Camera render_camera;                // the view as `raytracer` would see it at picture_size
    int film_w = 1, film_h = 1;              // the film the app asks for: the picture zoom, readout
                                             // and Save Image count in (the scene's picture_size
                                             // in the picture frame, else the window's)
    Rect area;                               // all the space for the picture (window units)
    Rect image;                              // where the app fits the film (letterboxed)
    float fb_scale = 1;                      // framebuffer pixels per window unit
    int max_samples = 1;
    double time_limit = 0;
    bool mouse_free = false;                 // not over a panel, no popup open
    bool keys_free = false;                  // no text field has the keyboard
    double now = 0;                          // seconds
    std::string scene_path;                  // the document's file (empty: not saved yet)
};

class ImageTools {
public:
    // The region and the final render run on `pool` (the viewer's one pool).
    ImageTools(bool verbose, rt::ThreadPool& pool);
    ~ImageTools();

    void begin(const ImageFrame& f) { f_ = f; }
    // Keys of the picture (see the help text). Ctrl+= / Ctrl+- / Ctrl+0 change the UI scale.
    void handle_keys();
    // Mouse over the picture, before the camera's gestures: true while the picture
    // tools own the mouse (Ctrl+wheel, Ctrl+drag, the split line).
    bool handle_mouse();
    // After the app has (re)started its render and uploaded the film: compare
    // textures, readout, region restarts, the final render's end.
    void update();
    // The picture and its overlays, on the background draw list.
    void draw();
    // The "Picture" controls, into the current ImGui window.
    void draw_panel();
    // Menu items: in File ("Render to file...") and in View (display, zoom, compare,
    // region, UI scale).
    void file_menu_items();
    void view_menu_items();
    // The "Render to file" dialog: call where the app draws its popups.
    void draw_popups();
    // Opens the dialog; the file name proposed is the scene's, ending in .png.
    void open_render_dialog();

    // The readout of the pixel under the cursor; empty when it is not over the picture.
    const std::string& readout_line() const { return readout_text_; }
    // Puts a pixel's readout on the clipboard (Ctrl+C over the picture, the picture's
    // context menu); copied() is the last text put there.
    void copy_pixel(const std::string& readout);
    const std::string& copied() const { return copied_; }
    // A message for the status bar (taken once).
    bool take_message(std::string& text, bool& error);
    // The app keeps its render as it is while a region refines (the rest keeps its
    // last picture), and pauses it while a final render runs.
    bool region_active() const { return !region_rect_.empty(); }
    // The film size the region was drawn on: another film size ends it.
    bool region_fits(int film_w, int film_h) const { return film_w == region_w_ && film_h == region_h_; }
    const RegionRenderer* region() const { return region_active() ? &region_ : nullptr; }
    bool final_render_running() const { return final_.active(); }
    // Something animates: a region or final render in progress, a drag.
    bool busy() const;
    // The UI scale the user asked for (saved); true once after each change.
    double ui_scale() const { return settings_.ui_scale(); }
    // All the saved settings (the sidebar keeps its width there too).
    UiSettings& settings() { return settings_; }
    const UiSettings& settings() const { return settings_; }
    bool take_ui_scale_change();
    // Zoomed or panned: the app's picking must use this image rectangle.
    Rect image_rect() const;
    bool fitted() const { return view_.fitted(); }
    const DisplaySettings& display() const { return display_; }

    // Scripting and tests.
    void keep_snapshot();
    void clear_region();

private:
    enum class Compare { Off, Split, Difference };
    enum class Drag { None, Region, Pan, Split };
    int film_w() const { return std::max(1, f_.film_w); }
    int film_h() const { return std::max(1, f_.film_h); }
    // The film on screen matches the one asked for (it lags a frame after a resize).
    bool film_ready() const {
        return f_.film && f_.renderer && f_.film->width() == f_.film_w && f_.film->height() == f_.film_h;
    }
    ViewTransform transform() const;
    double zoom_ratio() const;
    void message(const std::string& text, bool error = false);
    void set_exposure(double stops);
    void set_ui_scale(double scale);
    void set_compare(int mode);
    // Shift+B: compare with the snapshot before the one compared with (the newest after
    // the oldest), side by side if comparing was off.
    void next_snapshot();
    // draw() in steps, along the overlays it draws.
    struct PictureGeometry;
    void draw_picture(ImDrawList* dl, const PictureGeometry& g);
    void draw_pixel_grid(ImDrawList* dl, const PictureGeometry& g);
    void draw_region_outline(ImDrawList* dl, const PictureGeometry& g);
    void draw_split_labels(ImDrawList* dl, const PictureGeometry& g, const std::string& a);
    void draw_difference_legend(ImDrawList* dl, const PictureGeometry& g, const std::string& a, const Snapshot& snap);
    void draw_display_badge(ImDrawList* dl, const PictureGeometry& g);
    void draw_zoom_label(ImDrawList* dl, const PictureGeometry& g);
    // draw_panel() in steps, along its sections.
    void draw_display_controls();
    void draw_zoom_controls();
    void draw_compare_controls();
    void draw_snapshot_list();
    void draw_region_controls();
    void update_readout();
    // draw_popups(): the Render to file dialog's three states.
    void draw_render_setup();
    void draw_render_progress();
    void draw_render_result();
    void update_compare();
    void start_region(const PixelRect& r);
    void restart_region_if_needed();
    const Snapshot* compared() const;

    bool verbose_;
    ImageFrame f_;
    UiSettings settings_;
    bool ui_scale_changed_ = false;

    DisplaySettings display_;
    ImageView view_;

    // Readout
    std::string readout_text_;
    int readout_x_ = -1, readout_y_ = -1;
    double readout_time_ = -1;
    bool readout_done_ = false;            // the render's state the readout was made in
    std::uint64_t readout_generation_ = 0;

    // Snapshots and A/B
    SnapshotStore snapshots_;
    int compare_id_ = 0;  // the snapshot compared with (0: the newest)
    Compare compare_ = Compare::Off;
    double split_ = 0.5;  // fraction of the picture's width
    int diff_scale_log2_ = 3;
    FilmTexture compare_texture_;
    int compare_made_id_ = -1;
    DisplaySettings compare_made_display_;
    int compare_made_w_ = 0, compare_made_h_ = 0;
    double compare_made_time_ = -1;
    std::uint64_t compare_made_film_ = 0;
    DiffStats diff_stats_;

    // Region
    RegionRenderer region_;
    bool region_error_said_ = false;  // its error went to the status bar
    PixelRect region_rect_;       // in picture pixels (drawn with the zoom)
    std::shared_ptr<const rt::World> region_world_;  // the document world it renders
    rt::Camera region_camera_;
    int region_samples_ = 0;
    int region_w_ = 0, region_h_ = 0;

    // Mouse
    Drag drag_ = Drag::None;
    double drag_x_ = 0, drag_y_ = 0, drag_last_x_ = 0, drag_last_y_ = 0;

    // Render to file
    FinalRender final_;
    bool open_render_popup_ = false;
    std::string render_path_;
    int render_samples_ = 64;
    double render_time_limit_ = 0;
    bool render_adaptive_ = true;  // adaptive anti-aliasing, as the viewer refines
    double render_aa_threshold_ = kDefaultAaThreshold;
    std::string render_error_;
    // How the last final render ended, shown in the dialog until it is closed.
    enum class RenderResult { None, Saved, Failed } render_result_ = RenderResult::None;
    std::string render_result_text_;
    bool focus_render_path_ = false;
    bool render_scene_camera_ = false;  // the scene's camera instead of the view
    FileDialog render_browser_;          // "Browse..." for the file

    std::string copied_;

    std::string message_;
    bool message_error_ = false;
    bool has_message_ = false;
};

}  // namespace rtview
