// Output safety of the `raytracer` CLI (issue 6): a failed or interrupted render leaves
// an existing output byte-identical (same inode, same modification time), leaves no
// temporary file in the folder, says why, and exits non-zero. A successful render
// replaces the output by renaming a finished temporary file over it.
#include <doctest/doctest.h>
#include <sched.h>
#include <signal.h>
#include <fcntl.h>
#include <sys/mount.h>
#include <sys/ptrace.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "test_util.h"

namespace fs = std::filesystem;

namespace {

using rt_test::kRaytracer;

const char* const kGoodScene = R"(thing {
  sphere { material { colour 1 0.2 0.2 } position 5 0 0 radius 1 }
  sphere { material { reflection 0.5 scattering 0.5 } position 6 -2 0 radius 1 }
}
special_thing { plane { point 1 0 0 -1  point 2 1 0 -1  point 3 0 1 -1  point 4 0 0 0 } }
light { lamp { colour 30 30 30 position 0 0 5 size 0.2 } }
camera { position 0 0 0 centre 1 0 0 up 1 0 1 angle_x 60 angle_y 45 }
picture_size { x_max 16 y_max 12 }
end
)";

using rt_test::contains;
using rt_test::listing;
using rt_test::put;
using rt_test::slurp;

// What must not change about an existing output.
struct FileState {
    bool exists = false;
    std::string bytes;
    ino_t ino = 0;
    dev_t dev = 0;
    timespec mtime{};
    mode_t mode = 0;

    static FileState of(const fs::path& p) {
        FileState s;
        struct stat st;
        if (::stat(p.c_str(), &st) != 0) return s;
        s.exists = true;
        s.bytes = slurp(p);
        s.ino = st.st_ino;
        s.dev = st.st_dev;
        s.mtime = st.st_mtim;
        s.mode = st.st_mode;
        return s;
    }
    bool operator==(const FileState& o) const {
        return exists == o.exists && bytes == o.bytes && ino == o.ino && dev == o.dev &&
               mtime.tv_sec == o.mtime.tv_sec && mtime.tv_nsec == o.mtime.tv_nsec && mode == o.mode;
    }
};

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : " ") + x;
    return s;
}

// A fresh folder (mode 0755, so that an unprivileged child can enter it), removed
// afterwards. The CLI's stdout and stderr go to a sibling folder, so that listing the
// work folder shows only what the CLI itself left there.
struct Sandbox {
    fs::path root, work, logs;
    Sandbox() {
        std::string tmpl = (fs::temp_directory_path() / "rt-outsafe-XXXXXX").string();
        REQUIRE(mkdtemp(tmpl.data()) != nullptr);
        root = tmpl;
        work = root / "work";
        logs = root / "logs";
        fs::create_directories(work);
        fs::create_directories(logs);
        for (const auto& d : {root, work, logs}) ::chmod(d.c_str(), 0755);
    }
    ~Sandbox() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }
};

struct Run {
    int status = -1;  // exit status, or -1 if it did not exit normally
    int signal = 0;   // the terminating signal, if any
    std::string err;
};

// Starts the CLI in `cwd` with `args`; stdin is /dev/null. If `as_nobody`, it runs as
// uid/gid 65534 (root ignores file permissions). A `cpu_limit_s` kills it (SIGXCPU)
// once it has used that many seconds of CPU, however long that takes on the clock.
pid_t start(const Sandbox& box, const fs::path& cwd, const std::vector<std::string>& args, bool as_nobody = false,
            rlim_t cpu_limit_s = RLIM_INFINITY) {
    const std::string err_path = (box.logs / "stderr").string();
    const std::string out_path = (box.logs / "stdout").string();
    std::fflush(nullptr);  // or the child's freopen would write out the parent's buffered output
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        if (!freopen("/dev/null", "r", stdin) || !freopen(out_path.c_str(), "w", stdout) ||
            !freopen(err_path.c_str(), "w", stderr))
            _exit(97);
        if (chdir(cwd.c_str()) != 0) _exit(96);
        const rlimit cpu{cpu_limit_s, cpu_limit_s};
        if (setrlimit(RLIMIT_CPU, &cpu) != 0) _exit(94);
        if (as_nobody && (setgid(65534) != 0 || setuid(65534) != 0)) _exit(95);
        std::vector<char*> argv;
        argv.push_back(const_cast<char*>("raytracer"));
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(kRaytracer.c_str(), argv.data());
        _exit(98);
    }
    return pid;
}

