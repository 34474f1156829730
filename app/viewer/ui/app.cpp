// ViewerApp: the frame loop over the viewer's parts, loading, the layout and the host
// interface (see app.h). Its commands: app_commands.cpp; keyboard shortcuts and clicks
// on the picture: app_input.cpp; structural edits: app_edits.cpp; --print-layout:
// app_probe.cpp.
#include "app.h"

#include <imgui.h>
#include <imgui_internal.h>  // GetActiveID: 1.86 has no public equivalent

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <utility>

#include "default_scene.h"
#include "image_io.h"
#include "imgui_common.h"
#include "layout.h"
#include "scene_edits.h"
#include "scene_writer.h"
#include "diagnostic_text.h"
#include "number_field.h"
#include "paths.h"
#include "probe.h"
#include "status_notes.h"

namespace rtview {

namespace {

// Program start, near enough: for --verbose timings.
const auto g_start = std::chrono::steady_clock::now();
double since_start() { return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count(); }

std::string megabytes(std::uint64_t b) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", double(b) / (1 << 20));
    return buf;
}

// The process's pool, with the render threads asked for (0: one per hardware thread)
// when it is not running yet.
rt::ThreadPool& render_pool(int threads) {
    rt::set_process_threads(threads);
    return rt::process_pool();
}

}  // namespace

ViewerApp::ViewerApp(const Options& options, Host& host, bool interactive)
    : opt_(options),
      host_(host),
      interactive_(interactive),
      editor_(interactive, status_),
      nav_input_(nav_),
      pool_(render_pool(options.threads)),
      render_(pool_, interactive,
              options.samples > 0 ? options.samples : (interactive ? kDefaultSamplesWindow : kDefaultSamplesHeadless),
              options.time_limit, options.aa_threshold.value_or(kDefaultAaThreshold)),
      dialogs_(*this, editor_.recent()),
      tools_(options.verbose, pool_),
      panels_(*this, editor_, nav_, render_, layout_, status_, tools_) {
    layout_.fit = opt_.fit;
    render_.verbose = opt_.verbose;
    render_.clock = &since_start;
    // A finished load is taken in the next frame, not when the host next looks.
    loader_.set_on_finished([&host] { host.wake(); });
    if (opt_.handle == "turn") move_.set_mode(HandleMode::Turn);
    else if (opt_.handle == "size") move_.set_mode(HandleMode::Size);
    if (opt_.tab == "text") panels_.show_tab(Panels::Text);
    else if (opt_.tab == "render") panels_.show_tab(Panels::Render);
    else panels_.show_tab(Panels::Objects);
}

ViewerApp::~ViewerApp() = default;

rt::Status ViewerApp::open_initial(EarlyLoad* early) {
    Document& doc = editor_.doc();
    if (opt_.scene.empty()) {
        doc.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
        after_document_replaced();
    } else if (interactive_) {
        // The window paints and its menus work while the file loads. A file that
        // cannot be read at all is still a message for the terminal.
        if (::access(opt_.scene.c_str(), R_OK) != 0)
            return rt::Status::error("cannot open '" + opt_.scene + "': " + std::strerror(errno), rt::kExitUsage);
        doc.load_pending(base_name(opt_.scene));
        if (early && early->loader.active()) {
            doc.share_models(early->models);
            loader_.take_over(early->loader);
            status_.set("Opening " + opt_.scene);
        } else {
            start_load(opt_.scene);
        }
    } else {
        loader_.start(opt_.scene, true, &doc.models());
        std::optional<LoadResult> r = loader_.wait();
        std::shared_ptr<const rt::World> world;
        if (!r || !apply_load(*r, doc, world))
            return rt::Status::error("cannot open '" + opt_.scene + "': " + (r ? r->error : ""), rt::kExitUsage);
        if (world) render_.adopt_world(std::move(world), doc.content_version());
        after_document_replaced();
    }
    if (!opt_.select.empty()) panels_.select_from_option(opt_.select);
    return {};
}

