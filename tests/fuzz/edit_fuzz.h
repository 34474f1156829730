// The edit fuzzer's engine, shared by the libFuzzer target (fuzz_edits.cpp) and the
// viewer's unit tests (tests/viewer/test_edit_fuzz.cpp): a random scene text, then a
// sequence of what a user can do to it through the viewer's document (panel edits of
// every field of every kind of item, typed values, moves, add, duplicate, delete, CSG,
// lamp <-> spotlight, typing applied or not, undo, redo, save, reload), all chosen by
// the input's bytes. After every step it checks what the viewer promises:
//   - the scene is the parse of the text it came from, and the editor text parses
//     unless it is exactly what was typed;
//   - the world the viewer renders (ViewerWorld: WorldSync, as the viewer keeps it)
//     equals a full compile of that text, table for table and pixel for pixel;
//   - a saved file holds the editor text, and its render through core (as `raytracer`
//     renders it) is the viewer's picture;
//   - undo back to the start gives the original bytes, every state on the way one the
//     user saw; redo to the end gives the same bytes and scenes again;
//   - a text widget that follows the document's own changes of the text (as the Text
//     tab does: text_changes_since(), typing carried the other way) holds its text.
// A broken promise throws Broken (fuzz_common.h) naming it, with the steps so far.
// The run's parts: edit_fuzz_choices.h (the input's bytes as choices, numbers),
// edit_fuzz_scenes.h (random scene texts), edit_fuzz_world.h (the viewer's world and
// its comparison with a full compile).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "document.h"
#include "edit_fuzz_choices.h"
#include "edit_fuzz_scenes.h"
#include "edit_fuzz_world.h"
#include "fuzz_common.h"
#include "image_io.h"
#include "item_fields.h"
#include "scene_edits.h"
#include "scene_parser.h"
#include "scene_writer.h"
#include "text_buffer.h"

namespace rtfuzz {

// One run: a random scene opened, then the steps the bytes choose, each checked.
struct EditRunOptions {
    std::string dir;          // an existing folder for the scene's file (saves, reloads)
    std::size_t max_steps = 48;
};

class EditRun {
public:
    EditRun(const std::uint8_t* data, std::size_t size, EditRunOptions opt)
        : c_(data, size), opt_(std::move(opt)), path_(opt_.dir + "/scene.txt") {}

    void run() {
        open(new_scene(), "start");
        for (std::size_t k = 0; k < opt_.max_steps && c_.more(); ++k) {
            step();
            check();
        }
        log("the end: undo all, redo all");
        round_trip_history();
    }

private:
    using Doc = rtview::Document;
    using Item = rtview::SceneItem;

    // A new random scene; the file it includes (if any) written beside it.
    std::string new_scene() {
        SceneWriter w(c_);
        std::string text = w.scene();
        if (w.included_file()) {
            log("lib.txt written for the scene's include");
            if (rt::Status st = rt::write_file_atomic(lib_path(), *w.included_file()); !st)
                fail("cannot write the included file", st.message());
        }
        return text;
    }
    std::string lib_path() const { return opt_.dir + "/lib.txt"; }
    // The scene's text parsed as the document parses its file (includes from its folder).
    rt::ParseResult parse(const std::string& text) const {
        rt::ParseOptions o;
        o.base_dir = opt_.dir;
        return rt::parse_scene(text, o);
    }

    // A snapshot of what the document shows: editor text, applied text, scene. The
    // scene's items read from included files are left out: they are the files' as they
    // are on disk (check() compares the whole scene with the parse of its text), and an
    // undo after an included file changed shows them as they are now.
    struct State {
        std::string editor, applied;
        bool has_scene = false;
        rt::Scene scene;
        bool operator==(const State& o) const {
            return editor == o.editor && applied == o.applied && has_scene == o.has_scene &&
                   (!has_scene || scene == o.scene);
        }
    };
    static State state_of(const Doc& d) {
        State st{d.editor_text(), d.applied_text(), d.has_scene(), d.has_scene() ? d.scene() : rt::Scene{}};
        if (!st.scene.includes.empty()) {
            auto own = [](auto& v) {
                v.erase(std::remove_if(v.begin(), v.end(), [](const auto& x) { return x.origin != 0; }), v.end());
            };
            own(st.scene.objects);
            own(st.scene.planes);
            own(st.scene.lights);
            own(st.scene.materials);
            own(st.scene.defined);
        }
        return st;
    }
    State state() const { return state_of(doc_); }

    [[noreturn]] void broken(const std::string& what) const {
        std::string steps;
        for (const std::string& s : log_) steps += "\n  " + s;
        fail(what.c_str(), "after the steps:" + steps + "\n--- editor text ---\n" + doc_.editor_text() +
                               "\n--- applied text ---\n" + doc_.applied_text());
    }
    void log(std::string s) {
        if (log_.size() >= 200) log_.erase(log_.begin());
        log_.push_back(std::move(s));
    }