// Waits until a file written now in `dir` is stamped later than `t`: from then on, a
// rewrite of a file stamped `t` shows in its modification time (the file system's clock
// ticks coarsely).
void wait_for_later_mtime(const fs::path& dir, const timespec& t) {
    const fs::path probe = dir / ".clock-probe";
    rt_test::wait_until(
        [&] {
            put(probe, "tick\n");
            struct stat st;
            return ::stat(probe.c_str(), &st) == 0 &&
                   (st.st_mtim.tv_sec > t.tv_sec || (st.st_mtim.tv_sec == t.tv_sec && st.st_mtim.tv_nsec > t.tv_nsec));
        },
        "the file system's clock to pass the file's time");
    fs::remove(probe);
}

Run finish(const Sandbox& box, pid_t pid, double timeout_s = 120) {
    // Waits for the process to end; a guard kills it if it still runs after timeout_s.
    // (It is reaped only once the guard knows it ended: the guard never signals a
    // process id that may have been given to another process.)
    std::mutex m;
    std::condition_variable cv;
    bool ended = false, killed = false;
    std::thread guard([&] {
        std::unique_lock<std::mutex> lock(m);
        if (cv.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return ended; })) return;
        kill(pid, SIGKILL);
        killed = true;
    });
    siginfo_t info{};
    while (waitid(P_PID, id_t(pid), &info, WEXITED | WNOWAIT) != 0 && errno == EINTR) {
    }
    {
        std::lock_guard<std::mutex> lock(m);
        ended = true;
    }
    cv.notify_all();
    guard.join();
    int raw = 0;
    waitpid(pid, &raw, 0);
    if (killed) FAIL("the CLI did not finish within " << timeout_s << " s");
    Run run;
    if (WIFEXITED(raw)) run.status = WEXITSTATUS(raw);
    if (WIFSIGNALED(raw)) run.signal = WTERMSIG(raw);
    run.err = slurp(box.logs / "stderr");
    return run;
}

Run run_cli(const Sandbox& box, const fs::path& cwd, const std::vector<std::string>& args, bool as_nobody = false,
            rlim_t cpu_limit_s = RLIM_INFINITY) {
    return finish(box, start(box, cwd, args, as_nobody, cpu_limit_s));
}

// Runs `args` in box.work, where `out` exists with known content, and checks that the
// run failed with `exit_code` and a message containing `why`, leaving `out` and the
// folder exactly as they were.
void check_untouched(const Sandbox& box, const fs::path& watched_dir, const fs::path& out,
                     const std::vector<std::string>& args, int exit_code, const std::string& why,
                     bool as_nobody = false, rlim_t cpu_limit_s = RLIM_INFINITY) {
    // A day in the past: a rewrite, however soon, would show in mtime.
    std::error_code ec;  // (none to set on a file that is not there)
    fs::last_write_time(out, fs::file_time_type::clock::now() - std::chrono::hours(24), ec);
    const FileState before = FileState::of(out);
    const auto files_before = listing(watched_dir);
    const Run r = run_cli(box, box.work, args, as_nobody, cpu_limit_s);
    CAPTURE(r.err);
    CHECK(r.status == exit_code);
    CHECK(contains(r.err, why));
    CHECK(FileState::of(out) == before);
    CHECK(joined(listing(watched_dir)) == joined(files_before));
}