void ViewerApp::after_document_replaced() {
    panels_.clear_selection();
    selection_steps_.clear();
    nav_.cancel_gesture();
    editor_.replaced();
    if (editor_.doc().has_scene()) nav_.reset(editor_.doc().scene().camera);
}

void ViewerApp::start_load(const std::string& path) {
    // The document's store: a model the new scene shares with the old one is not read again.
    loader_.start(path, true, &editor_.doc().models());
    status_.set("Opening " + path);
}

void ViewerApp::poll_loader() {
    std::optional<LoadResult> r = loader_.poll();
    if (!r) return;
    if (r->status == LoadResult::Status::Failed) {
        // The old scene stays.
        status_.set("Cannot open " + r->path + ": " + r->error, true);
        if (r->path == opt_.scene && !document().has_scene() && document().editor_text().empty()) {
            // The start-up file could not be read: show the default scene instead.
            editor_.doc().load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
            after_document_replaced();
        }
        return;
    }
    Document& doc = editor_.doc();
    std::string path = r->path;
    bool ok = r->parsed.ok();
    const bool model = r->new_scene;
    const LoadResult::Times times = r->times;
    std::shared_ptr<const rt::World> world;
    if (!apply_load(*r, doc, world)) return;  // cancelled: the old scene stays
    if (world) render_.adopt_world(std::move(world), doc.content_version());
    {
        std::error_code ec;
        const std::filesystem::path p = std::filesystem::absolute(path, ec);
        if (!ec) last_folder_ = p.parent_path().string();
    }
    const rt::Status recent = remember_recent(path);
    if (path == opt_.scene)  // at most 20, as raytracer prints them
        std::fputs(rt::diagnostics_report(path, doc.diagnostics(), 20).c_str(), stderr);
    after_document_replaced();
    // --orbit in the window: once the start-up scene is there (headless orbits itself).
    if (interactive_ && path == opt_.scene && opt_.orbit != 0 && !orbited_) {
        orbited_ = true;
        orbit_degrees(opt_.orbit);
    }
    // --select likewise: the scene it names has only just arrived.
    if (interactive_ && path == opt_.scene && !opt_.select.empty() && !selected_) {
        selected_ = true;
        panels_.select_from_option(opt_.select);
    }
    // (A model opens as a new scene named after it: the file opened is the model.)
    const std::string opened = model ? base_name(path) + " as the new scene " + doc.name() : doc.name();
    status_.set((ok ? "Opened " + opened : "Opened " + opened + " (it has errors)") + light_note(doc) +
                    recent_note(recent),
                !ok || !recent);
    if (opt_.verbose)
        std::fprintf(stderr,
                     "raytracer-view: loaded %s at %.3f s (read %.3f s, parse %.3f s, build %.3f s: compile %.3f s "
                     "beside the layout scan %.3f s)\n",
                     path.c_str(), since_start(), times.read, times.parse, times.build, times.compile, times.scan);
}

// --- Frame

// What the status bar says while a file loads in the background.
LoadStatus ViewerApp::load_status() const {
    LoadStatus load;
    if (!loader_.active()) return load;
    SceneLoader::Progress p = loader_.progress();
    load.active = true;
    std::string name = base_name(p.path);
    switch (p.stage) {
        case SceneLoader::Stage::Reading:
            load.text = "Reading " + name + ": " + megabytes(p.bytes) + " of " + megabytes(p.total) + " MB";
            load.fraction = p.total ? 0.3 * double(p.bytes) / double(p.total) : 0;
            break;
        case SceneLoader::Stage::Parsing:
            load.text = "Parsing " + name + ": " + megabytes(p.bytes) + " of " + megabytes(p.total) + " MB, " +
                        std::to_string(p.objects) + " objects";
            load.fraction = p.total ? 0.3 + 0.45 * double(p.bytes) / double(p.total) : 0.3;
            break;
        case SceneLoader::Stage::Building:
            load.text = "Building the BVH of " + name + ": " + std::to_string(p.objects) + " objects";
            load.fraction = 0.75;
            break;
        default: load.text = "Opening " + name; break;
    }
    return load;
}