    // ---- opening -----------------------------------------------------------------
    void open(const std::string& text, const char* how) {
        if (rt::Status st = rt::write_file_atomic(path_, text); !st) fail("cannot write the scene file", st.message());
        if (rt::Status st = doc_.load_file(path_); !st) fail("cannot open the scene file", st.message());
        log(std::string(how) + ": open a scene of " + std::to_string(text.size()) + " bytes");
        history_start();
        saved_ = text;
        if (!parse(text).ok()) own_texts_.insert(text);
        check();
    }
    void history_start() {
        seen_.clear();
        seen_.push_back(state());
    }

    // ---- the steps ---------------------------------------------------------------
    void step() {
        const unsigned op = c_.below(22);
        // A held edit (a slider held while the user presses Ctrl+Z, Ctrl+S...) ends in
        // the call that commits it first; the other steps come after a release.
        const bool commits_first = op == 8 || op == 11 || op == 12 || op == 13 || op == 14 || op == 16 || op >= 19;
        if (doc_.edit_held()) {
            if (!commits_first || !c_.one_in(3)) {
                end_edit();
                check();
            } else {
                // The state the commit will make is one an undo may return to.
                Doc probe = doc_;
                probe.commit();
                seen_.push_back(state_of(probe));
            }
        }
        switch (op) {
            case 0: case 1: case 2: case 3: panel_edit(); break;
            case 4: typed_value(); break;
            case 5: case 6: move(); break;
            case 7: camera_edit(); break;
            case 8: structural(); break;
            case 9: case 10: typing(); break;
            case 11: apply_or_revert(); break;
            case 12: case 13: undo_redo(); break;
            case 14: save(); break;
            case 15: outside_change(); break;
            case 16: reopen(); break;
            case 17: restore_draft(); break;
            case 18: set_camera(); break;
            case 19: round_trip_history(); break;
            case 21: include_change(); break;
            default: structural(); break;
        }
    }

    void end_edit() {
        if (!doc_.edit_held()) return;
        if (c_.one_in(8)) {
            log("cancel the held edit");
            doc_.cancel_edit();
        } else {
            log("commit the held edit");
            doc_.commit();
        }
        (void)doc_.take_refusal();
    }

    // The item an edit goes to: an object (maybe a CSG operand), a plane or a light.
    std::optional<rtview::ItemRef> pick_item() {
        if (!doc_.has_scene()) return std::nullopt;
        const rt::Scene& s = doc_.scene();
        const std::size_t n = s.objects.size() + s.planes.size() + s.lights.size();
        if (n == 0) return std::nullopt;
        std::size_t k = c_.below(unsigned(n));
        rtview::ItemRef ref;
        if (k < s.objects.size()) {
            ref.item = {Item::Kind::Object, int(k)};
            const rt::Object* o = &s.objects[k];
            while (const auto* g = std::get_if<rt::Csg>(&o->shape)) {
                if (!c_.one_in(2)) break;
                const int side = int(c_.below(2));
                ref.path.push_back(side);
                o = &g->operands[std::size_t(side)];
            }
        } else if ((k -= s.objects.size()) < s.planes.size()) {
            ref.item = {Item::Kind::Plane, int(k)};
        } else {
            ref.item = {Item::Kind::Light, int(k - s.planes.size())};
        }
        return ref;
    }

    // A new value for field `f` (currently `v`): dragged a little, or anything.
    void new_value(const rtview::Field& f, rtview::FieldValue& v) {
        namespace sc = rt::schema;
        switch (f.kind) {
            case sc::Kind::Number:
            case sc::Kind::Integer: v.number = c_.one_in(2) ? v.number + plain_number(c_) * 0.1 : any_number(c_); break;
            case sc::Kind::Vec3:
                if (c_.one_in(3)) v.vec = any_vec(c_);
                else v.vec[int(c_.below(3))] += plain_number(c_) * 0.1;
                break;
            case sc::Kind::Choice:
                v.choice = c_.one_in(8) || f.choice->words.empty()
                               ? int(c_.below(256)) - 1
                               : f.choice->words[c_.below(unsigned(f.choice->words.size()))].value;
                break;
            case sc::Kind::Material:
                // A use of a named material: edited for every user, or made local.
                if (v.material.named >= 0 && c_.one_in(6)) v.material.named = -1;
                else material_value(v.material);
                break;
            case sc::Kind::Operand: break;
            case sc::Kind::File: break;  // (the fuzzer's scenes name no model files)
        }
    }
    void material_value(rt::Material& m) {
        switch (c_.below(6)) {
            case 0: m.reflection = any_number(c_); break;
            case 1: m.refraction = any_number(c_); break;
            case 2: m.scattering = any_number(c_); break;
            case 3: m.translusans = any_number(c_); break;
            case 4: m.refractive_index = any_number(c_); break;
            default: m.colour = c_.one_in(2) ? any_vec(c_) : plain_vec(c_); break;
        }
    }