// Whether the permission test can run: unprivileged, or as root with a binary that
// nobody (uid 65534) can reach (every folder on its path searchable by others).
// Decided before the tests run, so that a test that cannot run is reported as skipped.
bool can_test_permissions() {
    if (geteuid() != 0) return true;
    fs::path p = fs::absolute(kRaytracer);
    struct stat st;
    if (::stat(p.c_str(), &st) != 0 || !(st.st_mode & S_IXOTH)) return false;
    for (p = p.parent_path(); !p.empty() && p != p.root_path(); p = p.parent_path())
        if (::stat(p.c_str(), &st) != 0 || !(st.st_mode & S_IXOTH)) return false;
    return true;
}

// Whether a child process can make a private mount namespace and mount a tmpfs in it
// (root with CAP_SYS_ADMIN; not in every container).
bool can_mount_privately() {
    if (geteuid() != 0) return false;
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return false;
    if (pid == 0) {
        char dir[] = "/tmp/rt-mountprobe-XXXXXX";
        if (unshare(CLONE_NEWNS) != 0 || ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
            !mkdtemp(dir))
            _exit(1);
        const bool ok = ::mount("tmpfs", dir, "tmpfs", 0, "size=64k") == 0;
        if (ok) ::umount2(dir, MNT_DETACH);
        ::rmdir(dir);
        _exit(ok ? 0 : 1);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// Whether this process may trace its children (ptrace(2); not in every container).
bool can_trace_children() {
    std::fflush(nullptr);
    const pid_t pid = fork();
    if (pid < 0) return false;
    if (pid == 0) {
        for (;;) ::pause();
    }
    const bool ok = ::ptrace(PTRACE_SEIZE, pid, nullptr, nullptr) == 0;
    kill(pid, SIGKILL);
    int status = 0;
    waitpid(pid, &status, 0);
    return ok;
}

// One signal mask ("ShdPnd:", "SigBlk:", ...) from a /proc status file.
std::uint64_t signal_mask(const fs::path& status_file, const std::string& key) {
    std::ifstream in(status_file);
    for (std::string line; std::getline(in, line);)
        if (line.rfind(key, 0) == 0) return std::stoull(line.substr(key.size()), nullptr, 16);
    return 0;
}

// Whether the CLI has run its handler for every SIGTERM sent to it: none is pending,
// and the thread that takes them (the one that does not block SIGTERM) is back in
// pause(), sleeping.
bool sigterm_handled(pid_t pid) {
    const fs::path proc = "/proc/" + std::to_string(pid);
    const std::uint64_t term = std::uint64_t(1) << (SIGTERM - 1);
    if (signal_mask(proc / "status", "ShdPnd:") & term) return false;
    for (const auto& task : fs::directory_iterator(proc / "task")) {
        if (signal_mask(task.path() / "status", "SigBlk:") & term) continue;
        const std::string stat = slurp(task.path() / "stat");
        const std::size_t paren = stat.rfind(')');
        return !(signal_mask(task.path() / "status", "SigPnd:") & term) && paren != std::string::npos &&
               stat.compare(paren, 4, ") S ") == 0;
    }
    return false;
}

}  // namespace

TEST_CASE("output safety: a successful render replaces the output by rename, leaving no temporary") {
    Sandbox box;
    put(box.work / "scene.txt", kGoodScene);
    put(box.work / "out.ppm", "old picture\n");
    const FileState before = FileState::of(box.work / "out.ppm");
    const Run r = run_cli(box, box.work, {"--quiet", "scene.txt", "out.ppm"});
    CAPTURE(r.err);
    REQUIRE(r.status == 0);
    const FileState after = FileState::of(box.work / "out.ppm");
    CHECK(after.bytes.compare(0, 2, "P6") == 0);
    CHECK(after.ino != before.ino);  // a new file renamed over the old one, not a rewrite
    CHECK((after.mode & 07777) == (before.mode & 07777));
    CHECK(joined(listing(box.work)) == "out.ppm scene.txt");
}

TEST_CASE("output safety: a scene with errors leaves the existing output untouched") {
    Sandbox box;
    put(box.work / "bad.txt", "thing { sphere { radius x } }\nend\n");
    put(box.work / "out.ppm", "precious\n");
    put(box.work / "out.png", "precious png\n");
    check_untouched(box, box.work, box.work / "out.ppm", {"bad.txt", "out.ppm"}, 1, "bad.txt:1:25: error:");
    check_untouched(box, box.work, box.work / "out.png", {"bad.txt", "out.png"}, 1, "error:");
    // Unreadable or missing scene: I/O error, output untouched.
    check_untouched(box, box.work, box.work / "out.ppm", {"missing.txt", "out.ppm"}, 2, "missing.txt");
    check_untouched(box, box.work, box.work / "out.ppm", {".", "out.ppm"}, 2, "cannot read");
}

TEST_CASE("output safety: an unusable target folder fails early, saying why") {
    Sandbox box;
    put(box.work / "scene.txt", kGoodScene);
    put(box.work / "out.ppm", "precious\n");
    put(box.work / "plain-file", "not a folder\n");
    // The folder does not exist.
    check_untouched(box, box.work, box.work / "out.ppm", {"scene.txt", "no/such/folder/out.ppm"}, 2,
                    "does not exist");
    // The "folder" is a file.
    check_untouched(box, box.work, box.work / "plain-file", {"scene.txt", "plain-file/out.ppm"}, 2, "plain-file");
    // The output is a folder, or the scene itself.
    fs::create_directory(box.work / "dir.ppm");
    check_untouched(box, box.work, box.work / "out.ppm", {"scene.txt", "dir.ppm"}, 2, "directory");
    fs::remove(box.work / "dir.ppm");
    fs::copy_file(box.work / "scene.txt", box.work / "scene.ppm");
    check_untouched(box, box.work, box.work / "scene.ppm", {"scene.ppm", "scene.ppm"}, 2, "scene file itself");
}

TEST_CASE("output safety: a read-only folder leaves the existing output untouched" * doctest::skip(!can_test_permissions())) {
    Sandbox box;
    const fs::path ro = box.work / "ro";
    fs::create_directory(ro);
    put(box.work / "scene.txt", kGoodScene);
    put(ro / "out.ppm", "precious\n");
    ::chmod((box.work / "scene.txt").c_str(), 0644);
    ::chmod((ro / "out.ppm").c_str(), 0666);  // the file itself is writable; its folder is not
    ::chmod(ro.c_str(), 0555);
    // Root ignores the folder's mode, so as root the CLI runs as nobody (uid 65534).
    const bool root = geteuid() == 0;
    check_untouched(box, ro, ro / "out.ppm", {"scene.txt", "ro/out.ppm"}, 2, "not writable", root);
    ::chmod(ro.c_str(), 0755);
}

TEST_CASE("output safety: a full file system (64 KiB tmpfs) fails with a reason, output untouched" *
          doctest::skip(!can_mount_privately())) {
    Sandbox box;
    const fs::path small = box.work / "small";
    fs::create_directory(small);
    // The mount goes into a private mount namespace of this test process (the CLI
    // children inherit it): nobody else sees it, and it vanishes with the process even
    // if the process is killed before unmounting. The rest of the run is unaffected
    // (the namespace starts as a copy of the current one).
    static bool private_ns = unshare(CLONE_NEWNS) == 0 &&
                             ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) == 0;
    REQUIRE(private_ns);
    REQUIRE(::mount("tmpfs", small.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, "size=64k,mode=0755") == 0);
    struct Unmount {
        fs::path p;
        ~Unmount() { ::umount2(p.c_str(), MNT_DETACH); }
    } unmount{small};
    put(box.work / "scene.txt", kGoodScene);
    put(small / "out.ppm", "precious\n");
    put(small / "out.png", "precious png\n");
    // 300 x 300 x 3 bytes = 270 KB of PPM: cannot fit in 64 KiB.
    check_untouched(box, small, small / "out.ppm", {"--quiet", "--width", "300", "--height", "300", "scene.txt",
                                                    "small/out.ppm"},
                    2, "No space left on device");
    // A PNG of noise-free pixels compresses well; a big one still does not fit.
    check_untouched(box, small, small / "out.png", {"--quiet", "--width", "2000", "--height", "2000",
                                                    "scene.txt", "small/out.png"},
                    2, "No space left on device");
    // A new output that does not fit: nothing is left behind at all.
    const auto files_before = listing(small);
    const Run r = run_cli(box, box.work, {"--quiet", "--width", "300", "--height", "300", "scene.txt", "small/new.ppm"});
    CHECK(r.status == 2);
    CHECK(contains(r.err, "No space left on device"));
    CHECK(joined(listing(small)) == joined(files_before));
}

