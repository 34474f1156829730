// docs/rendering.md is what the code cites for how a pixel is computed: every citation
// "docs/rendering.md §N" in core/, app/ and tests/ must name a section the document has,
// and the document's contents list must match its sections.
#include <doctest/doctest.h>

#include <filesystem>
#include <regex>
#include <set>
#include <string>

#include "test_util.h"

namespace fs = std::filesystem;

namespace {

const std::string kDoc = RT_SOURCE_DIR "/docs/rendering.md";

// Section numbers of the document's "## N. Title" headings.
std::set<int> section_numbers(const std::string& md) {
    std::set<int> out;
    static const std::regex heading(R"((^|\n)## (\d+)\. )");
    for (std::sregex_iterator it(md.begin(), md.end(), heading), end; it != end; ++it)
        out.insert(std::stoi((*it)[2].str()));
    return out;
}

}  // namespace

TEST_CASE("docs/rendering.md: every section cited in the code exists") {
    const std::string md = rt_test::slurp(kDoc);
    REQUIRE_FALSE(md.empty());
    const std::set<int> sections = section_numbers(md);
    CHECK(sections.size() >= 10);

    // "docs/rendering.md §2", "docs/rendering.md §2-§6"
    static const std::regex cite(R"(rendering\.md §(\d+)(?:-§(\d+))?)");
    int citations = 0;
    for (const char* dir : {"core", "app", "tests"}) {
        for (const auto& e : fs::recursive_directory_iterator(std::string(RT_SOURCE_DIR) + "/" + dir)) {
            const std::string ext = e.path().extension().string();
            if (ext != ".cpp" && ext != ".h") continue;
            const std::string text = rt_test::slurp(e.path());
            for (std::sregex_iterator it(text.begin(), text.end(), cite), end; it != end; ++it) {
                ++citations;
                const std::string where = e.path().string() + ": " + it->str();
                // The project's document, not some other rendering.md.
                const auto at = std::size_t(it->position());
                CHECK_MESSAGE(at >= 5, where);
                if (at >= 5) CHECK_MESSAGE(text.compare(at - 5, 5, "docs/") == 0, where);
                const int first = std::stoi((*it)[1].str());
                const int last = (*it)[2].matched ? std::stoi((*it)[2].str()) : first;
                for (int n = first; n <= last; ++n) CHECK_MESSAGE(sections.count(n) == 1, where);
            }
        }
    }
    CHECK(citations >= 8);  // camera, shading, refraction, shapes, CSG, ties, mirror, rounding
}

TEST_CASE("docs/rendering.md: the contents list links every section, in order") {
    const std::string md = rt_test::slurp(kDoc);
    static const std::regex entry(R"(\n- \[§(\d+) )");
    std::set<int> listed;
    int previous = -1;
    for (std::sregex_iterator it(md.begin(), md.end(), entry), end; it != end; ++it) {
        const int n = std::stoi((*it)[1].str());
        CHECK(n > previous);
        previous = n;
        listed.insert(n);
    }
    CHECK(listed == section_numbers(md));
}