    bool blocked() {
        // The panels are disabled while the text blocks edits; now and then the fuzzer
        // edits anyway, and the document must refuse.
        return !doc_.edit_blocker().empty() && !c_.one_in(6);
    }

    // A field of the panel, dragged over a few frames (one undo step) or set once.
    void panel_edit() {
        auto ref = pick_item();
        if (!ref || blocked()) return;
        const std::vector<rtview::Field> fields = rtview::item_fields(doc_.scene(), *ref);
        if (fields.empty()) return;
        const rtview::Field& f = fields[c_.below(unsigned(fields.size()))];
        const int frames = c_.one_in(2) ? 1 : c_.between(2, 6);
        log("panel: " + f.label + " of " + rtview::item_label(doc_.scene(), *ref) + " over " + std::to_string(frames) +
            " frames");
        for (int k = 0; k < frames; ++k) {
            std::optional<rtview::FieldValue> v = rtview::field_value(doc_.scene(), *ref, f);
            if (!v) broken("field_value of a field item_fields gave");
            new_value(f, *v);
            (void)rtview::set_field(doc_, *ref, f, *v);
            frame();
        }
        if (!c_.one_in(5)) end_edit();
    }

    // Ctrl+click a number field and type into it: parse_typed_number, then set_field.
    void typed_value() {
        auto ref = pick_item();
        if (!ref || blocked()) return;
        std::vector<rtview::Field> fields = rtview::item_fields(doc_.scene(), *ref);
        fields.erase(std::remove_if(fields.begin(), fields.end(),
                                    [](const rtview::Field& f) {
                                        return f.kind != rt::schema::Kind::Number &&
                                               f.kind != rt::schema::Kind::Integer && f.kind != rt::schema::Kind::Vec3;
                                    }),
                     fields.end());
        if (fields.empty()) return;
        const rtview::Field& f = fields[c_.below(unsigned(fields.size()))];
        std::optional<rtview::FieldValue> v = rtview::field_value(doc_.scene(), *ref, f);
        if (!v) broken("field_value of a field item_fields gave");
        const int comp = int(c_.below(3));
        double& x = f.kind == rt::schema::Kind::Vec3 ? v->vec[comp] : v->number;
        const std::string text = typed_text(c_, x);
        log("type '" + printable(text) + "' into " + f.label + " of " + rtview::item_label(doc_.scene(), *ref));
        double typed = 0;
        const rt::Status st = rtview::parse_typed_number(text, typed);
        if (st) {
            if (!std::isfinite(typed) || std::fabs(typed) > 1e15) broken("parse_typed_number took an out-of-range number");
            x = typed;
            (void)rtview::set_field(doc_, *ref, f, *v);
        } else if (st.message().size() > 200) {
            broken("parse_typed_number's message is not short: " + printable(st.message()));
        }
        end_edit();
    }

    // The move handle (app/viewer/ui/move_tool.cpp): the item as it was at the press,
    // moved by the drag so far, every frame; released: one undo step (or none).
    void move() {
        auto ref = pick_item();
        if (!ref || blocked()) return;
        const std::size_t i = std::size_t(ref->item.index);
        const rt::Scene& s = doc_.scene();
        const rt::Object object = ref->item.kind == Item::Kind::Object ? s.objects[i] : rt::Object{};
        const rt::Plane plane = ref->item.kind == Item::Kind::Plane ? s.planes[i] : rt::Plane{};
        const rt::Light light = ref->item.kind == Item::Kind::Light ? s.lights[i] : rt::Light{};
        const int frames = c_.between(1, 5);
        log("move " + rtview::item_label(s, *ref) + " over " + std::to_string(frames) + " frames");
        rt::Vec3 d{0, 0, 0};
        for (int k = 0; k < frames; ++k) {
            const rt::Vec3 step = c_.one_in(8) ? any_vec(c_) : plain_vec(c_) * 0.25;
            if (!rt::finite(d + step)) continue;
            d = d + step;
            switch (ref->item.kind) {
                case Item::Kind::Object: {
                    rt::Object& o = doc_.edit_object(i);
                    o = object;
                    rtview::translate_operand(o, ref->path, d);
                    break;
                }
                case Item::Kind::Plane: rtview::translate(doc_.edit_plane(i) = plane, d); break;
                case Item::Kind::Light: rtview::translate(doc_.edit_light(i) = light, d); break;
            }
            doc_.name_edit("Move " + rtview::item_label(doc_.scene(), *ref));
            frame();
        }
        if (c_.one_in(6)) return;  // still held
        if (d == rt::Vec3{0, 0, 0} || c_.one_in(10)) {
            log("release: cancelled");
            doc_.cancel_edit();
        } else {
            end_edit();
        }
    }