TEST_CASE("output safety: an interrupted render (SIGINT, SIGTERM, SIGKILL) leaves the output untouched") {
    for (int sig : {SIGINT, SIGTERM, SIGKILL}) {
        CAPTURE(sig);
        Sandbox box;
        put(box.work / "scene.txt", kGoodScene);
        put(box.work / "out.ppm", "precious\n");
        const FileState before = FileState::of(box.work / "out.ppm");
        wait_for_later_mtime(box.work, before.mtime);
        // Far more work than anyone waits for; the signal comes once it is under way: its
        // handlers in place and 50 ms of CPU used (far more than reading the scene).
        pid_t pid = start(box, box.work,
                          {"--quiet", "--threads", "2", "--samples", "65536", "--width", "1000", "--height", "1000",
                           "scene.txt", "out.ppm"});
        rt_test::wait_until(
            [&] {
                return rt_test::catches_signal(pid, SIGINT) && rt_test::catches_signal(pid, SIGTERM) &&
                       rt_test::process_cpu_seconds(pid) >= 0.05;
            },
            "the render to be under way");
        const auto t0 = std::chrono::steady_clock::now();
        kill(pid, sig);
        const Run r = finish(box, pid, 30);
        const double stop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        CAPTURE(r.err);
        MESSAGE("signal " << sig << ": the CLI ended " << stop_s << " s after it");
        if (sig == SIGKILL) {
            CHECK(r.signal == SIGKILL);
        } else {
            CHECK(r.status == 128 + sig);
            CHECK(contains(r.err, "interrupted"));
            CHECK(contains(r.err, "nothing written"));
        }
        CHECK(FileState::of(box.work / "out.ppm") == before);
        CHECK(joined(listing(box.work)) == "out.ppm scene.txt");
    }
}

