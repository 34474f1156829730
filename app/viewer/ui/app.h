// The viewer itself, independent of how its window exists: ImGui panels, camera input,
// the render loop around rt::Renderer and the film texture. The GLFW window binary and
// the OSMesa headless binary both drive one ViewerApp per frame.
#pragma once

#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "camera_control.h"
#include "document.h"
#include "film_texture.h"
#include "options.h"
#include "recent_files.h"
#include "recovery.h"
#include "renderer.h"
#include "viewport.h"
#include "world.h"

namespace rtview {

// What the app needs from the program hosting it.
class Host {
public:
    virtual ~Host() = default;
    virtual void set_title(const std::string& title) = 0;
    virtual void quit() = 0;  // close the window now (the app has already asked)
};

struct Selection {
    enum class Kind { None, Object, Plane, Light } kind = Kind::None;
    int index = -1;         // top-level object, plane or light
    std::vector<int> path;  // CSG operand path below an object (0 = left, 1 = right)
    bool operator==(const Selection& o) const { return kind == o.kind && index == o.index && path == o.path; }
};

class ViewerApp {
public:
    ViewerApp(const Options& options, Host& host, bool interactive);
    ~ViewerApp();

    // Opens options.scene (or the default scene). Returns a message for the terminal
    // when the file cannot be read (the caller exits); parse errors open anyway.
    std::string open_initial();

    // One UI frame, between ImGui::NewFrame() and ImGui::Render().
    void frame();
    // After the frame is drawn into the framebuffer (before swapping): F12 screenshots.
    void after_render(int fb_width, int fb_height);

    // The window wants to close: true if it may (else the app asks about unsaved edits).
    bool close_requested();
    void drop_files(const std::vector<std::string>& paths);

    // How long the host may sleep for events: < 0 wait indefinitely, 0 poll.
    double wait_timeout() const;
    // Something other than input needs a new frame (render progress, a due check).
    bool needs_frame();
    // Cheap work while idle (checks the file on disk); true if a frame is then needed.
    bool idle_tick();

    // --- headless / scripting ----------------------------------------------------
    void orbit_degrees(double degrees);
    // All requested samples are in and the texture shows the final film.
    bool render_settled() const;
    rt::RenderProgress progress() const { return renderer_.progress(); }
    std::string write_view_scene(const std::string& path) const;
    std::string layout_text() const;
    const Document& document() const { return doc_; }

private:
    // ---- app.cpp: behaviour ------------------------------------------------------
    void update_layout();
    void handle_shortcuts();
    void handle_view_input();
    void update_render();
    void upload_film();
    void end_gestures();
    void set_camera(const rt::Camera& cam);  // part of the pending edit
    void commit_now();
    rt::Camera view_camera() const;
    rt::Vec3 pick_point_or(double px, double py, double fallback_distance, bool* hit = nullptr);
    double scene_size() const;
    rt::Vec3 world_up() const { return world_up_of(doc_.file_camera()); }
    void select_at(double px, double py);
    void frame_scene();
    void reset_camera();
    void toggle_pause();
    void status(const std::string& text, bool error = false);
    void after_document_replaced();
    // File actions; the ones that would drop unsaved edits ask first.
    enum class Action { None, Quit, Open, OpenDefault };
    void request(Action a, const std::string& path = {});
    void perform(Action a, const std::string& path);
    void do_save();
    bool do_save_as(const std::string& path);
    void do_save_image(const std::string& path);
    void do_open(const std::string& path);

    // ---- panels.cpp: ImGui -------------------------------------------------------
    void draw_menu_bar();
    void draw_sidebar();
    void draw_camera_panel();
    void draw_objects_tab();
    void draw_outline();
    void draw_object_node(const rt::Object& obj, int top, std::vector<int>& path, const std::string& label);
    void draw_properties();
    bool material_editor(const char* id, rt::Material& m);
    void draw_text_tab();
    void draw_render_tab();
    void draw_status_bar();
    void draw_popups();
    void draw_film();
    static int editor_callback(struct ImGuiInputTextCallbackData* data);