    // The scene camera's fields (app/viewer/ui/panels.cpp): taken only when the
    // camera they make is valid.
    void camera_edit() {
        if (!doc_.has_scene() || blocked()) return;
        rt::Camera cam = doc_.scene().camera;
        switch (c_.below(6)) {
            case 0: cam.position[int(c_.below(3))] += plain_number(c_); break;
            case 1: cam.centre = c_.one_in(4) ? any_vec(c_) : cam.centre + plain_vec(c_) * 0.1; break;
            case 2: cam.up[int(c_.below(3))] = any_number(c_); break;
            case 3: cam.angle_x = std::clamp(cam.angle_x + plain_number(c_), 0.5, 179.5); break;
            case 4: cam.angle_y = std::clamp(any_number(c_), 0.5, 179.5); break;
            default:
                cam.projection = cam.projection == rt::Projection::Linear ? rt::Projection::Polar : rt::Projection::Linear;
                break;
        }
        log("camera panel");
        if (rt::camera_problem(cam)) return;
        doc_.edit_camera() = cam;
        frame();
        if (!c_.one_in(4)) end_edit();
    }

    // "Set scene camera from view": the view camera is valid but may be anywhere.
    void set_camera() {
        if (!doc_.has_scene()) return;
        rt::Camera cam = doc_.scene().camera;
        cam.position = cam.position + (c_.one_in(6) ? any_vec(c_) : plain_vec(c_));
        cam.centre = cam.centre + plain_vec(c_) * 0.5;
        cam.up = cam.centre + rt::Vec3{0, 0, 1};
        if (rt::camera_problem(cam) || !rt::finite(cam.position)) return;
        log("set the scene camera from the view");
        doc_.set_camera(cam);
    }

    // Add, duplicate, delete, CSG, lamp <-> spotlight (app/viewer/ui/app.cpp, scene_edit):
    // one replacement of the text, which must parse to the scene with the edit made.
    void structural() {
        if (!doc_.has_scene()) return;
        // While a drag holds an edit the viewer refuses: the edit is planned on the text
        // and scene as they are, and committing the held edit would change both.
        const bool ui_allows = !doc_.editor_dirty() && !doc_.text_behind() && !doc_.edit_held();
        if (!ui_allows && !c_.one_in(6)) return;
        const rt::Scene before = doc_.scene();
        const std::string text = std::as_const(doc_).editor_text();
        std::optional<rtview::SceneEdit> e;
        std::optional<rt::Scene> want;  // the scene the edit must give, when known exactly
        std::string what;
        plan_structural(before, text, e, want, what);
        if (!e) {
            log(what + ": not offered");
            return;
        }
        log(what);
        const bool done = doc_.replace_text(e->replacement.offset, e->replacement.length, e->replacement.text, what);
        if (!ui_allows) {
            if (done) broken("replace_text edited a text with unapplied changes or a held edit");
            return;
        }
        if (!done) {
            std::string edited = text;
            e->replacement.apply(edited);
            const rt::ParseResult r = parse(edited);
            std::string why;
            for (const rt::Diagnostic& d : r.diagnostics) why += "\n  " + rt::format_diagnostic("edited", d);
            broken(what + " made a text that does not parse:" + why);
        }
        // (Where the includes stand among the file's own items is the parse's to say:
        // check() compares the scene with it.)
        if (want) want->includes = doc_.scene().includes;
        if (want && !(doc_.scene() == *want)) broken(what + " did not give the scene with the edit made");
    }
    void plan_structural(const rt::Scene& s, const std::string& text, std::optional<rtview::SceneEdit>& e,
                         std::optional<rt::Scene>& want, std::string& what) {
        const unsigned kind = c_.below(5);
        if (kind == 0) {
            const auto k = rtview::kNewItems[c_.below(unsigned(std::size(rtview::kNewItems)))];
            rtview::Placement at{plain_vec(c_), c_.one_in(2) ? rt::Vec3{0, 0, 1} : rt::Vec3{0, 0, 0}, plain_vec(c_)};
            what = std::string("add a ") + rtview::new_item_name(k);
            e = rtview::add_item(text, s, k, at);
            return;
        }
        auto ref = pick_item();
        if (!ref) {
            what = "structural edit of nothing";
            return;
        }
        const Item it = ref->item;
        const std::size_t i = std::size_t(it.index);
        what = rtview::item_label(s, {it, {}});
        rt::Scene w = s;
        if (kind == 1) {
            const rt::Vec3 off = c_.one_in(3) ? rt::Vec3{0, 0, 0} : plain_vec(c_);
            what = "duplicate " + what;
            e = rtview::duplicate_item(text, s, it, off);
            // The copy: the block's text as it is, or written moved by the offset.
            const bool moved = !(off == rt::Vec3{0, 0, 0});
            auto copy = [&](auto& list) {
                auto at = list.insert(list.begin() + std::ptrdiff_t(i) + 1, list[i]);
                if (moved) rtview::translate(*at, off);
            };
            if (it.kind == Item::Kind::Object) copy(w.objects);
            if (it.kind == Item::Kind::Plane) copy(w.planes);
            if (it.kind == Item::Kind::Light) copy(w.lights);
            want = w;
        } else if (kind == 2) {
            what = "delete " + what;
            e = rtview::delete_item(text, s, it);
            if (it.kind == Item::Kind::Object) w.objects.erase(w.objects.begin() + std::ptrdiff_t(i));
            if (it.kind == Item::Kind::Plane) w.planes.erase(w.planes.begin() + std::ptrdiff_t(i));
            if (it.kind == Item::Kind::Light) w.lights.erase(w.lights.begin() + std::ptrdiff_t(i));
            want = w;
        } else if (kind == 3 && it.kind == Item::Kind::Object && s.objects.size() >= 2) {
            const int b = int(c_.below(unsigned(s.objects.size())));
            const auto type = rt::CsgType("UIC"[c_.below(3)]);
            what = "make a CSG of objects " + std::to_string(i + 1) + " and " + std::to_string(b + 1);
            e = rtview::make_csg(text, s, int(i), b, type);
            if (int(i) != b) {
                rt::Object o;
                o.material = s.objects[i].material;
                o.has_material = s.objects[i].has_material;
                o.shape = rt::Csg{type, {s.objects[i], s.objects[std::size_t(b)]}};
                w.objects[i] = std::move(o);
                w.objects.erase(w.objects.begin() + b);
                want = w;
            }
        } else if (it.kind == Item::Kind::Light) {
            what = "switch " + what;
            e = rtview::switch_light_kind(text, s, int(i));
        } else {
            what = "structural edit of " + what + " offered nothing";
        }
    }