TEST_CASE("output safety: SIGTERM during the write, once or twice, leaves the old output and no temporary file" *
          doctest::skip(!can_trace_children())) {
    // Nothing to hit: a big picture renders fast, and its 27 MB of PPM are written in
    // pieces of 4 MiB, with a look for a signal before each.
    constexpr off_t kBytes = off_t(3000) * 3000 * 3 + 17;
    constexpr off_t kPiece = off_t(4) << 20;
    for (int signals : {1, 2}) {
        CAPTURE(signals);
        // The CLI's writing thread is held (ptrace) while its temporary file holds part
        // of the picture; the signals are sent and handled (on the CLI's thread for
        // them) meanwhile, and then it goes on: the signals came in the middle of the
        // write, and the write can take at most the piece it was at before it looks,
        // however loaded the machine. If it got too far before it was held, the attempt
        // is made again.
        bool caught = false;
        for (int attempt = 0; attempt < 20 && !caught; ++attempt) {
            Sandbox box;
            put(box.work / "scene.txt", R"(light { spotlight { position 2 3 6  colour 50 50 50 } }
camera { position 0 0 2  centre 5 0 1  up 5 0 2  angle_x 60  angle_y 46.8 }
picture_size { x_max 3000 y_max 3000 }
end
)");
            put(box.work / "out.ppm", "precious\n");
            const FileState before = FileState::of(box.work / "out.ppm");
            pid_t pid = start(box, box.work, {"--quiet", "scene.txt", "out.ppm"});
            // The temporary file (.out.ppm.XXXXXX) once it has data (not the empty one
            // the output check makes and removes before rendering), or the write is over.
            std::string temp;
            auto writing_or_done = [&] {
                std::error_code ec;
                for (const auto& name : listing(box.work))
                    if (name.rfind(".out.ppm.", 0) == 0 && fs::file_size(box.work / name, ec) > 0) temp = name;
                return !temp.empty() || !(FileState::of(box.work / "out.ppm") == before);
            };
            rt_test::wait_until(writing_or_done, "the write to begin");
            REQUIRE(::ptrace(PTRACE_SEIZE, pid, nullptr, nullptr) == 0);
            REQUIRE(::ptrace(PTRACE_INTERRUPT, pid, nullptr, nullptr) == 0);
            int held = 0;
            REQUIRE(waitpid(pid, &held, __WALL) == pid);
            if (!WIFSTOPPED(held)) continue;  // it had already ended (and is reaped)
            // Held open, the file's size can be read after the CLI has removed it.
            const int fd = temp.empty() ? -1 : ::open((box.work / temp).c_str(), O_RDONLY | O_CLOEXEC);
            struct stat st {};
            if (fd < 0 || ::fstat(fd, &st) != 0 || st.st_size + kPiece >= kBytes) {
                if (fd >= 0) ::close(fd);
                ::ptrace(PTRACE_DETACH, pid, nullptr, nullptr);
                finish(box, pid);
                continue;
            }
            caught = true;
            const off_t at_signal = st.st_size;
            for (int k = 0; k < signals; ++k) {
                kill(pid, SIGTERM);
                rt_test::wait_until([&] { return sigterm_handled(pid); }, "the CLI to handle SIGTERM");
            }
            REQUIRE(::ptrace(PTRACE_DETACH, pid, nullptr, nullptr) == 0);
            const Run r = finish(box, pid);
            REQUIRE(::fstat(fd, &st) == 0);
            ::close(fd);
            CAPTURE(r.err);
            CAPTURE(at_signal);
            CAPTURE(st.st_size);
            CHECK(r.status == 128 + SIGTERM);  // never 0: the signal is not ignored
            CHECK(contains(r.err, "interrupted"));
            // The write looked before its next piece and stopped: not a piece more.
            CHECK(st.st_size - at_signal <= kPiece);
            // Stopped before the rename: the old file, exactly.
            CHECK(FileState::of(box.work / "out.ppm") == before);
            CHECK(joined(listing(box.work)) == "out.ppm scene.txt");
        }
        CHECK(caught);
    }
}

