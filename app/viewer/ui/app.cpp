// ViewerApp behaviour: layout, keyboard shortcuts, camera gestures, the render loop
// (world compilation, renderer restarts, film upload) and file actions. The ImGui
// panels themselves are in panels.cpp.
#include "app.h"

#include <imgui.h>
#include <imgui_internal.h>  // GetActiveID, ClearActiveID: 1.86 has no public equivalent

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>

#include "default_scene.h"
#include "image_io.h"
#include "scene_writer.h"

namespace rtview {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOrbitRadPerPixel = 0.3 * kPi / 180;  // a 600-pixel drag turns 180 degrees
constexpr double kClickSlop = 3;                       // pixels a click may move and stay a click
constexpr double kWheelSettle = 0.4;                   // seconds of no wheel before the dolly is one undo step

// Letter and function keys as the GLFW backend reports them in io.KeysDown (GLFW key
// codes: letters are their upper-case ASCII codes). ImGui 1.86 maps only a few keys.
constexpr int kKeyA = 'A', kKeyD = 'D', kKeyE = 'E', kKeyF = 'F', kKeyO = 'O', kKeyP = 'P', kKeyQ = 'Q',
              kKeyR = 'R', kKeyS = 'S', kKeyW = 'W';
constexpr int kKeyF12 = 301;

bool key_down(int k) { return k >= 0 && k < int(IM_ARRAYSIZE(ImGui::GetIO().KeysDown)) && ImGui::GetIO().KeysDown[k]; }
bool key_pressed(int k, bool repeat = false) {
    return k >= 0 && k < int(IM_ARRAYSIZE(ImGui::GetIO().KeysDown)) && ImGui::IsKeyPressed(k, repeat);
}
bool imgui_key_pressed(ImGuiKey k, bool repeat = false) { return key_pressed(ImGui::GetKeyIndex(k), repeat); }

bool same_shapes(const rt::Scene& a, const rt::Scene& b) {
    if (a.objects.size() != b.objects.size()) return false;
    for (std::size_t i = 0; i < a.objects.size(); ++i)
        if (!(a.objects[i].shape == b.objects[i].shape)) return false;
    return true;
}

bool same_except_camera(const rt::Scene& a, const rt::Scene& b) {
    return a.objects == b.objects && a.planes == b.planes && a.lights == b.lights && a.width == b.width &&
           a.height == b.height;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

std::string stem_of(const std::string& name) {
    std::size_t dot = name.find_last_of('.');
    return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

}  // namespace

ViewerApp::ViewerApp(const Options& options, Host& host, bool interactive)
    : opt_(options), host_(host), interactive_(interactive), renderer_(options.threads) {
    max_samples_ = opt_.samples > 0 ? opt_.samples : (interactive_ ? kDefaultSamplesWindow : kDefaultSamplesHeadless);
    time_limit_ = opt_.time_limit;
    fit_ = opt_.fit;
    if (opt_.tab == "text") want_tab_ = 1;
    else if (opt_.tab == "render") want_tab_ = 2;
    else want_tab_ = 0;
}

ViewerApp::~ViewerApp() {
    renderer_.cancel();
    if (building_.valid()) building_.wait();
}

std::string ViewerApp::open_initial() {
    if (opt_.scene.empty()) {
        doc_.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
    } else {
        std::string err = doc_.load_file(opt_.scene);
        if (!err.empty()) return "cannot open '" + opt_.scene + "': " + err;
        if (interactive_) recent_.add(opt_.scene);
    }
    after_document_replaced();
    if (!opt_.select.empty()) {
        std::istringstream in(opt_.select);
        std::string kind;
        int n = 0;
        in >> kind >> n;
        const rt::Scene& s = doc_.scene();
        if (kind == "object" && n >= 1 && n <= int(s.objects.size())) selection_ = {Selection::Kind::Object, n - 1, {}};
        if (kind == "plane" && n >= 1 && n <= int(s.planes.size())) selection_ = {Selection::Kind::Plane, n - 1, {}};
        if (kind == "light" && n >= 1 && n <= int(s.lights.size())) selection_ = {Selection::Kind::Light, n - 1, {}};
        scroll_to_selection_ = true;
    }
    return {};
}

void ViewerApp::after_document_replaced() {
    selection_ = {};
    gesture_ = Gesture::None;
    editor_seen_version_ = 0;
    recovery_offer_ = false;
    if (interactive_) {
        // Text a crashed or killed session had not saved, for this same file.
        if (auto text = recovery_.find(doc_.path()); text && *text != doc_.editor_text()) {
            recovered_text_ = *text;
            recovery_offer_ = true;
        }
    }
    if (!doc_.has_scene() || doc_.has_errors()) want_tab_ = 1;  // show the errors
}

// ---------------------------------------------------------------------------------
// Frame

void ViewerApp::frame() {
    ++frames_;
    double now = ImGui::GetTime();

    update_layout();
    if (interactive_) handle_shortcuts();
    draw_menu_bar();
    draw_sidebar();
    draw_status_bar();
    draw_popups();
    if (interactive_) handle_view_input();
    end_gestures();
    if (check_due_ >= 0 && now >= check_due_) {
        doc_.check_text();
        check_due_ = -1;
    }
    if (interactive_ && now - last_disk_check_ >= 1.0) idle_tick();
    update_render();
    upload_film();
    draw_film();

    std::string title = doc_.title();
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
    if (interactive_ && !opt_.view_scene.empty() && !view_scene_written_ && started_world_) {
        std::string err = write_view_scene(opt_.view_scene);
        if (!err.empty()) status("view scene: " + err, true);
        view_scene_written_ = true;
    }
}

void ViewerApp::update_layout() {
    ImGuiIO& io = ImGui::GetIO();
    float W = io.DisplaySize.x, H = io.DisplaySize.y;
    fb_scale_ = io.DisplayFramebufferScale.x > 0 ? io.DisplayFramebufferScale.x : 1.f;
    float s = ImGui::GetFontSize() / 13.f;  // the UI scale the host chose
    menu_h_ = ImGui::GetFrameHeight();
    status_h_ = std::floor(ImGui::GetFrameHeight() + 8 * s);
    sidebar_w_ = std::floor(std::clamp(W * 0.34f, 320 * s, 470 * s));
    if (sidebar_w_ > W * 0.6f) sidebar_w_ = std::floor(W * 0.6f);
    area_ = {0, double(menu_h_), std::max(1.0, double(W - sidebar_w_)), std::max(1.0, double(H - menu_h_ - status_h_))};
    if (fit_ == FitMode::Picture && doc_.has_scene()) {
        film_w_ = doc_.scene().width;
        film_h_ = doc_.scene().height;
        image_ = letterbox(area_, film_w_, film_h_);
    } else {
        image_ = area_;
        film_w_ = std::max(1, int(std::lround(image_.w * fb_scale_)));
        film_h_ = std::max(1, int(std::lround(image_.h * fb_scale_)));
    }
}

rt::Camera ViewerApp::view_camera() const {
    const rt::Camera& c = doc_.scene().camera;
    return fit_ == FitMode::Window ? fit_camera_to_aspect(c, film_w_, film_h_) : c;
}

// ---------------------------------------------------------------------------------
// Keyboard

void ViewerApp::handle_shortcuts() {
    ImGuiIO& io = ImGui::GetIO();
    bool ctrl = io.KeyCtrl, shift = io.KeyShift;
    if (ctrl) {
        if (key_pressed(kKeyS)) {
            if (shift) {
                path_input_ = doc_.path().empty() ? doc_.name() : doc_.path();
                open_save_as_popup_ = true;
            } else {
                do_save();
            }
        }
        if (key_pressed(kKeyQ)) request(Action::Quit);  // asks first if there are unsaved edits
        if (key_pressed(kKeyO)) {
            path_input_.clear();
            open_open_popup_ = true;
        }
        if (key_pressed(kKeyP)) {
            path_input_ = stem_of(doc_.path().empty() ? doc_.name() : doc_.path()) + ".png";
            open_image_popup_ = true;
        }
        if (key_pressed(kKeyE)) {
            want_tab_ = 1;
            focus_editor_ = true;
        }
        if (imgui_key_pressed(ImGuiKey_Enter) || imgui_key_pressed(ImGuiKey_KeyPadEnter)) {
            bool ok = doc_.apply_text();
            status(ok ? "Applied the scene text" : "The scene text has errors; still showing the last good scene", !ok);
            if (editor_active_) {
                // ImGui drops focus on Ctrl+Enter; take it back with the cursor where it was.
                focus_editor_ = true;
                pending_cursor_ = editor_cursor_;
            }
        }
        // In a text field, Ctrl+Z/Y belong to the field's own undo.
        if (!io.WantTextInput) {
            if (imgui_key_pressed(ImGuiKey_Z, true)) {
                if (shift ? doc_.redo() : doc_.undo()) status(shift ? "Redo" : "Undo");
            } else if (imgui_key_pressed(ImGuiKey_Y, true)) {
                if (doc_.redo()) status("Redo");
            }
        }
    }
    if (key_pressed(kKeyF12)) {
        char name[64];
        std::time_t t = std::time(nullptr);
        std::strftime(name, sizeof name, "raytracer-view-%Y%m%d-%H%M%S.png", std::localtime(&t));
        screenshot_request_ = name;
    }
    if (!io.WantCaptureKeyboard && !ctrl && !io.KeyAlt) {
        if (imgui_key_pressed(ImGuiKey_Space)) toggle_pause();
        if (key_pressed(kKeyF)) frame_scene();
        if (key_pressed(kKeyR)) reset_camera();
    }
}

void ViewerApp::toggle_pause() {
    paused_ = !paused_;
    renderer_.set_paused(paused_);
    status(paused_ ? "Paused (Space resumes)" : "Resumed");
}

void ViewerApp::frame_scene() {
    if (!doc_.has_scene() || !world_) return;
    rt::Camera c = frame_bounds(view_camera(), world_->bounds());
    rt::Camera k = doc_.scene().camera;
    k.position = c.position;
    k.centre = c.centre;
    k.up = c.up;
    set_camera(k);
    commit_now();
}

void ViewerApp::reset_camera() {
    if (!doc_.has_scene()) return;
    set_camera(doc_.file_camera());
    commit_now();
}

// ---------------------------------------------------------------------------------
// Mouse and fly keys in the image area

rt::Vec3 ViewerApp::pick_point_or(double px, double py, double fallback_distance, bool* hit) {
    rt::Camera vc = view_camera();
    rt::Ray ray = ray_at(vc, image_, film_w_, film_h_, px, py);
    if (world_) {
        rt::PickResult r = pick_at(*world_, vc, image_, film_w_, film_h_, px, py);
        if (r.hit && std::isfinite(r.t)) {
            if (hit) *hit = true;
            return r.point;
        }
    }
    if (hit) *hit = false;
    return ray.origin + ray.dir * fallback_distance;
}

double ViewerApp::scene_size() const {
    if (world_) {
        rt::Aabb b = world_->bounds();
        if (!b.empty() && rt::finite(b.lo) && rt::finite(b.hi)) return std::max(rt::length(b.hi - b.lo), 1e-3);
    }
    const rt::Camera& c = doc_.scene().camera;
    return std::max(rt::length(c.centre - c.position), 1e-3);
}

void ViewerApp::set_camera(const rt::Camera& cam) {
    if (rt::camera_problem(cam) || !rt::finite(cam.position) || !rt::finite(cam.centre) || !rt::finite(cam.up))
        return;  // a degenerate camera would render nothing; keep the last good one
    if (cam == doc_.scene().camera) return;
    doc_.edit().camera = cam;
    change_time_ = std::chrono::steady_clock::now();
    timing_change_ = true;
}

void ViewerApp::commit_now() { doc_.commit(); }

void ViewerApp::handle_view_input() {
    ImGuiIO& io = ImGui::GetIO();
    double mx = io.MousePos.x, my = io.MousePos.y;
    bool usable = doc_.has_scene() && world_ && !ImGui::IsPopupOpen(nullptr, ImGuiPopupFlags_AnyPopupId);
    if (gesture_ == Gesture::None) {
        bool over = usable && !io.WantCaptureMouse && image_.contains(mx, my);
        if (over) {
            int button = -1;
            if (ImGui::IsMouseClicked(0)) button = 0;
            else if (ImGui::IsMouseClicked(1)) button = 1;
            else if (ImGui::IsMouseClicked(2)) button = 2;
            if (button >= 0) {
                gesture_button_ = button;
                gesture_ = (button == 0 && !io.KeyShift) ? Gesture::Click : Gesture::Pan;
                press_x_ = mx;
                press_y_ = my;
                press_camera_ = doc_.scene().camera;
                double centre_dist = rt::length(press_camera_.centre - press_camera_.position);
                anchor_ = pick_point_or(mx, my, centre_dist);
            }
            if (io.MouseWheel != 0 && gesture_ == Gesture::None) {
                const rt::Camera& c = doc_.scene().camera;
                rt::Vec3 target = pick_point_or(mx, my, rt::length(c.centre - c.position));
                set_camera(translate(c, dolly_offset(c.position, target, io.MouseWheel)));
                wheel_time_ = ImGui::GetTime();
            }
        }
    } else if (!ImGui::IsMouseDown(gesture_button_) || !usable) {
        if (gesture_ == Gesture::Click && usable) select_at(press_x_, press_y_);
        gesture_ = Gesture::None;
    } else {
        double dx = mx - press_x_, dy = my - press_y_;
        if (gesture_ == Gesture::Click && (std::fabs(dx) > kClickSlop || std::fabs(dy) > kClickSlop)) {
            gesture_ = Gesture::Orbit;
            // Pivot: the point under the cursor when the drag began, or the look-at
            // point if the ray missed everything.
            bool hit = false;
            rt::Vec3 p = pick_point_or(press_x_, press_y_, 1, &hit);
            anchor_ = hit ? p : press_camera_.centre;
        }
        if (gesture_ == Gesture::Orbit) {
            // Rotation is relative to the camera at the press, so it never drifts.
            set_camera(orbit(press_camera_, anchor_, world_up(), -dx * kOrbitRadPerPixel, dy * kOrbitRadPerPixel));
        } else if (gesture_ == Gesture::Pan) {
            rt::Camera vc = fit_ == FitMode::Window ? fit_camera_to_aspect(press_camera_, film_w_, film_h_) : press_camera_;
            rt::CameraBasis basis = rt::CameraBasis::make(vc, film_w_, film_h_, false);
            double i0, j0, i1, j1;
            window_to_film(image_, film_w_, film_h_, press_x_, press_y_, i0, j0);
            window_to_film(image_, film_w_, film_h_, mx, my, i1, j1);
            set_camera(translate(press_camera_, pan_offset(basis, anchor_, i0, j0, i1, j1)));
        }
    }

    // WASD/QE fly, scaled to the scene so that any scene crosses in a few seconds.
    // A key flies only if it went down without Ctrl/Alt: releasing Ctrl a moment
    // before the S of Ctrl+S must not turn into a step backwards.
    static const int fly_keys[6] = {kKeyD, kKeyA, kKeyE, kKeyQ, kKeyW, kKeyS};
    bool free_keys = usable && !io.WantCaptureKeyboard;
    for (int k = 0; k < 6; ++k) {
        if (!key_down(fly_keys[k]) || !free_keys) fly_armed_[k] = false;
        else if (key_pressed(fly_keys[k]) && !io.KeyCtrl && !io.KeyAlt && !io.KeySuper) fly_armed_[k] = true;
    }
    auto held = [&](int k) { return fly_armed_[k] && !io.KeyCtrl && !io.KeyAlt ? 1.0 : 0.0; };
    rt::Vec3 local{held(0) - held(1), held(2) - held(3), held(4) - held(5)};
    flying_ = rt::length2(local) > 0;
    if (flying_) {
        double step = scene_size() * 0.35 * std::clamp(double(io.DeltaTime), 0.0, 0.1) * (io.KeyShift ? 4 : 1);
        const rt::Camera& c = doc_.scene().camera;
        set_camera(translate(c, fly_offset(c, world_up(), local, step)));
    }
}

void ViewerApp::select_at(double px, double py) {
    if (!world_) return;
    rt::PickResult r = pick_at(*world_, view_camera(), image_, film_w_, film_h_, px, py);
    Selection s;
    if (r.object >= 0) s = {Selection::Kind::Object, r.object, {}};
    else if (r.plane >= 0) s = {Selection::Kind::Plane, r.plane, {}};
    else if (r.light >= 0) s = {Selection::Kind::Light, r.light, {}};
    selection_ = s;
    scroll_to_selection_ = true;
    if (s.kind != Selection::Kind::None && current_tab_ != 0) want_tab_ = 0;
}

void ViewerApp::end_gestures() {
    if (!doc_.editing()) return;
    double now = ImGui::GetTime();
    bool wheel_busy = wheel_time_ >= 0 && now - wheel_time_ < kWheelSettle;
    // A panel widget being dragged holds the edit open; the text editor being active
    // does not (it is not part of the edit, and may stay focused for a long time).
    bool widget_busy = ImGui::IsAnyItemActive() && (editor_id_ == 0 || ImGui::GetActiveID() != editor_id_);
    if (gesture_ != Gesture::None || flying_ || wheel_busy || widget_busy) return;
    doc_.commit();
    wheel_time_ = -1;
}

void ViewerApp::orbit_degrees(double degrees) {
    if (!doc_.has_scene()) return;
    const rt::Camera& c = doc_.scene().camera;
    set_camera(orbit(c, c.centre, world_up(), degrees * kPi / 180, 0));
    commit_now();
}

// ---------------------------------------------------------------------------------
// Rendering

void ViewerApp::update_render() {
    if (building_.valid() && building_.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        world_ = building_.get();
        world_scene_ = std::move(building_scene_);
        world_version_ = building_version_;
    }
    if (!doc_.has_scene()) {
        if (started_world_) {
            renderer_.cancel();
            started_world_ = nullptr;
        }
        return;
    }
    if (doc_.scene_version() != world_version_ && !building_.valid()) {
        const rt::Scene& s = doc_.scene();
        if (world_ && same_shapes(s, world_scene_)) {
            // Same geometry: materials, lights or only the camera changed. compile_world
            // reuses the BVH, so this stays well under a frame even for big scenes.
            if (same_except_camera(s, world_scene_)) {
                world_scene_.camera = s.camera;
            } else {
                world_ = rt::compile_world(s, world_.get());
                world_scene_ = s;
            }
            world_version_ = doc_.scene_version();
        } else {
            // New geometry: build the BVH on another thread; the last world keeps
            // rendering and the UI keeps running meanwhile.
            building_scene_ = s;
            building_version_ = doc_.scene_version();
            std::shared_ptr<const rt::World> prev = world_;
            building_ = std::async(std::launch::async, [scene = building_scene_, prev] {
                return rt::compile_world(scene, prev.get());
            });
        }
    }
    if (!world_ || film_w_ < 1 || film_h_ < 1) return;

    rt::Camera vc = view_camera();
    if (world_ != started_world_ || !(vc == started_camera_) || film_w_ != started_w_ || film_h_ != started_h_ ||
        settings_changed_) {
        auto w = std::make_shared<rt::World>(*world_);
        w->camera = vc;
        w->width = film_w_;
        w->height = film_h_;
        rt::RenderSettings st;
        st.width = film_w_;
        st.height = film_h_;
        st.max_samples = max_samples_;
        st.time_limit = time_limit_;
        if (paused_ && interactive_ && started_world_) {
            // Moving the view while paused would show nothing new; resume instead.
            paused_ = false;
            renderer_.set_paused(false);
        }
        renderer_.start(w, st);
        started_world_ = world_;
        started_camera_ = vc;
        started_w_ = film_w_;
        started_h_ = film_h_;
        settings_changed_ = false;
        final_uploaded_ = false;
    }
}

void ViewerApp::upload_film() {
    rt::RenderProgress before = renderer_.progress();
    int w = film_w_seen_, h = film_h_seen_;
    std::array<int, 4> changed{};
    if (renderer_.snapshot_rgba8(rgba_, w, h, film_version_, &changed)) {
        film_w_seen_ = w;
        film_h_seen_ = h;
        film_.upload(rgba_, w, h, changed);
        if (timing_change_ && (before.coarse_level > 0 || before.samples > 0) && w == film_w_ && h == film_h_) {
            last_latency_ms_ = seconds_since(change_time_) * 1000;
            timing_change_ = false;
            if (opt_.verbose)
                std::fprintf(stderr, "raytracer-view: view change -> first image on screen %.1f ms (renderer: %.1f ms, %dx%d)\n",
                             last_latency_ms_, before.first_coarse_time * 1000, w, h);
        }
    }
    // RenderProgress::elapsed keeps counting after the render is done; the status bar
    // wants the time the render took, so keep the value seen when it finished.
    if (before.done && done_generation_ != before.generation) {
        done_generation_ = before.generation;
        done_elapsed_ = before.elapsed;
    }
    // The snapshot was taken after `before`: if the render was already done then, the
    // texture now holds the final film.
    if (before.done && started_world_ && w >= 0) final_uploaded_ = true;
}

bool ViewerApp::render_settled() const {
    if (!doc_.has_scene() || !started_world_ || building_.valid()) return false;
    rt::RenderProgress p = renderer_.progress();
    return p.done && final_uploaded_ && p.width == film_w_ && p.height == film_h_;
}

double ViewerApp::wait_timeout() const {
    if (!interactive_) return 0;
    // The icon of busy-ness: anything animating or arriving needs display-rate frames.
    rt::RenderProgress p = renderer_.progress();
    bool busy = p.running || building_.valid() || gesture_ != Gesture::None || flying_ || doc_.editing() ||
                (!final_uploaded_ && !paused_ && doc_.has_scene()) || check_due_ >= 0 || frames_ < 3 ||
                // Focus and cursor requests take effect over the next frames.
                focus_editor_ || pending_cursor_ >= 0 || want_tab_ >= 0 || !screenshot_request_.empty();
    // Right after a view change the coarse pass lands within a few milliseconds: look
    // for it more often than the display rate so it shows without a frame's delay.
    if (timing_change_ && p.running) return 0.004;
    if (busy) return 1.0 / 60;
    // Idle: sleep until input, waking once a second to look at the file on disk.
    return 1.0;
}

bool ViewerApp::needs_frame() { return wait_timeout() < 0.5; }

bool ViewerApp::idle_tick() {
    last_disk_check_ = ImGui::GetTime();
    // While an offer is pending the old copy stays on disk untouched.
    if (!recovery_offer_) {
        std::string err = recovery_.update(doc_.path(), doc_.editor_text(), doc_.modified(), last_disk_check_);
        if (!err.empty()) status("cannot keep a recovery copy: " + err, true);
    }
    switch (doc_.check_disk()) {
        case Document::DiskEvent::None: return false;
        case Document::DiskEvent::Reloaded: status("Reloaded " + doc_.name() + " (changed on disk)"); break;
        case Document::DiskEvent::Conflict: status(doc_.name() + " changed on disk; you have unsaved edits"); break;
        case Document::DiskEvent::Removed: status(doc_.name() + " was removed on disk; Save writes it again", true); break;
    }
    return true;
}

// ---------------------------------------------------------------------------------
// Files

void ViewerApp::status(const std::string& text, bool error) {
    status_text_ = text;
    status_error_ = error;
    status_time_ = ImGui::GetTime();
}

void ViewerApp::request(Action a, const std::string& path) {
    if ((a == Action::Quit || a == Action::Open || a == Action::OpenDefault) && doc_.modified()) {
        pending_action_ = a;
        pending_path_ = path;
        open_unsaved_popup_ = true;
        return;
    }
    perform(a, path);
}

void ViewerApp::perform(Action a, const std::string& path) {
    switch (a) {
        case Action::None: break;
        case Action::Quit:
            // Quitting is the user's decision about unsaved text: no recovery copy.
            if (!recovery_offer_) recovery_.discard(doc_.path());
            host_.quit();
            break;
        case Action::Open: do_open(path); break;
        case Action::OpenDefault:
            doc_.load_text(rt::kDefaultScene, "", rt::kDefaultSceneName);
            after_document_replaced();
            status("Opened the built-in default scene");
            break;
    }
}

void ViewerApp::do_open(const std::string& path) {
    std::string err = doc_.load_file(path);
    if (!err.empty()) {
        status("Cannot open " + path + ": " + err, true);
        return;
    }
    if (interactive_) recent_.add(path);
    after_document_replaced();
    status(doc_.has_errors() ? "Opened " + doc_.name() + " (it has errors)" : "Opened " + doc_.name(),
           doc_.has_errors());
}

void ViewerApp::do_save() {
    if (doc_.path().empty()) {
        path_input_ = doc_.name();
        open_save_as_popup_ = true;
        return;
    }
    std::string err = doc_.save();
    if (err.empty()) status("Saved " + doc_.path());
    else status("Save failed: " + err, true);
}

bool ViewerApp::do_save_as(const std::string& path) {
    std::string err = doc_.save_as(path);
    if (!err.empty()) {
        status("Save failed: " + err, true);
        return false;
    }
    if (interactive_) recent_.add(path);
    status("Saved " + doc_.path());
    return true;
}

void ViewerApp::do_save_image(const std::string& path) {
    rt::Image img = renderer_.snapshot();
    if (img.width < 1) {
        status("There is no image to save yet", true);
        return;
    }
    if (rt::format_from_path(path) == rt::ImageFormat::Unknown) {
        status("Image names must end in .png or .ppm", true);
        return;
    }
    std::string err = rt::write_image(path, img);
    if (err.empty()) status("Wrote " + path + " (" + std::to_string(img.width) + "x" + std::to_string(img.height) + ")");
    else status("Cannot write " + path + ": " + err, true);
}

bool ViewerApp::close_requested() {
    if (!doc_.modified()) return true;
    request(Action::Quit);
    return false;
}

void ViewerApp::drop_files(const std::vector<std::string>& paths) {
    if (!paths.empty()) request(Action::Open, paths.front());
}

void ViewerApp::after_render(int fb_width, int fb_height) {
    if (screenshot_request_.empty()) return;
    std::string path = screenshot_request_;
    screenshot_request_.clear();
    std::string err = save_framebuffer(path, fb_width, fb_height);
    if (err.empty()) status("Wrote screenshot " + path);
    else status("Screenshot failed: " + err, true);
}

std::string ViewerApp::write_view_scene(const std::string& path) const {
    if (!doc_.has_scene()) return "the scene has errors";
    rt::Scene s = doc_.scene();
    s.camera = view_camera();
    s.width = film_w_;
    s.height = film_h_;
    return rt::write_file_atomic(path, rt::write_scene(s));
}

std::string ViewerApp::layout_text() const {
    auto px = [this](const Rect& r) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%ld %ld %ld %ld", std::lround(r.x * fb_scale_), std::lround(r.y * fb_scale_),
                      std::lround(r.w * fb_scale_), std::lround(r.h * fb_scale_));
        return std::string(buf);
    };
    ImGuiIO& io = ImGui::GetIO();
    Rect window{0, 0, io.DisplaySize.x, io.DisplaySize.y};
    Rect sidebar{window.w - sidebar_w_, menu_h_, sidebar_w_, window.h - menu_h_};
    Rect bar{0, window.h - status_h_, area_.w, status_h_};
    std::string s;
    s += "window " + px(window) + "\n";
    s += "image " + px(image_) + "\n";
    s += "film " + std::to_string(film_w_) + " " + std::to_string(film_h_) + "\n";
    s += "sidebar " + px(sidebar) + "\n";
    s += "camera " + px(camera_panel_) + "\n";
    s += "outline " + px(current_tab_ == 0 ? outline_rect_ : Rect{}) + "\n";
    s += "editor " + px(current_tab_ == 1 ? editor_rect_ : Rect{}) + "\n";
    s += "diagnostics " + px(current_tab_ == 1 ? diag_rect_ : Rect{}) + "\n";
    s += "status " + px(bar) + "\n";
    return s;
}

}  // namespace rtview
