// Recursive-descent reader for the scene format, driven by the schema (scene_schema.h):
// a block's keys, their kinds, ranges and messages come from there. It collects
// diagnostics instead of stopping at the first problem: after an error it skips to the
// next key it knows in the same block (or the block's closing brace), so one typo gives
// one message. Positions are byte offsets until a diagnostic or an item's location
// needs a line and column.
//
// Big files are read in pieces side by side (ParseOptions::threads): helpers read the
// items of a thing section from guessed item starts onwards, and the main reading,
// which goes through the whole file as it always does, takes a helper's items instead
// of reading them itself when it arrives exactly at that start, in a thing section.
// A helper gives up at its first diagnostic of any kind, so what it hands over is
// what the main reading would have made itself, with no diagnostic, and the result
// cannot depend on the guesses or on timing; only the speed does.
#include "scene_parser.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <map>
#include <memory>
#include <mutex>
#include <new>
#include <set>
#include <thread>
#include <type_traits>

#include "diagnostic_text.h"
#include "image_io.h"
#include "pages.h"
#include "parallel.h"
#include "scene_lexer.h"
#include "scene_schema.h"

namespace rt {
namespace {

namespace sc = schema;

// Raised to abandon parsing (too many errors, or the end of the file inside a block).
struct Stop {};
// Raised when the progress callback asks to stop.
struct Cancelled {};
// Raised in a helper at its first diagnostic: the main reading takes over there.
struct Bail {};

std::string quote(std::string_view s) {
    std::string out = "'";
    for (char c : s.substr(0, 40)) {
        unsigned char u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02x", u);
            out += buf;
        } else {
            out += c;
        }
    }
    if (s.size() > 40) out += "...";
    return out + "'";
}

// Every number must stay well inside double range so that squares and products in
// the tracer stay finite.
constexpr double kMaxMagnitude = 1e15;
constexpr std::size_t kNone = std::size_t(-1);

// What the parser tracks about one item while reading its block: which keys were
// given, where each one's last value was (for range errors), and whether an error
// made the item unusable.
struct ItemState {
    static constexpr int kMaxKeys = 32;  // bits of `given`; every block has fewer keys (checked below)
    unsigned given = 0;
    std::array<std::size_t, kMaxKeys> value_at = filled();
    static std::array<std::size_t, kMaxKeys> filled() {
        std::array<std::size_t, kMaxKeys> a;
        a.fill(kNone);
        return a;
    }
    bool bad = false;
};

template <class T>
int key_index(const sc::Block<T>& b, const sc::Key<T>& k) {
    const int i = int(&k - b.keys.data());
    if (i >= ItemState::kMaxKeys) std::abort();  // a block with more keys than ItemState holds
    return i;
}

// The items of a thing section from `start` on, read by a helper (an item of a loop on
// the process pool beside the main reading).
struct Piece {
    std::size_t start = 0;    // a guessed item start (the offset of an object name)
    std::size_t stop_at = 0;  // the helper ends at the first item starting at or after it
    std::size_t max_counted = 0;  // the helper gives up past this many objects
    std::atomic<bool> quit{false};  // the main reading passed `start`: the work is not needed
    std::atomic<std::size_t> at{0}, made{0};  // how far the helper got, for progress
    // Set by whichever comes first: the helper starting, or the main reading that
    // arrives at or passes `start` (then no helper begins, and the main reading reads
    // the items itself).
    std::atomic<bool> claimed{false};
    std::mutex mutex;
    std::condition_variable finished;
    // Under mutex: the objects read so far without a diagnostic, handed over in chunks
    // of whole items as the helper goes (ParseOptions::chunk_objects each, the last
    // one shorter), so that the main reading can move them while the helper reads on.
    std::vector<std::vector<Object>> chunks;
    std::size_t taken = 0;  // (the main reading's) objects of `chunks` it has moved
    bool done = false;  // under mutex; then the fields below are the helper's result
    // The items read without a diagnostic, which the limit counts as `counted` (CSG
    // operands too), end where the token at `end` starts.
    std::size_t counted = 0;
    std::size_t end = 0;
    // The helper's line map, which has scanned past the main reading's: handed on.
    // It counts lines from the one holding `start` (the objects' lines too, until the
    // main reading, which knows that line's number, takes them).
    LineMap lines{std::string_view()};
};

class Parser {
public:
    Parser(std::string_view text, const ParseOptions& opt, ParseResult& out)
        : lex_(text), lines_(text), opt_(opt), out_(out) {
        if (opt_.progress) next_tick_ = 0;
        struct stat st;
        if (!opt_.scene_file.empty() && ::stat(opt_.scene_file.c_str(), &st) == 0)
            own_shared_.scene_id = std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    }
    // A helper reading `piece`.
    Parser(std::string_view text, const ParseOptions& opt, ParseResult& out, Piece& piece)
        : lex_(text, piece.start), lines_(text, piece.start), opt_(opt), out_(out), piece_(&piece) {}

    void run(std::vector<Piece*> pieces = {}) {
        pieces_ = std::move(pieces);
        next_start_ = pieces_.empty() ? kNone : pieces_.front()->start;
        try {
            parse_top();
            finish_textures();
            if (errors_ == 0) validate();
        } catch (const Stop&) {
            // Too many errors: what was collected is the result.
        } catch (const Cancelled&) {
            out_.cancelled = true;
        } catch (...) {
            end_pieces();
            throw;
        }
        end_pieces();
        // In the scene file's order: an included file's problems where it was included.
        auto place = [](const Diagnostic& d) {
            return d.included_from.empty() ? std::make_pair(d.line, d.col)
                                           : std::make_pair(d.included_from.back().line, d.included_from.back().col);
        };
        std::stable_sort(out_.diagnostics.begin(), out_.diagnostics.end(),
                         [&](const Diagnostic& a, const Diagnostic& b) { return place(a) < place(b); });
    }

    // The helper's work: thing items from piece_->start up to the first diagnostic,
    // the end of the section, or the first item at or after stop_at.
    void run_piece() {
        Piece& p = *piece_;
        if (p.claimed.exchange(true)) return;  // the main reading got there first
        std::vector<Object>& objects = out_.scene.objects;
        std::size_t kept = 0, handed = 0, counted = 0, end = p.start;
        const std::size_t chunk = std::max<std::size_t>(opt_.chunk_objects, 1);
        try {
            objects.reserve(chunk);
            for (;;) {
                const Token& t = lex_.peek();
                const sc::Block<Object>* b = sc::object_block(t.text);  // (then not a section)
                if (t.offset >= p.stop_at || t.eof() || t.is('}') || (!b && sc::find_section(t.text)) ||
                    p.quit.load(std::memory_order_relaxed))
                    break;
                thing_item(b);
                if (objects_ > p.max_counted) break;
                kept = objects.size();
                counted = objects_;
                end = lex_.peek().offset;
                p.at.store(end, std::memory_order_relaxed);
                p.made.store(handed + kept, std::memory_order_relaxed);
                if (kept >= chunk) {
                    std::vector<Object> full;
                    full.swap(objects);
                    hand_over(p, std::move(full));
                    handed += kept;
                    kept = 0;
                    objects.reserve(chunk);
                }
            }
        } catch (...) {
            // Bail, Stop, or no memory: the main reading does the rest itself.
        }
        objects.erase(objects.begin() + std::ptrdiff_t(kept), objects.end());
        std::lock_guard<std::mutex> lock(p.mutex);
        if (!objects.empty() && !p.quit.load(std::memory_order_relaxed)) p.chunks.push_back(std::move(objects));
        if (p.quit.load(std::memory_order_relaxed)) std::vector<std::vector<Object>>().swap(p.chunks);
        p.lines = std::move(lines_);
        p.counted = counted;
        p.end = end;
        p.done = true;
        p.finished.notify_all();
    }

private:
    // ---- pieces and progress -----------------------------------------------------
    // A helper's chunk of whole items, for the main reading to take.
    static void hand_over(Piece& p, std::vector<Object>&& chunk) {
        {
            std::lock_guard<std::mutex> lock(p.mutex);
            if (p.quit.load(std::memory_order_relaxed)) return;  // (then freed here)
            p.chunks.push_back(std::move(chunk));
        }
        p.finished.notify_all();
    }

