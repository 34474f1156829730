// What the benchmark tools share besides the scene (bench_scene.h): a clock and the
// command line `TOOL SCENE.txt [--FLAG N]`.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace bench {

// Seconds on the steady clock.
inline double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Prints `usage: LINE` and gives main's exit code for a wrong command line (2).
inline int usage(const char* line) {
    std::fprintf(stderr, "usage: %s\n", line);
    return 2;
}

// The count after `flag` on the command line (argv[2] on), at least 1; `fallback` when
// it is not given.
inline int count_option(int argc, char** argv, const char* flag, int fallback) {
    int n = fallback;
    for (int i = 2; i + 1 < argc; ++i)
        if (!std::strcmp(argv[i], flag)) n = std::max(1, std::atoi(argv[++i]));
    return n;
}

}  // namespace bench