TEST_CASE("output safety: a read-only OUT is refused before rendering, untouched" * doctest::skip(!can_test_permissions())) {
    Sandbox box;
    put(box.work / "scene.txt", kGoodScene);
    put(box.work / "out.ppm", "precious\n");
    const bool root = geteuid() == 0;
    // Root may replace anything, so as root the CLI runs as nobody, who owns the file.
    if (root) {
        REQUIRE(::chown((box.work / "out.ppm").c_str(), 65534, 65534) == 0);
        ::chmod(box.work.c_str(), 0777);
    }
    ::chmod((box.work / "out.ppm").c_str(), 0444);
    // A picture of hours: the refusal must come first. A render first would be killed
    // at 10 s of CPU, which the refusal is nowhere near, however loaded the machine.
    check_untouched(box, box.work, box.work / "out.ppm",
                    {"--quiet", "--samples", "65536", "--width", "2000", "--height", "2000", "scene.txt", "out.ppm"}, 2,
                    "read-only (Permission denied)", root, 10);
}

TEST_CASE("output safety: another user's file in a sticky folder is refused before rendering" * doctest::skip(geteuid() != 0 || !can_test_permissions())) {
    Sandbox box;
    const fs::path sticky = box.work / "sticky";
    fs::create_directory(sticky);
    ::chmod(sticky.c_str(), 01777);
    put(box.work / "scene.txt", kGoodScene);
    put(sticky / "out.ppm", "precious\n");
    ::chmod((sticky / "out.ppm").c_str(), 0666);  // root's, writable by all: only the sticky bit protects it
    // A picture of hours, refused first (a render first would be killed at 10 s of CPU).
    check_untouched(box, sticky, sticky / "out.ppm",
                    {"--quiet", "--samples", "65536", "--width", "2000", "--height", "2000", "scene.txt",
                     "sticky/out.ppm"},
                    2, "sticky folder cannot be replaced (Operation not permitted)", true, 10);
}