    // At an item boundary of a thing section: takes the pieces that start right here
    // (one may end where the next starts), and lets go of those already passed.
    void take_pieces() {
        while (next_piece_ < pieces_.size()) {
            Piece& p = *pieces_[next_piece_];
            const std::size_t here = lex_.peek().offset;
            if (p.start > here) {
                next_start_ = p.start;
                return;
            }
            if (p.start < here) {
                p.quit = true;
                keep_from_helper(p);
                ++next_piece_;
                continue;
            }
            take(p);
            ++next_piece_;
        }
        next_start_ = kNone;
    }

    // An object a helper read, with lines counted from its piece's first line, which
    // is the text's line first_line.
    static void to_true_lines(Object& o, int first_line) {
        o.loc.line += first_line - 1;
        if (Csg* c = std::get_if<Csg>(&o.shape))
            for (Object& operand : c->operands) to_true_lines(operand, first_line);
    }

    // Sees that no helper begins `p` if none has yet: then it is done, with nothing
    // read (p.end is p.start).
    static void keep_from_helper(Piece& p) {
        if (p.claimed.exchange(true)) return;
        std::lock_guard<std::mutex> lock(p.mutex);
        p.done = true;
    }

    // The objects of `p`, which starts right here, from its helper: each chunk moved in
    // as soon as the helper hands it over (its objects hot in the cache, and the move
    // beside the helper's reading rather than after it), up to the helper's end. If the
    // sequential reading would have stopped at the limit of objects inside the piece,
    // they are let go again and the main reading reads the piece itself, to report it.
    void take(Piece& p) {
        keep_from_helper(p);  // (done at once, with nothing, when no helper has begun)
        std::vector<Object>& objects = out_.scene.objects;
        const std::size_t size0 = objects.size();
        const int first_line = loc_of(p.start).line;
        std::vector<std::vector<Object>> got;
        for (bool done = false; !done;) {
            {
                std::unique_lock<std::mutex> lock(p.mutex);
                while (p.chunks.empty() && !p.done) {
                    if (opt_.progress) {
                        lock.unlock();
                        on_tick(lex_.peek().offset);
                        lock.lock();
                        if (!p.chunks.empty() || p.done) break;
                    }
                    p.finished.wait_for(lock, std::chrono::milliseconds(20));
                }
                got.swap(p.chunks);
                done = p.done;
            }
            for (std::vector<Object>& chunk : got) {
                append(chunk, first_line);
                p.taken += chunk.size();
                std::vector<Object>().swap(chunk);  // (freed while its memory is hot)
            }
            got.clear();
        }
        // The sequential reading would count the same objects one by one; if one of
        // them went over the limit, it reports that itself.
        if (p.end == p.start || objects_ + p.counted > Limits::max_objects) {
            objects.erase(objects.begin() + std::ptrdiff_t(size0), objects.end());
            return;
        }
        out_.objects_read_ahead += objects.size() - size0;
        objects_ += p.counted;
        lex_.seek(p.end);
        lines_.rebase(std::move(p.lines), first_line);
    }

    // Moves a helper's chunk of objects to the end of the scene's, each with its true
    // line.
    void append(std::vector<Object>& chunk, int first_line) {
        std::vector<Object>& objects = out_.scene.objects;
        if (objects.capacity() - objects.size() < chunk.size())
            objects.reserve(objects.size() + std::max(objects.size(), chunk.size()));
        // The first-touch faults of the objects' new place taken in one call.
        populate_pages(reinterpret_cast<const void*>(std::uintptr_t(objects.data()) + objects.size() * sizeof(Object)),
                       chunk.size() * sizeof(Object));
        for (Object& o : chunk) {
            to_true_lines(o, first_line);
            objects.push_back(std::move(o));
        }
    }

    // Stops the helpers still reading and waits for them; those not begun never do.
    void end_pieces() {
        for (Piece* p : pieces_) p->quit = true;
        for (Piece* p : pieces_) {
            keep_from_helper(*p);
            std::unique_lock<std::mutex> lock(p->mutex);
            p->finished.wait(lock, [&] { return p->done; });
        }
        pieces_.clear();
    }

    // Called with the offset reached at the top of each loop over tokens; cheap unless
    // there is a progress callback and a MB has gone by.
    void tick(std::size_t offset) {
        if (offset >= next_tick_) on_tick(offset);
    }
    void on_tick(std::size_t offset) {
        next_tick_ = offset + (std::size_t(1) << 20);
        std::size_t bytes = offset, objects = out_.scene.objects.size();
        for (std::size_t k = next_piece_; k < pieces_.size(); ++k) {
            const Piece& p = *pieces_[k];
            if (p.quit.load(std::memory_order_relaxed)) continue;
            bytes += p.at.load(std::memory_order_relaxed) - std::min(p.start, p.at.load(std::memory_order_relaxed));
            objects += p.made.load(std::memory_order_relaxed) - p.taken;
        }
        bytes = std::max(std::min(bytes, lex_.text().size()), bytes_shown_);
        bytes_shown_ = bytes;
        if (!opt_.progress(bytes, objects)) throw Cancelled{};
    }

    // ---- diagnostics -------------------------------------------------------------
    SourceLoc loc_of(std::size_t offset) {
        LineCol lc = lines_.at(offset);
        return {lc.line, lc.col};
    }
    void report(Diagnostic::Severity severity, SourceLoc at, std::string msg) {
        if (piece_) throw Bail{};
        out_.diagnostics.push_back({severity, at.line, at.col, std::move(msg), file_, included_from_});
        if (severity == Diagnostic::Severity::Error && ++errors_ >= opt_.max_errors) throw Stop{};
    }
    void error_at(SourceLoc at, std::string msg) { report(Diagnostic::Severity::Error, at, std::move(msg)); }
    void error_at(std::size_t offset, std::string msg) { error_at(loc_of(offset), std::move(msg)); }
    void error(const Token& t, std::string msg) { error_at(t.offset, std::move(msg)); }
    void report(const sc::Problem& p, SourceLoc at) {
        report(p.severity == sc::Problem::Severity::Error ? Diagnostic::Severity::Error
                                                          : Diagnostic::Severity::Warning,
               at, p.message);
    }
    [[noreturn]] void fatal(const Token& t, std::string msg) {
        error(t, std::move(msg));
        throw Stop{};
    }
    static std::string got(const Token& t) { return t.eof() ? "end of file" : quote(t.text); }

    // ---- structure ---------------------------------------------------------------
    // A section name inside a block almost always means a '}' is missing before it.
    // Report that once and let the caller close the block, so the rest still parses.
    bool section_inside(const Token& t, std::string_view what) {
        if (!sc::find_section(t.text)) return false;
        error(t, quote(t.text) + " inside " + quote(what) + ": is a '}' missing before it?");
        return true;
    }

    // Consumes '{' after a block name; false (with an error) if it is not there.
    bool open(const Token& name) {
        const Token& t = lex_.peek();
        if (t.is('{')) {
            lex_.next();
            return true;
        }
        if (t.eof()) fatal(t, "unexpected end of file: expected '{' after " + quote(name.text));
        error(t, "expected '{' after " + quote(name.text) + ", got " + got(t));
        return false;
    }