    // Typing in the scene text: a few edits of the editor text, then maybe applied.
    void typing() {
        follow_text();
        std::string& t = doc_.typing_text();
        const int edits = c_.between(1, 3);
        for (int k = 0; k < edits; ++k) type_once(t);
        typed_in_widget(t);
        doc_.note_typed();
        own_texts_.insert(t);
        log("type: now " + std::to_string(t.size()) + " bytes");
        const std::string typed = t;
        seen_.push_back(state());  // what the user sees before applying it
        if (c_.one_in(3)) {
            const rt::Scene before = doc_.has_scene() ? doc_.scene() : rt::Scene{};
            const bool had = doc_.has_scene();
            const bool ok = doc_.apply_text();
            log(ok ? "apply: taken" : "apply: refused");
            const rt::ParseResult r = parse(typed);
            if (ok != r.ok()) broken("apply_text's verdict is not the parser's");
            if (std::as_const(doc_).editor_text() != typed) broken("apply_text changed the typed text");
            if (ok && !(doc_.scene() == r.scene)) broken("the applied scene is not the parse of the text");
            if (!ok && (doc_.has_scene() != had || (had && !(doc_.scene() == before))))
                broken("a refused apply changed the scene");
        } else if (c_.one_in(3)) {
            doc_.check_text();
        }
        if (std::as_const(doc_).editor_text() != typed) broken("the editor text is not what was typed");
    }
    void type_once(std::string& t) {
        static const char* const kSnippets[] = {" ", "\n", "// x", "{", "}", "radius 2 ", "sphere { radius 1 }",
                                                "\r\n", "\t", "end", "thing { }", "light { lamp { } }",
                                                "\x00", "\xff\xfe", "camera { angle_x 170 }", "1e16", "x_max 0"};
        const std::size_t at = t.empty() ? 0 : c_.below(unsigned(t.size() + 1));
        switch (c_.below(4)) {
            case 0: {
                const char* s = kSnippets[c_.below(sizeof kSnippets / sizeof kSnippets[0])];
                t.insert(at, *s ? std::string(s) : std::string(1, '\0'));
                break;
            }
            case 1: t.erase(at, c_.between(1, 24)); break;
            case 2: t.insert(at, number_text(any_number(c_), c_)); break;
            default: replace_number(t, at); break;
        }
    }
    // The number token at or after `at` becomes another number.
    void replace_number(std::string& t, std::size_t at) {
        const std::size_t b = t.find_first_of("0123456789", at);
        if (b == std::string::npos) return;
        std::size_t s = b, e = b;
        while (s > 0 && std::strchr("+-.0123456789eE", t[s - 1])) --s;
        while (e < t.size() && std::strchr("+-.0123456789eE", t[e])) ++e;
        t.replace(s, e - s, number_text(any_number(c_), c_));
    }