void ViewerApp::frame() {
    frame_timing_begin();
    ++frames_;
    double now = ImGui::GetTime();
    Document& doc = editor_.doc();
    const std::uint64_t key_before = visible_key();
    begin_probe_frame();

    poll_loader();
    update_layout();
    tools_.begin(image_frame(now));
    // A number being typed has the keys, also in the frame or two before its field
    // takes the keyboard ("1" of "1.25" is not the 1:1 zoom).
    esc_closed_menu_ = false;
    if (interactive_ && !number_typing()) {
        // Menus are not modal: Escape closes them, and a Ctrl shortcut closes them and
        // works (the picture tools then see the keys free again).
        const bool was_open = ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId);
        esc_closed_menu_ = close_menus_for_keys();
        if (was_open && !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId)) tools_.begin(image_frame(now));
        handle_shortcuts();
        tools_.handle_keys();
    }
    panels_.draw_menu_bar();
    panels_.draw_sidebar();
    if (const int passed = editor_.take_passed_undo()) run(passed > 0 ? Command::Undo : Command::Redo);
    // A document from the list of earlier sessions' copies: opened, its copy then offered.
    if (std::optional<std::string> path = editor_.take_open_request())
        run(path->empty() ? Command::OpenDefault : Command::Open, *path);
    panels_.draw_status_bar(load_status());
    const std::string image_kind = std::string(layout_.fit == FitMode::Window ? "the window's picture, " : "the scene's picture, ") +
                                   std::to_string(layout_.film_w) + "x" + std::to_string(layout_.film_h);
    dialogs_.draw(doc.name(), !doc.path().empty(), image_kind.c_str());
    tools_.draw_popups();

    // The view follows real edits of the scene camera (panel fields, undo, reload).
    if (doc.has_scene()) nav_.follow(doc.scene().camera);
    bool usable = doc.has_scene() && render_.world() && !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId);
    if (interactive_) {
        // Ctrl+wheel, Ctrl+drag and the A/B split line belong to the picture tools:
        // navigation then sees no image under the mouse.
        Layout nav_layout = layout_;
        bool tool_mouse = (box_select(usable) || tools_.handle_mouse()) && !move_.dragging();
        if (tool_mouse) nav_layout.image = Rect{};
        else if (doc.has_scene() && nav_.has_view() &&
                 move_.handle_mouse(doc, panels_.selected(), screen_view(), layout_.image, usable && !nav_.dragging(),
                                    status_))
            nav_layout.image = Rect{};  // the move handle has the pointer
        NavigationInput::Result r = nav_input_.handle(nav_layout, render_.world(), usable, scene_extent(editor_.doc().scene(), render_.world()));
        if (r.clicked) select_at(r.x, r.y, r.shift ? Pick::Toggle : Pick::Only);
        handle_context_menu(usable);
        draw_context_menu();
    }
    end_edits();
    editor_.tick(now);
    if (interactive_ && now - last_disk_check_ >= 1.0) idle_tick();
    update_render(now);
    panels_.draw_surround();
    if (doc.has_scene() || render_.started()) draw_picture();
    if (!doc.has_scene()) draw_no_image();
    probe_frame();
    publish_outputs();
    again_ = visible_key() != key_before;
    frame_timing_end();
}

// The picture: while the view moves, the UI thread's own preview; else the film as the
// picture tools show it (zoom, display mapping, A/B, region). The move handle over it.
void ViewerApp::draw_picture() {
    Document& doc = editor_.doc();
    if (render_.showing_preview()) {
        // Zoomed, the picture reaches past the area: the preview stays within it.
        ImDrawList* dl = ImGui::GetBackgroundDrawList();
        const Rect& a = layout_.area;
        dl->PushClipRect(ImVec2(float(a.x), float(a.y)), ImVec2(float(a.x + a.w), float(a.y + a.h)), true);
        render_.draw(layout_.image, layout_.fb_scale);
        dl->PopClipRect();
    } else {
        tools_.draw();
    }
    // Over the picture, not in the film: a saved image stays clean.
    if (interactive_ && doc.has_scene() && nav_.has_view() && render_.world())
        move_.draw(doc, panels_.selected(), screen_view(), render_.world(), layout_.image, layout_.area,
                   layout_.film_w, layout_.film_h);
    draw_box();
}