    // Consumes tokens up to and including the '}' that brings `depth` open braces back
    // to none; iterative so that absurd nesting cannot exhaust the stack. At the end of
    // the file: `eof_outer` if only the outermost block is open, else "unbalanced".
    void skip_to_close(std::size_t depth, const char* eof_outer = nullptr) {
        while (depth > 0) {
            tick(lex_.peek().offset);
            Token t = lex_.next();
            if (t.eof())
                fatal(t, depth == 1 && eof_outer ? eof_outer : "unexpected end of file: unbalanced '{'");
            depth += t.is('{') ? 1 : t.is('}') ? -1 : 0;
        }
    }
    // Skips a balanced { ... } block if one comes next.
    void skip_block() {
        if (!lex_.peek().is('{')) return;
        lex_.next();
        skip_to_close(1);
    }
    // Skips the rest of the block we are in, its closing '}' included.
    void skip_rest_of_block() { skip_to_close(1, "unexpected end of file: expected '}'"); }

    // After an error inside a block: skip to the next known key, a nested block, or
    // the closing brace.
    template <class T>
    void recover(const sc::Block<T>& b) {
        for (;;) {
            const Token& t = lex_.peek();
            tick(t.offset);
            if (t.eof() || t.is('}') || b.find(t.text)) return;
            if (t.is('{'))
                skip_block();
            else
                lex_.next();
        }
    }

    void unknown_key(const Token& t, std::string_view what, const std::string& keys) {
        if (t.is('{')) {
            error(t, "unexpected '{' in " + quote(what));
            skip_to_close(1);  // an unnamed block: skip it whole
        } else {
            error(t, "unknown key " + quote(t.text) + " in " + std::string(what) + " (expected " + keys + ")");
        }
    }

    // Reads the body of a block up to and including its '}' into `item`.
    template <class T>
    void read_block(const sc::Block<T>& b, T& item, ItemState& st) {
        for (;;) {
            Token t = lex_.peek();
            tick(t.offset);
            if (t.eof()) fatal(t, "unexpected end of file inside " + quote(b.name) + ": expected '}'");
            if (t.is('}')) {
                lex_.next();
                return;
            }
            const sc::Key<T>* k = b.find(t.text);
            if (!k) {
                if (section_inside(t, b.name)) return;
                lex_.next();
                unknown_key(t, b.name, b.key_list());
                recover(b);
                continue;
            }
            lex_.next();
            if (!read_key(b, *k, t, item, st)) recover(b);
        }
    }

    // One key's value (after its name). False after an error that calls for recovery.
    template <class T>
    bool read_key(const sc::Block<T>& b, const sc::Key<T>& k, const Token& name, T& item, ItemState& st) {
        int i = 0;
        if (k.count > 0) {
            long n = 0;
            if (!integer(name, 1, k.count, n, k.count_error)) return false;
            i = int(n - 1);
        }
        const int index = key_index(b, k);
        const std::size_t at = lex_.peek().offset;
        switch (k.kind) {
        case sc::Kind::Number:
            if (!number(name, k.access.number(item, i))) return false;
            break;
        case sc::Kind::Vec3:
            if (!(k.one_or_three ? one_or_three(name, k.access.vec3(item, i)) : vec3(name, k.access.vec3(item, i))))
                return false;
            break;
        case sc::Kind::File:
            if (!file_name(name, k.access.text(item, i))) return false;
            break;
        case sc::Kind::Integer: {
            long v = 0;
            if (!integer(name, long(k.range.min), long(k.range.max), v, k.range.message)) return false;
            k.access.integer(item, i) = int(v);
            break;
        }
        case sc::Kind::Choice:
            return choice(k, name, item, st, index);
        case sc::Kind::Material: {
            Material m;
            const Token v = lex_.peek();
            if (is_name(v.text)) {
                if (!named_material(v, m)) return false;
            } else if (!material(name, m)) {
                return false;
            }
            k.access.material(item, i) = m;
            k.access.has_material(item, i) = true;
            break;
        }
        case sc::Kind::Operand:
            if constexpr (std::is_same_v<T, Object>) return operand(k, name, item, st, index);
            return false;
        }
        st.given |= 1u << index;
        st.value_at[index] = at;
        return true;
    }

    // ---- values ------------------------------------------------------------------
    bool number(const Token& key, double& v) {
        const Token& t = lex_.peek();
        if (short_decimal(t.text, v)) {
            lex_.skip();
            return true;
        }
        if (t.eof()) fatal(t, "unexpected end of file: expected a number after " + quote(key.text));
        double fast = 0;
        const NumberScan scan = scan_number(t.text, fast);
        if (usual_number(t, scan, fast)) {
            v = fast;
            lex_.skip();
            return true;
        }
        if (scan == NumberScan::NotNumber) {  // braces included
            error(t, "expected a number after " + quote(key.text) + ", got " + got(t));
            return false;
        }
        return take_number(lex_.next(), scan, fast, v);
    }
    // Whether take_number would accept the token as scan_number read it: the common
    // case, checked inline (fast values are finite; NaN fails the comparison).
    static bool usual_number(const Token& t, NumberScan scan, double fast) {
        return scan == NumberScan::Exact && t.text.size() <= Limits::max_token_length &&
               std::fabs(fast) <= kMaxMagnitude;
    }
    // A token of number syntax, with what scan_number found.
    bool take_number(const Token& t, NumberScan scan, double fast, double& v) {
        if (t.text.size() > Limits::max_token_length) {
            error(t, "number too long (" + std::to_string(t.text.size()) + " characters, limit " +
                         std::to_string(Limits::max_token_length) + ")");
            return false;
        }
        const double d = scan == NumberScan::Exact ? fast : library_number_value(t.text);
        if (!std::isfinite(d) || std::fabs(d) > kMaxMagnitude) {
            error(t, "number " + quote(t.text) + " is out of range (magnitude at most 1e15)");
            return false;
        }
        v = d;
        return true;
    }

    bool vec3(const Token& key, Vec3& v) {
        Vec3 r;
        for (int i = 0; i < 3; ++i) {
            const Token& t = lex_.peek();
            if (short_decimal(t.text, r[i])) {
                lex_.skip();
                continue;
            }
            if (t.eof()) return number(key, r[i]);  // reports the end of the file
            double fast = 0;
            const NumberScan scan = scan_number(t.text, fast);
            if (usual_number(t, scan, fast)) {
                r[i] = fast;
                lex_.skip();
                continue;
            }
            if (scan == NumberScan::NotNumber) {
                error(t, "expected 3 numbers after " + quote(key.text) + ", got " + got(t));
                return false;
            }
            if (!take_number(lex_.next(), scan, fast, r[i])) return false;
        }
        v = r;
        return true;
    }

    // One number for all three (`scale 2`), or three.
    bool one_or_three(const Token& key, Vec3& v) {
        double x = 0;
        if (!number(key, x)) return false;
        double unused;
        if (scan_number(lex_.peek().text, unused) == NumberScan::NotNumber) {
            v = {x, x, x};
            return true;
        }
        Vec3 r{x, 0, 0};
        if (!number(key, r.y) || !number(key, r.z)) return false;
        v = r;
        return true;
    }

    // A file name in double quotes, on one line; spaces inside are part of it (so the
    // closing quote is looked for in the text, not among the tokens). A name without
    // quotes is one word.
    bool file_name(const Token& key, std::string& out) {
        const Token t = lex_.peek();
        if (t.eof()) fatal(t, "unexpected end of file: expected a file name after " + quote(key.text));
        if (t.is('{') || t.is('}')) {
            error(t, "expected a file name in double quotes after " + quote(key.text) + ", got " + got(t));
            return false;
        }
        std::string_view name = t.text;
        if (t.text[0] == '"') {
            const std::string_view text = lex_.text();
            std::size_t end = t.offset + 1;
            while (end < text.size() && text[end] != '"' && text[end] != '\n' && text[end] != '\r') ++end;
            if (end >= text.size() || text[end] != '"') {
                lex_.skip();
                error(t, "the file name has no closing quote on its line");
                return false;
            }
            const char after = end + 1 < text.size() ? text[end + 1] : ' ';
            if (!(after == ' ' || (after >= '\t' && after <= '\r') || after == '{' || after == '}')) {
                lex_.skip();
                error(t, "expected a space after the file name's closing quote");
                return false;
            }
            name = text.substr(t.offset + 1, end - t.offset - 1);
            lex_.seek(end + 1);
        } else {
            lex_.skip();
        }
        if (name.empty()) {
            error(t, "the file name is empty");
            return false;
        }
        if (name.size() > 4096) {
            error(t, "file name too long (" + std::to_string(name.size()) + " characters, limit 4096)");
            return false;
        }
        for (char c : name)
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == '"') {
                error(t, "the file name " + quote(name) + (c == '"' ? " holds a double quote" : " holds a control character"));
                return false;
            }
        out = std::string(name);
        return true;
    }

