// The document's structural edits made in place (see Document::replace_text): the block
// an edit brings is parsed on its own, the scene's list and the text's layout take it
// (or lose an item) where the edit says, and every source position after the edit
// moves as the text did. Undo and redo do the same backwards and forwards, so an Add,
// Duplicate or Delete costs its block and a pass over the lists, not a parse of the
// whole text, whatever the scene's size.
#include "document.h"

#include <algorithm>
#include <string_view>
#include <utility>

#include "parallel.h"
#include "scene_writer.h"
#include "splice_locs.h"

namespace rtview {

namespace {

// The line and column of byte `target` of `text`, from those of byte `anchor` (only
// the text between them, and the start of target's line, is read).
rt::SourceLoc loc_at(std::string_view text, std::size_t anchor, rt::SourceLoc anchor_loc, std::size_t target) {
    if (target >= anchor) return loc_after(anchor_loc, text.substr(anchor, target - anchor));
    std::size_t start = target;
    while (start > 0 && text[start - 1] != '\n' && text[start - 1] != '\r') --start;
    const rt::SourceLoc from_start = loc_after({1, 1}, text.substr(start, anchor - start));
    return {anchor_loc.line - (from_start.line - 1), int(target - start) + 1};
}

// A source position of the block parsed on its own (after `prefix` bytes on its first
// line) as one of the text, the block's text starting at `at`.
struct LocMap {
    rt::SourceLoc at;
    std::size_t prefix = 0;
    void operator()(rt::SourceLoc& l) const {
        if (l.line <= 0) return;
        if (l.line == 1) l = {at.line, at.col + l.col - 1 - int(prefix)};
        else l.line = at.line + l.line - 1;
    }
    void operator()(rt::Object& o) const {
        (*this)(o.loc);
        if (rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
            for (rt::Object& k : g->operands) (*this)(k);
    }
};

std::size_t count_of(const rt::Scene& s, ItemList list) {
    return list == ItemList::Object ? s.objects.size() : list == ItemList::Plane ? s.planes.size() : s.lights.size();
}

rt::SourceLoc loc_of(const rt::Scene& s, ItemList list, std::size_t i) {
    return list == ItemList::Object ? s.objects[i].loc : list == ItemList::Plane ? s.planes[i].loc : s.lights[i].loc;
}

const char* section_of(ItemList list) {
    return list == ItemList::Object ? "thing" : list == ItemList::Plane ? "special_thing" : "light";
}

// Whether [from, to) of `text` is nothing but blanks and line ends.
bool blank_only(std::string_view text, std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i)
        if (text[i] != ' ' && text[i] != '\t' && text[i] != '\r' && text[i] != '\n') return false;
    return true;
}

// Whether [from, to) of `text` is what may follow a removed block on its line: blanks,
// then perhaps a // comment to the line's end, then perhaps that line end.
bool tail_only(std::string_view text, std::size_t from, std::size_t to) {
    std::size_t i = from;
    while (i < to && (text[i] == ' ' || text[i] == '\t')) ++i;
    if (i + 1 < to && text[i] == '/' && text[i + 1] == '/')
        while (i < to && text[i] != '\n' && text[i] != '\r') ++i;
    if (i < to && text[i] == '\r') ++i;
    if (i < to && text[i] == '\n') ++i;
    return i == to;
}

// Whether a span of any list but `list` (or of `list` but its `index`) starts within
// [from, to): the replacement would take more than the one block.
bool other_block_within(const SceneLayout& l, ItemList list, std::size_t index, std::size_t from, std::size_t to) {
    for (ItemList k : {ItemList::Object, ItemList::Plane, ItemList::Light}) {
        const std::vector<TextSpan>& v = spans_of(l, k);
        auto it = std::lower_bound(v.begin(), v.end(), from, [](const TextSpan& s, std::size_t x) { return s.begin < x; });
        for (; it != v.end() && it->begin < to; ++it)
            if (k != list || std::size_t(it - v.begin()) != index) return true;
        // (A span reaching into the range from before it.)
        if (it != v.begin() && std::prev(it)->end > from && (k != list || std::size_t(std::prev(it) - v.begin()) != index))
            return true;
    }
    return false;
}

// Positions of the layout after [pos, pos + old_len) became new_len bytes: those after
// it move; at pos itself, an insertion goes after a block's end and before a block's
// start (and before `end`).
void move_positions(SceneLayout& l, std::size_t pos, std::size_t old_len, std::size_t new_len) {
    if (old_len == new_len) return;
    auto fix = [&](std::size_t& x, bool start) {
        if (x > pos + old_len || (x == pos + old_len && (old_len > 0 || start))) x = x - old_len + new_len;
    };
    for (auto* v : {&l.objects, &l.planes, &l.lights, &l.cameras}) {
        // (Spans are in order and apart: those ending before pos stay.)
        auto it = std::partition_point(v->begin(), v->end(), [&](const TextSpan& t) { return t.end < pos; });
        for (; it != v->end(); ++it) {
            fix(it->begin, true);
            fix(it->end, false);
        }
    }
    fix(l.append_at, true);
}

// Whether replacing [pos, pos + length) of `doc` by `text` is what `sp` says; if so
// `anchor` and `anchor_loc` are a place whose line and column are known (an item's
// start) at or before the replacement.
bool splice_anchor(const SceneLayout& l, const rt::Scene& scene, std::string_view doc, std::size_t pos,
                   std::size_t length, const std::string& text, const ItemSplice& sp, std::size_t& anchor,
                   rt::SourceLoc& anchor_loc) {
    const std::vector<TextSpan>& spans = spans_of(l, sp.list);
    const std::size_t n = spans.size();
    switch (sp.op) {
        case ItemSplice::Op::Insert:
            if (length != 0 || sp.index > n) return false;
            if (sp.section) {
                if (n != 0 || pos != l.append_at) return false;
                // From the last block before it, whichever list it is in.
                for (ItemList k : {ItemList::Object, ItemList::Plane, ItemList::Light}) {
                    const std::vector<TextSpan>& v = spans_of(l, k);
                    if (!v.empty() && v.back().begin >= anchor && v.back().begin <= pos) {
                        anchor = v.back().begin;
                        anchor_loc = loc_of(scene, k, v.size() - 1);
                    }
                }
            } else {
                if (sp.index == 0 || pos != spans[sp.index - 1].end) return false;
                anchor = spans[sp.index - 1].begin;
                anchor_loc = loc_of(scene, sp.list, sp.index - 1);
            }
            break;
        case ItemSplice::Op::Remove: {
            if (sp.index >= n || !text.empty()) return false;
            const TextSpan b = spans[sp.index];
            if (pos > b.begin || pos + length < b.end || !blank_only(doc, pos, b.begin) ||
                !tail_only(doc, b.end, pos + length) || other_block_within(l, sp.list, sp.index, pos, pos + length))
                return false;
            anchor = b.begin;
            anchor_loc = loc_of(scene, sp.list, sp.index);
            break;
        }
        case ItemSplice::Op::Replace:
            if (sp.index >= n || pos != spans[sp.index].begin || length != spans[sp.index].end - pos) return false;
            anchor = pos;
            anchor_loc = loc_of(scene, sp.list, sp.index);
            break;
    }
    return true;
}

// The new block read on its own: inside a section of its list (unless it is one),
// with the scene's camera and size so that it is a whole scene. It must read as
// exactly one item of that list with no word from the parser (a name defined
// elsewhere in the text, say, does not: the whole text is parsed then). Its items,
// placed in the text at `pos` (from `s.at`), go to `s.after` and its span to
// `s.block_after`.
bool read_block(const std::string& text, std::size_t pos, const ItemSplice& sp, const rt::Scene& scene,
                const rt::ParseOptions& options, SplicedItem& s) {
    const std::string prefix = sp.section ? std::string() : std::string(section_of(sp.list)) + " { ";
    rt::Scene frame;
    frame.camera = scene.camera;
    frame.width = scene.width;
    frame.height = scene.height;
    const std::string block_text = prefix + text + (sp.section ? "\n" : "\n}\n") + rt::write_scene(frame);
    rt::ParseResult r = rt::parse_scene(block_text, options);
    if (!r.ok() || !r.diagnostics.empty() || !r.scene.materials.empty() || !r.scene.defined.empty() ||
        !r.scene.includes.empty() || count_of(r.scene, sp.list) != 1 ||
        r.scene.objects.size() + r.scene.planes.size() + r.scene.lights.size() != 1)
        return false;
    const SceneLayout bl = scan_layout(block_text);
    const std::vector<TextSpan>& bs = spans_of(bl, sp.list);
    if (!bl.ok || bs.size() != 1 || bs[0].begin < prefix.size() || bs[0].end > prefix.size() + text.size())
        return false;
    s.block_after = {pos + bs[0].begin - prefix.size(), pos + bs[0].end - prefix.size()};
    const LocMap map{s.at, prefix.size()};
    for (rt::Object& o : r.scene.objects) map(o);
    for (rt::Plane& p : r.scene.planes) map(p.loc);
    for (rt::Light& li : r.scene.lights) map(li.loc);
    s.after.objects = std::move(r.scene.objects);
    s.after.planes = std::move(r.scene.planes);
    s.after.lights = std::move(r.scene.lights);
    return true;
}

// Object `i` of `v` removed (`inserted` null) or `*inserted` put before it, each object
// after the place moved one along and its source positions shifted on the way.
void move_objects(std::vector<rt::Object>& v, std::size_t i, const rt::Object* inserted, const LocShift& shift) {
    // In two halves at once where a worker is free: each half's one element that
    // the other half overwrites is set aside first.
    const bool two = v.size() - i > (std::size_t(1) << 16);
    if (!inserted) {
        // v[k] = v[k + 1] for k in [i, n - 1); split at m.
        const std::size_t n = v.size(), m = i + (n - 1 - i) / 2;
        rt::Object saved = std::move(v[m]);
        rt::two_ways(two, [&](int part) {
            const std::size_t from = part == 0 ? i : m, to = part == 0 ? m : n - 1;
            for (std::size_t k = from; k < to; ++k) {
                v[k] = std::move(k + 1 == m ? saved : v[k + 1]);
                shift(v[k]);
            }
        });
        v.pop_back();
    } else {
        // v[k] = v[k - 1] for k in (i, n]; split at m.
        v.emplace_back();
        const std::size_t n = v.size() - 1, m = i + (n - i) / 2;
        rt::Object saved = std::move(v[m]);
        rt::two_ways(two, [&](int part) {
            const std::size_t top = part == 0 ? m : n, bottom = part == 0 ? i : m;
            for (std::size_t k = top; k > bottom; --k) {
                v[k] = std::move(k - 1 == m && part == 1 ? saved : v[k - 1]);
                shift(v[k]);
            }
        });
        v[i] = *inserted;
    }
}

// Every source position of `scene` after the replacement moved as `shift` says (the
// objects' unless `objects_shifted`).
void shift_positions(rt::Scene& scene, const LocShift& shift, bool objects_shifted) {
    if (shift.none()) return;
    // Each list is in the order of the text (a scene without includes): only the
    // items from the first one after the replacement on move.
    auto from = [&](auto& v) {
        return std::partition_point(v.begin(), v.end(), [&](const auto& x) { return before(x.loc, shift.old_end); });
    };
    if (!objects_shifted) {
        // In two halves at once where a worker is free (a million objects after an edit
        // near the top).
        const std::size_t first = std::size_t(from(scene.objects) - scene.objects.begin()), n = scene.objects.size();
        const std::size_t mid = first + (n - first) / 2;
        rt::two_ways(n - first > (std::size_t(1) << 16), [&](int part) {
            for (std::size_t k = part == 0 ? first : mid, end = part == 0 ? mid : n; k < end; ++k) shift(scene.objects[k]);
        });
    }
    for (auto it = from(scene.planes); it != scene.planes.end(); ++it) shift(it->loc);
    for (auto it = from(scene.lights); it != scene.lights.end(); ++it) shift(it->loc);
    for (rt::NamedMaterial& m : scene.materials) shift(m.loc);
    for (rt::NamedObject& d : scene.defined) shift(d.loc);
    shift(scene.camera_loc);
}

// The line and column of byte `pos` of `text`, counted from its start (the line ends a
// word at a time where the text has no CR).
rt::SourceLoc loc_of_offset(std::string_view text, std::size_t pos) {
    const std::string_view head = text.substr(0, pos);
    if (head.find('\r') != std::string_view::npos) return loc_after({1, 1}, head);
    const std::size_t lines = std::size_t(std::count(head.begin(), head.end(), '\n'));
    const std::size_t ls = head.rfind('\n');
    return {int(lines) + 1, int(pos - (ls == std::string_view::npos ? 0 : ls + 1)) + 1};
}

}  // namespace

rt::SourceLoc Document::follow_positions(std::size_t pos, std::string_view removed, std::string_view inserted,
                                        const rt::SourceLoc* known) {
    const rt::SourceLoc at = known && known->line > 0 ? *known : loc_of_offset(editor_, pos);
    const LocShift shift{loc_after(at, removed), loc_after(at, inserted)};
    if (shift.none()) return at;
    if (scene_.includes.empty() && shift.old_end.line == shift.new_end.line) {
        // The same lines: only what follows on the replacement's last line moves (the
        // lists are in the text's order).
        const int line = shift.old_end.line;
        auto rest_of_line = [&](auto& v, const auto& f) {
            auto it = std::partition_point(v.begin(), v.end(), [&](const auto& x) { return before(x.loc, shift.old_end); });
            for (; it != v.end() && it->loc.line == line; ++it) f(*it);
        };
        rest_of_line(scene_.objects, [&](rt::Object& o) { shift(o); });
        rest_of_line(scene_.planes, [&](rt::Plane& p) { shift(p.loc); });
        rest_of_line(scene_.lights, [&](rt::Light& l) { shift(l.loc); });
        for (rt::NamedMaterial& m : scene_.materials) shift(m.loc);
        for (rt::NamedObject& d : scene_.defined) shift(d.loc);
        shift(scene_.camera_loc);
    } else if (scene_.includes.empty()) {
        shift_positions(scene_, shift, false);
    } else {
        // Items an include brought are placed in their own files: theirs stay.
        for (rt::Object& o : scene_.objects)
            if (o.origin == 0) shift(o);
        for (rt::Plane& p : scene_.planes)
            if (p.origin == 0) shift(p.loc);
        for (rt::Light& l : scene_.lights)
            if (l.origin == 0) shift(l.loc);
        for (rt::NamedMaterial& m : scene_.materials)
            if (m.origin == 0) shift(m.loc);
        for (rt::NamedObject& d : scene_.defined)
            if (d.origin == 0) shift(d.loc);
        for (rt::Include& inc : scene_.includes) shift(inc.loc);
    }
    auto move = [&shift](int& line, int& col) {
        rt::SourceLoc l{line, col};
        shift(l);
        line = l.line, col = l.col;
    };
    for (rt::Diagnostic& d : diagnostics_) {
        if (d.file.empty()) move(d.line, d.col);
        for (rt::Diagnostic::Site& site : d.included_from)
            if (site.file.empty()) move(site.line, site.col);
    }
    return at;
}

bool Document::follow_layout(const std::vector<TextReplacement>& reps) {
    if (!layout_) return false;
    for (const TextReplacement& r : reps) {
        // Only a replacement of one whole block (a panel edit's) keeps the layout's shape.
        TextSpan* hit = nullptr;
        for (auto* v : {&layout_->objects, &layout_->planes, &layout_->lights, &layout_->cameras}) {
            auto it = std::lower_bound(v->begin(), v->end(), r.offset,
                                       [](const TextSpan& t, std::size_t x) { return t.begin < x; });
            if (it != v->end() && it->begin == r.offset && it->end == r.offset + r.length) hit = &*it;
        }
        if (!hit || r.length == 0) {
            layout_.reset();
            return false;
        }
        move_positions(*layout_, r.offset, r.length, r.text.size());
        hit->end = r.offset + r.text.size();
    }
    layout_key_ = layout_key(1);
    return true;
}

const SceneLayout* Document::layout() {
    const std::uint64_t key = layout_key();
    if (!layout_ || layout_key_ != key) {
        layout_ = scan_layout(editor_, has_scene_ ? scene_.objects.size() : 0);
        layout_key_ = key;
    }
    return layout_->ok ? &*layout_ : nullptr;
}

bool Document::plan_splice(std::size_t pos, std::size_t length, const std::string& text, const ItemSplice& sp,
                           const SceneLayout& l, SplicedItem& s) const {
    if (sp.list == ItemList::Camera || pos > editor_.size() || length > editor_.size() - pos) return false;
    const std::vector<TextSpan>& spans = spans_of(l, sp.list);
    if (spans.size() != count_of(scene_, sp.list)) return false;
    // The replacement must be what the splice says, and a place whose line and column
    // are known (an item's) must be near it.
    std::size_t anchor = 0;
    rt::SourceLoc anchor_loc{1, 1};
    if (!splice_anchor(l, scene_, editor_, pos, length, text, sp, anchor, anchor_loc)) return false;
    if (anchor_loc.line <= 0) return false;
    s.op = sp.op;
    s.list = sp.list;
    s.index = sp.index;
    s.at = loc_at(editor_, anchor, anchor_loc, pos);
    // A definition after the place would need its position moved in every instance
    // that shares it: those texts are parsed whole.
    for (const rt::NamedObject& d : scene_.defined)
        if (!before(d.loc, s.at)) return false;
    const rt::SourceLoc removed_end = loc_after(s.at, std::string_view(editor_).substr(pos, length));
    for (const rt::NamedMaterial& m : scene_.materials)
        if (!before(m.loc, s.at) && before(m.loc, removed_end)) return false;
    if (sp.op != ItemSplice::Op::Insert) {
        s.block_before = spans[sp.index];
        if (sp.list == ItemList::Object) s.before.objects.push_back(scene_.objects[sp.index]);
        else if (sp.list == ItemList::Plane) s.before.planes.push_back(scene_.planes[sp.index]);
        else s.before.lights.push_back(scene_.lights[sp.index]);
    }
    return sp.op == ItemSplice::Op::Remove || read_block(text, pos, sp, scene_, parse_options(path_), s);
}

bool Document::splice_text(std::size_t pos, std::size_t length, const std::string& text, const std::string& name,
                           const ItemSplice& sp) {
    // Positions of warnings, and items an include brings, would need more than this.
    if (!has_scene_ || applied_ || !scene_.includes.empty() || !diagnostics_.empty()) return false;
    const SceneLayout* l = layout();
    if (!l || !layout_matches(*l, scene_)) return false;
    SplicedItem s;
    if (!plan_splice(pos, length, text, sp, *l, s)) return false;
    DocStep step;
    step.name = name;
    step.has_scene_before = step.has_scene_after = true;
    step.made({pos, length, text}, editor_);
    if (step.editor.size() != 1) return false;
    const std::string removed = editor_.substr(pos, length);
    editor_.replace(pos, length, text);
    apply_splice(s, true, pos, removed, text, true);
    step.spliced = std::move(s);
    ++scene_version_;
    changed(splice_delta(*step.spliced));
    text_changed(step, true);
    record(std::move(step));
    return true;
}

void Document::apply_splice(const SplicedItem& s, bool forward, std::size_t pos, std::string_view removed,
                            std::string_view inserted, bool layout_valid) {
    using Op = ItemSplice::Op;
    ++spliced_count_;
    // Forward an insertion inserts, back it removes; a removal the other way round.
    const bool insert = (s.op == Op::Insert) == forward && s.op != Op::Replace;
    const bool remove = (s.op == Op::Remove) == forward && s.op != Op::Replace;
    const rt::Scene& value = forward ? s.after : s.before;
    const TextSpan block = forward ? s.block_after : s.block_before;
    const std::size_t i = s.index;
    const LocShift shift{loc_after(s.at, removed), loc_after(s.at, inserted)};
    // The objects after the place move in the list and in the text in one pass over
    // them (a million objects' list is hundreds of MB: each pass costs).
    bool objects_shifted = false;
    if (s.list == ItemList::Object && (insert || remove)) {
        move_objects(scene_.objects, i, remove ? nullptr : &value.objects.at(0), shift);
        objects_shifted = true;
    } else if (remove) {
        if (s.list == ItemList::Plane) scene_.planes.erase(scene_.planes.begin() + std::ptrdiff_t(i));
        else scene_.lights.erase(scene_.lights.begin() + std::ptrdiff_t(i));
    }
    shift_positions(scene_, shift, objects_shifted);
    if (insert) {
        if (s.list == ItemList::Object) {
            // (Inserted above.)
        } else if (s.list == ItemList::Plane) scene_.planes.insert(scene_.planes.begin() + std::ptrdiff_t(i), value.planes.at(0));
        else scene_.lights.insert(scene_.lights.begin() + std::ptrdiff_t(i), value.lights.at(0));
    } else if (!remove) {
        if (s.list == ItemList::Object) restore_object(i, value.objects.at(0));
        else if (s.list == ItemList::Plane) restore_plane(i, value.planes.at(0));
        else scene_.lights[i] = value.lights.at(0);
    }
    if (!layout_valid || !layout_) {
        layout_.reset();
        return;
    }
    std::vector<TextSpan>& spans = spans_of(*layout_, s.list);
    if (remove) spans.erase(spans.begin() + std::ptrdiff_t(i));
    move_positions(*layout_, pos, removed.size(), inserted.size());
    if (insert) spans.insert(spans.begin() + std::ptrdiff_t(i), block);
    else if (!remove) spans[i] = block;
    // The text changes its version next (text_changed): the layout is that version's.
    layout_key_ = layout_key(1);
}

}  // namespace rtview
