// The viewer itself, independent of how its window exists. ViewerApp wires its parts
// together and runs one UI frame; each part has one job:
//   DocumentEditor    the document, the text editor, recent files, crash recovery
//   Navigator         the view camera (not the document) and its gestures
//   NavigationInput   ImGui mouse and fly keys -> Navigator
//   RenderController  renderer, compiled world, preview pacing, film texture
//   SceneLoader       reading, parsing and building a file off the UI thread
//   Panels, Dialogs   ImGui drawing; they act through Commands
//   ImageTools        looking at the picture: exposure, readout, zoom, snapshots,
//                     render region, render to file, UI scale
// The GLFW window binary and the OSMesa headless binary both drive one ViewerApp.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "dialogs.h"
#include "editor.h"
#include "image_tools.h"
#include "loader.h"
#include "move_tool.h"
#include "navigation.h"
#include "navigator.h"
#include "options.h"
#include "panels.h"
#include "render_controller.h"
#include "scene_edits.h"
#include "selection.h"
#include "status.h"
#include "commands.h"
#include "layout.h"
#include "status_line.h"

namespace rtview {

// What the app needs from the program hosting it.
class Host {
public:
    virtual ~Host() = default;
    virtual void set_title(const std::string& title) = 0;
    virtual void quit() = 0;  // close the window now (the app has already asked)
    // From any thread: ends the host's wait for events now (work done elsewhere, such
    // as a load, wants a frame).
    virtual void wake() {}
};

// A load of the start-up scene begun before the app exists (while the window opens),
// with the store its models are read into.
struct EarlyLoad {
    SceneLoader loader;
    std::shared_ptr<rt::ModelStore> models = std::make_shared<rt::ModelStore>();
};

class ViewerApp : private Commands {
public:
    ViewerApp(const Options& options, Host& host, bool interactive);
    ~ViewerApp() override;

    // Opens options.scene (or the default scene). Interactive: the file loads in the
    // background and this returns at once (the window paints meanwhile); headless: it
    // loads now. Returns a message for the terminal when the file cannot be read (the
    // caller exits); parse errors open anyway. `early`: the window's load of that
    // file, begun already; it is taken over instead of starting another.
    rt::Status open_initial(EarlyLoad* early = nullptr);

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
    // Something is in progress (a render, a load, a gesture, a dialog's work). When
    // it stops, the host draws a few more frames: ImGui shows some changes (a popup
    // closed, a hover) only in the frames after the one that made them.
    bool working() const;
    // Cheap work while idle (checks the file on disk); true if a frame is then needed.
    bool idle_tick();

    // --- headless / scripting ----------------------------------------------------
    void orbit_degrees(double degrees);
    // All requested samples are in and the texture shows the final film.
    bool render_settled() const;
    rt::RenderProgress progress() const { return render_.progress(); }
    rt::Status write_view_scene(const std::string& path) const;
    std::string layout_text() const;
    const Document& document() const { return editor_.doc(); }
    const Navigator& navigator() const { return nav_; }
    bool loading() const { return loader_.active(); }
    // How long the last frame's film upload took (its bytes made and sent to the texture).
    double last_upload_seconds() const { return render_.last_upload_seconds(); }
    // The UI scale the user chose (Ctrl+ / Ctrl-); true once after each change, when
    // the host rebuilds the font.
    double ui_scale() const { return tools_.ui_scale(); }
    bool take_ui_scale_change() { return tools_.take_ui_scale_change(); }

private:
    bool run(Command c, const std::string& arg = {}, bool confirmed = false) override;
    std::string failure() const override { return failure_; }

