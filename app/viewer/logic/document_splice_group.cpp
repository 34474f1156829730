// A group of structural edits (a group Delete or Duplicate: Document::splice_texts) as
// one pass: the text rebuilt once (each unchanged run of it moved once), each list of
// the scene and of the layout compacted or spread once, every source position and span
// moved once by what the edits before it in the text did together. Undo and redo of
// the group's step do the same. The result is what the edits' single splices
// (document_splice.cpp), made one after the other, give; a group whose edits are not
// in the order that needs (apart, the last in the text first, all insertions or all
// removals) is made that way instead.
#include "document.h"

#include <algorithm>
#include <cstring>
#include <string_view>
#include <utility>

#include "splice_locs.h"

namespace rtview {

namespace {

// One edit of a group as the pass makes it, in the coordinates of the text, scene and
// layout before the pass.
struct Part {
    std::size_t pos = 0, old_len = 0;  // the bytes replaced
    std::string_view inserted;
    rt::SourceLoc old_end, new_end;  // the positions from old_end on move to new_end on
    ItemList list = ItemList::Object;
    bool insert = false;     // else the item at `index` is removed
    std::size_t index = 0;   // the item removed, or the one the new item goes before
    const rt::Scene* value = nullptr;  // the new item (its list's only one)
    TextSpan block;                    // and its span
};

// The edits in the text's order, and what the first r of them do together.
struct Group {
    std::vector<Part> parts;
    // The new items' positions and spans are as their own edit alone would put them
    // (made forward): the edits before them in the text move them on.
    bool local = false;
    std::vector<int> lines;             // lines[r]: the lines the first r edits add
    std::vector<std::ptrdiff_t> bytes;  // bytes[r]: and the bytes