    void apply_or_revert() {
        if (c_.one_in(2)) {
            log("apply (Ctrl+Enter)");
            Doc probe = doc_;  // a held edit is committed into the text first
            probe.commit();
            const std::string typed = std::as_const(probe).editor_text();
            const bool ok = doc_.apply_text();
            if (std::as_const(doc_).editor_text() != typed) broken("apply_text changed the editor text");
            if (ok != parse(typed).ok()) broken("apply_text's verdict is not the parser's");
        } else {
            log("revert the text");
            doc_.revert_text();
            if (doc_.has_scene() && doc_.editor_dirty()) broken("the text differs from the applied text after a revert");
        }
    }

    void undo_redo() {
        const int n = c_.between(1, 4);
        const bool undo = c_.one_in(2) || !doc_.can_redo();
        log(std::string(undo ? "undo" : "redo") + " x" + std::to_string(n));
        for (int k = 0; k < n; ++k) {
            const bool moved = undo ? doc_.undo() : doc_.redo();
            if (!moved) break;
            if (undo && !seen_before(state())) broken("an undo went to a state the user never saw");
            if (!undo) seen_.push_back(state());
        }
    }

    // Ctrl+S (app/viewer/ui/app.cpp, do_save): a draft that parses is applied first; one
    // that does not is saved only when the user says so.
    void save() {
        doc_.commit();
        (void)doc_.take_refusal();
        doc_.apply_parsing_draft();
        const bool problem = doc_.save_problem().has_value();
        if (problem && !c_.one_in(2)) {
            log("save: asked, cancelled");
            return;
        }
        const bool as = c_.one_in(5);
        log(as ? "save as" : "save");
        const std::string other = opt_.dir + "/other.txt";
        const rt::Status st = as ? doc_.save_as(other) : doc_.save();
        if (!st) broken("saving failed: " + st.message());
        std::string disk;
        if (!rt::read_file(doc_.path(), disk, std::size_t(64) << 20)) broken("cannot read the saved file");
        if (disk != std::as_const(doc_).editor_text()) broken("the saved file is not the editor text");
        if (doc_.modified()) broken("modified() after a save");
        saved_ = disk;
        if (as) {
            // Back under the usual name (the file was just written there too).
            if (!doc_.save_as(path_)) broken("save as back to the scene's name failed");
        }
        check_saved_render(disk);
    }
    // `raytracer` on the saved text: parse, compile, render; the viewer's world (through
    // the scene camera it shows) must make the same picture.
    void check_saved_render(const std::string& disk) {
        const rt::ParseResult r = parse(disk);
        if (!r.ok()) {
            if (doc_.has_scene() && !doc_.editor_dirty()) broken("the saved text does not parse");
            return;  // saved with errors at the user's word: raytracer refuses it too
        }
        if (doc_.editor_dirty()) broken("a saved text that parses was not applied");
        const rt::World* got = world_.settled(doc_);
        const std::shared_ptr<const rt::World> want = rt::compile_world(r.scene);
        if (!got) broken("no world for a scene");
        if (!(doc_.scene().camera == r.scene.camera)) broken("the saved camera is not the scene's");
        if (std::string d = world_difference(*got, *want, r.scene.camera); !d.empty())
            broken("raytracer's render of the saved text differs from the viewer's: " + d);
    }

    // Another program writes the file; the viewer notices (check_disk) and reloads or
    // asks, and the user answers.
    void outside_change() {
        std::string text = c_.one_in(3) ? new_scene() : std::as_const(doc_).editor_text();
        if (c_.one_in(2) && !text.empty()) text.insert(c_.below(unsigned(text.size())), "// outside\n");
        if (rt::Status st = rt::write_file_atomic(path_, text); !st) fail("cannot write the scene file", st.message());
        if (!parse(text).ok()) own_texts_.insert(text);
        const bool was_modified = doc_.modified();
        const State before = state();
        const auto included_before = included_counts();
        const Doc::DiskEvent ev = doc_.check_disk();
        log("outside change of the file: event " + std::to_string(int(ev)));
        if (ev == Doc::DiskEvent::Reloaded) {
            if (was_modified) broken("reloaded over unsaved edits");
            saved_ = text;
            if (std::as_const(doc_).editor_text() != text) broken("the reloaded text is not the file's");
            reloaded(before, included_before);
        } else if (ev == Doc::DiskEvent::Conflict) {
            if (c_.one_in(2)) {
                log("conflict: reload");
                doc_.resolve_conflict_reload();
                saved_ = text;
                if (std::as_const(doc_).editor_text() != text) broken("the reloaded text is not the file's");
                reloaded(before, included_before);
            } else {
                log("conflict: keep mine");
                doc_.resolve_conflict_keep();
            }
        }
        settle_disk();
    }