void ViewerApp::update_render(double now) {
    Document& doc = editor_.doc();
    render_.sync_world(doc);
    // A slider held in a panel is motion too: previews within the frame budget (but
    // not a number being typed: nothing changes until it is entered).
    bool widget_busy = ImGui::IsAnyItemActive() && !number_typing() &&
                       (editor_.widget_id() == 0 || ImGui::GetActiveID() != editor_.widget_id());
    bool moving = nav_input_.moving(now) || widget_busy || move_.dragging();
    // While a render region refines, the rest of the picture stays as it was (the
    // region re-renders on edits and view changes); a new film size ends the region.
    bool region_holds = tools_.region_active() && tools_.region_fits(layout_.film_w, layout_.film_h);
    // A final render ("Render to file..."), a refining region or a file being parsed
    // and compiled gets the processors (the old scene's picture stays as it is
    // meanwhile; not while reading, which may wait for a pipe's writer).
    const bool compiling = loader_.active() && loader_.progress().stage != SceneLoader::Stage::Reading;
    render_.set_yield(tools_.final_render_running() || (region_holds && tools_.busy()) || compiling);
    if (doc.has_scene() && nav_.has_view() && !region_holds)
        render_.update(nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window}),
                       layout_.film_w, layout_.film_h, moving);
    // The outline and handle are for a user at the window (the headless screenshots
    // show the picture alone).
    if (interactive_ && doc.has_scene() && nav_.has_view())
        move_.update_outline(doc, panels_.selected(), render_,
                             nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window}),
                             layout_.film_w, layout_.film_h);
    tools_.begin(image_frame(now));  // the world and view as the render now has them
    render_.set_display(tools_.display(), tools_.region());
    render_.upload();
    tools_.update();
    {
        std::string text;
        bool error = false;
        if (tools_.take_message(text, error)) status_.set(text, error);
    }
    // A render thread that ran out of memory stopped the render: say so once.
    const rt::RenderProgress p = render_.progress();
    if (!p.error.empty() && p.generation != render_error_shown_) {
        render_error_shown_ = p.generation;
        status_.set("Render stopped: " + p.error, true);
    }
}

void ViewerApp::draw_no_image() {
    std::string opening = "Opening " + base_name(loader_.progress().path) + " ...";
    const char* msg = loader_.active() ? opening.c_str() : "No image: the scene text has errors (see the Text tab).";
    // Wrapped within the image area (narrow at a large UI scale), centred.
    const float wrap = std::max(float(layout_.area.w) - 2 * ImGui::GetFontSize(), ImGui::GetFontSize() * 4);
    ImVec2 sz = ImGui::CalcTextSize(msg, nullptr, false, wrap);
    ImGui::GetBackgroundDrawList()->AddText(
        ImGui::GetFont(), ImGui::GetFontSize(),
        ImVec2(float(layout_.area.x + (layout_.area.w - sz.x) / 2), float(layout_.area.y + (layout_.area.h - sz.y) / 2)),
        ImGui::GetColorU32(loader_.active() ? ImVec4(0.75f, 0.75f, 0.75f, 1.0f) : ImVec4(1.0f, 0.42f, 0.42f, 1.0f)),
        msg, nullptr, wrap);
}

void ViewerApp::publish_outputs() {
    std::string title = editor_.doc().title();
    if (loader_.active()) title = "(loading) " + title;
    if (title != last_title_) {
        host_.set_title(title);
        last_title_ = title;
    }
    if (opt_.print_layout) {
        std::string l = layout_text();
        if (l != last_layout_) {
            std::fputs(l.c_str(), stdout);
            std::fputs("end-layout\n", stdout);
            std::fflush(stdout);
            last_layout_ = l;
        }
    }
    if (interactive_ && !opt_.view_scene.empty() && !view_scene_written_ && render_.started()) {
        if (rt::Status st = write_view_scene(opt_.view_scene); !st) status_.set("view scene: " + st.message(), true);
        view_scene_written_ = true;
    }
}