    Options opt_;
    Host& host_;
    bool interactive_;
    Document doc_;
    RecentFiles recent_;
    Recovery recovery_;
    bool recovery_offer_ = false;  // a previous session's unsaved text is waiting
    std::string recovered_text_;

    // Rendering
    rt::Renderer renderer_;
    std::shared_ptr<const rt::World> world_;  // compiled doc scene (file camera)
    rt::Scene world_scene_;                   // the scene world_ was compiled from
    std::uint64_t world_version_ = 0;         // doc scene_version world_ matches
    std::future<std::shared_ptr<const rt::World>> building_;  // geometry changed: BVH built off the UI thread
    rt::Scene building_scene_;
    std::uint64_t building_version_ = 0;
    std::shared_ptr<const rt::World> started_world_;  // as last given to the renderer
    rt::Camera started_camera_;
    int started_w_ = 0, started_h_ = 0;
    int max_samples_ = kDefaultSamplesWindow;
    double time_limit_ = 0;
    bool settings_changed_ = false;
    bool paused_ = false;
    FitMode fit_ = FitMode::Window;
    FilmTexture film_;
    std::vector<std::uint8_t> rgba_;
    std::uint64_t film_version_ = 0;
    int film_w_seen_ = 0, film_h_seen_ = 0;  // the size rgba_ holds
    std::uint64_t done_generation_ = ~std::uint64_t(0);
    double done_elapsed_ = 0;
    bool final_uploaded_ = false;
    // Timing of "a view change -> coarse image on screen" (printed with --verbose).
    std::chrono::steady_clock::time_point change_time_{};
    bool timing_change_ = false;
    double last_latency_ms_ = -1;

    // Layout (ImGui logical coordinates) and the film it implies (framebuffer pixels).
    float menu_h_ = 0, status_h_ = 0, sidebar_w_ = 0;
    Rect area_;   // all space for the image
    Rect image_;  // where the film is drawn
    int film_w_ = 1, film_h_ = 1;
    float fb_scale_ = 1;
    Rect camera_panel_, editor_rect_, diag_rect_, outline_rect_;
    std::string last_layout_;

    // Input gestures in the image area.
    enum class Gesture { None, Click, Orbit, Pan };
    Gesture gesture_ = Gesture::None;
    int gesture_button_ = 0;
    double press_x_ = 0, press_y_ = 0;
    rt::Camera press_camera_;
    rt::Vec3 anchor_;  // orbit pivot or pan anchor
    double wheel_time_ = -1;
    bool flying_ = false;
    bool fly_armed_[6] = {};  // D A E Q W S went down without a modifier

    // Selection and panels.
    Selection selection_;
    bool scroll_to_selection_ = false;
    int want_tab_ = -1;  // 0 objects, 1 text, 2 render: select this tab on the next frame
    int current_tab_ = 0;

    // Editor widget state.
    std::uint64_t editor_seen_version_ = 0;
    unsigned editor_id_ = 0;
    bool editor_active_ = false;
    bool focus_editor_ = false;
    int pending_cursor_ = -1;
    int editor_cursor_ = 0;
    double check_due_ = -1;  // live syntax check of the draft after typing stops

    // Popups and messages.
    Action pending_action_ = Action::None;
    std::string pending_path_;
    bool open_unsaved_popup_ = false, open_open_popup_ = false, open_save_as_popup_ = false,
         open_image_popup_ = false, open_help_popup_ = false;
    std::string path_input_;
    std::string status_text_;
    bool status_error_ = false;
    double status_time_ = -100;
    std::string screenshot_request_;
    std::string last_title_;
    double last_disk_check_ = 0;
    bool view_scene_written_ = false;
    int frames_ = 0;
};

}  // namespace rtview