    // How many items of each list the included files brought.
    std::tuple<std::size_t, std::size_t, std::size_t> included_counts() const {
        if (!doc_.has_scene()) return {};
        auto count = [](const auto& v) {
            return std::size_t(std::count_if(v.begin(), v.end(), [](const auto& x) { return x.origin != 0; }));
        };
        const rt::Scene& s = doc_.scene();
        return {count(s.objects), count(s.planes), count(s.lights)};
    }
    // The file was read again (its includes with it): when these brought another number
    // of items, the history before the reload is gone (its steps name items by their
    // place), and the reload is its one step.
    void reloaded(const State& before, const std::tuple<std::size_t, std::size_t, std::size_t>& included_before) {
        if (!before.has_scene || !doc_.has_scene() || included_counts() == included_before) return;
        if (doc_.undo_names(2).size() != 1) broken("included items came or went in a reload, and the history stayed");
        seen_ = {before};
    }

    // Another program writes the included file: the viewer reads it again (the text
    // and its unsaved edits stay), or keeps the scene when it no longer reads.
    // (A library that does not read is left to the unit tests: the scene then keeps the
    // included items as they were, which no parse of the text gives.)
    void include_change() {
        if (doc_.edit_held() || !doc_.has_scene() || doc_.scene().includes.empty()) return;
        SceneWriter w(c_);
        std::string lib = w.library();
        // (A size no earlier version had: the change shows in the file's stamp.)
        lib += "// version " + std::to_string(++lib_versions_) + "\n";
        if (rt::Status st = rt::write_file_atomic(lib_path(), lib); !st) fail("cannot write the included file", st.message());
        log("outside change of lib.txt");
        settle_disk();
    }
    // The viewer's polling until nothing more is new on disk: included files read again
    // (the text stays; when items came or went the history was dropped, its steps
    // naming items by their place).
    void settle_disk() {
        for (int k = 0; k < 4; ++k) {
            const std::string text = std::as_const(doc_).editor_text();
            auto counts = [this] {
                const rt::Scene& s = doc_.scene();
                return std::make_tuple(s.objects.size(), s.planes.size(), s.lights.size());
            };
            const auto before = counts();
            const Doc::DiskEvent ev = doc_.check_disk();
            if (ev == Doc::DiskEvent::None) return;
            log("disk: event " + std::to_string(int(ev)));
            if (ev != Doc::DiskEvent::IncludesReloaded) broken("an event other than an include's reload while settling");
            if (std::as_const(doc_).editor_text() != text) broken("an include's reload changed the text");
            if (counts() != before) {
                if (doc_.can_undo() || doc_.can_redo()) broken("items came or went, and the history stayed");
                history_start();
            }
        }
        broken("check_disk() kept finding changes");
    }

    // File > Open: the file (as saved, or a new scene) replaces the document.
    void reopen() {
        doc_.commit();
        if (c_.one_in(2)) {
            std::string disk;
            if (!rt::read_file(path_, disk, std::size_t(64) << 20)) broken("cannot read the scene file");
            open(disk, "reopen");
        } else {
            open(new_scene(), "open another");
        }
    }

    // A crash-recovery copy restored as a draft.
    void restore_draft() {
        std::string text = std::as_const(doc_).editor_text();
        if (!text.empty()) text.insert(c_.below(unsigned(text.size())), c_.one_in(2) ? "// recovered\n" : "{");
        log("restore a recovered text");
        own_texts_.insert(text);
        doc_.restore_draft(text);
        if (std::as_const(doc_).editor_text() != text) broken("the restored text is not the recovered one");
    }

    // ---- the checks ---------------------------------------------------------------
    // The viewer's frame: the world follows the document without waiting for a build
    // (World::update where it can). Now and then a frame goes unchecked, so that a
    // build may still be under way when the next change comes.
    void follow_world() { world_.follow(doc_); }
    void frame() {
        follow_world();
        if (!c_.one_in(3)) check_pending();
    }

    bool seen_before(const State& s) {
        // Going back in history, each state is one seen before, earlier than the last.
        for (std::size_t k = seen_.size(); k-- > 0;)
            if (seen_[k] == s) {
                seen_.resize(k + 1);
                return true;
            }
        return false;
    }

    // While an edit is held: the text is as it was, the world is the scene's.
    void check_pending() {
        if (!doc_.has_scene()) return;
        follow_world_check(doc_.scene(), "the edited scene");
    }
    void follow_world_check(const rt::Scene& want_scene, const char* what) {
        const rt::World* got = world_.settled(doc_);
        const std::shared_ptr<const rt::World> want = rt::compile_world(want_scene);
        if (!got) broken(std::string("no world for ") + what);
        if (std::string d = world_difference(*got, *want, want_scene.camera); !d.empty())
            broken(std::string("the viewer's world differs from a full compile of ") + what + ": " + d);
    }