void ViewerApp::update_layout() {
    ImGuiIO& io = ImGui::GetIO();
    float W = io.DisplaySize.x, H = io.DisplaySize.y;
    Layout& l = layout_;
    l.fb_scale = io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.f;
    float s = ImGui::GetFontSize() / 13.f;  // the UI scale the host chose
    l.menu_h = ImGui::GetFrameHeight();
    l.status_h = std::floor(ImGui::GetFrameHeight() + 8 * s);
    // Wide enough for the property fields' labels and numbers at this UI scale, unless
    // the user chose a width (dragging its edge) or hid it (Tab).
    const float content = std::max(320 * s, panels_.min_sidebar_width());
    l.sidebar_w = l.sidebar_hidden ? 0.f : sidebar_width(W, float(tools_.ui_scale()), content, tools_.settings().sidebar_share());
    l.status_h = std::max(l.status_h, panels_.status_height(W - l.sidebar_w));
    l.area = {0, double(l.menu_h), std::max(1.0, double(W - l.sidebar_w)), std::max(1.0, double(H - l.menu_h - l.status_h))};
    const Document& doc = editor_.doc();
    if (l.fit == FitMode::Picture && doc.has_scene()) {
        // The scene's picture, at its picture_size (what `raytracer` makes of the same
        // camera, and what Save Image writes), shown letterboxed at its aspect.
        l.fit_image = letterbox(l.area, doc.scene().width, doc.scene().height);
        picture_film_size(doc.scene().width, doc.scene().height, l.film_w, l.film_h);
    } else {
        // The window's own picture, one pixel per framebuffer pixel.
        l.fit_image = l.area;
        l.film_w = std::max(1, int(std::lround(l.area.w * l.fb_scale)));
        l.film_h = std::max(1, int(std::lround(l.area.h * l.fb_scale)));
    }
    l.image = l.fit_image;
    // Zoom and pan place that film; they never change it (the render goes on).
    if (!tools_.fitted()) {
        tools_.begin(image_frame(ImGui::GetTime()));
        l.image = tools_.image_rect();
    }
}

ImageFrame ViewerApp::image_frame(double now) {
    const Document& doc = editor_.doc();
    ImageFrame f;
    f.renderer = &render_.renderer();
    f.film = &render_.film_view();
    f.texture = &render_.texture();
    f.world = render_.world_ptr();
    f.scene = doc.has_scene() ? &doc.scene() : nullptr;
    ViewGeometry g{layout_.fit_image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window};
    if (nav_.has_view()) {
        f.view_camera = nav_.display_camera(g);
        f.render_camera = nav_.camera();
    } else if (doc.has_scene()) {
        f.view_camera = f.render_camera = doc.scene().camera;
    }
    f.film_w = layout_.film_w;
    f.film_h = layout_.film_h;
    f.area = layout_.area;
    f.image = layout_.fit_image;
    f.fb_scale = layout_.fb_scale;
    f.max_samples = render_.max_samples();
    f.time_limit = render_.time_limit();
    ImGuiIO& io = ImGui::GetIO();
    bool modal = ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId);
    f.mouse_free = !io.WantCaptureMouse && !modal;
    f.keys_free = !io.WantCaptureKeyboard && !modal;
    f.now = now;
    f.scene_path = doc.path();
    return f;
}

ScreenView ViewerApp::screen_view() const {
    return ScreenView(nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window}),
                      layout_.image, layout_.film_w, layout_.film_h);
}