    // Unsigned integer slot; `lo..hi` inclusive.
    bool integer(const Token& key, long lo, long hi, long& v, const char* range_msg) {
        Token t = lex_.peek();
        if (t.eof()) fatal(t, "unexpected end of file: expected an integer after " + quote(key.text));
        if (!is_integer_syntax(t.text)) {
            error(t, "expected an integer after " + quote(key.text) + ", got " + got(t));
            if (!t.is('{') && !t.is('}')) lex_.next();
            return false;
        }
        lex_.next();
        std::string_view digits = t.text[0] == '+' ? t.text.substr(1) : t.text;
        while (digits.size() > 1 && digits[0] == '0') digits.remove_prefix(1);
        long value = 0;
        if (digits.size() > 9) {
            value = hi + 1;
        } else {
            for (char c : digits) value = value * 10 + (c - '0');
        }
        if (value < lo || value > hi) {
            error(t, range_msg);
            return false;
        }
        v = value;
        return true;
    }

    template <class T>
    bool choice(const sc::Key<T>& k, const Token& name, T& item, ItemState& st, int index) {
        const sc::Choice& c = *k.choice;
        const Token v = lex_.peek();
        if (v.eof()) fatal(v, "unexpected end of file: expected " + std::string(c.eof_expects) + " after " + quote(name.text));
        const bool brace = v.is('{') || v.is('}');
        int value = 0;
        if (!brace && c.find(v.text, value)) {
            lex_.next();
            k.access.set_choice(item, value);
            st.given |= 1u << index;
            return true;
        }
        error(v, std::string(brace && c.brace ? c.brace : c.wrong) + got(v));
        if (!brace) lex_.next();
        if (!c.drops_item) return false;
        st.bad = true;
        return true;
    }

    bool material(const Token& key, Material& out) {
        if (!open(key)) return false;
        const sc::Block<Material>& b = sc::material_block();
        Material m = b.make();
        ItemState st;
        const int errors_before = errors_;
        read_block(b, m, st);
        finish(b, m, st, key.offset, [&] { return loc_of(key.offset); });
        if (!m.texture.empty() && errors_ == errors_before) {
            const std::size_t at = st.value_at[key_index(b, *b.find("texture"))];
            read_texture(m, at != kNone ? at : key.offset);
        }
        out = m;
        return true;
    }

    // Clamps and range rules of the item's numbers, then the block's rule across keys
    // (reported at the item's name: `name_loc` gives its line and column).
    template <class T, class LocFn>
    void finish(const sc::Block<T>& b, T& item, const ItemState& st, std::size_t name_offset, LocFn name_loc) {
        check_ranges(b, item, st, name_offset);
        if (b.check)
            if (sc::Problem p = b.check(item)) report(p, name_loc());
    }

    // The clamps and range rules of the item's numbers.
    template <class T>
    void check_ranges(const sc::Block<T>& b, T& item, const ItemState& st, std::size_t name_offset) {
        for (const sc::Key<T>& k : b.keys) {
            if (k.kind == sc::Kind::Vec3 && k.range.rule == sc::Range::Rule::Error && (st.given & (1u << key_index(b, k)))) {
                const Vec3 v = k.vec3(item, 0);
                if (!(k.range.contains(v.x) && k.range.contains(v.y) && k.range.contains(v.z)))
                    error_at(st.value_at[key_index(b, k)], k.range.message);
                continue;
            }
            if (k.kind != sc::Kind::Number || k.range.rule == sc::Range::Rule::None) continue;
            // An optional key left out keeps its default, which may stand for "not set"
            // (focus_distance 0: the centre's distance).
            if (k.optional && !(st.given & (1u << key_index(b, k)))) continue;
            double& v = k.access.number(item, 0);
            if (k.range.contains(v)) continue;
            if (k.range.rule == sc::Range::Rule::Clamp) {
                v = std::clamp(v, k.range.min, k.range.max);
            } else {
                const std::size_t at = st.value_at[key_index(b, k)];
                error_at(at != kNone ? at : name_offset, k.range.message);
            }
        }
    }