    bool ui_busy() const;
    // A digest of what the frame shows that other threads or late parts of a frame
    // change (status text, dialogs, progress, diagnostics, the readout): a frame that
    // changed it drew some of its parts with the old state, so another frame follows.
    std::uint64_t visible_key() const;
    void update_layout();
    ImageFrame image_frame(double now);
    void handle_shortcuts();
    // Escape with a menu open closes it (true: the key is used up); a Ctrl shortcut
    // closes it too, and then does what it does.
    bool close_menus_for_keys();
    void end_edits();
    void poll_loader();
    // Parts of frame(): the render follows the scene, the view and the picture tools;
    // the message where there is no picture; the picture (the preview or the film, the
    // move handle over it); the title, --print-layout and --view-scene once they change.
    void update_render(double now);
    void draw_no_image();
    void draw_picture();
    void publish_outputs();
    // --print-layout: what the frame showed, in words (probe.h).
    void probe_frame();
    // The UI thread's CPU time of each frame(): a frame over kSlowFrame counts as slow
    // (said with --verbose, counted for --print-layout's "slow_frames").
    void frame_timing_begin();
    void frame_timing_end();
    static constexpr double kSlowFrame = 0.050;
    double frame_cpu0_ = 0, slowest_frame_ = 0;
    long slow_frames_ = 0, very_slow_frames_ = 0;  // over kSlowFrame, over twice that
    // The frame's wall time too: a frame that waits (for the pool's workers in a parse
    // it shares, say) stops the window without using the UI thread's CPU. Over
    // kStalledFrame it counts as stalled.
    static constexpr double kStalledFrame = 0.250;
    double frame_wall0_ = 0, longest_frame_ = 0;
    long stalled_frames_ = 0;
    LoadStatus load_status() const;
    void after_document_replaced();
    void start_load(const std::string& path);
    // A click on the picture at (px, py): what is under it selected alone (Only), added
    // or taken out (Toggle: Shift+click), or, for the context menu, left as it is when
    // it is one of several selected (KeepGroup).
    enum class Pick { Only, Toggle, KeepGroup };
    void select_at(double px, double py, Pick how = Pick::Only);
    void pick_item(const ItemRef& item, Pick how);
    // Ctrl+Shift+left drag on the picture: a box; what it sees joins the selection on
    // the release (true while it has the pointer). Drawn over the picture.
    bool box_select(bool usable);
    void finish_box(double x0, double y0, double x1, double y1);
    void draw_box() const;
    bool box_active_ = false;
    double box_x0_ = 0, box_y0_ = 0;
    // Delete and Duplicate of several things: one undo step, which gives the selection
    // back (selection_steps_).
    bool group_edit(Command c);
    SelectionSteps selection_steps_;
    // Escape with nothing else to close or cancel: nothing selected.
    void escape_clears_selection();
    // The scene camera's focus_distance set to the surface under (px, py) (one undo step).
    void focus_at(double px, double py);
    // The view the picture is rendered through, as the move tool projects with it.
    ScreenView screen_view() const;
    // Structural edits and the image's context menu.
    bool scene_edit(const std::string& arg, Command c);
    // File > Add model's mesh block for the model at `path` (read through the
    // document's models); none, with the status saying why, if it cannot be read.
    std::optional<SceneEdit> model_edit(const std::string& path);
    // Where an added item goes (placement.h): at the point pointed at (right-click >
    // Add here), else near the picture's centre (an object: where it stands clear of
    // the others).
    Placement new_item_placement(bool object);
    // How far Duplicate moves the copy.
    rt::Vec3 duplicate_offset(const rt::Scene& scene) const;
    bool cancel_load();
    // Ctrl+Z / Ctrl+Y, or a step of the Edit menu's history: `steps` steps back or
    // forward, saying which in the status bar.
    bool undo_redo(bool undo, int steps);
    // The commands that change the view, the pause or the fit.
    bool view_command(Command c);
    void handle_context_menu(bool usable);
    void draw_context_menu();
    bool ready_to_save(Command c, const std::string& arg, bool confirmed);
    // `confirmed`: the user said to save text that does not parse.
    bool do_save(bool confirmed = false);
    bool do_save_as(const std::string& path, bool confirmed = false);
    // Puts `path` first in the recent-files list (in the window only); fails when the
    // list could not be saved.
    rt::Status remember_recent(const std::string& path);
    void do_save_image(const std::string& path);
    std::string default_image_name() const;

    Options opt_;
    Host& host_;
    bool interactive_;
    bool orbited_ = false;  // --orbit applied to the start-up scene
    bool selected_ = false;  // --select applied to the start-up scene
    StatusLine status_;
    Layout layout_;
    DocumentEditor editor_;
    Navigator nav_;
    NavigationInput nav_input_;
    // The process's pool (rt::process_pool()), of --threads workers: the progressive
    // render, the moving view's preview (with the UI thread), the region and the final
    // render, and the loading's and the builds' parallel parts.
    rt::ThreadPool& pool_;
    RenderController render_;
    SceneLoader loader_;  // after editor_: its worker reads into the document's model store, and is joined first
    Dialogs dialogs_;
    ImageTools tools_;
    Panels panels_;
    MoveTool move_;  // the selection's outline and translate handle

    // Right button in the image: a click (no drag) opens the context menu there.
    bool rclick_armed_ = false;
    double rclick_x_ = 0, rclick_y_ = 0;
    double place_x_ = -1, place_y_ = -1;  // where AddItem puts things (screen); < 0: image centre
    double model_place_x_ = -1, model_place_y_ = -1;  // place_x_/y_ while the Add model dialog asks
    ItemRef menu_prev_selection_;         // the selection before the right click (for CSG)
    std::string menu_readout_;            // the pixel readout where it was opened
    std::string screenshot_request_;
    std::string last_title_, last_layout_;
    double last_disk_check_ = 0;
    bool view_scene_written_ = false;
    int frames_ = 0;
    std::uint64_t render_error_shown_ = 0;  // the render generation whose error was shown
    bool again_ = false;  // the last frame changed visible_key(): draw one more
    bool esc_closed_menu_ = false;  // this frame's Escape closed a menu
    std::string failure_;  // why the last save failed (Commands::failure)
    std::string last_folder_;  // of the last file opened or saved (Save As of an unsaved scene starts there)
    std::string save_as_start() const;
};

}  // namespace rtview