// A panel edit (a slider drag) is one undo step: committed when no widget is held.
void ViewerApp::end_edits() {
    Document& doc = editor_.doc();
    if (!doc.edit_held()) return;
    // The text editor being active does not hold the edit open (it is not part of the
    // edit, and may stay focused for a long time).
    bool widget_busy = ImGui::IsAnyItemActive() && (editor_.widget_id() == 0 || ImGui::GetActiveID() != editor_.widget_id());
    if (!widget_busy && !move_.dragging()) doc.commit();
    if (const std::string refused = doc.take_refusal(); !refused.empty()) status_.set(refused, true);
}

void ViewerApp::orbit_degrees(double degrees) {
    if (editor_.doc().has_scene()) nav_.follow(editor_.doc().scene().camera);
    nav_.orbit_degrees(degrees);
}

// --- Host interface

bool ViewerApp::render_settled() const {
    return editor_.doc().has_scene() && render_.settled(layout_.film_w, layout_.film_h) &&
           render_.picture_current(editor_.doc().content_version());
}

bool ViewerApp::ui_busy() const {
    const Document& doc = editor_.doc();
    return nav_.dragging() || nav_input_.moving(ImGui::GetTime()) || doc.edit_held() || frames_ < 3 ||
           move_.dragging() || move_.wants_frames() ||
           editor_.wants_frames() || panels_.wants_frames() || dialogs_.wants_frames() || !screenshot_request_.empty() ||
           render_.building() || tools_.busy();
}

double ViewerApp::wait_timeout() const {
    if (!interactive_) return 0;
    // Right after a view change the coarse pass lands within a few milliseconds: look
    // for it more often than the display rate so it shows without a frame's delay
    // (looking is cheap: a frame is drawn only when there is something new).
    if (again_) return 0;
    if (render_.awaiting_preview()) return 0.004;
    // Anything animating or arriving needs display-rate frames.
    if (ui_busy() || render_.busy()) return 1.0 / 60;
    // A load's progress needs a few frames a second, not 60: its threads want the CPU
    // (and its end wakes the host at once).
    if (loader_.active()) return 0.25;
    // Idle: sleep until input, waking once a second to look at the file on disk.
    return 1.0;
}

bool ViewerApp::needs_frame() {
    if (!interactive_) return true;
    // A frame costs the UI thread and the GL rasteriser CPU time the render threads
    // could use: draw one only for new pixels or for UI that is changing.
    if (again_) return true;
    return ui_busy() || loader_.active() || render_.has_new_picture() || (render_.busy() && !render_.awaiting_preview());
}

bool ViewerApp::working() const {
    return ui_busy() || loader_.active() || render_.busy() || again_;
}

bool ViewerApp::idle_tick() {
    last_disk_check_ = ImGui::GetTime();
    if (loader_.active()) return false;
    return editor_.idle_tick();
}

bool ViewerApp::close_requested() {
    if (!editor_.doc().modified()) return true;
    run(Command::Quit);
    return false;
}

void ViewerApp::drop_files(const std::vector<std::string>& paths) {
    if (!paths.empty()) run(Command::Open, paths.front());
}

void ViewerApp::after_render(int fb_width, int fb_height) {
    if (frames_ == 1 && opt_.verbose)
        std::fprintf(stderr, "raytracer-view: first frame drawn at %.3f s\n", since_start());
    if (screenshot_request_.empty()) return;
    std::string path = screenshot_request_;
    screenshot_request_.clear();
    const rt::Status st = save_framebuffer(path, fb_width, fb_height);
    // (The full path: the working folder is not shown anywhere.)
    std::error_code ec;
    const std::filesystem::path full = std::filesystem::absolute(path, ec);
    if (!ec) path = full.lexically_normal().string();
    if (st) status_.set("Wrote screenshot " + path);
    else status_.set("Cannot write the screenshot " + path + ": " + st.message(), true);
}

rt::Status ViewerApp::write_view_scene(const std::string& path) const {
    const Document& doc = editor_.doc();
    if (!doc.has_scene()) return rt::Status::error("the scene has errors");
    rt::Scene s = doc.scene();
    s.camera = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    s.width = layout_.film_w;
    s.height = layout_.film_h;
    return rt::write_file_atomic(path, rt::write_scene(s));
}

}  // namespace rtview