    // The Text tab's widget, brought up to the document's text version as the tab does.
    void follow_text() {
        const Doc& d = doc_;
        if (d.text_version() == widget_version_) return;
        std::vector<rtview::TextReplacement> changes;
        if (widget_version_ != 0 && d.text_changes_since(widget_version_, changes)) {
            for (const rtview::TextReplacement& ch : changes) widget_.follow_replacement(ch.offset, ch.length, ch.text);
        } else {
            widget_.set_text(d.editor_text());
        }
        widget_version_ = d.text_version();
    }
    // Typing reaches the document from the widget: the same change, made in the widget.
    void typed_in_widget(const std::string& typed) {
        const std::string before = widget_.text();
        std::size_t head = 0, tail = 0;
        while (head < before.size() && head < typed.size() && before[head] == typed[head]) ++head;
        while (tail < before.size() - head && tail < typed.size() - head &&
               before[before.size() - 1 - tail] == typed[typed.size() - 1 - tail])
            ++tail;
        widget_.replace_bytes(head, before.size() - head - tail, typed.substr(head, typed.size() - head - tail));
    }
    void check_text_widget() {
        follow_text();
        if (widget_.text() != doc_.editor_text()) broken("the text widget following the document holds another text");
    }

    void check() {
        follow_world();
        check_text_widget();
        if (doc_.edit_held()) {
            check_pending();
            return;
        }
        const Doc& d = doc_;
        const std::string& editor = d.editor_text();
        if (d.has_scene()) {
            const rt::ParseResult r = parse(d.applied_text());
            if (!r.ok()) broken("the scene's text does not parse");
            if (!(r.scene == d.scene())) broken("the scene is not the parse of its text");
            rtfuzz::check_scene(d.scene());
            follow_world_check(r.scene, "the scene's text");
        }
        if (d.editor_dirty() || !d.has_scene()) {
            if (!parse(editor).ok() && !own_texts_.count(editor))
                broken("the editor text does not parse, and is not a text the user typed or opened");
        }
        if (d.modified() != (editor != saved_)) broken("modified() disagrees with the file as last saved");
        (void)d.undo_names(3);
        (void)d.redo_names(3);
        if (seen_.empty() || !(seen_.back() == state())) seen_.push_back(state());
    }

    // Undo to the start: the original bytes, through states seen before; redo to the end:
    // the same states again in turn, ending where it began.
    void round_trip_history() {
        doc_.commit();
        (void)doc_.take_refusal();
        check();
        const State end = state();
        // What the history menu lists is what undo and redo then do, name for name.
        const std::vector<std::string> undo_names = doc_.undo_names(100000);
        const std::vector<std::string> redo_names = doc_.redo_names(100000);
        std::vector<State> back{end};
        std::vector<State> seen = seen_;
        while (doc_.undo()) {
            check_text_widget();
            back.push_back(state());
            if (!seen_before(back.back())) broken("an undo went to a state the user never saw");
            if (back.size() - 2 >= undo_names.size() || doc_.last_step_name() != undo_names[back.size() - 2])
                broken("undo took back another step than undo_names() listed");
        }
        if (back.size() - 1 != undo_names.size()) broken("undo_names() listed more steps than undo took back");
        if (!(back.back() == seen_.front())) broken("undo to the start did not give the original text and scene");
        seen_ = std::move(seen);
        for (std::size_t k = back.size() - 1; k-- > 0;) {
            if (!doc_.redo()) broken("redo stopped before the end");
            check_text_widget();
            if (!(state() == back[k])) broken("redo did not retrace the undo's states");
        }
        if (!(state() == end)) broken("redo to the end did not give the same text and scene");
        // The redo branch an earlier undo left (typing since then has dropped it).
        if (doc_.redo_names(100000) != redo_names) broken("undo and redo changed the redo branch");
        check();
    }

    static std::string printable(const std::string& s) {
        std::string out;
        for (char ch : s.substr(0, 60)) {
            if (ch >= 32 && ch < 127) out += ch;
            else {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(static_cast<unsigned char>(ch)));
                out += buf;
            }
        }
        return s.size() > 60 ? out + "..." : out;
    }

    Choices c_;
    EditRunOptions opt_;
    std::string path_;
    int lib_versions_ = 0;
    Doc doc_;
    ViewerWorld world_;
    rtview::TextBuffer widget_;
    std::uint64_t widget_version_ = 0;
    std::string saved_;                 // the file as the document last loaded or saved it
    std::set<std::string> own_texts_;   // texts the user typed, restored or opened that do not parse
    std::vector<State> seen_;           // states since the history began, oldest first
    std::vector<std::string> log_;
};

// Plays the run the bytes describe; throws Broken if a promise broke.
inline void run_edits(const std::uint8_t* data, std::size_t size, const EditRunOptions& opt) {
    EditRun(data, size, opt).run();
}

}  // namespace rtfuzz
