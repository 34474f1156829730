// ViewerApp: the frame loop over the viewer's parts, keyboard shortcuts, the layout
// and the commands menus, panels, dialogs and keys ask for (see app.h).
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
#include <ctime>
#include <filesystem>
#include <optional>
#include <utility>

#include "default_scene.h"
#include "imgui_common.h"
#include "layout.h"
#include "new_scene.h"
#include "image_io.h"
#include "scene_edits.h"
#include "scene_writer.h"
#include "diagnostic_text.h"
#include "number_field.h"
#include "probe.h"

namespace rtview {

namespace {

std::string stem_of(const std::string& name) {
    std::size_t dot = name.find_last_of('.');
    return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

std::string base_name(const std::string& path) {
    std::size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Program start, near enough: for --verbose timings.
const auto g_start = std::chrono::steady_clock::now();
double since_start() { return std::chrono::duration<double>(std::chrono::steady_clock::now() - g_start).count(); }

std::string megabytes(std::uint64_t b) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", double(b) / (1 << 20));
    return buf;
}

// What the status bar adds about a scene without lights: everything in it is black.
std::string light_note(const Document& doc) {
    if (!doc.has_scene() || !doc.scene().lights.empty()) return {};
    return "; the scene has no lights, so it renders black: add a lamp (right-click the picture > Add here > lamp)";
}

// What the status bar adds when the recent-files list could not be saved.
std::string recent_note(const rt::Status& recent) {
    return recent ? std::string() : "; recent files not saved: " + recent.message();
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
    const LoadResult::Times times = r->times;
    std::shared_ptr<const rt::World> world;
    if (!apply_load(*r, doc, world)) return;  // cancelled: the old scene stays
    if (world) render_.adopt_world(std::move(world), doc.content_version());
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
    status_.set((ok ? "Opened " + doc.name() : "Opened " + doc.name() + " (it has errors)") + light_note(doc) +
                    recent_note(recent),
                !ok || !recent);
    if (opt_.verbose)
        std::fprintf(stderr,
                     "raytracer-view: loaded %s at %.3f s (read %.3f s, parse %.3f s, build %.3f s: compile %.3f s "
                     "beside the layout scan %.3f s)\n",
                     path.c_str(), since_start(), times.read, times.parse, times.build, times.compile, times.scan);
}

// ---------------------------------------------------------------------------------
// Frame

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
        bool tool_mouse = tools_.handle_mouse() && !move_.dragging();
        if (tool_mouse) nav_layout.image = Rect{};
        else if (doc.has_scene() && nav_.has_view() &&
                 move_.handle_mouse(doc, panels_.selection(), screen_view(), layout_.image, usable && !nav_.dragging(),
                                    status_))
            nav_layout.image = Rect{};  // the move handle has the pointer
        NavigationInput::Result r = nav_input_.handle(nav_layout, render_.world(), usable, panels_.scene_extent());
        if (r.clicked) select_at(r.x, r.y);
        handle_context_menu(usable);
        draw_context_menu();
    }
    end_edits();
    editor_.tick(now);
    if (interactive_ && now - last_disk_check_ >= 1.0) idle_tick();
    update_render(now);
    panels_.draw_surround();
    if (doc.has_scene() || render_.started()) {
        // While the view moves, the UI thread's own preview; else the film as the
        // picture tools show it (zoom, display mapping, A/B, region).
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
            move_.draw(doc, panels_.selection(), screen_view(), render_.world(), layout_.image, layout_.area,
                       layout_.film_w, layout_.film_h);
    }
    if (!doc.has_scene()) draw_no_image();
    probe_frame();
    publish_outputs();
    again_ = visible_key() != key_before;
}

void ViewerApp::probe_frame() {
    if (!opt_.print_layout) return;
    const Document& doc = editor_.doc();
    probe("title", doc.title());
    probe("load", loader_.active() ? "loading" : doc.has_scene() ? "ready" : "no scene");
    probe("message", (status_.error() ? "error: " : "") + status_.text());
    std::string popups;
    for (const ImGuiPopupData& p : GImGui->OpenPopupStack)
        if (p.Window) popups += (popups.empty() ? "" : "|") + std::string(p.Window->Name);
    probe("popups", popups.empty() ? "none" : popups);
    probe("readout", tools_.readout_line().empty() ? "none" : tools_.readout_line());
    {
        const ImGuiIO& io = ImGui::GetIO();
        char pointer[96];
        std::snprintf(pointer, sizeof pointer, "%.0f %.0f%s%s", io.MousePos.x, io.MousePos.y,
                      io.WantCaptureMouse ? " ui" : "", ImGui::IsAnyMouseDown() ? " down" : "");
        probe("pointer", pointer);
    }
    const rt::RenderProgress p = render_.progress();
    // What another program would paste, once something was copied.
    if (!tools_.copied().empty()) {
        const char* clip = ImGui::GetClipboardText();
        probe("clipboard", clip ? clip : "");
    }
    // The picture rendered (not its place on the screen), and how far it has come.
    probe("film", std::to_string(p.width) + "x" + std::to_string(p.height) + " " + std::to_string(p.samples) +
                      " spp generation " + std::to_string(p.generation));
    probe("render", std::to_string(p.samples) + " " + (p.done ? "done" : p.running ? "running" : "idle"));
    // As raytracer's options would ask for this render (scripts render its twin).
    probe("render_settings", "--samples " + std::to_string(render_.max_samples()) +
                                 (render_.aa_threshold() >= 0 ? " --aa-threshold " + rt::format_number(render_.aa_threshold())
                                                               : std::string()));
    probe("diagnostics", std::to_string(doc.diagnostics().size()) +
                             (doc.diagnostics().empty() ? "" : " " + doc.diagnostics().front().message));
    probe("text", std::string(doc.editor_dirty() ? "unapplied" : "applied") + (doc.text_behind() ? " behind" : ""));
}

std::uint64_t ViewerApp::visible_key() const {
    std::uint64_t h = 1469598103934665603ull;
    auto mix = [&h](std::uint64_t v) { h = (h ^ v) * 1099511628211ull; };
    auto mix_text = [&mix](const std::string& s) { mix(text_hash(s)); };
    const Document& doc = editor_.doc();
    mix_text(status_.text());
    mix(status_.error());
    mix(doc.text_version());
    mix(doc.typed());
    mix(doc.scene_version());
    mix(doc.has_scene());
    const auto& diags = doc.diagnostics();
    mix(diags.size());
    for (std::size_t k = 0; k < diags.size() && k < 32; ++k) {
        mix(std::uint64_t(diags[k].line) << 32 | std::uint32_t(diags[k].col));
        mix_text(diags[k].message);
    }
    mix(loader_.active());
    if (loader_.active()) mix(std::uint64_t(loader_.progress().stage));
    mix(tools_.busy());
    mix(tools_.final_render_running());
    mix_text(tools_.readout_line());
    // A zoom key changes where the picture is after this frame's layout was made.
    const Rect zoomed = tools_.image_rect();
    for (double v : {zoomed.x, zoomed.y, zoomed.w, zoomed.h}) mix(std::uint64_t(std::llround(v * 16)));
    const rt::RenderProgress p = render_.progress();
    mix(p.generation);
    mix(std::uint64_t(p.samples));
    mix(p.done);
    mix(render_.paused());
    return h;
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
        move_.update_outline(doc, panels_.selection(), render_,
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
    l.sidebar_w = l.sidebar_hidden ? 0.f : sidebar_width(W, float(tools_.ui_scale()), content, tools_.settings().sidebar_width());
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

// ---------------------------------------------------------------------------------
// Keyboard

bool ViewerApp::close_menus_for_keys() {
    ImGuiContext& g = *GImGui;
    if (g.OpenPopupStack.empty()) return false;
    // A modal dialog (or a popup not drawn yet) handles its own keys.
    for (const ImGuiPopupData& p : g.OpenPopupStack)
        if (!p.Window || (p.Window->Flags & ImGuiWindowFlags_Modal)) return false;
    if (imgui_key_pressed(ImGuiKey_Escape)) {
        ImGui::ClosePopupsExceptModals();
        return true;
    }
    if (ImGui::GetIO().KeyCtrl)
        for (int k = 'A'; k <= 'Z'; ++k)
            if (key_pressed(k)) {
                ImGui::ClosePopupsExceptModals();
                break;
            }
    return false;
}

void ViewerApp::handle_shortcuts() {
    ImGuiIO& io = ImGui::GetIO();
    bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (ctrl) {
        if (key_pressed(keys::kS)) run(shift ? Command::SaveAsDialog : Command::Save);
        if (key_pressed(keys::kQ)) run(Command::Quit);  // asks first if there are unsaved edits
        if (key_pressed(keys::kO)) run(Command::OpenDialog);
        if (key_pressed(keys::kN)) run(Command::NewScene);
        if (key_pressed(keys::kP)) run(Command::SaveImageDialog);
        if (key_pressed(keys::kE)) run(Command::EditText);
        if (key_pressed(keys::kK)) run(Command::SetSceneCamera);
        if (imgui_key_pressed(ImGuiKey_Enter) || imgui_key_pressed(ImGuiKey_KeyPadEnter)) run(Command::ApplyText);
        // In a text field, Ctrl+Z/Y belong to the field's own undo.
        if (!io.WantTextInput) {
            if (imgui_key_pressed(ImGuiKey_Z, true)) run(shift ? Command::Redo : Command::Undo);
            else if (imgui_key_pressed(ImGuiKey_Y, true)) run(Command::Redo);
        }
    }
    if (key_pressed(keys::kF12)) {
        char name[64];
        std::time_t t = std::time(nullptr);
        std::strftime(name, sizeof name, "raytracer-view-%Y%m%d-%H%M%S.png", std::localtime(&t));
        run(Command::Screenshot, name);
    }
    if (loader_.active() && imgui_key_pressed(ImGuiKey_Escape) && !esc_closed_menu_ &&
        !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId))
        run(Command::CancelLoad);
    if (!io.WantCaptureKeyboard && ctrl && !io.KeyAlt && key_pressed(keys::kD)) run(Command::Duplicate);
    if (!io.WantCaptureKeyboard && !ctrl && !io.KeyAlt) {
        if (imgui_key_pressed(ImGuiKey_Delete)) run(Command::Delete);
        if (imgui_key_pressed(ImGuiKey_Space)) run(Command::TogglePause);
        if (key_pressed(keys::kF)) run(Command::FrameScene);
        if (key_pressed(keys::kR)) run(Command::ResetView);
        // The picture alone, as Tab hides the panels of image editors.
        if (imgui_key_pressed(ImGuiKey_Tab) && !io.KeyShift && !ImGui::IsAnyItemActive()) {
            layout_.sidebar_hidden = !layout_.sidebar_hidden;
            status_.set(layout_.sidebar_hidden ? "Sidebar hidden (Tab shows it)" : "Sidebar shown (drag its edge to resize)");
        }
    }
}

void ViewerApp::select_at(double px, double py) {
    const rt::World* w = render_.world();
    if (!w) return;
    // What is drawn over the picture comes first: the selection's handle (it stays
    // selected), a light's marker.
    if (move_.over_handle(editor_.doc(), panels_.selection(), screen_view(), px, py)) return;
    if (int light = move_.light_under(px, py); light >= 0) {
        panels_.select({{SceneItem::Kind::Light, light}, {}});
        return;
    }
    rt::Camera vc = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    rt::PickResult r = pick_at(*w, vc, layout_.image, layout_.film_w, layout_.film_h, px, py);
    ItemRef s;
    if (r.object >= 0) s = {{SceneItem::Kind::Object, r.object}, {}};
    else if (r.plane >= 0) s = {{SceneItem::Kind::Plane, r.plane}, {}};
    else if (r.light >= 0) s = {{SceneItem::Kind::Light, r.light}, {}};
    panels_.select(s);
}

ScreenView ViewerApp::screen_view() const {
    return ScreenView(nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window}),
                      layout_.image, layout_.film_w, layout_.film_h);
}