    // ---- names, definitions, includes ---------------------------------------------
    // A name: a letter or '_' first, then letters, digits and '_' (never a number).
    static bool is_name(std::string_view w) {
        auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; };
        if (w.empty() || w.size() > 64 || !letter(w[0])) return false;
        for (char c : w)
            if (!letter(c) && !(c >= '0' && c <= '9')) return false;
        return true;
    }

    // `material NAME` where a material block goes: the definition's values, and its index.
    bool named_material(const Token& v, Material& out) {
        if (piece_) throw Bail{};  // (the definitions are the main reading's)
        lex_.next();
        auto it = shared_->materials.find(std::string(v.text));
        if (it == shared_->materials.end()) {
            error(v, "unknown material " + quote(v.text) +
                         " (a named material is defined before its first use: define { material " +
                         std::string(v.text) + " { ... } })");
            return false;
        }
        out = out_.scene.materials[std::size_t(it->second)].material;
        out.named = it->second;
        return true;
    }

    // One item of a `define` section: `material NAME { ... }`.
    void definition() {
        const Token kind = lex_.next();
        const bool is_object = sc::same_word(kind.text, "object");
        if (!sc::same_word(kind.text, "material") && !is_object) {
            error(kind, "unknown definition " + quote(kind.text) + " (expected material or object)");
            skip_block();
            return;
        }
        const Token name = lex_.peek();
        if (!is_name(name.text)) {
            if (name.eof()) fatal(name, "unexpected end of file: expected a name after " + quote(kind.text));
            error(name, "expected a name after " + quote(kind.text) +
                            " (a letter or '_', then letters, digits and '_'), got " + got(name));
            if (!name.is('{') && !name.is('}')) lex_.next();
            skip_block();
            return;
        }
        lex_.next();
        if (is_object) return object_definition(name);
        count_object(name);
        Material m;
        if (!material(name, m)) return;
        const std::string key(name.text);
        if (auto it = shared_->materials.find(key); it != shared_->materials.end()) {
            const NamedMaterial& first = out_.scene.materials[std::size_t(it->second)];
            error(name, "material " + quote(key) + " is defined twice (first at line " + std::to_string(first.loc.line) +
                            ", column " + std::to_string(first.loc.col) +
                            (first_file_of(it->second).empty() ? "" : " of " + first_file_of(it->second)) + ")");
            return;
        }
        if (shared_->objects.count(key)) {
            error(name, "the name " + quote(key) + " is already an object's");
            return;
        }
        shared_->materials.emplace(key, int(out_.scene.materials.size()));
        shared_->material_files.push_back(file_);
        out_.scene.materials.push_back({key, m, 0, loc_of(name.offset)});
    }
    const std::string& first_file_of(int index) const { return shared_->material_files[std::size_t(index)]; }

    // `object NAME { OBJECT }` in a define section (after the name).
    void object_definition(const Token& name) {
        if (!open(name)) return;
        const Token& first = lex_.peek();
        const sc::Block<Object>* ob = sc::object_block(first.text);
        if (!ob || is_mesh(*ob) || sc::same_word(ob->name, "instance")) {
            error(first, !ob ? "expected one object in the definition of " + quote(name.text) + ", got " + got(first)
                             : is_mesh(*ob) ? "a mesh cannot be defined as an object: mesh blocks already share their model"
                                            : "an instance cannot be defined as an object: define the object itself");
            skip_rest_of_block();
            return;
        }
        auto obj = std::make_shared<Object>();
        const bool ok = object(*obj);
        const Token& close = lex_.peek();
        if (!close.is('}')) {
            error(close, "expected '}' after the object defined as " + quote(name.text) + " (it holds exactly one object), got " +
                             got(close));
            skip_rest_of_block();
            return;
        }
        lex_.next();
        if (!ok) return;
        const std::string key(name.text);
        if (shared_->objects.count(key) || shared_->materials.count(key)) {
            error(name, (shared_->objects.count(key) ? "object " : "the name ") + quote(key) +
                            (shared_->objects.count(key) ? " is defined twice" : " is already a material's"));
            return;
        }
        shared_->objects.emplace(key, int(out_.scene.defined.size()));
        out_.scene.defined.push_back({key, std::move(obj), 0, loc_of(name.offset)});
    }

    // An instance's object name, resolved; its material is the definition's unless it
    // gives one.
    bool resolve_instance(Object& obj, std::size_t at) {
        Instance& in = std::get<Instance>(obj.shape);
        auto it = shared_->objects.find(in.object);
        if (it == shared_->objects.end()) {
            error_at(at, shared_->materials.count(in.object)
                             ? quote(in.object) + " is a material, not an object"
                             : "unknown object " + quote(in.object) +
                                   " (an object is defined before its first use: define { object " + in.object +
                                   " { ... } })");
            return false;
        }
        in.defined = out_.scene.defined[std::size_t(it->second)].object;
        if (!obj.has_material) obj.material = in.defined->material;
        return true;
    }

    // `include "FILE"`: the file's definitions, things, planes and lights, read here.
    // An include's file: a regular file not already being read (its id: device and
    // inode). False, with the error, otherwise.
    template <class Chain>
    bool include_target(const std::string& name, const std::string& path, SourceLoc at, Chain chain, std::string& id,
                        struct stat& st) {
        const std::string& shown = path;
        if (::stat(path.c_str(), &st) != 0) {
            error_at(at, "cannot include " + quote(name) + ": " + std::strerror(errno));
            return false;
        }
        if (S_ISDIR(st.st_mode)) {
            error_at(at, "cannot include " + quote(name) + ": it is a folder, not a scene file");
            return false;
        }
        if (!S_ISREG(st.st_mode)) {
            error_at(at, "cannot include " + quote(name) + ": not a regular file (a device, pipe or socket)");
            return false;
        }
        id = std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
        if (std::find(shared_->stack.begin(), shared_->stack.end(), id) != shared_->stack.end() || id == shared_->scene_id) {
            error_at(at, "include cycle: " + (chain().empty() ? std::string("the scene") : chain()) + " includes " + shown +
                             (id == shared_->scene_id ? ", the scene itself" : ", which is already being read"));
            return false;
        }
        return true;
    }

    // An included file, as it was before it was read (a change while reading shows as
    // one later): Scene::files_read.
    void note_read(const std::string& path, const struct stat& st) {
        out_.scene.files_read.push_back({path, FileId::of(st)});
    }

    // The items from the given counts on came from include number `origin`.
    void mark_origin(std::uint16_t origin, std::size_t objects0, std::size_t planes0, std::size_t lights0,
                     std::size_t materials0, std::size_t defined0) {
        Scene& scene = out_.scene;
        for (std::size_t k = objects0; k < scene.objects.size(); ++k) scene.objects[k].origin = origin;
        for (std::size_t k = planes0; k < scene.planes.size(); ++k) scene.planes[k].origin = origin;
        for (std::size_t k = lights0; k < scene.lights.size(); ++k) scene.lights[k].origin = origin;
        for (std::size_t k = materials0; k < scene.materials.size(); ++k) scene.materials[k].origin = origin;
        for (std::size_t k = defined0; k < scene.defined.size(); ++k) scene.defined[k].origin = origin;
    }

    void include(const Token& kw) {
        std::string name;
        if (!file_name(kw, name)) return;
        const SourceLoc at = loc_of(kw.offset);
        const std::string path = resolve_model_path(opt_.base_dir, name);
        const std::string shown = path;
        auto chain = [&] {
            std::string c;
            for (const std::string& f : shared_->stack_names) c += (c.empty() ? "" : " includes ") + f;
            return c;
        };
        if (int(shared_->stack.size()) >= Limits::max_include_depth) {
            error_at(at, "includes nested too deeply (limit " + std::to_string(Limits::max_include_depth) +
                             " files): " + chain() + " includes " + shown);
            return;
        }
        if (included_from_.empty() && ++includes_ > Limits::max_includes) {
            error_at(at, "too many includes (limit " + std::to_string(Limits::max_includes) + ")");
            return;
        }
        std::string id;
        struct stat st {};
        if (!include_target(name, path, at, chain, id, st)) return;
        std::string text;
        ReadControl control;
        control.strict = true;
        const Status read = read_file(path, text, Limits::max_file_size, &control);
        if (!read.ok()) {
            std::string why = read.message();
            while (!why.empty() && why.back() == '\n') why.pop_back();
            error_at(at, "cannot include " + quote(name) + ": " + why);
            return;
        }
        Scene& scene = out_.scene;
        note_read(path, st);
        const std::size_t objects0 = scene.objects.size(), planes0 = scene.planes.size(), lights0 = scene.lights.size(),
                          materials0 = scene.materials.size(), defined0 = scene.defined.size();
        ParseOptions child_opt = opt_;
        child_opt.base_dir = folder_of(path);
        child_opt.progress = nullptr;
        child_opt.scene_file.clear();  // (known already)
        Parser child(text, child_opt, out_);
        child.shared_ = shared_;
        child.file_ = shown;
        child.included_from_.push_back({file_, at.line, at.col});
        child.included_from_.insert(child.included_from_.end(), included_from_.begin(), included_from_.end());
        child.errors_ = errors_;
        child.objects_ = objects_;
        shared_->stack.push_back(id);
        shared_->stack_names.push_back(shown);
        struct Back {
            Parser& p;
            Parser& child;
            ~Back() {
                p.errors_ = child.errors_;
                p.objects_ = child.objects_;
                p.shared_->stack.pop_back();
                p.shared_->stack_names.pop_back();
            }
        } back{*this, child};
        child.parse_top();
        if (!included_from_.empty()) return;
        // In the scene file: what this include brought is marked as its, and the
        // include kept where it stands among the file's own items.
        mark_origin(std::uint16_t(scene.includes.size() + 1), objects0, planes0, lights0, materials0, defined0);
        Include inc;
        inc.file = name;
        inc.loc = at;
        inc.objects = objects0 - included_.objects;
        inc.planes = planes0 - included_.planes;
        inc.lights = lights0 - included_.lights;
        inc.materials = materials0 - included_.materials;
        inc.defined = defined0 - included_.defined;
        included_.objects += scene.objects.size() - objects0;
        included_.planes += scene.planes.size() - planes0;
        included_.lights += scene.lights.size() - lights0;
        included_.materials += scene.materials.size() - materials0;
        included_.defined += scene.defined.size() - defined0;
        scene.includes.push_back(std::move(inc));
    }

    // ---- sections ----------------------------------------------------------------
    void parse_top() {
        for (;;) {
            tick(lex_.peek().offset);
            Token t = lex_.next();
            if (t.eof()) {
                if (!included_from_.empty()) return;  // an included file needs no `end`
                error(t, "missing 'end' at the end of the scene");
                return;
            }
            const sc::Section* s = sc::find_section(t.text);
            if (!s) {
                unknown_section(t);
                continue;
            }
            switch (s->kind) {
            case sc::SectionKind::End:
                // The 2013 program stopped reading here too; New: say so.
                if (const Token rest = lex_.peek(); !rest.eof())
                    report(Diagnostic::Severity::Warning, loc_of(rest.offset),
                           "text after 'end' is not read (the scene ends at 'end')");
                return;
            case sc::SectionKind::Include:
                include(t);
                break;
            case sc::SectionKind::Define:
                if (open(t)) section_items(*s, [&] { definition(); });
                break;
            case sc::SectionKind::Things:
                if (open(t)) section_items(*s, [&] { thing_item(); }, true);
                break;
            case sc::SectionKind::Specials:
                if (open(t)) section_items(*s, [&] { item(*s, sc::plane_blocks(), out_.scene.planes); });
                break;
            case sc::SectionKind::Lights:
                if (open(t)) section_items(*s, [&] { item(*s, sc::light_blocks(), out_.scene.lights); });
                break;
            case sc::SectionKind::Camera:
                if (!included_from_.empty()) {
                    error(t, "'camera' belongs in the scene file itself, not in an included file");
                    skip_block();
                    break;
                }
                if (!open(t)) break;
                if (!camera_seen_) camera_loc_ = loc_of(t.offset);
                camera_seen_ = true;
                read_block(sc::camera_block(), out_.scene.camera, camera_keys_);
                // (Its rule across keys waits for the whole file: validate().)
                check_ranges(sc::camera_block(), out_.scene.camera, camera_keys_, t.offset);
                break;
            case sc::SectionKind::PictureSize:
                if (!included_from_.empty()) {
                    error(t, "'picture_size' belongs in the scene file itself, not in an included file");
                    skip_block();
                    break;
                }
                if (!size_seen_) size_loc_ = loc_of(t.offset);
                size_seen_ = true;
                if (open(t)) read_block(sc::picture_size_block(), out_.scene, size_keys_);
                break;
            }
        }
    }

    void unknown_section(const Token& t) {
        error(t, "unknown section " + quote(t.text) + " (expected " + sc::section_list() + ")");
        skip_block();
        // Resynchronise on the next section name.
        for (;;) {
            const Token& u = lex_.peek();
            tick(u.offset);
            if (u.eof() || sc::find_section(u.text)) return;
            if (u.is('{'))
                skip_block();
            else
                lex_.next();
        }
    }

    // The items of a section up to its '}'; `read_item` reads one.
    template <class ReadItem>
    void section_items(const sc::Section& s, ReadItem read_item, bool things = false) {
        for (;;) {
            if (things && lex_.peek().offset >= next_start_) take_pieces();
            const Token& t = lex_.peek();
            tick(t.offset);
            if (t.eof()) fatal(t, "unexpected end of file inside " + quote(s.name) + ": expected '}'");
            if (t.is('}')) {
                lex_.next();
                return;
            }
            // An object name (never a section's) goes straight to its block.
            if (things)
                if (const sc::Block<Object>* b = sc::object_block(t.text)) {
                    thing_item(b);
                    continue;
                }
            if (section_inside(t, s.name)) return;
            read_item();
        }
    }

    void count_object(const Token& t) {
        if (++objects_ > Limits::max_objects) fatal(t, "too many objects (limit " + std::to_string(Limits::max_objects) + ")");
    }

    // A plane or a light.
    template <class T>
    void item(const sc::Section& s, const std::vector<sc::Block<T>>& blocks, std::vector<T>& out) {
        const Token t = lex_.next();
        const sc::Block<T>* b = nullptr;
        for (const sc::Block<T>& x : blocks)
            if (sc::same_word(x.name, t.text)) b = &x;
        if (!b) {
            error(t, "unknown " + std::string(s.item_noun) + " " + quote(t.text) + " (expected " + sc::names_of(blocks) +
                         ")");
            skip_block();
            return;
        }
        count_object(t);  // planes and lights cost memory like objects
        T it = b->make();
        it.loc = loc_of(t.offset);
        if (!open(t)) return;
        ItemState st;
        read_block(*b, it, st);
        finish(*b, it, st, t.offset, [&] { return it.loc; });
        out.push_back(std::move(it));
    }

    // Read in place: an Object is ~200 bytes, and big scenes hold millions.
    // `known`: the block of the object's name, if the caller looked it up.
    void thing_item(const sc::Block<Object>* known = nullptr) {
        std::vector<Object>& objects = out_.scene.objects;
        if (objects.size() >= populated_) populate_ahead(objects);
        if (!known) {
            if (!object(objects.emplace_back())) objects.pop_back();
            return;
        }
        // The block's defaults made right in their place (the conversion's result
        // initialises the new element itself), not made apart and moved in.
        struct Made {
            const sc::Block<Object>* b;
            operator Object() const { return b->make(); }
        };
        if (!object(objects.emplace_back(Made{known}), known, true)) objects.pop_back();
    }
    // The first-touch faults of the next objects' pages, taken in one call for a few
    // MB of them: cheaper than one fault at a time as the objects are written.
    void populate_ahead(const std::vector<Object>& objects) {
        constexpr std::size_t kAhead = 16384;  // objects (about 3 MB)
        const std::size_t n = std::min(kAhead, objects.capacity() - objects.size());
        if (objects.size() < kAhead || n == 0) {  // small files: not worth a call
            populated_ = objects.size() + kAhead;
            return;
        }
        populate_pages(objects.data() + objects.size(), n * sizeof(Object));
        populated_ = objects.size() + n;
    }

    // Reads one object (its name is the next token). False if it was unusable.
    // `made`: obj already holds known's defaults.
    bool object(Object& obj, const sc::Block<Object>* known = nullptr, bool made = false) {
        const Token t = lex_.next();
        obj.loc = loc_of(t.offset);
        if (const sc::Block<Object>* b = known ? known : sc::object_block(t.text)) return object_body(*b, t, obj, made);
        if (t.is('{') || t.is('}')) {
            error(t, "expected an object name (" + sc::names_of(sc::object_blocks()) + "), got " + got(t));
            if (t.is('{')) skip_to_close(1);  // we already consumed its '{'
            return false;
        }
        error(t, "unknown object " + quote(t.text) + " (expected " + sc::names_of(sc::object_blocks()) + ")");
        skip_block();
        return false;
    }

    bool object_body(const sc::Block<Object>& b, const Token& t, Object& obj, bool made = false) {
        // Models are read by the main reading only (a helper would read them again), and
        // only it knows the definitions.
        if (piece_ && (is_mesh(b) || sc::same_word(b.name, "instance"))) throw Bail{};
        count_object(t);
        const bool nests = std::any_of(b.keys.begin(), b.keys.end(),
                                       [](const sc::Key<Object>& k) { return k.kind == sc::Kind::Operand; });
        if (nests && depth_ >= Limits::max_csg_depth) {
            error(t, "CSG nested too deeply (limit " + std::to_string(Limits::max_csg_depth) + " levels)");
            skip_block();
            return false;
        }
        if (!open(t)) return false;
        if (!made) {
            const SourceLoc loc = obj.loc;
            obj = b.make();
            obj.loc = loc;
        }
        ItemState st;
        const int errors_before = errors_;
        read_block(b, obj, st);
        finish(b, obj, st, t.offset, [&] { return obj.loc; });
        if (std::holds_alternative<Instance>(obj.shape) && errors_ == errors_before) {
            const std::size_t at = st.value_at[key_index(b, *b.find("object"))];
            if (!resolve_instance(obj, at != kNone ? at : t.offset)) st.bad = true;
        }
        if (Mesh* m = std::get_if<Mesh>(&obj.shape); m && errors_ == errors_before) {
            const std::size_t at = st.value_at[key_index(b, *b.find("file"))];
            read_model(*m, at != kNone ? at : t.offset);
        }
        for (const sc::Key<Object>& k : b.keys)
            if (k.kind == sc::Kind::Operand && !(st.given & (1u << key_index(b, k)))) {
                error_at(obj.loc, "CSG is missing its '" + std::string(k.name) + "' operand");
                st.bad = true;
            }
        return !st.bad;
    }

    // The model a mesh names, read once per parse however many meshes name it; its
    // errors are reported at the file name, with the model file's own line.
    void read_model(Mesh& m, std::size_t at) {
        if (!opt_.read_models) return;
        const std::string path = resolve_model_path(opt_.base_dir, m.file);
        auto it = models_.find(path);
        if (it == models_.end()) {
            if (models_.size() >= ModelLimits::max_files) {
                error_at(at, "too many model files (limit " + std::to_string(ModelLimits::max_files) + ")");
                return;
            }
            it = models_.emplace(path, (opt_.models ? *opt_.models : own_models_)
                                           .load(path, &texture_store()))
                     .first;
            if (const MeshModel* model = it->second.model.get()) {
                triangles_ += model->data().triangle_count();
                shared_->models_read.push_back(it->second.model);
            }
            if (triangles_ > ModelLimits::max_triangles) {
                error_at(at, "the scene's models hold more than " + std::to_string(ModelLimits::max_triangles) +
                                 " triangles in all");
                it->second.model.reset();
                it->second.error = {0, "(over the scene's limit of triangles)"};
                return;
            }
        }
        const ModelStore::Loaded& l = it->second;
        if (!l.model) {
            error_at(at, m.file + (l.error.line > 0 ? ":" + std::to_string(l.error.line) : "") + ": " + l.error.message);
            return;
        }
        for (const Material& mm : l.model->data().materials)
            if (mm.texture_image && !count_texels(*mm.texture_image)) {
                error_at(at, m.file + ": the scene's textures hold more than " +
                                 std::to_string(TextureLimits::max_scene_texels) + " pixels in all");
                return;
            }
        m.model = l.model;
        for (const ModelError& w : l.model->data().warnings)
            report(Diagnostic::Severity::Warning, loc_of(at),
                   m.file + (w.line > 0 ? ":" + std::to_string(w.line) : "") + ": " + w.message);
    }

    // The texture a material names, decoded once per parse however many materials name
    // it; its errors are reported at the file name.
    void read_texture(Material& m, std::size_t at) {
        // Textures are read by the main reading only (a helper would read them again).
        if (piece_) throw Bail{};
        if (!opt_.read_textures || !opt_.read_models) return;
        const std::string path = resolve_model_path(opt_.base_dir, m.texture);
        auto it = textures_.find(path);
        if (it == textures_.end()) {
            if (textures_.size() >= TextureLimits::max_files) {
                error_at(at, "too many texture files (limit " + std::to_string(TextureLimits::max_files) + ")");
                return;
            }
            // Decoded on the pool while the reading goes on; waited for at the end.
            it = textures_.emplace(path, texture_store().load(path, /*later=*/true)).first;
            if (it->second.texture)
                shared_->decoding.push_back({it->second.texture, m.texture, loc_of(at), file_, included_from_});
        }
        const TextureStore::Loaded& l = it->second;
        if (!l.texture) {
            error_at(at, m.texture + ": " + l.error);
            return;
        }
        if (!count_texels(*l.texture)) {
            error_at(at, "the scene's textures hold more than " + std::to_string(TextureLimits::max_scene_texels) +
                             " pixels in all");
            it->second = {nullptr, "(over the scene's limit of texture pixels)"};
            return;
        }
        m.texture_image = l.texture;
    }
    // The textures still being decoded (the included files' too) waited for, and those
    // that could not be reported at their first use. Meanwhile, the models' trees are built on this
    // thread: they would be next (compiling the scene), and the decoding has a core.
    void finish_textures() {
        std::vector<Decoding> decoding;
        decoding.swap(shared_->decoding);
        bool waiting = false;
        for (const Decoding& d : decoding) waiting = waiting || !d.texture->decoded();
        if (waiting && errors_ == 0)  // (a scene with errors is never compiled)
            for (const std::shared_ptr<const MeshModel>& model : shared_->models_read) model->accel();
        shared_->models_read.clear();
        for (const Decoding& d : decoding)
            if (const std::string e = d.texture->wait(); !e.empty()) {
                // Where the texture was named (maybe in an included file), as report() says it.
                out_.diagnostics.push_back(
                    {Diagnostic::Severity::Error, d.loc.line, d.loc.col, d.name + ": " + e, d.file, d.included_from});
                if (++errors_ >= opt_.max_errors) throw Stop{};
            }
    }
    TextureStore& texture_store() {
        return opt_.textures ? *opt_.textures : opt_.models ? opt_.models->textures() : own_textures_;
    }
    // Counts a texture's pixels toward the scene's limit (each texture once); false
    // once over it.
    bool count_texels(const Texture& t) {
        if (!counted_textures_.insert(&t).second) return true;
        texels_ += std::uint64_t(t.width()) * std::uint64_t(t.height());
        return texels_ <= TextureLimits::max_scene_texels;
    }

    // A CSG's `left { OBJECT }` or `right { OBJECT }` (after its name).
    bool operand(const sc::Key<Object>& k, const Token& name, Object& csg, ItemState& st, int index) {
        if (!open(name)) return false;
        const std::string side(name.text);
        const Token& first = lex_.peek();
        if (first.is('}')) {
            error(first, "CSG " + side + " operand is empty: expected one object");
            lex_.next();
            st.bad = true;
            return true;
        }
        const sc::Block<Object>* ob = sc::object_block(first.text);
        if (ob && sc::same_word(ob->name, "instance")) {
            error(first, "an instance cannot be a CSG operand: define the whole CSG as an object and place that");
            skip_rest_of_block();
            st.bad = true;
            st.given |= 1u << index;
            return true;
        }
        if (!ob || is_mesh(*ob)) {
            error(first, ob ? "a mesh cannot be a CSG operand: CSG combines solids (" + csg_operands() + ")"
                            : "unknown object " + got(first) + " in CSG " + side + " operand (expected " +
                                  csg_operands() + ")");
            skip_rest_of_block();
            st.bad = true;
            if (ob) st.given |= 1u << index;  // it is there, just not allowed: no second message
            return true;
        }
        Object operand;
        ++depth_;
        if (!object(operand)) st.bad = true;
        --depth_;
        *k.access.operand(csg, 0) = std::move(operand);  // make() gave the CSG both
        st.given |= 1u << index;
        const Token& close = lex_.peek();
        if (!close.is('}')) {
            error(close, "expected '}' after the CSG " + side + " operand (it holds exactly one object), got " +
                             got(close));
            skip_rest_of_block();
            st.bad = true;
            return true;
        }
        lex_.next();
        return true;
    }

    // The objects a CSG may hold: all but meshes, which are surfaces, not solids.
    static std::string csg_operands() {
        std::string out;
        for (const sc::Block<Object>& b : sc::object_blocks())
            if (!is_mesh(b) && !sc::same_word(b.name, "instance")) out += (out.empty() ? "" : ", ") + std::string(b.name);
        return out;
    }
    static bool is_mesh(const sc::Block<Object>& b) { return sc::same_word(b.name, "mesh"); }

    // Whole-scene checks that need every section read.
    void validate() {
        // Just past the token after `end` (or the end of the file), where the old
        // line-counting lexer stood.
        const std::size_t eof = lex_.peek().end();
        required(sc::camera_block(), out_.scene.camera, camera_seen_, camera_loc_, camera_keys_, eof);
        required(sc::picture_size_block(), out_.scene, size_seen_, size_loc_, size_keys_, eof);
        out_.scene.camera_loc = camera_loc_;
    }

    // A section that must be present with all its required keys.
    template <class T>
    void required(const sc::Block<T>& b, const T& item, bool seen, SourceLoc at, const ItemState& st, std::size_t eof) {
        if (!seen) {
            error_at(eof, "the scene has no '" + std::string(b.name) + "' section");
            return;
        }
        bool complete = true;
        for (const sc::Key<T>& k : b.keys)
            if (k.required && !(st.given & (1u << key_index(b, k)))) {
                error_at(at, std::string(b.name) + ": missing '" + std::string(k.name) + "'");
                complete = false;
            }
        if (complete && b.check)
            if (sc::Problem p = b.check(item)) report(p, at);
    }

    struct Decoding {
        std::shared_ptr<const Texture> texture;
        std::string name;  // as the scene names it
        SourceLoc loc;     // its first use, in file (included from included_from)
        std::string file;
        std::vector<Diagnostic::Site> included_from;
    };
    // What the reading of a scene file and of the files it includes share.
    struct Shared {
        std::map<std::string, int, std::less<>> materials;  // name -> index in Scene::materials
        std::map<std::string, int, std::less<>> objects;    // name -> index in Scene::defined
        std::vector<std::string> material_files;  // the file of each definition ("": the scene's)
        std::vector<std::string> stack, stack_names;  // the included files being read (device:inode, name)
        std::string scene_id;  // the scene file's device:inode, when known
        std::vector<Decoding> decoding;  // textures read `later`, not yet waited for
        std::vector<std::shared_ptr<const MeshModel>> models_read;
    };

    SceneLexer lex_;
    LineMap lines_;
    const ParseOptions& opt_;
    Shared own_shared_;
    Shared* shared_ = &own_shared_;
    std::string file_;  // "" for the scene file; else the included file, as diagnostics name it
    std::vector<Diagnostic::Site> included_from_;  // where this file was included, innermost first
    std::size_t includes_ = 0;  // include lines read in the scene file
    Include included_;  // (counts only) items brought in by the includes so far
    ParseResult& out_;
    Piece* piece_ = nullptr;  // set in a helper
    std::vector<Piece*> pieces_;  // the helpers' pieces, in file order
    std::size_t next_piece_ = 0;  // pieces_ before it are taken or passed
    std::size_t next_start_ = kNone;  // its start
    std::size_t next_tick_ = kNone;
    std::size_t bytes_shown_ = 0;
    int errors_ = 0;
    int depth_ = 0;  // CSG nesting of the object being read
    std::size_t objects_ = 0;
    std::size_t populated_ = 0;  // objects.size() at which populate_ahead is next called
    std::map<std::string, ModelStore::Loaded> models_;  // by resolved path
    ModelStore own_models_;  // when the options give no store
    std::map<std::string, TextureStore::Loaded> textures_;  // by resolved path
    TextureStore own_textures_;  // when the options give no store
    std::set<const Texture*> counted_textures_;  // those counted in texels_
    std::uint64_t texels_ = 0;  // of the textures read, toward the scene's limit
    std::size_t triangles_ = 0;  // in the models read
    bool camera_seen_ = false, size_seen_ = false;
    ItemState camera_keys_, size_keys_;  // keys accumulate over repeated sections
    SourceLoc camera_loc_, size_loc_;
};