    void finish() {
        lines.assign(1, 0);
        bytes.assign(1, 0);
        for (const Part& p : parts) {
            lines.push_back(lines.back() + p.new_end.line - p.old_end.line);
            bytes.push_back(bytes.back() + std::ptrdiff_t(p.inserted.size()) - std::ptrdiff_t(p.old_len));
        }
    }
    // Position `l`, after the first `r` edits and before the others, where they put it
    // (the edits' shifts composed: beyond the line of the r-th edit's end only lines move).
    void map(rt::SourceLoc& l, std::size_t r) const {
        if (l.line <= 0 || r == 0) return;
        if (l.line > parts[r - 1].old_end.line) {
            l.line += lines[r];
            return;
        }
        for (std::size_t k = r; k-- > 0;) LocShift{parts[k].old_end, parts[k].new_end}(l);
    }
    void map(rt::Object& o, std::size_t r) const {
        map(o.loc, r);
        if (rt::Csg* g = std::get_if<rt::Csg>(&o.shape))
            for (rt::Object& k : g->operands) map(k, r);
    }
    // How many edits end at or before `l`, from a guess `r` (positions come in order).
    std::size_t region(const rt::SourceLoc& l, std::size_t r) const {
        while (r > 0 && before(l, parts[r - 1].old_end)) --r;
        while (r < parts.size() && !before(l, parts[r].old_end)) ++r;
        return r;
    }
    // Byte `x` of the layout (a span's start or end) where the edits put it, each as
    // move_positions() moves it; `r` as for region().
    std::size_t move(std::size_t x, bool start, std::size_t& r) const {
        auto moves = [&](const Part& p) {
            const std::size_t end = p.pos + p.old_len;
            return x > end || (x == end && (p.old_len > 0 || start));
        };
        while (r > 0 && !moves(parts[r - 1])) --r;
        while (r < parts.size() && moves(parts[r])) ++r;
        return std::size_t(std::ptrdiff_t(x) + bytes[r]);
    }
};

// Part `t` (in the text's order) of a step's edits made forward, in the coordinates
// before them; false if it does not follow part t - 1 as the pass needs.
bool forward_part(const DocStep& s, std::size_t t, std::vector<Part>& parts, std::ptrdiff_t* last) {
    const std::size_t k = s.spliced_many.size() - 1 - t;  // (the step holds them last in the text first)
    const SplicedItem& it = s.spliced_many[k];
    const TextReplacement& r = s.editor[k];
    if (it.op == ItemSplice::Op::Replace || it.op != s.spliced_many[0].op || it.list == ItemList::Camera) return false;
    Part& p = parts[t];
    p.pos = r.offset;
    p.old_len = r.length;
    p.inserted = r.text;
    p.old_end = loc_after(it.at, s.editor_back[k].text);
    p.new_end = loc_after(it.at, r.text);
    p.list = it.list;
    p.insert = it.op == ItemSplice::Op::Insert;
    p.index = it.index;
    p.value = &it.after;
    p.block = it.block_after;
    // All insertions or all removals (the text only grows or only shrinks), apart, and
    // in the order of the text and of their lists.
    if ((p.insert ? p.old_len != 0 : !p.inserted.empty()) || s.editor_back[k].text.size() != r.length) return false;
    std::ptrdiff_t& prev = last[int(p.list)];
    if (std::ptrdiff_t(p.index) <= prev) return false;
    prev = std::ptrdiff_t(p.index);
    if (t == 0) return true;
    const Part& q = parts[t - 1];
    const std::size_t q_end = q.pos + q.old_len;
    if (before(it.at, q.old_end)) return false;
    return q_end < p.pos || (q_end == p.pos && q.old_len > 0 && p.old_len > 0);
}

// A step's edits as the pass makes them forward (as made) or back; false when they
// are not in the order the pass needs.
bool group_of(const DocStep& s, bool forward, Group& g) {
    const std::size_t n = s.spliced_many.size();
    if (n == 0 || s.editor.size() != n || s.editor_back.size() != n) return false;
    Group f;
    f.parts.resize(n);
    std::ptrdiff_t last[3] = {-1, -1, -1};
    for (std::size_t t = 0; t < n; ++t)
        if (!forward_part(s, t, f.parts, last)) return false;
    f.finish();
    if (forward) {
        g = std::move(f);
        g.local = true;
        return true;
    }
    // Back: each edit where the ones before it in the text (made) put it, undone.
    g.parts.resize(n);
    std::ptrdiff_t count[3] = {0, 0, 0};  // items the edits so far added to each list
    for (std::size_t t = 0; t < n; ++t) {
        const std::size_t k = n - 1 - t;
        const SplicedItem& it = s.spliced_many[k];
        const Part& a = f.parts[t];
        Part& p = g.parts[t];
        rt::SourceLoc at = it.at;
        f.map(at, t);
        p.pos = std::size_t(std::ptrdiff_t(a.pos) + f.bytes[t]);
        p.old_len = s.editor[k].text.size();
        p.inserted = s.editor_back[k].text;
        p.old_end = loc_after(at, s.editor[k].text);
        p.new_end = loc_after(at, s.editor_back[k].text);
        p.list = a.list;
        p.insert = !a.insert;
        std::ptrdiff_t& c = count[int(a.list)];
        p.index = std::size_t(std::ptrdiff_t(a.index) + c);
        c += a.insert ? 1 : -1;
        p.value = &it.before;
        p.block = it.block_before;
    }
    g.finish();
    return true;
}

// The text after the group's edits: from the first edit on, each unchanged run moved
// once (front to back when it shrinks, back to front when it grows).
void rebuild_text(std::string& text, const Group& g) {
    const std::vector<Part>& ps = g.parts;
    const std::size_t n = ps.size(), old_size = text.size();
    auto run_end = [&](std::size_t t) { return t + 1 < n ? ps[t + 1].pos : old_size; };
    if (g.bytes.back() <= 0) {
        std::size_t w = ps[0].pos;
        for (std::size_t t = 0; t < n; ++t) {
            std::memcpy(&text[w], ps[t].inserted.data(), ps[t].inserted.size());
            w += ps[t].inserted.size();
            const std::size_t from = ps[t].pos + ps[t].old_len, len = run_end(t) - from;
            std::memmove(&text[w], text.data() + from, len);
            w += len;
        }
        text.resize(w);
        return;
    }
    text.resize(std::size_t(std::ptrdiff_t(old_size) + g.bytes.back()));
    std::size_t w = text.size();
    for (std::size_t t = n; t-- > 0;) {
        const std::size_t from = ps[t].pos + ps[t].old_len, len = run_end(t) - from;
        w -= len;
        std::memmove(&text[w], text.data() + from, len);
        w -= ps[t].inserted.size();
        std::memcpy(&text[w], ps[t].inserted.data(), ps[t].inserted.size());
    }
}

// `v` without the items at the sorted indices `at`, each item kept from `lo` on moved
// once, front to back, and passed to fix(item, cursor). (On one thread: split in two
// halves on the process pool, as a single splice's move is, it took twice as long at a
// load of 5 on two cores, the worker's half waiting for a core.)
template <class T, class Fix>
void compact(std::vector<T>& v, const std::vector<std::size_t>& at, std::size_t lo, const Fix& fix) {
    std::size_t j = 0, cursor = 0;
    for (std::size_t src = lo; src < v.size(); ++src) {
        if (j < at.size() && at[j] == src) {
            ++j;
            continue;
        }
        if (j != 0) v[src - j] = std::move(v[src]);
        fix(v[src - j], cursor);
    }
    v.erase(v.end() - std::ptrdiff_t(at.size()), v.end());
}

// `v` with a new item before each item at the sorted indices `at` (the j-th new one,
// make(j), lands at at[j] + j), each old item from `lo` on moved once, back to front,
// and passed to fix(item, cursor).
template <class T, class Fix, class Make>
void spread(std::vector<T>& v, const std::vector<std::size_t>& at, std::size_t lo, const Fix& fix, const Make& make) {
    const std::size_t n = v.size();
    v.resize(n + at.size());
    std::size_t j = at.size(), cursor = 0;
    for (std::size_t src = n; src-- > lo;) {
        while (j > 0 && at[j - 1] > src) --j;
        if (j != 0) v[src + j] = std::move(v[src]);
        fix(v[src + j], cursor);
    }
    for (j = 0; j < at.size(); ++j) v[at[j] + j] = make(j);
}

// List `list` of the scene or layout (`v`) after the group: its edits' items removed or
// new ones put in, the items from `lo` on passed to fix().
template <class T, class Fix, class Make>
void regroup(std::vector<T>& v, const Group& g, ItemList list, std::size_t lo, const Fix& fix, const Make& make) {
    std::vector<std::size_t> at, part;
    for (std::size_t t = 0; t < g.parts.size(); ++t)
        if (g.parts[t].list == list) {
            at.push_back(g.parts[t].index);
            part.push_back(t);
        }
    if (!at.empty()) lo = std::min(lo, at[0]);
    if (at.empty() || !g.parts[part[0]].insert) compact(v, at, lo, fix);
    else spread(v, at, lo, fix, [&](std::size_t j) { return make(g.parts[part[j]], part[j]); });
}

// Whether the indices of the group's items are within the lists (`sizes`: each list's).
bool within(const Group& g, const std::size_t* sizes) {
    for (const Part& p : g.parts)
        if (p.index > sizes[int(p.list)] || (!p.insert && p.index == sizes[int(p.list)])) return false;
    return true;
}

// The scene after the group: its lists regrouped, every source position moved.
void regroup_scene(rt::Scene& scene, const Group& g) {
    const rt::SourceLoc first = g.parts[0].old_end;
    auto from = [&](const auto& v) {
        return std::size_t(std::partition_point(v.begin(), v.end(), [&](const auto& x) { return before(x.loc, first); }) - v.begin());
    };
    auto value = [&](auto pick) {
        return [&g, pick](const Part& p, std::size_t t) {
            auto x = pick(*p.value);
            if (g.local) g.map(x.loc, t);
            return x;
        };
    };
    auto fix_loc = [&](auto& x, std::size_t& c) {
        c = g.region(x.loc, c);
        g.map(x.loc, c);
    };
    regroup(scene.objects, g, ItemList::Object, from(scene.objects), [&](rt::Object& o, std::size_t& c) {
        c = g.region(o.loc, c);
        g.map(o, c);
    }, [&](const Part& p, std::size_t t) {
        rt::Object o = p.value->objects.at(0);
        if (g.local) g.map(o, t);
        return o;
    });
    regroup(scene.planes, g, ItemList::Plane, from(scene.planes), fix_loc, value([](const rt::Scene& s) { return s.planes.at(0); }));
    regroup(scene.lights, g, ItemList::Light, from(scene.lights), fix_loc, value([](const rt::Scene& s) { return s.lights.at(0); }));
    std::size_t c = 0;
    for (rt::NamedMaterial& m : scene.materials) fix_loc(m, c);
    for (rt::NamedObject& d : scene.defined) fix_loc(d, c);
    c = g.region(scene.camera_loc, 0);
    g.map(scene.camera_loc, c);
}

// The layout after the group: its lists regrouped, every span moved.
void regroup_layout(SceneLayout& l, const Group& g) {
    auto fix = [&g](TextSpan& s, std::size_t& c) {
        std::size_t c_end = c;
        s.begin = g.move(s.begin, true, c);
        s.end = g.move(s.end, false, c_end);
    };
    auto make = [&g](const Part& p, std::size_t t) {
        TextSpan b = p.block;
        if (g.local) b = {std::size_t(std::ptrdiff_t(b.begin) + g.bytes[t]), std::size_t(std::ptrdiff_t(b.end) + g.bytes[t])};
        return b;
    };
    const std::size_t pos = g.parts[0].pos;
    auto from = [&](const std::vector<TextSpan>& v) {
        return std::size_t(std::partition_point(v.begin(), v.end(), [&](const TextSpan& t) { return t.end < pos; }) - v.begin());
    };
    for (ItemList k : {ItemList::Object, ItemList::Plane, ItemList::Light})
        regroup(spans_of(l, k), g, k, from(spans_of(l, k)), fix, make);
    std::size_t c = 0;
    for (TextSpan& s : l.cameras) fix(s, c);
    c = 0;
    l.append_at = g.move(l.append_at, true, c);
}

}  // namespace

bool Document::apply_group(const DocStep& s, bool forward, bool layout_valid) {
    Group g;
    if (!group_of(s, forward, g)) return false;
    const std::size_t sizes[3] = {scene_.objects.size(), scene_.planes.size(), scene_.lights.size()};
    if (!within(g, sizes) || g.parts.back().pos + g.parts.back().old_len > editor_.size()) return false;
    if (layout_valid && layout_) {
        const std::size_t spans[3] = {layout_->objects.size(), layout_->planes.size(), layout_->lights.size()};
        if (!within(g, spans)) layout_.reset();
    }
    rebuild_text(editor_, g);
    regroup_scene(scene_, g);
    spliced_count_ += g.parts.size();
    ++group_passes_;
    if (!layout_valid || !layout_) {
        layout_.reset();
        return true;
    }
    regroup_layout(*layout_, g);
    // The text changes its version next (text_changed): the layout is that version's.
    layout_key_ = layout_key(1);
    return true;
}

bool Document::plan_group(const std::vector<SpliceEdit>& edits, DocStep& step) const {
    // Each planned on the text as it is: those before it in the list are after it in
    // the text (apply_group() checks that), so what it reads is the same.
    for (const SpliceEdit& e : edits) {
        const TextReplacement& r = e.replacement;
        SplicedItem s;
        if (r.empty() || e.splice.section || e.splice.op == ItemSplice::Op::Replace ||
            !plan_splice(r.offset, r.length, r.text, e.splice, *layout_, s))
            return false;
        step.made(r, editor_);
        step.spliced_many.push_back(std::move(s));
    }
    return true;
}

bool Document::splice_each(const std::vector<SpliceEdit>& edits, DocStep& step) {
    // Each edit planned on the text, scene and layout the ones before it left (the
    // layout is kept in step by apply_splice: it is read directly, not through layout()).
    for (const SpliceEdit& e : edits) {
        const TextReplacement& r = e.replacement;
        SplicedItem s;
        if (r.empty() || !plan_splice(r.offset, r.length, r.text, e.splice, *layout_, s)) {
            // Those made go back, the last first; the layout is scanned again when next asked for.
            for (std::size_t k = step.spliced_many.size(); k-- > 0;) {
                const TextReplacement& made = step.editor[k];
                const TextReplacement& back = step.editor_back[k];
                editor_.replace(back.offset, back.length, back.text);
                apply_splice(step.spliced_many[k], false, made.offset, made.text, back.text, false);
            }
            spliced_count_ -= 2 * step.spliced_many.size();
            layout_.reset();
            return false;
        }
        step.made(r, editor_);
        editor_.replace(r.offset, r.length, r.text);
        apply_splice(s, true, r.offset, step.editor_back.back().text, r.text, true);
        step.spliced_many.push_back(std::move(s));
    }
    return true;
}

bool Document::splice_texts(const std::vector<SpliceEdit>& edits, const std::string& name) {
    if (edits.empty() || held_) return false;
    flush_typing();  // text typed since the last step is a step of its own, first
    normalize_applied();
    if (!has_scene_ || applied_ || behind_ || !scene_.includes.empty() || !diagnostics_.empty()) return false;
    if (!layout() || !layout_matches(*layout_, scene_)) return false;
    DocStep step;
    step.name = name;
    step.has_scene_before = step.has_scene_after = true;
    // As one pass where the edits allow it, else one after the other.
    if (!plan_group(edits, step) || !apply_group(step, true, true)) {
        step.editor.clear();
        step.editor_back.clear();
        step.spliced_many.clear();
        if (!splice_each(edits, step)) return false;
    }
    rt::SceneDelta delta;
    for (const SplicedItem& s : step.spliced_many) delta.merge(splice_delta(s));
    ++scene_version_;
    changed(std::move(delta));
    text_changed(step, true);
    record(std::move(step));
    return true;
}

}  // namespace rtview