// A panel edit (a slider drag) is one undo step: committed when no widget is held.
void ViewerApp::end_edits() {
    Document& doc = editor_.doc();
    if (!doc.editing()) return;
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

// ---------------------------------------------------------------------------------
// Commands

bool ViewerApp::run(Command c, const std::string& arg, bool confirmed) {
    Document& doc = editor_.doc();
    auto ask_first = [&](Command cmd) {
        if (confirmed || !doc.modified()) return false;
        dialogs_.ask_unsaved(cmd, arg);
        return true;
    };
    switch (c) {
        case Command::OpenDialog: dialogs_.show(Dialogs::Kind::Open); return true;
        case Command::Open:
            if (ask_first(c)) return true;
            start_load(arg);
            return true;
        case Command::OpenDefault:
            if (ask_first(c)) return true;
            loader_.cancel();
            doc.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
            after_document_replaced();
            status_.set("Opened the built-in default scene");
            return true;
        case Command::NewScene:
            if (ask_first(c)) return true;
            loader_.cancel();
            doc.load_text(kNewScene, "", kNewSceneName);
            after_document_replaced();
            // A new scene is written by hand: the text, ready for typing.
            panels_.show_tab(Panels::Text);
            editor_.focus();
            status_.set(std::string("New scene ") + kNewSceneName + ": Ctrl+Enter applies the text, Ctrl+S saves it");
            return true;
        case Command::CancelLoad: return cancel_load();
        case Command::Save: return do_save(confirmed);
        case Command::SaveAsDialog: dialogs_.show(Dialogs::Kind::SaveAs, doc.path().empty() ? doc.name() : doc.path()); return true;
        case Command::SaveAs: return do_save_as(arg, confirmed);
        case Command::SaveImageDialog: dialogs_.show(Dialogs::Kind::SaveImage, default_image_name()); return true;
        case Command::SaveImage: do_save_image(arg); return true;
        case Command::Screenshot: screenshot_request_ = arg; return true;
        case Command::Quit:
            if (ask_first(c)) return true;
            // Quitting is the user's decision about unsaved text: no recovery copy.
            editor_.discard_recovery();
            host_.quit();
            return true;
        case Command::Undo:
        case Command::Redo: return undo_redo(c == Command::Undo, arg.empty() ? 1 : std::atoi(arg.c_str()));
        case Command::EditText:
            panels_.show_tab(Panels::Text);
            editor_.focus();
            return true;
        case Command::ApplyText: editor_.apply(); return true;
        case Command::RevertText: doc.revert_text(); return true;
        case Command::FrameScene:
        case Command::ResetView:
        case Command::SetSceneCamera:
        case Command::CopyCamera:
        case Command::TogglePause:
        case Command::FitWindow:
        case Command::FitPicture: return view_command(c);
        case Command::Help: dialogs_.show(Dialogs::Kind::Help); return true;
        case Command::FormatHelp: dialogs_.show(Dialogs::Kind::Format); return true;
        case Command::AddItem:
        case Command::Duplicate:
        case Command::Delete:
        case Command::SwitchLight:
        case Command::MakeCsg:
        case Command::AddModel: return scene_edit(arg, c);
        case Command::AddModelDialog:
            // The model goes where the menu was opened (or in the middle): kept for the
            // dialog's answer, so a dialog cancelled leaves no point for the next Add.
            model_place_x_ = std::exchange(place_x_, -1);
            model_place_y_ = std::exchange(place_y_, -1);
            dialogs_.show(Dialogs::Kind::AddModel, rt::folder_of(doc.path()));
            return true;
    }
    return false;
}

bool ViewerApp::undo_redo(bool undo, int steps) {
    Document& doc = editor_.doc();
    int done = 0;
    while (done < std::max(steps, 1) && (undo ? doc.undo() : doc.redo())) ++done;
    if (done == 0) return false;
    // Say what was taken back or done again: "Undid: Move sphere 3".
    const std::string& last = doc.last_step_name();
    const std::string what =
        done == 1 ? ": " + last : " " + std::to_string(done) + " steps, " + (undo ? "back to before " : "up to ") + last;
    status_.set(std::string(undo ? "Undid" : "Redid") + what + (undo ? " (Ctrl+Y redoes)" : " (Ctrl+Z undoes)"));
    return true;
}

bool ViewerApp::cancel_load() {
    if (!loader_.active()) return false;
    loader_.cancel();
    Document& doc = editor_.doc();
    if (!doc.has_scene() && doc.editor_text().empty() && doc.path().empty()) {
        // The start-up file was cancelled: there is no old scene to keep showing.
        doc.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
        after_document_replaced();
    }
    status_.set("Cancelled opening; showing " + doc.name());
    return true;
}

bool ViewerApp::view_command(Command c) {
    Document& doc = editor_.doc();
    switch (c) {
        case Command::FrameScene:
            if (render_.world())
                nav_.frame(frame_target(*render_.world()),
                           {layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
            return true;
        case Command::ResetView:
            if (doc.has_scene()) nav_.reset(doc.scene().camera);
            return true;
        case Command::SetSceneCamera:
            if (!doc.has_scene() || !nav_.has_view()) return false;
            if (const std::string blocked = doc.edit_blocker(); !blocked.empty()) {
                status_.set(blocked, true);
                return false;
            }
            if (doc.set_camera(nav_.camera())) status_.set("The scene camera is now the view (Ctrl+Z undoes)");
            return true;
        case Command::CopyCamera:
            ImGui::SetClipboardText(rt::write_camera(nav_.camera()).c_str());
            status_.set("Copied the view's camera block to the clipboard");
            return true;
        case Command::TogglePause:
            render_.set_paused(!render_.paused());
            status_.set(render_.paused() ? "Paused (Space resumes)" : "Resumed");
            return true;
        case Command::FitWindow:
            layout_.fit = FitMode::Window;
            status_.set("Fill the window: the picture's sides may differ from the scene's");
            return true;
        case Command::FitPicture:
            layout_.fit = FitMode::Picture;
            status_.set("Picture frame: exactly the scene's picture");
            return true;
        default: return false;
    }
}

// ---------------------------------------------------------------------------------
// Structural edits: one text replacement each (scene_edits.h), applied by the document
// as one undo step. The text must be the scene's: a draft is applied or reverted first.

Placement ViewerApp::placement_at(const rt::Camera& vc, double px, double py) const {
    // On the surface under the point (its normal from two neighbouring picks), or in
    // front of the camera at the distance it looks at.
    const Rect& im = layout_.image;
    Placement at;
    const rt::World* w = render_.world();
    rt::PickResult r0 = w ? pick_at(*w, vc, im, layout_.film_w, layout_.film_h, px, py) : rt::PickResult{};
    if (r0.hit && std::isfinite(r0.t)) {
        at.point = r0.point;
        rt::PickResult rx = pick_at(*w, vc, im, layout_.film_w, layout_.film_h, px + 2, py);
        rt::PickResult ry = pick_at(*w, vc, im, layout_.film_w, layout_.film_h, px, py + 2);
        bool same = rx.hit && ry.hit && rx.object == r0.object && ry.object == r0.object && rx.plane == r0.plane &&
                    ry.plane == r0.plane;
        if (same) {
            rt::Vec3 n = rt::normalize(rt::cross(rx.point - r0.point, ry.point - r0.point));
            if (rt::dot(n, vc.position - r0.point) < 0) n = -n;
            at.normal = n;
        }
    } else {
        rt::Ray ray = ray_at(vc, im, layout_.film_w, layout_.film_h, px, py);
        at.point = ray.origin + ray.dir * rt::length(vc.centre - vc.position);
    }
    at.toward = vc.position - at.point;
    return at;
}

Placement ViewerApp::new_item_placement(bool object) {
    const Rect& im = layout_.image;
    const bool pointed = place_x_ >= 0;
    const double px = pointed ? place_x_ : im.x + im.w / 2, py = pointed ? place_y_ : im.y + im.h / 2;
    place_x_ = place_y_ = -1;
    const rt::Camera vc = nav_.display_camera({im, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    const Placement centre = placement_at(vc, px, py);
    const Document& doc = editor_.doc();
    const rt::Scene* scene = doc.has_scene() ? &doc.scene() : nullptr;
    if (pointed || !object || !scene) return centre;
    // From the menu, an object goes where it is seen and stands free: on a surface in
    // the picture, nearest the point under its centre, where it meets no other object
    // (in front of an object it would hide it, or stand inside it); in the air only
    // where no surface has room.
    std::vector<std::pair<double, Placement>> around;
    const double step = std::max(1.0, im.w / 16.0);
    for (int j = -5; j <= 5; ++j)
        for (int i = -7; i <= 7; ++i) {
            const double x = px + i * step, y = py + j * step;
            if ((i == 0 && j == 0) || x < im.x || y < im.y || x >= im.x + im.w || y >= im.y + im.h) continue;
            Placement at = placement_at(vc, x, y);
            const double d = rt::length(at.point - centre.point);
            if (std::isfinite(d)) around.push_back({rt::length2(at.normal) > 0 ? d : 1e300, at});
        }
    std::stable_sort(around.begin(), around.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Placement> candidates{centre};
    for (auto& a : around) candidates.push_back(a.second);
    // ... and the whole of it in the picture.
    const ScreenView view(vc, im, layout_.film_w, layout_.film_h);
    auto in_picture = [&](const rt::Vec3& middle, double reach) {
        for (int axis = 0; axis < 3; ++axis)
            for (double side : {-reach, reach}) {
                rt::Vec3 q = middle;
                (axis == 0 ? q.x : axis == 1 ? q.y : q.z) += side;
                const std::optional<ScreenPoint> sp = view.project(q);
                if (!sp || sp->x < im.x || sp->y < im.y || sp->x > im.x + im.w || sp->y > im.y + im.h) return false;
            }
        return true;
    };
    const std::optional<std::size_t> k = first_clear(*scene, candidates, in_picture);
    return k ? candidates[*k] : centre;
}

rt::Vec3 ViewerApp::duplicate_offset(const rt::Scene& scene) const {
    // One object-width to the right in the view, so that the copy is seen (a round
    // step: the copy's numbers stay as short as the original's).
    rt::Camera vc = nav_.display_camera({layout_.image, layout_.film_w, layout_.film_h, layout_.fit == FitMode::Window});
    rt::Vec3 right = rt::normalize(rt::cross(vc.centre - vc.position, nav_.world_up()));
    double step = 2.5 * typical_object_size(scene);
    double q = std::pow(10.0, std::floor(std::log10(step > 0 ? step : 1.0)) - 1);
    rt::Vec3 off = right * step;
    off = {std::round(off.x / q) * q, std::round(off.y / q) * q, std::round(off.z / q) * q};
    return rt::finite(off) ? off : rt::Vec3{};
}

namespace {
// The item an "add" command names ("sphere", ..., "spotlight"), as in the format.
std::optional<NewItem> new_item_kind(const std::string& name) {
    static const std::pair<const char*, NewItem> kinds[] = {
        {"sphere", NewItem::Sphere}, {"cylinder", NewItem::Cylinder}, {"tetrahedron", NewItem::Tetrahedron},
        {"torus", NewItem::Torus},   {"plane", NewItem::Plane},       {"chess_plane", NewItem::ChessPlane},
        {"lamp", NewItem::Lamp},     {"spotlight", NewItem::Spotlight}};
    for (const auto& k : kinds)
        if (name == k.first) return k.second;
    return std::nullopt;
}
}  // namespace

bool ViewerApp::scene_edit(const std::string& arg, Command c) {
    Document& doc = editor_.doc();
    if (!doc.has_scene() || loader_.active()) return false;
    if (doc.editor_dirty() || doc.text_behind()) {
        status_.set("The scene text has unapplied changes: apply (Ctrl+Enter) or revert them first", true);
        return false;
    }
    if (doc.editing()) {
        // (The edit would be planned on the scene as dragged so far, but the text the
        // drag writes only when it ends.)
        status_.set("Finish the drag first", true);
        return false;
    }
    const std::string& text = std::as_const(doc).editor_text();
    const rt::Scene& scene = doc.scene();
    std::optional<SceneEdit> e;
    std::string done, name;  // the status bar's message; the undo step's name
    std::optional<SceneItem> sel = item_of_selection(panels_.selection());
    const std::string label = sel ? item_label(scene, ItemRef{*sel, {}}) : std::string();
    switch (c) {
        case Command::AddItem: {
            const std::optional<NewItem> kind = new_item_kind(arg);
            if (!kind) return false;
            e = add_item(text, scene, *kind, new_item_placement(*kind <= NewItem::Torus));
            done = std::string("Added a ") + arg;
            name = std::string("Add a ") + arg;
            break;
        }
        case Command::AddModel:
            if (!(e = model_edit(arg))) return false;
            done = "Added " + base_name(arg);
            name = "Add model " + base_name(arg);
            break;
        case Command::Duplicate: {
            if (!sel) return false;
            e = duplicate_item(text, scene, *sel, duplicate_offset(scene));
            done = "Duplicated";
            name = "Duplicate " + label;
            break;
        }
        case Command::Delete: {
            if (!sel) return false;
            const ItemRef& ref = panels_.selection();
            const bool operand = !ref.path.empty();  // its CSG becomes the other operand
            e = operand ? delete_operand(text, scene, sel->index, ref.path) : delete_item(text, scene, *sel);
            done = operand ? "Deleted the operand: its CSG is the other operand now" : "Deleted";
            name = "Delete " + (operand ? item_label(scene, ref) : label);
            break;
        }
        case Command::SwitchLight:
            if (!sel || sel->kind != SceneItem::Kind::Light) return false;
            e = switch_light_kind(text, scene, sel->index);
            done = scene.lights[std::size_t(sel->index)].lamp ? "The lamp is a spotlight now (its size is kept)"
                                                              : "The spotlight is a lamp now";
            name = "Make " + label + (scene.lights[std::size_t(sel->index)].lamp ? " a spotlight" : " a lamp");
            break;
        case Command::MakeCsg: {
            char type = arg.empty() ? 'U' : arg[0];
            int other = arg.size() > 2 ? std::atoi(arg.c_str() + 2) : -1;
            if (!sel || sel->kind != SceneItem::Kind::Object || (type != 'U' && type != 'I' && type != 'C')) return false;
            e = make_csg(text, scene, sel->index, other, rt::CsgType(type));
            done = "Made a CSG of the two objects";
            name = "Make a CSG of objects " + std::to_string(sel->index + 1) + " and " + std::to_string(other + 1);
            break;
        }
        default: return false;
    }
    if (!e || !doc.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, name)) {
        status_.set("Cannot do that to this scene text", true);
        return false;
    }
    panels_.select({e->select, {}});
    status_.set(done + " (Ctrl+Z undoes)" + light_note(doc));
    return true;
}

std::optional<SceneEdit> ViewerApp::model_edit(const std::string& path) {
    Document& doc = editor_.doc();
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path file = fs::absolute(path, ec).lexically_normal();
    const rt::ModelStore::Loaded l = doc.models().load(file.string());
    if (!l.model) {
        const std::string line = l.error.line > 0 ? ":" + std::to_string(l.error.line) : "";
        status_.set("Cannot add " + path + line + ": " + l.error.message, true);
        return std::nullopt;
    }
    // Named from the scene's folder when it is in it (the scene and its models then
    // move together), else by its absolute path.
    std::string name = file.string();
    if (!doc.path().empty()) {
        const fs::path rel = file.lexically_relative(fs::absolute(rt::folder_of(doc.path()), ec).lexically_normal());
        if (!rel.empty() && *rel.begin() != "..") name = rel.string();
    }
    place_x_ = std::exchange(model_place_x_, -1);
    place_y_ = std::exchange(model_place_y_, -1);
    std::optional<SceneEdit> e = add_model(std::as_const(doc).editor_text(), doc.scene(), name, *l.model, new_item_placement(true));
    if (!e) status_.set("Cannot add a mesh to this scene text", true);
    return e;
}

void ViewerApp::handle_context_menu(bool usable) {
    ImGuiIO& io = ImGui::GetIO();
    double mx = io.MousePos.x, my = io.MousePos.y;
    if (usable && ImGui::IsMouseClicked(1) && !io.WantCaptureMouse && layout_.image.contains(mx, my)) {
        rclick_armed_ = true;
        rclick_x_ = mx;
        rclick_y_ = my;
    }
    if (rclick_armed_ && !ImGui::IsMouseDown(1)) {
        rclick_armed_ = false;
        // A right drag pans; only a click (the pointer stayed put) opens the menu.
        if (std::hypot(mx - rclick_x_, my - rclick_y_) < 4 && usable) {
            menu_prev_selection_ = panels_.selection();
            menu_readout_ = tools_.readout_line();  // the menu takes the hover away
            select_at(rclick_x_, rclick_y_);
            ImGui::OpenPopup("image_menu");
        }
    }
}

void ViewerApp::draw_context_menu() {
    if (!ImGui::BeginPopup("image_menu")) return;
    const ItemRef& sel = panels_.selection();
    const rt::Scene& scene = editor_.doc().scene();
    // (probe_item: where the rows are, for scripts that click them)
    if (ImGui::BeginMenu("Add here")) {
        static const char* const kinds[] = {"sphere", "cylinder", "tetrahedron", "torus", "plane", "chess_plane", "lamp", "spotlight"};
        for (const char* k : kinds) {
            const bool chosen = ImGui::MenuItem(k);
            probe_item(std::string("menu:") + k);
            if (chosen) {
                place_x_ = rclick_x_;
                place_y_ = rclick_y_;
                run(Command::AddItem, k);
            }
        }
        const bool model = ImGui::MenuItem("model...");
        probe_item("menu:model");
        if (model) {
            place_x_ = rclick_x_;
            place_y_ = rclick_y_;
            run(Command::AddModelDialog);
        }
        ImGui::EndMenu();
    }
    probe_item("menu:Add here");
    bool has = !sel.none();
    if (ImGui::MenuItem("Duplicate", "Ctrl+D", false, has)) run(Command::Duplicate);
    if (ImGui::MenuItem("Delete", "Del", false, has)) run(Command::Delete);
    if (sel.is(SceneItem::Kind::Light) && std::size_t(sel.item.index) < scene.lights.size()) {
        bool lamp = scene.lights[std::size_t(sel.item.index)].lamp;
        const char* label = lamp ? "Make it a spotlight" : "Make it a lamp";
        const bool chosen = ImGui::MenuItem(label);
        probe_item(std::string("menu:") + label);
        if (chosen) run(Command::SwitchLight);
    }
    const ItemRef& prev = menu_prev_selection_;
    if (sel.is(SceneItem::Kind::Object) && prev.is(SceneItem::Kind::Object) && prev.item.index != sel.item.index &&
        std::size_t(prev.item.index) < scene.objects.size()) {
        std::string label = "CSG of object " + std::to_string(prev.item.index + 1) + " and this one";
        if (ImGui::BeginMenu(label.c_str())) {
            std::string other = " " + std::to_string(sel.item.index);
            auto csg = [&](const char* type) {
                panels_.select(prev);  // the left operand
                run(Command::MakeCsg, type + other);
            };
            if (ImGui::MenuItem("union")) csg("U");
            if (ImGui::MenuItem("intersection")) csg("I");
            if (ImGui::MenuItem("difference (first minus this)")) csg("C");
            ImGui::EndMenu();
        }
    }
    ImGui::Separator();
    // The pixel's readout, as the status line showed it.
    if (ImGui::MenuItem("Copy pixel", "Ctrl+C", false, !menu_readout_.empty())) tools_.copy_pixel(menu_readout_);
    ImGui::EndPopup();
}

std::string ViewerApp::default_image_name() const {
    const Document& doc = editor_.doc();
    return stem_of(doc.path().empty() ? doc.name() : doc.path()) + ".png";
}

// Before a save: a draft that parses is applied (the file will be the scene shown);
// text that does not parse is saved only once the user has said so (false: asked).
bool ViewerApp::ready_to_save(Command c, const std::string& arg, bool confirmed) {
    Document& doc = editor_.doc();
    doc.commit();
    if (doc.apply_parsing_draft()) status_.set("Applied the scene text");
    if (confirmed) return true;
    if (std::optional<std::string> problem = doc.save_problem()) {
        dialogs_.ask_save_with_errors(*problem, c, arg);
        return false;
    }
    return true;
}

bool ViewerApp::do_save(bool confirmed) {
    Document& doc = editor_.doc();
    if (doc.path().empty()) {
        dialogs_.show(Dialogs::Kind::SaveAs, doc.name());
        return false;
    }
    if (!ready_to_save(Command::Save, {}, confirmed)) return false;
    const rt::Status st = doc.save();
    if (st) editor_.saved();
    if (st) status_.set("Saved " + doc.path());
    else status_.set("Save failed: " + st.message(), true);
    return st.ok();
}

bool ViewerApp::do_save_as(const std::string& path, bool confirmed) {
    Document& doc = editor_.doc();
    if (!ready_to_save(Command::SaveAs, path, confirmed)) return false;
    if (rt::Status st = doc.save_as(path); !st) {
        status_.set("Save failed: " + st.message(), true);
        return false;
    }
    editor_.saved_as();
    const rt::Status recent = remember_recent(path);
    status_.set("Saved " + doc.path() + recent_note(recent), !recent);
    return true;
}

rt::Status ViewerApp::remember_recent(const std::string& path) {
    if (!interactive_) return {};
    return editor_.recent().add(path);
}

// The film as rendered so far: in the picture frame the scene's picture at its
// picture_size (zoom and pan only place it on the screen), else the window's.
void ViewerApp::do_save_image(const std::string& path) {
    const rt::RenderProgress p = render_.progress();
    rt::Image img = render_.snapshot();
    if (img.width < 1) {
        status_.set("There is no image to save yet", true);
        return;
    }
    if (rt::format_from_path(path) == rt::ImageFormat::Unknown) {
        status_.set("Image names must end in .png or .ppm", true);
        return;
    }
    const rt::Status st = rt::write_image(path, img);
    if (!st) {
        status_.set("Cannot write " + path + ": " + st.message(), true);
        return;
    }
    std::string what = std::to_string(img.width) + "x" + std::to_string(img.height) + ", " + std::to_string(p.samples) +
                       (p.done ? "" : " of " + std::to_string(render_.max_samples())) + " samples per pixel";
    const Document& doc = editor_.doc();
    if (layout_.fit == FitMode::Window) what += ", the window's picture (View > Picture frame saves picture_size)";
    else if (doc.has_scene() && (img.width != doc.scene().width || img.height != doc.scene().height))
        what += ", smaller than picture_size " + std::to_string(doc.scene().width) + "x" +
                std::to_string(doc.scene().height) + " (Render to file makes it)";
    status_.set("Wrote " + path + " (" + what + ")");
}

// ---------------------------------------------------------------------------------
// Host interface

bool ViewerApp::render_settled() const {
    return editor_.doc().has_scene() && render_.settled(layout_.film_w, layout_.film_h);
}

bool ViewerApp::ui_busy() const {
    const Document& doc = editor_.doc();
    return nav_.dragging() || nav_input_.moving(ImGui::GetTime()) || doc.editing() || frames_ < 3 ||
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
    return editor_.idle_tick(last_disk_check_);
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
    if (st) status_.set("Wrote screenshot " + path);
    else status_.set("Screenshot failed: " + st.message(), true);
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

std::string ViewerApp::layout_text() const {
    float fb = layout_.fb_scale;
    auto px = [fb](const Rect& r) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%ld %ld %ld %ld", std::lround(r.x * fb), std::lround(r.y * fb),
                      std::lround(r.w * fb), std::lround(r.h * fb));
        return std::string(buf);
    };
    ImGuiIO& io = ImGui::GetIO();
    const Layout& l = layout_;
    Rect window{0, 0, io.DisplaySize.x, io.DisplaySize.y};
    Rect sidebar{window.w - l.sidebar_w, l.menu_h, l.sidebar_w, window.h - l.menu_h};
    Rect bar{0, window.h - l.status_h, l.area.w, l.status_h};
    Panels::Tab tab = panels_.current_tab();
    std::string s;
    s += "window " + px(window) + "\n";
    s += "area " + px(l.area) + "\n";
    s += "image " + px(l.image) + "\n";
    s += "film " + std::to_string(l.film_w) + " " + std::to_string(l.film_h) + "\n";
    s += "sidebar " + px(sidebar) + "\n";
    s += "camera " + px(l.camera_panel) + "\n";
    s += "outline " + px(tab == Panels::Objects ? l.outline : Rect{}) + "\n";
    s += "editor " + px(tab == Panels::Text ? l.editor : Rect{}) + "\n";
    s += "diagnostics " + px(tab == Panels::Text ? l.diagnostics : Rect{}) + "\n";
    s += "status " + px(bar) + "\n";
    // Where the move handle of the selection sits (its anchor) and what it moves
    // ("object 3", 1-based as in the outline), for tests that drag it.
    const Document& doc = editor_.doc();
    std::optional<SceneItem> item = item_of_selection(panels_.selection());
    std::optional<rt::Vec3> anchor;
    const std::vector<int>& path = panels_.selection().path;
    if (item && doc.has_scene() && nav_.has_view()) anchor = item_anchor(doc.scene(), *item, path);
    std::optional<ScreenPoint> at;
    if (anchor) at = screen_view().project(*anchor);
    if (at) {
        const char* kind = item->kind == SceneItem::Kind::Object ? "object" : item->kind == SceneItem::Kind::Plane ? "plane" : "light";
        s += "handle " + std::to_string(std::lround(at->x * fb)) + " " + std::to_string(std::lround(at->y * fb)) + " " +
             kind + " " + std::to_string(item->index + 1);
        for (int k : path) s += k == 0 ? " left" : " right";  // an operand: "object 4 left"
        s += "\n";
    }
    else s += "handle none\n";
    for (const auto& [key, value] : probes()) s += "state " + key + " " + value + "\n";
    return s;
}

}  // namespace rtview
