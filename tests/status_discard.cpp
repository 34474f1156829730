// Compiled, not run: with -Werror=unused-result it must fail to compile as it stands
// (a Status and an Expected are dropped) and compile with -DUSE_RESULTS. Registered
// as the tests status_nodiscard and status_nodiscard_control in tests/CMakeLists.txt.
#include "status.h"

rt::Status save() { return rt::Status::error("disk full", rt::kExitUsage); }
rt::Expected<int> count() { return 3; }

int main() {
#ifdef USE_RESULTS
    rt::Status s = save();
    rt::Expected<int> n = count();
    return s.ok() && n.ok() ? 0 : 1;
#else
    save();
    count();
    return 0;
#endif
}