// Where helpers may start: after each of the first n - 1 n-ths of the text, the first
// object name that follows a '}' (the end of an item) or the '{' of `thing`, with a
// '{' after it. A guess that turns out not to be an item start costs only time.
std::vector<std::size_t> piece_starts(std::string_view text, std::size_t n) {
    auto space = [](char c) { return c == ' ' || (c >= '\t' && c <= '\r'); };
    auto word_end = [&](std::size_t i) {
        while (i < text.size() && !space(text[i]) && text[i] != '{' && text[i] != '}') ++i;
        return i;
    };
    std::vector<std::size_t> starts;
    for (std::size_t k = 1; k < n; ++k) {
        std::size_t i = text.size() / n * k;
        const std::size_t limit = text.size() / n * (k + 1);
        for (; i < limit; ++i) {
            const char* brace = static_cast<const char*>(std::memchr(text.data() + i, '}', limit - i));
            if (!brace) break;
            i = std::size_t(brace - text.data());
            std::size_t j = i + 1;
            while (j < text.size() && space(text[j])) ++j;
            const std::size_t e = word_end(j);
            if (e == j || !sc::object_block(text.substr(j, e - j))) continue;
            std::size_t b = e;
            while (b < text.size() && space(text[b])) ++b;
            if (b < text.size() && text[b] == '{' && (starts.empty() || starts.back() < j)) {
                starts.push_back(j);
                break;
            }
        }
    }
    return starts;
}

}  // namespace

