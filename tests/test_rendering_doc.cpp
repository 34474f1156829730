// docs/rendering.md is what the code cites for how a pixel is computed: every citation
// "docs/rendering.md §N" in core/, app/ and tests/ must name a section the document has,
// and the document's contents list must match its sections.
#include <doctest/doctest.h>

#include <cctype>
#include <filesystem>
#include <set>
#include <string>

#include "test_util.h"

namespace fs = std::filesystem;

namespace {

const std::string kDoc = RT_SOURCE_DIR "/docs/rendering.md";
const std::string kSection = "\xC2\xA7";  // §

// The number at text[at...], or -1 if there is none.
int number_at(const std::string& text, std::size_t at) {
    int n = -1;
    while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at])))
        n = (n < 0 ? 0 : n * 10) + (text[at++] - '0');
    return n;
}

// Section numbers of the document's "## N. Title" headings.
std::set<int> section_numbers(const std::string& md) {
    std::set<int> out;
    for (std::size_t at = md.find("\n## "); at != std::string::npos; at = md.find("\n## ", at + 1)) {
        const int n = number_at(md, at + 4);
        if (n >= 0 && md.compare(at + 4 + std::to_string(n).size(), 2, ". ") == 0) out.insert(n);
    }
    return out;
}

}  // namespace

TEST_CASE("docs/rendering.md: every section cited in the code exists") {
    const std::string md = rt_test::slurp(kDoc);
    REQUIRE_FALSE(md.empty());
    const std::set<int> sections = section_numbers(md);
    CHECK(sections.size() >= 10);

    // "docs/rendering.md §2", "docs/rendering.md §2-§6"
    const std::string cite = "rendering.md " + kSection;
    int citations = 0;
    for (const char* dir : {"core", "app", "tests"}) {
        for (const auto& e : fs::recursive_directory_iterator(std::string(RT_SOURCE_DIR) + "/" + dir)) {
            const std::string ext = e.path().extension().string();
            if (ext != ".cpp" && ext != ".h") continue;
            const std::string text = rt_test::slurp(e.path());
            for (std::size_t at = text.find(cite); at != std::string::npos; at = text.find(cite, at + 1)) {
                const std::size_t num = at + cite.size();
                const int first = number_at(text, num);
                if (first < 0) continue;  // prose about citations, like this file's
                ++citations;
                const std::string where = e.path().string() + ": " + text.substr(at, 24);
                // The project's document, not some other rendering.md.
                CHECK_MESSAGE((at >= 5 && text.compare(at - 5, 5, "docs/") == 0), where);
                int last = first;
                const std::size_t after = num + std::to_string(first).size();
                if (text.compare(after, 1 + kSection.size(), "-" + kSection) == 0)
                    last = number_at(text, after + 1 + kSection.size());
                CHECK_MESSAGE(last >= first, where);
                for (int n = first; n <= last; ++n) CHECK_MESSAGE(sections.count(n) == 1, where);
            }
        }
    }
    CHECK(citations >= 8);  // camera, shading, refraction, shapes, CSG, ties, mirror, rounding
}

TEST_CASE("docs/rendering.md: the contents list links every section, in order") {
    const std::string md = rt_test::slurp(kDoc);
    const std::string entry = "\n- [" + kSection;
    std::set<int> listed;
    int previous = -1;
    for (std::size_t at = md.find(entry); at != std::string::npos; at = md.find(entry, at + 1)) {
        const int n = number_at(md, at + entry.size());
        CHECK(n > previous);
        previous = n;
        listed.insert(n);
    }
    CHECK(listed == section_numbers(md));
}