ParseResult parse_scene(std::string_view text, const ParseOptions& options) {
    ParseResult result;
    result.max_errors = options.max_errors;
    if (text.size() > Limits::max_file_size) {
        result.diagnostics.push_back({Diagnostic::Severity::Error, 1, 1,
                                      "scene file too large (" + std::to_string(text.size()) +
                                          " bytes, limit " + std::to_string(Limits::max_file_size) + ")"});
        return result;
    }
    // Growing the object list by doubling would move every object about once more and
    // touch twice its final memory. Files spend well over 64 bytes on an object in
    // practice, so this is usually enough; pages the list never reaches are never
    // touched, so an overestimate costs address space only.
    try {
        result.scene.objects.reserve(text.size() / 64);
    } catch (const std::bad_alloc&) {
        // Then the list grows as it goes.
    }
    std::size_t threads = options.threads > 0 ? std::size_t(options.threads) : std::size_t(process_pool().size());
    threads = std::min({threads, text.size() / std::max<std::size_t>(options.min_piece_bytes, 1), std::size_t(64)});
    std::vector<std::unique_ptr<Piece>> pieces;
    if (threads > 1) {
        const std::vector<std::size_t> starts = piece_starts(text, threads);
        for (std::size_t k = 0; k < starts.size(); ++k) {
            auto p = std::make_unique<Piece>();
            p->start = p->end = starts[k];
            p->at = starts[k];
            p->stop_at = k + 1 < starts.size() ? starts[k + 1] : text.size() + 1;
            p->max_counted = Limits::max_objects / starts.size();
            pieces.push_back(std::move(p));
        }
    }
    if (pieces.empty()) {
        Parser(text, options, result).run();
        return result;
    }
    // The main reading is item 0, on this thread (progress is reported here); the
    // helpers, the others. Each thread runs what it takes to the end, and the main
    // reading never waits for a helper not begun, so the loop ends whichever threads
    // are free.
    std::vector<Piece*> own;
    for (auto& p : pieces) own.push_back(p.get());
    process_pool().parallel_for(int(pieces.size()) + 1, [&](int k) {
        if (k == 0) {
            Parser(text, options, result).run(own);
            return;
        }
        Piece* piece = pieces[std::size_t(k - 1)].get();
        if (piece->claimed.load()) return;
        ParseResult helper_out;
        Parser(text, options, helper_out, *piece).run_piece();
    });
    return result;
}

Status ParseResult::status(const std::string& file, int max_shown) const {
    if (ok()) return {};
    if (cancelled) return Status::error(escape_text(file) + ": reading was cancelled\n", kExitUsage);
    int errors = 0;
    for (const Diagnostic& d : diagnostics) errors += d.is_error();
    return Status::error(diagnostics_report(file, diagnostics, max_shown, errors >= max_errors), kExitScene);
}

std::string format_diagnostic(const std::string& file, const Diagnostic& d) {
    std::string out = (d.file.empty() ? file : d.file) + ":" + std::to_string(d.line) + ":" + std::to_string(d.col) + ": " +
                      (d.is_error() ? "error: " : "warning: ") + d.message;
    for (std::size_t k = 0; k < d.included_from.size(); ++k) {
        const Diagnostic::Site& at = d.included_from[k];
        out += (k == 0 ? " (included from " : ", from ") + (at.file.empty() ? file : at.file) + ":" +
               std::to_string(at.line) + ":" + std::to_string(at.col);
    }
    return d.included_from.empty() ? out : out + ")";
}

}  // namespace rt
